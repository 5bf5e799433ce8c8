#!/usr/bin/python3
"""Precision as a mode: fix griddem precision single against double on LAMMPS's chute (bench/in.chute,
32,000 atoms), both with griddem/hooke/history/kk, and stock gran/hooke/history/kk as the yardstick
of round-off: two double-precision codes that sum the same forces in another order drift apart in
a chaotic flow too, so single precision costs accuracy only where it drifts faster than that.
Each runs once timed, then again dumped every --every steps; per dump the largest and the RMS distance between the same atom's
positions (in particle diameters) for single vs double and for stock vs griddem (double); at step
0 the largest force difference over the largest force. Appends to results/precision.jsonl
(with each run's atom-steps/s) and draws doc/tradeoff-precision.png. Runs with Kokkos on the CPU
(-k on t N) or, with --gpu, on one GPU.

usage: /usr/bin/python3 bench/precision.py [--lmp build-kk/lmp] [--threads 2 | --gpu] [--steps 2000]
                                           [--every 200] [--lammps-bench DIR]"""
import argparse
import datetime
import json
import math
import os
import shutil
import sys
import tempfile

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
from griddemtools import dump  # noqa: E402

STOCK_PAIR = "gran/hooke/history 200000.0 NULL 50.0 NULL 0.5 0"
RUNS = [  # (label, pair style, extra input)
    ("double", "griddem/hooke/history 200000.0 NULL 50.0 NULL 0.5 0", "fix grid all griddem precision double"),
    ("single", "griddem/hooke/history 200000.0 NULL 50.0 NULL 0.5 0", "fix grid all griddem precision single"),
    ("stock", STOCK_PAIR, ""),
]


def script(base, pair, extra, steps, every):
    """the chute with pair and extra for steps, dumped every `every` steps (0: no dumps)"""
    text = base.replace(STOCK_PAIR, pair + "\n" + extra)
    dump = ("dump d all custom %d dump.* id xu yu zu fx fy fz\n"
            "dump_modify d sort id format float %%.17g\n" % every) if every else ""
    lines = [l for l in text.splitlines() if not l.strip().startswith("run")]
    return "\n".join(lines) + "\n" + dump + "run %d\n" % steps


def read_dump(path):
    """{id: (x, y, z, fx, fy, fz)} of the dump's one snapshot (columns id xu yu zu fx fy fz)"""
    snapshot = dump.read_dump(path)[0]
    if snapshot.columns != ["id", "xu", "yu", "zu", "fx", "fy", "fz"]:
        raise SystemExit("%s: columns %s, not id xu yu zu fx fy fz" % (path, " ".join(snapshot.columns)))
    return {k: tuple(v) for k, v in snapshot.by_id().items()}


def distances(a, b):
    """largest and RMS distance between the same atoms' positions"""
    d2 = [sum((a[k][m] - b[k][m]) ** 2 for m in range(3)) for k in a]
    return math.sqrt(max(d2)), math.sqrt(sum(d2) / len(d2))


def force_error(a, b):
    top = max(math.sqrt(sum(b[k][3 + m] ** 2 for m in range(3))) for k in b)
    return max(math.sqrt(sum((a[k][3 + m] - b[k][3 + m]) ** 2 for m in range(3))) for k in a) / top


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lmp", default=os.path.join(TOP, "build-kk", "lmp"))
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--gpu", action="store_true")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--every", type=int, default=200)
    ap.add_argument("--lammps-bench", default=os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench"))
    args = ap.parse_args()
    kk = ["-k", "on"] + (["g", "1"] if args.gpu else ["t", str(args.threads)]) + [
        "-sf", "kk", "-pk", "kokkos", "newton", "off", "neigh", "half"]
    device = ("GPU" if args.gpu else "%s, Kokkos, %d threads" % (benchlib.device(), args.threads))
    wd = tempfile.mkdtemp(prefix="griddem-precision-")
    shutil.copy(os.path.join(args.lammps_bench, "data.chute"), wd)
    base = open(os.path.join(args.lammps_bench, "in.chute")).read()
    dumps, speed = {}, {}
    for label, pair, extra in RUNS:
        run_dir = os.path.join(wd, label)
        os.mkdir(run_dir)
        os.symlink(os.path.join(wd, "data.chute"), os.path.join(run_dir, "data.chute"))
        for every in (0, args.every):  # timed without dumps, then dumped
            loop, steps, natoms, _ = benchlib.run_lmp(
                os.path.abspath(args.lmp), run_dir, script(base, pair, extra, args.steps, every), 1,
                args.threads, kk, {"OMP_PROC_BIND": "spread", "OMP_PLACES": "threads"})
            if not every:
                speed[label] = natoms * steps / loop
        dumps[label] = {s: read_dump(os.path.join(run_dir, "dump.%d" % s))
                        for s in range(0, args.steps + 1, args.every)}
    steps = sorted(dumps["double"])
    record = {"date": datetime.date.today().isoformat(), "device": device, "scene": "chute",
              "natoms": len(dumps["double"][0]), "style": "griddem/hooke/history/kk",
              "atom_steps_per_s": {k: round(v) for k, v in speed.items()}, "steps": steps,
              "force_error_step0": {
                  "single vs double": force_error(dumps["single"][0], dumps["double"][0]),
                  "stock vs double": force_error(dumps["stock"][0], dumps["double"][0])}}
    for name, a in (("single vs double", "single"), ("stock vs double", "stock")):
        pairs = [distances(dumps[a][s], dumps["double"][s]) for s in steps]
        record["max_distance_" + name.split()[0]] = [p[0] for p in pairs]
        record["rms_distance_" + name.split()[0]] = [p[1] for p in pairs]
    print(json.dumps(record))
    with open(os.path.join(HERE, "results", "precision.jsonl"), "a") as f:
        f.write(json.dumps(record) + "\n")

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    floor = 1e-17  # a distance of exactly 0 drawn at the bottom of the log axis
    for key, label, style in (("single", "single vs double (griddem kk)", "C0"),
                              ("stock", "stock kk vs griddem kk, both double", "C1")):
        ax.semilogy(steps, [max(v, floor) for v in record["max_distance_" + key]], style + "-o",
                    label=label + ", largest")
        ax.semilogy(steps, [max(v, floor) for v in record["rms_distance_" + key]], style + "--",
                    label=label + ", RMS")
    ax.set_xlabel("step")
    ax.set_ylabel("distance between the same atom's positions (diameters)")
    ax.set_title("Chute, 32,000 atoms: precision single against the round-off of double\n"
                 "%s, %s" % (device, record["date"]), fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(TOP, "doc", "tradeoff-precision.png"), dpi=110)
    shutil.rmtree(wd, ignore_errors=True)


main()
