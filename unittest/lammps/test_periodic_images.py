"""A periodic box thinner than twice the largest contact distance is refused by the history
styles, by name, on 1 and 2 ranks: there a sphere can touch two periodic images of one partner,
or its own image, and the contact history, kept per partner ID, would give those contacts one
history (griddem/hooke/history differed from the same slab replicated along its thin axis by a
factor 390 in kinetic energy on one such slab). The limit is 2 x (2 r_max + pull-off reach); a box
just wider runs, a style without history runs in the thin box, and a box that fix deform shrinks
past the limit stops at the step it crosses it."""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

SLAB = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block 0 6 0 6 0 {lz}
create_box 1 box
lattice sc 1.0
create_atoms 1 box
set type 1 diameter 0.9
set type 1 density 1.0
velocity all create 1.5 4928459 loop geom
pair_style {pair}
pair_coeff * *
{fix}
timestep 1e-3
fix integrate all nve/sphere
thermo 10
run {steps}
"""
HISTORY = "griddem/hooke/history 2000.0 NULL 50.0 NULL 0.5 0"
REFUSAL = (r"the periodic box is ([0-9.e+-]+) wide along z, less than twice the largest contact distance "
           r"([0-9.e+-]+) .*at least ([0-9.e+-]+) wide along z")


def refused(out):
    m = re.search(REFUSAL, out)
    return (float(m.group(1)), float(m.group(2)), float(m.group(3))) if m else None


def main():
    WD = t.workdir()
    for nprocs in (1, 2):
        rc, out = t.run_lmp(SLAB.format(lz=1.2, pair=HISTORY, fix="", steps=10), WD, nprocs, name="in.thin%d" % nprocs)
        got = refused(out)
        t.check(rc != 0 and got is not None, "np %d: a slab 1.2 thick with spheres of diameter 0.9 is refused: %s" % (
            nprocs, t.errors(out)[:1] or out[-300:]))
        if got:
            width, contact, limit = got
            t.check(abs(width - 1.2) < 1e-12 and abs(contact - 0.9) < 1e-12 and abs(limit - 1.8) < 1e-12,
                    "np %d: the message names width 1.2, contact distance 0.9, limit 1.8: %s" % (nprocs, got))
        t.check("Step" not in out, "np %d: refused before the first step is computed" % nprocs)

        rc, out = t.run_lmp(SLAB.format(lz=1.85, pair=HISTORY, fix="", steps=10), WD, nprocs, name="in.wide%d" % nprocs)
        t.check(rc == 0, "np %d: a slab 1.85 thick (above 2 x 0.9) runs: %s" % (nprocs, t.errors(out)[:1]))

        rc, out = t.run_lmp(SLAB.format(lz=1.2, pair="griddem/hooke 2000.0 NULL 50.0 NULL 0.5 0", fix="", steps=10),
                            WD, nprocs, name="in.nohistory%d" % nprocs)
        t.check(rc == 0, "np %d: griddem/hooke (no history) runs in the thin slab: %s" % (nprocs, t.errors(out)[:1]))

        # 3.0 shrinks to 1.0 over 100 steps: below 1.8 from step 60 on
        rc, out = t.run_lmp(SLAB.format(lz=3.0, pair=HISTORY, fix="fix squeeze all deform 1 z final 0 1.0 remap x",
                                        steps=100), WD, nprocs, name="in.deform%d" % nprocs)
        got = refused(out)
        steps = [int(line.split()[0]) for line in out.splitlines() if re.match(r"\s*\d+\s+[-0-9.e+]+\s", line)]
        t.check(rc != 0 and got is not None and 1.7 < got[0] < 1.8,
                "np %d: fix deform past the limit stops there: %s" % (nprocs, got or t.errors(out)[:1]))
        t.check(steps and 50 <= steps[-1] <= 60, "np %d: the last thermo step before the refusal is 50 or 60: %s" % (
            nprocs, steps[-3:]))
    t.finish()


if __name__ == "__main__":
    main()
