"""compute griddem/grid: the channels as LAMMPS grid data. On 1 and 4 ranks the cell counts sum to
the number of atoms, the solid fractions times the cell volume sum to the spheres' volume, the
mass-averaged velocity is the velocity all atoms share, and dump grid/vtk writes a rectilinear
grid with one value (solid fraction) or three (velocity) per cell for ParaView."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

TEXT = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
velocity all set 0.3 -0.2 0.1
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
fix integrate all nve/sphere
compute channels all griddem/grid 5 4 3 count solid vx vy vz
compute contacts all contact/atom
compute contact_sum all reduce sum c_contacts
thermo_style custom step c_contact_sum f_GRIDDEM[5]
thermo_modify norm no
dump cells all grid 5 grid.*.txt c_channels:grid:data[*]
dump_modify cells format float %.17g
dump solid all grid/vtk 5 solid.*.vti c_channels:grid:data[2]
dump vel all grid/vtk 5 vel.*.vti c_channels:grid:data[3] c_channels:grid:data[4] c_channels:grid:data[5]
run 0
"""


def read_grid_dump(path):
    with open(path) as f:
        lines = f.read().splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("ITEM: GRID CELLS")) + 1
    return [[float(v) for v in line.split()] for line in lines[start:] if line.strip()]


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.g")
    n, box = 300, (4.0, 4.0, 4.0)
    t.write_random_spheres(data, n, box, 0.1, 0.3, seed=5, lattice=None)
    volume = 0.0
    with open(data) as f:
        atoms = f.read().split("Atoms # sphere")[1].split("Velocities")[0]
    for line in atoms.strip().splitlines():
        volume += math.pi / 6.0 * float(line.split()[2]) ** 3
    cellvol = box[0] * box[1] * box[2] / 60.0
    for ranks in (1, 4):
        sub = os.path.join(wd, "np%d" % ranks)
        os.mkdir(sub)
        out = t.run_ok(TEXT.format(data=data), sub, nprocs=ranks, name="in.grid")
        seen, pairs = t.thermo_values(out, "c_contact_sum"), t.thermo_values(out, "f_GRIDDEM[5]")
        t.check(seen and pairs and pairs[0] > 50 and seen[0] == 2 * pairs[0],
                "%d ranks: compute contact/atom counts each of the %s contacts from both atoms (%s)" % (ranks, pairs, seen))
        cells = read_grid_dump(os.path.join(sub, "grid.0.txt"))
        t.check(len(cells) == 60, "%d ranks: 5x4x3 cells written (%d)" % (ranks, len(cells)))
        t.check(sum(c[0] for c in cells) == n, "%d ranks: counts sum to %d atoms" % (ranks, n))
        solid = sum(c[1] for c in cells) * cellvol
        t.check(abs(solid - volume) <= 1e-9 * volume, "%d ranks: solid volume %.12g, spheres %.12g" % (ranks, solid, volume))
        occupied = [c for c in cells if c[0] > 0]
        worst = max(abs(c[2] - 0.3) + abs(c[3] + 0.2) + abs(c[4] - 0.1) for c in occupied)
        t.check(worst <= 1e-12, "%d ranks: cell velocities equal the common velocity (%.3g)" % (ranks, worst))
        t.check(all(c[2] == 0.0 for c in cells if c[0] == 0), "%d ranks: empty cells have zero velocity" % ranks)
        with open(os.path.join(sub, "vel.0.vti")) as f:
            vti = f.read()
        t.check('WholeExtent="0 5 0 4 0 3"' in vti and 'NumberOfComponents="3"' in vti,
                "%d ranks: velocity .vti is a 5x4x3 rectilinear grid of vectors" % ranks)
        t.check(os.path.exists(os.path.join(sub, "solid.0.vti")), "%d ranks: solid fraction .vti written" % ranks)

    rc, out = t.run_lmp("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\n"
                        "compute c all griddem/grid 2 2 2 count pressure\n", wd, name="in.bad")
    t.check(rc != 0 and "unknown value pressure" in out, "unknown field refused by name")
    for setup, args, expect in [("atom_style sphere\nregion b block 0 1 0 1 0 1", "0 2 2 count", "grid count x must be between 1 and 100000, not 0"),
                                ("atom_style sphere\nregion b prism 0 1 0 1 0 1 0.1 0 0", "2 2 2 count", "does not support triclinic"),
                                ("atom_style atomic\nregion b block 0 1 0 1 0 1", "2 2 2 count", "requires atom attributes radius and rmass")]:
        rc, out = t.run_lmp("units lj\n%s\ncreate_box 1 b\ncompute c all griddem/grid %s\n" % (setup, args), wd,
                            name="in.bad")
        t.check(rc != 0 and expect in out, "compute griddem/grid %s: '%s'" % (args, expect))
    t.finish()


if __name__ == "__main__":
    main()
