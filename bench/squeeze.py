#!/usr/bin/env python3
"""CPU benchmark: the 1:4 bidisperse squeeze (12 spheres of diameter 4 among 1,940 of diameter 1,
fix deform to 0.7 of the box, Hooke kn 1000, dt 0.001: python/griddemtools/squeeze.py, the scene
of unittest/lammps/test_bidisperse_squeeze.py) with stock gran/hooke/history and
griddem/hooke/history (defaults, and each cell mode given), on 1 and 2 MPI ranks, in one job.
Appends one JSON line per run to bench/results/cpu.jsonl; --rounds N runs every variant N times
in turn and prints each one's median and its ratio to stock's.

usage: bench/squeeze.py [--steps 3000] [--ranks 1,2] [--lmp build/lmp] [--build NAME] [--only LABEL,...]
                        [--rounds N]"""
import argparse
import os
import sys
import tempfile

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(TOP, "python"))  # griddemtools
from griddemtools import squeeze as scene  # noqa: E402

VARIANTS = [("gran/hooke/history", "", "stock"),
            ("griddem/hooke/history", "", "griddem defaults"),
            ("griddem/hooke/history", "fix grid all griddem cell exact", "griddem exact"),
            ("griddem/hooke/history", "fix grid all griddem cell multi", "griddem multi"),
            ("griddem/hooke/history", "fix grid all griddem cell classes", "griddem classes")]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=3000)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    ap.add_argument("--build", default=None, help="name of the build measured (default: git commit)")
    ap.add_argument("--only", default=None)
    ap.add_argument("--rounds", type=int, default=1, help="runs of each variant, in turn (benchlib.run_rounds)")
    args = ap.parse_args()
    build = args.build or benchlib.commit()
    only = args.only.split(",") if args.only else None
    wd = tempfile.mkdtemp(prefix="griddem-squeeze-")
    data = os.path.join(wd, "data.squeeze")
    scene.write_packing(data)
    runs = []
    for ranks in [int(r) for r in args.ranks.split(",")]:
        for style, fix, label in VARIANTS:
            if only and label not in only:
                continue
            text = scene.TEMPLATE.format(data=data, pair=style, scale=scene.SCALE, most="", steps=args.steps,
                                         name="bench").replace("pair_coeff * *", "pair_coeff * *\n" + fix)
            runs.append((label, text, ranks, 1))
    benchlib.run_rounds(args.lmp, wd, runs, args.rounds, os.path.join(HERE, "results", "cpu.jsonl"), "squeeze 1:4",
                        build)

main()
