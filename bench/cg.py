#!/usr/bin/env python3
"""CPU benchmark: compute griddem/cg against one DEM step. A periodic simple cubic lattice of
touching spheres (diameter 1.02, spacing 1, random velocities, griddem/hooke/history) runs the same
steps twice: plain, and with a dump grid (to /dev/null) invoking the compute every step (all 13 values, grid of
2 particle spacings, W = 1), which also makes the pair style tally per-atom virials. The
difference per step is the compute's cost. 32k and 1M atoms on 1 and 2 MPI ranks; one JSON line per
run in bench/results/cg.jsonl.

usage: bench/cg.py [--sizes 32,100] [--ranks 1,2] [--lmp build/lmp]"""
import argparse
import os
import tempfile

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
VALUES = "solid density vx vy vz pxx pyy pzz pxy pxz pyz temperature coordination"
SCENE = """units lj
atom_style sphere
boundary p p p
comm_modify vel yes
lattice sc 1.0
region b block 0 {n} 0 {n} 0 {n}
create_box 1 b
create_atoms 1 box
set group all diameter 1.02
velocity all create 0.01 5 loop geom
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
fix integrate all nve/sphere
timestep 0.001
{cg}
run {steps}
"""
CG = ("compute cg all griddem/cg {g} {g} {g} 1.0 " + VALUES +
      "\ndump every all grid 1 /dev/null c_cg:grid:pxz")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", default="32,100", help="lattice points per side (32^3 = 32k, 100^3 = 1M)")
    ap.add_argument("--ranks", default="1,2")
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    args = ap.parse_args()
    wd = tempfile.mkdtemp(prefix="griddem-cg-")
    for n in [int(s) for s in args.sizes.split(",")]:
        steps = max(5, 3200000 // n ** 3)
        for ranks in [int(r) for r in args.ranks.split(",")]:
            plain = benchlib.run_lmp(args.lmp, wd, SCENE.format(n=n, cg="", steps=steps), ranks)
            with_cg = benchlib.run_lmp(args.lmp, wd, SCENE.format(n=n, cg=CG.format(g=n // 2), steps=steps), ranks)
            step_s = plain[0] / steps
            cg_s = (with_cg[0] - plain[0]) / steps
            for label, run in (("griddem/hooke/history", plain), ("griddem/hooke/history + griddem/cg every step", with_cg)):
                benchlib.record(os.path.join(HERE, "results", "cg.jsonl"), "sc lattice %d^3" % n, label, ranks, 1,
                                run[0], run[1], run[2], grid=n // 2, values=13, step_s=step_s,
                                cg_per_call_s=cg_s, cg_over_step=cg_s / step_s)


main()
