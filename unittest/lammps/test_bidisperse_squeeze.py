"""A bidisperse 1:4 packing squeezed by fix deform: 12 spheres of diameter 4 among 1,940 of
diameter 1 (random, non-overlapping, seeded), compressed to 0.7 of the box in x, y and z with
remap x until it jams, with gran/hooke/history and with griddem/hooke/history left at its
defaults (no fix griddem line: the history starts at the default size per atom and must grow,
since each big sphere ends with more than 24 contacts). Asserted: the runs complete on 1 and 2
ranks; the big spheres end with more than 24 contacts (compute contact/atom, and the most
contacts of one atom reported by fix GRIDDEM); positions, velocities and forces at the end equal
stock's, and griddem's on 2 ranks its own on 1, to 1e-11 relative (ROUNDOFF; a compressed packing
amplifies round-off over the run, which stock shows between its own 1- and 2-rank runs)."""
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

NBIG, NSMALL = 12, 1940
DBIG, DSMALL = 4.0, 1.0
STEPS = 1000
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
# round-off amplified over the run. Measured (largest relative difference of positions, velocities
# and forces): stock 2 ranks vs 1 rank 7.7e-13, griddem vs stock 1.2e-12, griddem 2 ranks vs 1
# rank 1.1e-13. Allowed: 13 times stock's own rank difference; kn changed by 1e-9 relative in the
# griddem run alone moves the end state by 4.8e-9. Stock's rank difference must stay 5 times below.
ROUNDOFF = 1e-11
STATE = ["x", "y", "z", "vx", "vy", "vz"]
FORCES = ["fx", "fy", "fz"]


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


def run(wd, name, data, pair, nprocs):
    most = "f_GRIDDEM[6]" if pair.startswith("griddem") else ""
    text = TEMPLATE.format(data=data, pair=pair, scale=SCALE, most=most, steps=STEPS, name=name)
    rc, out = t.run_lmp(text, wd, nprocs=nprocs, name="in." + name)
    t.check(rc == 0, "%s: the run completes (exit %d): %s" % (
        name, rc, t.errors(out)[:1] or out.strip().splitlines()[-1:]))
    if rc != 0:
        return None, out
    return t.read_dump(os.path.join(wd, "dump." + name)), out


def big_contacts(snap):
    columns, atoms = snap
    itype, ic = columns.index("type"), columns.index("c_c")
    return sorted(int(v[ic]) for v in atoms.values() if v[itype] == 2)


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.squeeze")
    write_packing(data)

    stock1, stock_out = run(wd, "stock_np1", data, "gran/hooke/history", 1)
    stock2, _ = run(wd, "stock_np2", data, "gran/hooke/history", 2)
    if stock1 is None or stock2 is None:
        t.finish()
    big = big_contacts(stock1)
    t.check(len(big) == NBIG and min(big) > 24, "stock: every big sphere ends with > 24 contacts (%s)" % big)
    # what ordering alone changes in stock: the tolerance below must stay well above it
    drift = t.max_rel_diff(stock2, stock1, STATE + FORCES)
    t.check(drift <= ROUNDOFF / 5, "stock 2 ranks vs 1 rank: %.3g relative (round-off growth)" % drift)

    grid = {}
    for n in (1, 2):
        snap, out = run(wd, "grid_np%d" % n, data, "griddem/hooke/history", n)
        if snap is None:
            continue
        grid[n] = snap
        t.check(snap[1].keys() == stock1[1].keys(), "griddem, %d ranks: no atom lost" % n)
        big = big_contacts(snap)
        t.check(len(big) == NBIG and min(big) > 24,
                "griddem, %d ranks: every big sphere ends with > 24 contacts (%s)" % (n, big))
        most = t.thermo_values(out, "f_GRIDDEM[6]")
        t.check(most and most[-1] > 24, "griddem, %d ranks: fix GRIDDEM's most contacts of one atom "
                "ends above 24 (%s)" % (n, most[-1:]))
        t.check(t.thermo_values(out, "c_cmax") == t.thermo_values(stock_out, "c_cmax"),
                "griddem, %d ranks: the most contacts of one atom follows stock's at every thermo step" % n)
        err = t.max_rel_diff(snap, stock1, STATE)
        t.check(err <= ROUNDOFF, "griddem, %d ranks: positions/velocities differ from stock by %.3g relative" % (n, err))
        err = t.max_rel_diff(snap, stock1, FORCES)
        t.check(err <= ROUNDOFF, "griddem, %d ranks: forces differ from stock by %.3g relative" % (n, err))
    if 1 in grid and 2 in grid:
        err = t.max_rel_diff(grid[2], grid[1], STATE + FORCES)
        t.check(err <= ROUNDOFF, "griddem 2 ranks vs 1 rank: %.3g relative" % err)
    t.finish()


if __name__ == "__main__":
    main()
