#!/usr/bin/env python3
"""CPU benchmark: LAMMPS's chute scene (bench/in.chute, 32,000 atoms) with stock
gran/hooke/history and with griddem/hooke/history with its defaults and in each cell mode, on 1
and 2 MPI ranks (and griddem multi with 2 OpenMP threads where the cores allow), in one job on
one machine. --law LAW: each style's pair granular twin (stock granular, griddem/granular) with a
composed law of the examples (benchlib.GRANULAR_LAWS) instead. Appends one JSON line per run to
bench/results/cpu.jsonl, naming the build (--build, default the checkout's commit) so that two
builds run back to back compare. --rounds N runs every variant N times in turn and prints each
one's median and its ratio to stock's.

usage: bench/chute.py [--steps N] [--ranks 1,2] [--lmp build/lmp] [--build NAME] [--only LABEL,...]
                      [--law rolling|nohistory] [--lammps-bench DIR] [--rounds N]"""
import argparse
import os
import re
import shutil
import sys
import tempfile

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
from griddemtools.log import timing_sections  # noqa: E402
# (pair style, extra input, label, OpenMP threads per rank)
VARIANTS = [
    ("gran/hooke/history", "", "stock", 1),
    ("griddem/hooke/history", "", "griddem defaults", 1),
    ("griddem/hooke/history", "fix grid all griddem cell exact", "griddem exact", 1),
    ("griddem/hooke/history", "fix grid all griddem cell multi", "griddem multi", 1),
    ("griddem/hooke/history", "fix grid all griddem cell multi", "griddem multi, 2 threads", 2),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    ap.add_argument("--build", default=None, help="name of the build measured (default: git commit)")
    ap.add_argument("--only", default=None, help="comma-separated variant labels to run")
    ap.add_argument("--law", choices=sorted(benchlib.GRANULAR_LAWS), default=None,
                    help="pair granular with this law (default: gran/hooke/history's)")
    ap.add_argument("--lammps-bench", default=os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench"))
    ap.add_argument("--rounds", type=int, default=1, help="runs of each variant, in turn (benchlib.run_rounds)")
    args = ap.parse_args()

    wd = tempfile.mkdtemp(prefix="griddem-chute-")
    shutil.copy(os.path.join(args.lammps_bench, "data.chute"), wd)
    with open(os.path.join(args.lammps_bench, "in.chute")) as f:
        stock = f.read()
    out_path = os.path.join(HERE, "results", "cpu.jsonl")
    build = args.build or benchlib.commit()
    only = args.only.split(",") if args.only else None
    runs = []
    for ranks in [int(r) for r in args.ranks.split(",")]:
        for style, fix, label, threads in VARIANTS:
            if ranks * threads > (os.cpu_count() or 1) or (only and label not in only):
                continue
            text = stock.replace("gran/hooke/history", style)
            text = text.replace("pair_coeff      * *", "pair_coeff      * *\n" + fix)
            text = re.sub(r"run\s+100", "run %d" % args.steps, text)
            if args.law:
                text = benchlib.chute_granular(text, args.law)
            runs.append((label, text, ranks, threads))

    def fields(out):
        sections = timing_sections(out)
        return dict(({"law": args.law} if args.law else {}), pair_pct=sections.get("Pair"),
                    neigh_pct=sections.get("Neigh"))
    benchlib.run_rounds(args.lmp, wd, runs, args.rounds, out_path, "chute", build, fields)

main()
