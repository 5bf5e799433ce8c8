"""The 1:4 bidisperse squeeze (unittest/lammps/test_bidisperse_squeeze.py, bench/squeeze.py,
bench/callgrind.py, bench/tradeoff.py): 12 spheres of diameter 4 among 1,940 of diameter 1 placed
at random in a periodic cube, squeezed by fix deform to SCALE of the box; its data file and its
input (TEMPLATE: data, pair, scale, most (extra thermo columns), steps, name)."""
import math
import random

NBIG, NSMALL = 12, 1940
DBIG, DSMALL = 4.0, 1.0
SCALE = 0.7

TEMPLATE = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
pair_style {pair} 1000 NULL 50 NULL 0.5 1
pair_coeff * *
timestep 0.001
fix integrate all nve/sphere
fix squeeze all deform 1 x scale {scale} y scale {scale} z scale {scale} remap x
compute c all contact/atom
compute cmax all reduce max c_c
thermo_style custom step ke press c_cmax {most}
thermo_modify format float %.17g
thermo 100
dump snap all custom {steps} dump.{name} id type x y z vx vy vz fx fy fz c_c
dump_modify snap format float %.17g sort id
run {steps}
"""


def write_packing(path, seed=2025, fraction=0.24):
    """Random sequential placement in a periodic cube at the given solid fraction: the big spheres
    first, then the small ones, no two overlapping; small random velocities."""
    rng = random.Random(seed)
    volume = math.pi / 6.0 * (NBIG * DBIG ** 3 + NSMALL * DSMALL ** 3) / fraction
    box = volume ** (1.0 / 3.0)
    placed = []  # (x, y, z, diameter)
    ncell = int(box // DBIG)
    edge = box / ncell
    cells = {}

    def cell_of(p):
        return tuple(int(c // edge) % ncell for c in p)

    def free(p, d):
        cx, cy, cz = cell_of(p)
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for dz in (-1, 0, 1):
                    for q in cells.get(((cx + dx) % ncell, (cy + dy) % ncell, (cz + dz) % ncell), ()):
                        r2 = 0.0
                        for a in range(3):
                            s = p[a] - q[a]
                            s -= box * round(s / box)
                            r2 += s * s
                        if r2 < (0.5 * (d + q[3])) ** 2:
                            return False
        return True

    for n, d in ((NBIG, DBIG), (NSMALL, DSMALL)):
        for _ in range(n):
            for attempt in range(100000):
                p = tuple(rng.uniform(0.0, box) for _ in range(3))
                if free(p, d):
                    break
            else:
                raise SystemExit("could not place a sphere of diameter %g" % d)
            placed.append(p + (d,))
            cells.setdefault(cell_of(p), []).append(p + (d,))
    lines = ["bidisperse 1:4 packing (seed %d)" % seed, "", "%d atoms" % len(placed), "2 atom types", "",
             "0 %.17g xlo xhi" % box, "0 %.17g ylo yhi" % box, "0 %.17g zlo zhi" % box, "",
             "Atoms # sphere", ""]
    vel = ["", "Velocities", ""]
    for i, (x, y, z, d) in enumerate(placed, 1):
        lines.append("%d %d %.17g 1.0 %.17g %.17g %.17g" % (i, 2 if d == DBIG else 1, d, x, y, z))
        vel.append("%d %s 0 0 0" % (i, " ".join("%.17g" % rng.uniform(-0.2, 0.2) for _ in range(3))))
    with open(path, "w") as f:
        f.write("\n".join(lines + vel) + "\n")
