#!/usr/bin/env python3
"""CPU benchmark: a 1:10 polydisperse poured bed (continuous distribution of diameters 0.25-2.5,
fix pour into a periodic 24 x 24 box onto a frictional floor under gravity, Hooke kn 2000), with
stock gran/hooke/history and griddem/hooke/history (defaults, and cell multi), on 1 and 2 MPI
ranks, in one job. The scene is the same for both: fix pour's random stream does not depend on
the pair style. Appends one JSON line per run to bench/results/cpu.jsonl with the atoms present
at the end; --rounds N runs every variant N times in turn and prints each one's median and its
ratio to stock's.

usage: bench/poured_bed.py [--steps 20000] [--ranks 1,2] [--lmp build/lmp] [--build NAME] [--only LABEL,...]
                           [--rounds N]"""
import argparse
import os
import tempfile

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
VARIANTS = [("gran/hooke/history", "", "stock"),
            ("griddem/hooke/history", "", "griddem defaults"),
            ("griddem/hooke/history", "fix grid all griddem cell multi", "griddem multi")]
SCENE = """
units lj
atom_style sphere
boundary p p fm
comm_modify vel yes
region box block 0 24 0 24 0 60 units box
create_box 1 box
pair_style {style} 2000.0 NULL 50.0 NULL 0.5 1
pair_coeff * *
{fix}
timestep 0.0005
fix integrate all nve/sphere
fix gravity all gravity 1.0 vector 0 0 -1
fix floor all wall/gran hooke/history 2000.0 NULL 50.0 NULL 0.5 1 zplane 0.0 NULL
region slab block 1 23 1 23 20 55 units box
fix feed all pour 4000 1 2837461 vol 0.25 50 diam range 0.25 2.5 region slab
thermo 5000
run {steps}
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    ap.add_argument("--build", default=None, help="name of the build measured (default: git commit)")
    ap.add_argument("--only", default=None)
    ap.add_argument("--rounds", type=int, default=1, help="runs of each variant, in turn (benchlib.run_rounds)")
    args = ap.parse_args()
    build = args.build or benchlib.commit()
    only = args.only.split(",") if args.only else None
    wd = tempfile.mkdtemp(prefix="griddem-bed-")
    runs = []
    for ranks in [int(r) for r in args.ranks.split(",")]:
        for style, fix, label in VARIANTS:
            if only and label not in only:
                continue
            runs.append((label, SCENE.format(style=style, fix=fix, steps=args.steps), ranks, 1))
    benchlib.run_rounds(args.lmp, wd, runs, args.rounds, os.path.join(HERE, "results", "cpu.jsonl"),
                        "poured bed 1:10", build)

if __name__ == "__main__":
    main()
