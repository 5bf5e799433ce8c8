#!/usr/bin/env python3
"""Instructions per step (valgrind callgrind, one OpenMP thread) of the run loop, the pair style's
compute and LAMMPS's neighbor-list builds, for stock gran/hooke/history and griddem/hooke/history
on LAMMPS's chute (bench/in.chute, 32,000 atoms) or the 1:4 bidisperse squeeze of
bench/squeeze.py. Instruction counts do not depend on what else runs on the machine, so two
builds compare where wall times drift. Only the timestep loop is counted (Verlet::run, not the
setup); stock rebuilds its lists every ~50 steps on the chute, so give it enough steps (100) for
its neighbor share to show. Appends one JSON line per run to bench/results/callgrind.jsonl.

usage: bench/callgrind.py [--scene chute|squeeze] [--steps N] [--lmp build/lmp] [--build NAME]
                          [--only stock,griddem] [--lammps-bench DIR]"""
import argparse
import datetime
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
STYLES = {"stock": "gran/hooke/history", "griddem": "griddem/hooke/history"}
# inclusive counts reported, by a pattern of callgrind_annotate's function names
FUNCTIONS = {"loop": r"PROGRAM TOTALS",
             "pair": r"LAMMPS_NS::Pair\w+::compute\(int, int\)",
             "neigh_build": r"LAMMPS_NS::Neighbor::build\(int\)",
             "neigh_decide": r"LAMMPS_NS::Neighbor::decide\(\)"}


def chute_input(args, style, wd):
    shutil.copy(os.path.join(args.lammps_bench, "data.chute"), wd)
    with open(os.path.join(args.lammps_bench, "in.chute")) as f:
        text = f.read()
    return re.sub(r"run\s+100", "run %d" % args.steps, text.replace("gran/hooke/history", style))


def squeeze_input(args, style, wd):
    sys.path.insert(0, os.path.join(TOP, "unittest", "lammps"))
    import test_bidisperse_squeeze as scene
    data = os.path.join(wd, "data.squeeze")
    scene.write_packing(data)
    return scene.TEMPLATE.format(data=data, pair=style, scale=scene.SCALE, most="", steps=args.steps, name="cg")


def count(args, label, wd):
    text = (chute_input if args.scene == "chute" else squeeze_input)(args, STYLES[label], wd)
    with open(os.path.join(wd, "in.run"), "w") as f:
        f.write(text)
    out = os.path.join(wd, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", "--collect-atstart=no", "--toggle-collect=*Verlet::run*",
                    "--callgrind-out-file=" + out, args.lmp, "-in", "in.run", "-log", "none"], cwd=wd,
                   env=dict(os.environ, OMP_NUM_THREADS="1"), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   check=True)
    report = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, universal_newlines=True).stdout
    counts = {}
    for key, pattern in FUNCTIONS.items():
        found = [int(m.group(1).replace(",", "")) for m in re.finditer(r"^\s*([\d,]+) .*" + pattern, report, re.M)]
        counts[key] = max(found) if found else 0
    return {k: v / args.steps for k, v in counts.items()}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", choices=["chute", "squeeze"], default="chute")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    ap.add_argument("--build", default=None, help="name of the build measured (default: git commit)")
    ap.add_argument("--only", default="stock,griddem")
    ap.add_argument("--lammps-bench", default=os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench"))
    args = ap.parse_args()
    build = args.build or subprocess.run(["git", "-C", TOP, "rev-parse", "--short", "HEAD"],
                                         stdout=subprocess.PIPE, universal_newlines=True).stdout.strip()
    for label in args.only.split(","):
        wd = tempfile.mkdtemp(prefix="griddem-callgrind-")
        per_step = count(args, label, wd)
        line = {"date": datetime.date.today().isoformat(), "device": benchlib.device(), "scene": args.scene,
                "steps": args.steps, "style": label, "build": build,
                "instructions_per_step": {k: round(v) for k, v in per_step.items()}}
        print(json.dumps(line))
        with open(os.path.join(HERE, "results", "callgrind.jsonl"), "a") as f:
            f.write(json.dumps(line) + "\n")
        shutil.rmtree(wd)


main()
