#!/usr/bin/env python3
"""Instructions per step (valgrind callgrind, one OpenMP thread) of the run loop, the pair style's
compute and LAMMPS's neighbor-list builds, for stock gran/hooke/history and griddem/hooke/history
on LAMMPS's chute (bench/in.chute, 32,000 atoms), the 1:4 bidisperse squeeze of
bench/squeeze.py or the 1:10 poured bed of bench/poured_bed.py (give it its 20,000 steps: the
pour is the scene); or stock granular and griddem/granular on the chute with a composed law of
pair granular (--scene chute-granular, --law: the law of examples/rom-blade and rom-hopper,
"rolling", or of examples/hopper, packing and sliding, "nohistory"). Instruction counts do not
depend on what else runs on the machine, so two builds compare where wall times drift. Only the
timestep loop is counted (Verlet::run, not the setup); stock rebuilds its lists every ~50 steps
on the chute, so give it enough steps (100) for its neighbor share to show. The cost per touching pair is the pair compute's instructions a step
over the pairs in contact a step (mean over the counted steps), counted in a second, plain run by
LAMMPS's compute contact/atom, the same counter for both styles. Appends one JSON line per run to
bench/results/callgrind.jsonl; --keep DIR keeps each callgrind output there for callgrind_annotate.

usage: bench/callgrind.py [--scene chute|squeeze|poured-bed|chute-granular] [--law rolling|nohistory] [--steps N]
                          [--lmp build/lmp] [--build NAME] [--only stock,griddem] [--lammps-bench DIR]
                          [--keep DIR] [--cell MODE]"""
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
import poured_bed

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
from griddemtools import lammps, log, squeeze  # noqa: E402

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


def poured_bed_input(args, style, wd):
    return poured_bed.SCENE.format(style=style, fix="", steps=args.steps)


def chute_granular_input(args, style, wd):
    return benchlib.chute_granular(chute_input(args, style, wd), args.law)


def squeeze_input(args, style, wd):
    data = os.path.join(wd, "data.squeeze")
    squeeze.write_packing(data)
    return squeeze.TEMPLATE.format(data=data, pair=style, scale=squeeze.SCALE, most="", steps=args.steps, name="cg")


def touching_pairs(args, text, wd):
    """Mean pairs in contact over steps 1..steps (the steps callgrind counts): contact/atom's sum
    over atoms counts each pair from both of its atoms."""
    head, _, tail = text.rpartition("\nrun")
    counting = head + ("\ncompute griddem_bench_contacts all contact/atom\n"
                       "compute griddem_bench_sum all reduce sum c_griddem_bench_contacts\n"
                       "thermo_style custom step c_griddem_bench_sum\nthermo_modify norm no\nthermo 1\nrun" + tail)
    with open(os.path.join(wd, "in.pairs"), "w") as f:
        f.write(counting)
    out = lammps.run(args.lmp, ["-in", "in.pairs", "-log", "none"], wd, check=True).stdout
    sums = {int(step): value for step, value in log.thermo_table(out, "Step", "c_griddem_bench_sum")}
    steps = [sums[k] for k in sorted(sums) if k > 0]
    return 0.5 * sum(steps) / len(steps)


def count(args, label, wd):
    scene = {"chute": chute_input, "squeeze": squeeze_input, "poured-bed": poured_bed_input,
             "chute-granular": chute_granular_input}[args.scene]
    text = scene(args, STYLES[label], wd)
    if args.cell and label == "griddem":
        head, _, tail = text.rpartition("\nrun")
        text = head + "\nfix griddem_bench_grid all griddem cell %s\nrun" % args.cell + tail
    with open(os.path.join(wd, "in.run"), "w") as f:
        f.write(text)
    out = os.path.join(wd, "callgrind.out")
    subprocess.run(["valgrind", "--tool=callgrind", "--collect-atstart=no", "--toggle-collect=*Verlet::run*",
                    "--callgrind-out-file=" + out, args.lmp, "-in", "in.run", "-log", "none"], cwd=wd,
                   env=lammps.environment(), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   check=True)
    report = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", out],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, universal_newlines=True).stdout
    counts = {}
    for key, pattern in FUNCTIONS.items():
        found = [int(m.group(1).replace(",", "")) for m in re.finditer(r"^\s*([\d,]+) .*" + pattern, report, re.M)]
        counts[key] = max(found) if found else 0
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
        shutil.copy(out, os.path.join(args.keep, "callgrind.%s.%s.%s.out" % (args.scene, label, args.build_name)))
    return {k: v / args.steps for k, v in counts.items()}, touching_pairs(args, text, wd)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", choices=["chute", "squeeze", "poured-bed", "chute-granular"], default="chute")
    ap.add_argument("--law", choices=sorted(benchlib.GRANULAR_LAWS), default="rolling", help="chute-granular's law")
    ap.add_argument("--steps", type=int, default=20)
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    ap.add_argument("--build", default=None, help="name of the build measured (default: git commit)")
    ap.add_argument("--only", default="stock,griddem")
    ap.add_argument("--lammps-bench", default=os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench"))
    ap.add_argument("--keep", default=None, help="folder to keep the callgrind outputs in")
    ap.add_argument("--cell", default=None, help="griddem's cell mode or edge (fix griddem cell ...; default: the pair's)")
    args = ap.parse_args()
    build = args.build or benchlib.commit()
    args.build_name = re.sub(r"[^\w.+-]", "_", build)
    for label in args.only.split(","):
        wd = tempfile.mkdtemp(prefix="griddem-callgrind-")
        per_step, pairs = count(args, label, wd)
        line = {"date": datetime.date.today().isoformat(), "device": benchlib.device(), "scene": args.scene,
                **({"law": args.law} if args.scene == "chute-granular" else {}),
                "steps": args.steps, "style": label, "build": build,
                **({"cell": args.cell} if args.cell and label == "griddem" else {}),
                "instructions_per_step": {k: round(v) for k, v in per_step.items()},
                "touching_pairs_per_step": round(pairs, 1),
                "pair_instructions_per_touching_pair": round(per_step["pair"] / pairs, 1)}
        print(json.dumps(line))
        with open(os.path.join(HERE, "results", "callgrind.jsonl"), "a") as f:
            f.write(json.dumps(line) + "\n")
        shutil.rmtree(wd)


main()
