"""A cell mode that tests far more candidates than the default warns once, naming both numbers
and the mode to use. The scene: one sphere of diameter 20 under 4851 of diameter 0.2 on a lattice.
With cell multi the cells are sized for the large sphere (edge 20), so all N centres share one
cell, and every pair is a candidate: (N - 1)/2 per atom. On 2 ranks each process bins every atom
(its own, and the other's as ghosts: the large sphere's contact distance spans the box), so the
pairs are tested twice: N - 1 per atom. The default's grid per size class gives the small spheres
cells of their own size: a few tens per atom. Without the large sphere, multi is the default's one
grid and says nothing; neither does the default.

Cell auto measures the same two layouts and takes one grid where a grid per size class would not
test 1.5 times fewer candidates: at 1:100 above it keeps a grid per class (its occupied cells,
fix griddem's value 1, are cell classes'); with a few spheres of diameter 0.2 among a lattice of
diameter 1 (1:5, two size classes) the few small spheres cannot make the class grids test fewer
candidates, and it takes cell multi's one grid (its occupied cells are multi's, not classes',
which add the small spheres' own grid)."""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

SCENE = """
units lj
atom_style sphere
boundary f f f
comm_modify vel yes
region box block 0 10 0 10 -12 10
create_box 2 box
lattice sc 64.0
region bed block 0 5 0 5 0 2.5 units box    # lattice sc 64: spacing 64^(-1/3) = 0.25 (lj units)
create_atoms 1 region bed
{big}
set type 1 diameter 0.2
set type 2 diameter 20.0
set group all density 1.0
pair_style griddem/hooke/history 2000.0 NULL 50.0 NULL 0.5 0
pair_coeff * *
{fix}
timestep 1e-4
fix integrate all nve/sphere
run 0
run 0
"""
BIG = "create_atoms 2 single 5 5 -10.1 units box"
WARNING = (r"WARNING: Pair style griddem/hooke/history: fix \S+ cell multi tests ([0-9.e+]+) candidate pairs per atom, "
           r"([0-9.e+]+) times the ([0-9.e+]+) of cell auto, and holds up to (\d+) centres in one cell")
FEW_SMALL = """
units lj
atom_style sphere
boundary f f f
comm_modify vel yes
region box block 0 10 0 10 0 10
create_box 2 box
lattice sc 1.0
region bed block 0 6 0 6 0 6 units box
create_atoms 1 region bed
create_atoms 2 random 8 4721 bed
set type 1 diameter 1.0
set type 2 diameter 0.2
set group all density 1.0
pair_style griddem/hooke/history 2000.0 NULL 50.0 NULL 0.5 0
pair_coeff * *
fix grid all griddem {mode}
thermo_style custom step f_grid[1]
timestep 1e-4
fix integrate all nve/sphere
run 0
"""


def occupied_cells(out):
    """fix griddem's value 1 (occupied cells, all grids, all processes) after run 0"""
    rows = re.findall(r"^\s+0\s+(\d+)\s*$", out, re.M)
    return int(rows[-1]) if rows else -1


def check_auto_choice(WD, nprocs):
    cells = {}
    for mode in ("cell multi", "cell classes", "cell auto"):
        name = "in.%s%d" % (mode.split()[1], nprocs)
        big = SCENE.format(big=BIG, fix="fix grid all griddem %s\nthermo_style custom step f_grid[1]" % mode)
        few = FEW_SMALL.format(mode=mode)
        cells[mode] = (occupied_cells(t.run_ok(big, WD, nprocs, name=name + ".big")),
                       occupied_cells(t.run_ok(few, WD, nprocs, name=name + ".few")))
    multi, classes, auto = cells["cell multi"], cells["cell classes"], cells["cell auto"]
    t.check(min(multi + classes + auto) > 0 and multi[0] != classes[0] and multi[1] != classes[1],
            "np %d: the layouts differ (occupied cells, 1:100 and 1:5: multi %s, classes %s)" % (nprocs, multi, classes))
    t.check(auto[0] == classes[0], "np %d: at 1:100 cell auto keeps a grid per class: %d cells, classes %d, multi %d"
            % (nprocs, auto[0], classes[0], multi[0]))
    t.check(auto[1] == multi[1], "np %d: with a few small spheres cell auto takes one grid: %d cells, multi %d, "
            "classes %d" % (nprocs, auto[1], multi[1], classes[1]))


def main():
    WD = t.workdir()

    for nprocs in (1, 2):
        out = t.run_ok(SCENE.format(big=BIG, fix="fix grid all griddem cell multi"), WD, nprocs, name="in.multi%d" % nprocs)
        found = re.findall(WARNING, out)
        n = sum(int(m) for m in re.findall(r"Created (\d+) atoms", out))
        t.check(len(found) == 1, "np %d: cell multi at 1:100 warns once over two runs: %d warnings" % (nprocs, len(found)))
        if found:
            here, ratio, auto, most = float(found[0][0]), float(found[0][1]), float(found[0][2]), int(found[0][3])
            t.check(n == 4852 and here == (n - 1) / 2.0 * nprocs,
                    "np %d: multi tests (N - 1)/2 candidates per atom on each process, N = %d: %g" % (nprocs, n, here))
            t.check(most == n, "np %d: all %d centres in one cell: %d" % (nprocs, n, most))
            t.check(ratio > 8.0 and auto < 50.0 and abs(ratio - here / auto) < 1e-3 * ratio,
                    "np %d: auto tests %g per atom, %g times fewer" % (nprocs, auto, ratio))
        t.check("use cell auto" in out, "np %d: the warning names the mode to use" % nprocs)

        out = t.run_ok(SCENE.format(big=BIG, fix=""), WD, nprocs, name="in.auto%d" % nprocs)
        t.check("candidate pairs per atom" not in out, "np %d: the default says nothing" % nprocs)
        out = t.run_ok(SCENE.format(big="", fix="fix grid all griddem cell multi"), WD, nprocs, name="in.mono%d" % nprocs)
        t.check("candidate pairs per atom" not in out, "np %d: multi without the large sphere says nothing" % nprocs)
        check_auto_choice(WD, nprocs)
    t.finish()


if __name__ == "__main__":
    main()
