"""Contacts keyed by partner and periodic image: in a periodic box narrower than twice the largest
contact distance a sphere touches two images of one partner, and its own images, and each such
contact keeps its own history. A thin slab (spheres of diameter 0.85-1.15 in a box 1.1 thick along
z; also thin along y and z, and a triclinic one with xz and yz tilts) must move as the same slab
replicated 3 times along its thin axes (3.3 wide: no two images of one partner reach one sphere
there, so its distinct atoms are plain contacts): unwrapped positions, velocities, forces and
torques of the original atoms after 300 steps of gran/hooke/history's laws (griddem/hooke/history
and griddem/granular with linear_history tangential and sds rolling: 3 and 6 history values)
agree to 1e-10 relative, on 1 and 2 ranks (split along z, so that images come from the other rank), with atoms wrapping across the thin boundary during the
run, and a run restarted at step 150 (write_restart, read_restart) ends in the same state, as
does one whose atoms get new IDs at step 150 (reset_atoms id sort yes: the keys follow them with
their images; 1 and 2 ranks, KE to 1e-10 and the same contacts). The
old key (partner ID alone) fails this by far. A box under 1/8 of
the contact distance along a periodic axis (the images the key tells apart) is refused by name, and
a style without history runs in any box."""
import math
import os
import random
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

STEPS = 300
THIN = 1.1          # < 2 x 1.15: the slab's thin axes
WIDE = 3.0          # >= 2 x 1.15: the other axes
HISTORY = "griddem/hooke/history 2000.0 NULL 50.0 NULL 0.5 0"
GRANULAR = ("griddem/granular", "pair_coeff * * hooke 2000.0 50.0 tangential linear_history 571.0 1.0 0.5 "
            "rolling sds 500.0 20.0 0.3")
LAWS = {"hooke/history": (HISTORY, "pair_coeff * *"), "granular": GRANULAR}
VECTORS = {"x": ("xu", "yu", "zu"), "v": ("vx", "vy", "vz"), "f": ("fx", "fy", "fz"), "torque": ("tqx", "tqy", "tqz")}

# (name, box edges, tilts xy xz yz, number of copies per axis in the twin, spheres)
SLABS = [
    ("z", (WIDE, WIDE, THIN), (0.0, 0.0, 0.0), (1, 1, 3), 7),
    ("yz", (2 * WIDE, THIN, THIN), (0.0, 0.0, 0.0), (1, 3, 3), 5),
    ("z triclinic", (WIDE, WIDE, THIN), (0.4, 0.3, -0.2), (1, 1, 3), 7),
]

