"""Data files of random polydisperse spheres (read_data, atom_style sphere): the tests' scenes and
the benchmarks' (bench/tradeoff.py)."""
import random


def write_random_spheres(path, n, box, rmin, rmax, seed, density=1.0, vscale=1.0, wscale=1.0,
                         triclinic=None, lattice=None, ntypes=1, flat=False):
    """Random polydisperse spheres with random linear and angular velocities, dense enough that
    many overlap. box = (lx, ly, lz) from 0; triclinic = (xy, xz, yz) or None; lattice = spacing
    of a simple cubic lattice to put the centres on (no overlaps if > 2 rmax) instead; atom i
    gets type 1 + i % ntypes. flat: for a 2d run, centres at z = 0 in a box from -lz/2 to lz/2,
    velocities in the plane, spins about z."""
    rng = random.Random(seed)
    lines = ["GRIDDEM test configuration (seed %d)" % seed, "", "%d atoms" % n, "%d atom types" % ntypes, ""]
    zlo = -0.5 * box[2] if flat else 0.0
    lines += ["0 %.17g xlo xhi" % box[0], "0 %.17g ylo yhi" % box[1], "%.17g %.17g zlo zhi" % (zlo, zlo + box[2])]
    if triclinic:
        lines.append("%.17g %.17g %.17g xy xz yz" % triclinic)
    lines += ["", "Atoms # sphere", ""]
    vel = ["", "Velocities", ""]
    for i in range(1, n + 1):
        r = rng.uniform(rmin, rmax)
        if lattice:
            m = int(round(box[0] / lattice))
            x, y, z = ((i - 1) % m * lattice, (i - 1) // m % m * lattice, (i - 1) // (m * m) * lattice)
        else:
            x, y, z = (rng.uniform(0, box[d]) for d in range(3))
        v = [rng.uniform(-vscale, vscale) for _ in range(3)]
        w = [rng.uniform(-wscale, wscale) for _ in range(3)]
        if flat:
            z, v[2], w[0], w[1] = 0.0, 0.0, 0.0, 0.0
        lines.append("%d %d %.17g %.17g %.17g %.17g %.17g" % (i, 1 + i % ntypes, 2 * r, density, x, y, z))
        vel.append("%d %s" % (i, " ".join("%.17g" % c for c in v + w)))
    with open(path, "w") as f:
        f.write("\n".join(lines + vel) + "\n")