SCRIPT = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
processors 1 1 *
{start}
pair_style {pair}
{coeffs}
timestep 1e-3
fix integrate all nve/sphere
fix tether all spring/self 100.0
thermo_style custom step ke f_GRIDDEM[5]
thermo 50
{run}
"""
DUMP = ("write_dump all custom {dump} id xu yu zu vx vy vz fx fy fz tqx tqy tqz ix iy iz "
        "modify sort id format float %.17g\n")


def slab_atoms(n, edges, tilt, seed):
    """n spheres at random in the box (fractional coordinates), overlapping no image of another by
    more than 0.1 (their own images along the thin axes by up to 0.05), with random velocities
    (the first one heading across the z boundary) and spins: [(diameter, frac, v, omega)]. Each is
    tethered to where it starts (fix spring/self), so contacts last and slide."""
    rng = random.Random(seed)
    atoms = []
    for _ in range(100000):
        d = rng.uniform(0.85, 1.15)
        f = [rng.random() for _ in range(3)]
        v = [rng.uniform(-1.0, 1.0) for _ in range(3)]
        if not atoms:
            f[2], v[2] = 0.96, 2.5
        if all(min_distance(f, g, edges, tilt) > 0.5 * (d + dg) - 0.1 for dg, g, _, _ in atoms):
            atoms.append((d, f, v, [rng.uniform(-3.0, 3.0) for _ in range(3)]))
            if len(atoms) == n:
                return atoms
    raise RuntimeError("no room for %d spheres in the slab %s" % (n, edges))


def cartesian(f, edges, tilt):
    xy, xz, yz = tilt
    return (f[0] * edges[0] + f[1] * xy + f[2] * xz, f[1] * edges[1] + f[2] * yz, f[2] * edges[2])


def min_distance(f, g, edges, tilt):
    best = math.inf
    for s in ((a, b, c) for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)):
        p = cartesian([g[k] + s[k] - f[k] for k in range(3)], edges, tilt)
        best = min(best, math.sqrt(sum(x * x for x in p)))
    return best


def write_slab(path, atoms, edges, tilt, copies):
    """The slab as a data file, copied copies[d] times along each box vector d (copy c of atom i
    has ID i + c n, at its position plus the shifts); the box grows as many times."""
    n = len(atoms)
    big = [edges[d] * copies[d] for d in range(3)]
    tilts = (tilt[0] * copies[1], tilt[1] * copies[2], tilt[2] * copies[2])
    lines = ["thin slab", "", "%d atoms" % (n * copies[0] * copies[1] * copies[2]), "1 atom types", "",
             "0 %.17g xlo xhi" % big[0], "0 %.17g ylo yhi" % big[1], "0 %.17g zlo zhi" % big[2]]
    if any(tilt):
        lines.append("%.17g %.17g %.17g xy xz yz" % tilts)
    lines += ["", "Atoms # sphere", ""]
    vel = ["", "Velocities", ""]
    c = 0
    for a in range(copies[0]):
        for b in range(copies[1]):
            for k in range(copies[2]):
                for i, (d, f, v, w) in enumerate(atoms):
                    x = cartesian([f[0] + a, f[1] + b, f[2] + k], edges, tilt)
                    tag = 1 + i + c * n
                    lines.append("%d 1 %.17g 1.0 %.17g %.17g %.17g" % (tag, d, x[0], x[1], x[2]))
                    vel.append("%d %s" % (tag, " ".join("%.17g" % u for u in v + w)))
                c += 1
    with open(path, "w") as f:
        f.write("\n".join(lines + vel) + "\n")


def run_slab(wd, name, data, law, nprocs=1, extra=(), threads=None, restarted=False):
    """The slab run STEPS steps, in two runs with a restart file written between them (a run's
    setup evaluates the damping at full-step velocities, so the break is the same everywhere);
    restarted: the second run from the restart file. Returns the last snapshot and the output."""
    pair, coeffs = LAWS[law]
    dump, restart = os.path.join(wd, "dump." + name), os.path.join(wd, "restart." + name)
    half = STEPS // 2
    text = SCRIPT.format(start="read_data %s" % data, pair=pair, coeffs=coeffs,
                         run="run %d\nwrite_restart %s\nrun %d\n" % (half, restart, STEPS - half) + DUMP.format(dump=dump))
    rc, out = t.run_lmp(text, wd, nprocs, name="in." + name, extra=extra, threads=threads)
    if rc == 0 and restarted:
        text = SCRIPT.format(start="read_restart %s" % restart, pair=pair, coeffs=coeffs,
                             run="run %d\n" % (STEPS - half) + DUMP.format(dump=dump))
        rc, out = t.run_lmp(text, wd, nprocs, name="in." + name + "_restarted", extra=extra, threads=threads)
    t.check(rc == 0, "%s runs: %s" % (name, t.errors(out)[:1] or out[-500:]))
    return (t.read_dump(dump) if rc == 0 else None), out


def vector_diff(a, b):
    """Largest |a - b| of a component of positions, velocities, forces or torques, over the atoms
    of b, relative to the largest component of that vector in b: {vector: difference}."""
    (names_a, da), (names_b, db) = a, b
    diffs = {}
    for vec, cols in VECTORS.items():
        ia, ib = [names_a.index(c) for c in cols], [names_b.index(c) for c in cols]
        scale = max(abs(v[k]) for v in db.values() for k in ib) or 1.0
        diffs[vec] = max(abs(da[tag][ka] - vb[kb]) for tag, vb in db.items() for ka, kb in zip(ia, ib)) / scale
    return diffs


def originals(snapshot, n):
    """The snapshot's atoms 1..n (the slab's own atoms in a twin)."""
    columns, atoms = snapshot
    return columns, {k: v for k, v in atoms.items() if k <= n}


def slab_files(wd, seed=1):
    """{slab name: (thin data file, twin data file, n)} for SLABS."""
    files = {}
    for name, edges, tilt, copies, n in SLABS:
        atoms = slab_atoms(n, edges, tilt, seed)
        tag = name.replace(" ", "_")
        thin, twin = os.path.join(wd, "data.thin_" + tag), os.path.join(wd, "data.twin_" + tag)
        write_slab(thin, atoms, edges, tilt, (1, 1, 1))
        write_slab(twin, atoms, edges, tilt, copies)
        files[name] = (thin, twin, n)
    return files


def check_twin(wd, files):
    for slab, (thin, twin, n) in files.items():
        for law in LAWS:
            label = "%s slab, %s" % (slab, law)
            tag = re.sub(r"\W", "_", label)
            ref, out = run_slab(wd, "twin_" + tag, twin, law)
            if ref is None:
                continue
            ref = originals(ref, n)
            contacts = t.thermo_values(out, "f_GRIDDEM[5]")
            t.check(contacts and min(contacts) > 0, "%s: the twin keeps contacts all along: %s" % (label, contacts))
            runs = [("np %d" % p, dict(nprocs=p)) for p in (1, 2)] + [("restarted at step %d" % (STEPS // 2), dict(restarted=True))]
            for what, kw in runs:
                got, out = run_slab(wd, "thin_%s_%s" % (tag, re.sub(r"\W", "_", what)), thin, law, **kw)
                if got is None:
                    continue
                if what == "np 1":
                    flags = [v[-3:] for v in got[1].values()]
                    t.check(any(f[2] != 0 for f in flags), "%s: an atom wraps across the z boundary (image flags %s)" % (
                        label, flags))
                t.check(sorted(got[1]) == sorted(ref[1]), "%s, %s: the slab's atoms" % (label, what))
                diffs = vector_diff(got, ref)
                print("%s, %s: relative difference from the twin %s" % (
                    label, what, ", ".join("%s %.3g" % d for d in diffs.items())))
                t.check(max(diffs.values()) < 1e-10, "%s, %s: the thin slab moves as its replicated twin: %s" % (
                    label, what, diffs))


def check_renumbered(wd, files):
    """Atoms given new IDs between the two halves (reset_atoms id sort yes) in the thin z slab,
    whose keys hold periodic images: the contacts follow the new IDs with their images, so the run
    ends as the one without the reset (KE, and the contacts at every thermo step), on 1 and 2
    ranks."""
    thin = files["z"][0]
    pair, coeffs = LAWS["hooke/history"]
    half = STEPS // 2
    for nprocs in (1, 2):
        ends = {}
        for label, between in (("kept", ""), ("reset", "reset_atoms id sort yes\n")):
            text = SCRIPT.format(start="read_data %s" % thin, pair=pair, coeffs=coeffs,
                                 run="thermo_modify format float %%.17g\nrun %d\n%srun %d\n" % (half, between, STEPS - half))
            rc, out = t.run_lmp(text, wd, nprocs, name="in.renumbered_%s_%d" % (label, nprocs))
            t.check(rc == 0, "z slab, %s, %d rank(s): runs (%s)" % (label, nprocs, t.errors(out)[:1]))
            ends[label] = (t.thermo_values(out, "KinEng"), t.thermo_values(out, "f_GRIDDEM[5]"))
        (ke, contacts), (ke_reset, contacts_reset) = ends["kept"], ends["reset"]
        err = abs(ke_reset[-1] - ke[-1]) / abs(ke[-1]) if ke and ke_reset else float("inf")
        t.check(contacts and min(contacts) > 0 and contacts_reset == contacts and err <= 1e-10,
                "z slab, %d rank(s): reset_atoms id sort yes at step %d, then as without it: KE relative error "
                "%.3g, contacts %s" % (nprocs, half, err, contacts_reset[-3:]))


def check_limits(wd):
    slab = os.path.join(wd, "data.refused")
    # 0.12 thick, contact distance up to 1.15: 1/8 of it is 0.14375
    atoms = [(1.0, [0.3, 0.5, 0.5], [0.0] * 3, [0.0] * 3), (1.15, [0.62, 0.5, 0.5], [0.0] * 3, [0.0] * 3)]
    write_slab(slab, atoms, (WIDE, WIDE, 0.12), (0.0, 0.0, 0.0), (1, 1, 1))
    for nprocs in (1, 2):
        text = SCRIPT.format(start="read_data %s" % slab, pair=HISTORY, coeffs="pair_coeff * *", run="run 10")
        rc, out = t.run_lmp(text, wd, nprocs, name="in.refused%d" % nprocs)
        said = re.search(r"the periodic box is ([0-9.e+-]+) wide along z, less than ([0-9.e+-]+) \(1/8 of the largest "
                         r"contact distance ([0-9.e+-]+)", out)
        t.check(rc != 0 and said is not None and "Step" not in out,
                "np %d: a box 0.12 thick is refused before the first step: %s" % (nprocs, t.errors(out)[:1] or out[-300:]))
        if said:
            got = [float(g) for g in said.groups()]
            t.check(abs(got[0] - 0.12) < 1e-12 and abs(got[1] - 0.14375) < 1e-12 and abs(got[2] - 1.15) < 1e-12,
                    "np %d: the message names width 0.12, limit 0.14375, contact distance 1.15: %s" % (nprocs, got))
        text = SCRIPT.format(start="read_data %s" % slab, pair="griddem/hooke 2000.0 NULL 50.0 NULL 0.5 0",
                             coeffs="pair_coeff * *", run="run 10")
        rc, out = t.run_lmp(text, wd, nprocs, name="in.nohistory%d" % nprocs)
        t.check(rc == 0, "np %d: griddem/hooke (no history) runs in the box 0.12 thick: %s" % (nprocs, t.errors(out)[:1]))


def check_transition(wd):
    """A box squeezed along z from wide to thin (fix deform) past twice the contact distance (2.3)
    and then widened again: each crossing is warned of once, naming the axis and the step, since
    contacts across that boundary restart their history there; a style without history says
    nothing."""
    slab = os.path.join(wd, "data.transition")
    atoms = slab_atoms(7, (WIDE, WIDE, WIDE), (0.0, 0.0, 0.0), 3)
    write_slab(slab, atoms, (WIDE, WIDE, WIDE), (0.0, 0.0, 0.0), (1, 1, 1))
    # z from 3.0 to 2.0 over 100 steps crosses 2.3 after 70 steps, back over the next 100 after 30
    run = ("fix squeeze all deform 1 z final 0 2.0 remap x\nrun 100\nunfix squeeze\n"
           "fix widen all deform 1 z final 0 3.0 remap x\nrun 100\n")
    for pair, coeffs, expect in ((HISTORY, "pair_coeff * *", 2), ("griddem/hooke 2000.0 NULL 50.0 NULL 0.5 0", "pair_coeff * *", 0)):
        text = SCRIPT.format(start="read_data %s" % slab, pair=pair, coeffs=coeffs, run=run)
        rc, out = t.run_lmp(text, wd, 1, name="in.transition")
        said = re.findall(r"WARNING: Pair style \S+: at step (\d+) the periodic box became (narrower|wider) than twice "
                          r"the largest contact distance along z", out)
        t.check(rc == 0, "%s: the squeezed and widened box runs: %s" % (pair.split()[0], t.errors(out)[:1]))
        if expect == 0:
            t.check(said == [], "%s (no history): no warning of the box's width: %s" % (pair.split()[0], said))
            continue
        steps = [int(step) for step, _ in said]
        t.check([w for _, w in said] == ["narrower", "wider"] and 70 <= steps[0] <= 72 and 130 <= steps[1] <= 132,
                "%s: warned once on becoming narrower (step 70-72) and once on becoming wider (130-132): %s"
                % (pair.split()[0], said))


def main():
    wd = t.workdir()
    files = slab_files(wd)
    check_twin(wd, files)
    check_renumbered(wd, files)
    check_limits(wd)
    check_transition(wd)
    t.finish()


if __name__ == "__main__":
    main()
