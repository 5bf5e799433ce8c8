"""Forces, torques, virial and 20-step trajectories of griddem/hooke/history, griddem/hooke and
griddem/hertz/history equal those of stock gran/hooke/history, gran/hooke and gran/hertz/history to
1e-10 relative, on a dense random
polydisperse (1:3) configuration with random linear and angular velocities; in every cell mode,
as the one sub-style of pair hybrid, hybrid/overlay and hybrid/scaled (and overlaid with gran/hooke), with limit_damping, dampflag 0, no friction, units metal (hertz: Kn, Kt in pressure units), fix
freeze, a triclinic box, rigid clumps (fix rigid/small, neigh_modify
exclude molecule/intra), radii that grow during the run (fix adapt), and in 2d. Every candidate kernel the processor
runs (fix griddem kernel: plain C, AVX2, AVX-512) gives the same numbers to the bit, the fix's value 8 naming the
kernel that ran."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

TEMPLATE = t.PERIODIC_SPHERES + """
{extra}
timestep 1e-5
fix integrate all nve/sphere
compute virial all pressure NULL pair
thermo_style custom step ke press c_virial[1] c_virial[2] c_virial[3] c_virial[4] c_virial[5] c_virial[6]
thermo_modify format float %.17g
thermo 10
dump snap all custom 20 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz
dump_modify snap format float %.17g sort id
run 20
"""

FORCES = ["fx", "fy", "fz", "tqx", "tqy", "tqz"]
STATE = ["x", "y", "z", "vx", "vy", "vz"]


def run(wd, name, data, pair, extra="", coeffs="pair_coeff * *", dimension=3, units="lj"):
    if pair.startswith("griddem/hooke/history") and "griddem" not in extra:
        extra += "\nfix grid all griddem contacts 64"
    head = "dimension 2\n" if dimension == 2 else ""
    text = TEMPLATE.format(data=data, pair=pair, coeffs=coeffs, extra=extra, name=name)
    out = t.run_ok(head + text.replace("units lj\n", "units %s\n" % units), wd, name="in." + name)
    return t.read_dumps(os.path.join(wd, "dump." + name)), out


KERNELS = ["scalar", "avx2", "avx512"]


def kernels(wd, label, data, pair, ref, extra):
    """The run of `pair` (fix grid's keywords in extra) with each candidate kernel this processor
    runs: each equals stock's (ref) as the other runs do, and the first to the bit; the fix's value
    8 (0 plain C, 1 AVX2, 2 AVX-512) names the kernel that ran. A kernel the processor lacks stops
    the run with an error saying so, and is left out."""
    first, ran = None, []
    for code, kernel in enumerate(KERNELS):
        name = "grid_kernel_%s_%s" % (label.replace("/", "_").replace(" ", "_").replace(":", "_"), kernel)
        text = TEMPLATE.format(data=data, pair=pair, coeffs="pair_coeff * *", name=name,
                               extra="%s kernel %s" % (extra, kernel))
        rc, out = t.run_lmp(text + 'print "KERNEL $(f_grid[8])"\n', wd, name="in." + name)
        if rc != 0 and "this processor or build does not run it" in out:
            continue
        t.check(rc == 0, "%s kernel %s: the run stopped: %s" % (label, kernel, t.errors(out)))
        if rc != 0:
            continue
        t.check("KERNEL %d" % code in out, "%s kernel %s: fix grid's value 8 names another kernel" % (label, kernel))
        test = (t.read_dumps(os.path.join(wd, "dump." + name)), out)
        compare("%s kernel %s" % (label, kernel), ref, test)
        if first is None:
            first = (kernel, test)
            continue
        for k in (0, 1):
            err = t.max_rel_diff(test[0][k], first[1][0][k], FORCES + STATE)
            t.check(err == 0.0, "%s: kernel %s against %s, snapshot %d: relative difference %.3g"
                    % (label, kernel, first[0], k, err))
        t.check(t.thermo_values(out, "Press") == t.thermo_values(first[1][1], "Press"),
                "%s: kernel %s's pressures differ from kernel %s's" % (label, kernel, first[0]))
        ran.append(kernel)
    t.check(first is not None and first[0] == "scalar", label + ": the plain-C kernel ran")
    print("%s: kernels compared to the plain-C one: %s" % (label, ", ".join(ran) or "none on this processor"))


def growing_text(data, pair, name):
    """TEMPLATE with radii that grow by a fifth in its 20 steps (fix adapt, atom_style sphere 1),
    and a skin that covers the growth (stock's lists need it)."""
    text = TEMPLATE.format(data=data, pair=pair, coeffs="pair_coeff * *", name=name, extra=(
        "neighbor 0.5 bin\nvariable grow equal 1+0.01*step\n"
        "fix grow all adapt 1 atom diameter v_grow scale yes reset no"))
    return text.replace("atom_style sphere\n", "atom_style sphere 1\n")


CLUMP = """# three overlapping spheres (density 1)

3 atoms

Coords

1 0.0 0.0 0.0
2 0.35 0.0 0.0
3 0.15 0.3 0.05

Types

1 1
2 1
3 1

Diameters

1 0.5
2 0.5
3 0.4

Masses

1 %.17g
2 %.17g
3 %.17g
""" % (math.pi / 6 * 0.125, math.pi / 6 * 0.125, math.pi / 6 * 0.064)



def clump_box(boundary, width, height):
    """The start of a script with clumps: a box, molecule IDs (fix property/atom mol) and the
    template CLUMP as molecule `clump` (format key {clump}: its file)."""
    return """
units lj
atom_style sphere
atom_modify map array
boundary %s
comm_modify vel yes
region box block 0 %g 0 %g 0 %g units box
create_box 1 box
fix mols all property/atom mol ghost yes
molecule clump {clump}
""" % (boundary, width, width, height)


# rigid clumps (fix rigid/small) of three spheres each, at random in a periodic box, their
# spheres of one clump excluded from each other by molecule (fix property/atom mol)
CLUMPS = clump_box("p p p", 3.5, 3.5) + """create_atoms 0 random 80 4711 NULL mol clump 9876
pair_style {pair}
pair_coeff * *
neigh_modify exclude molecule/intra all
velocity all create 1.0 8765 loop geom
timestep 1e-4
fix bodies all rigid/small molecule
compute virial all pressure NULL pair
thermo_style custom step c_virial[1] c_virial[2] c_virial[3] c_virial[4] c_virial[5] c_virial[6]
thermo_modify format float %.17g
thermo 10
dump snap all custom 20 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz
dump_modify snap format float %.17g sort id
run 20
"""
# (the bodies take more degrees of freedom than their spheres' translations give a temperature:
# no thermo column from one)


def clumps(wd, name, pair):
    path = os.path.join(wd, "clump.mol")
    with open(path, "w") as f:
        f.write(CLUMP)
    out = t.run_ok(CLUMPS.format(clump=path, pair=pair, name=name), wd, name="in." + name)
    return t.read_dumps(os.path.join(wd, "dump." + name)), out


def compare(label, ref, test, thermo=("Press", "c_virial[1]", "c_virial[4]", "c_virial[6]")):
    (ref_snaps, ref_out), (snaps, out) = ref, test
    t.check(len(snaps) == 2 and len(ref_snaps) == 2, label + ": two snapshots (steps 0 and 20)")
    for k, step in enumerate((0, 20)):
        err = t.max_rel_diff(snaps[k], ref_snaps[k], FORCES)
        t.check(err <= 1e-10, "%s step %d: force/torque relative error %.3g" % (label, step, err))
    err = t.max_rel_diff(snaps[1], ref_snaps[1], STATE)
    t.check(err <= 1e-10, "%s step 20: position/velocity relative error %.3g" % (label, err))
    for col in thermo:
        a, b = t.thermo_values(out, col), t.thermo_values(ref_out, col)
        t.check(len(a) == len(b) == 3, "%s: thermo %s printed 3 times" % (label, col))
        scale = max(abs(v) for v in b) or 1.0
        worst = max(abs(x - y) for x, y in zip(a, b)) / scale if a else 1.0
        t.check(worst <= 1e-10, "%s: %s relative error %.3g" % (label, col, worst))
    forces = [abs(v[3]) for v in ref_snaps[0][1].values()]
    t.check(sum(1 for f in forces if f > 0) > 0.9 * len(forces), label + ": most atoms are in contact")


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.dense")
    t.write_random_spheres(data, 1500, (4.5, 4.5, 4.5), 0.1, 0.3, seed=7, vscale=1.0, wscale=5.0)
    tri = os.path.join(wd, "data.tri")
    t.write_random_spheres(tri, 1200, (4.2, 4.2, 4.2), 0.1, 0.3, seed=11, triclinic=(0.8, -0.5, 0.3))

    hist = "1e4 NULL 50 NULL 0.5 1"
    nofric = "1e4 NULL 50 NULL 0.0 1"
    ref = run(wd, "stock_hh", data, "gran/hooke/history " + hist)
    for cell in ["exact", "multi", "0.37", "classes"]:
        compare("hooke/history cell " + cell, ref,
                run(wd, "grid_hh_" + cell, data, "griddem/hooke/history " + hist,
                    "fix grid all griddem contacts 64 cell " + cell))

    kernels(wd, "hooke/history", data, "griddem/hooke/history " + hist, ref, "fix grid all griddem contacts 64")

    args = "2e4 3e3 80 20 0.3 0 limit_damping"
    compare("hooke/history dampflag 0 limit_damping", run(wd, "stock_ld", data, "gran/hooke/history " + args),
            run(wd, "grid_ld", data, "griddem/hooke/history " + args))

    # equal masses in the frozen group: for two frozen atoms stock's meff depends on list order
    freeze = "group base id <= 200\nset group base diameter 0.4\nset group base density 1.0\nfix frozen base freeze"
    compare("hooke/history with fix freeze", run(wd, "stock_fr", data, "gran/hooke/history " + hist, freeze),
            run(wd, "grid_fr", data, "griddem/hooke/history " + hist, freeze))

    compare("hooke", run(wd, "stock_h", data, "gran/hooke " + hist),
            run(wd, "grid_h", data, "griddem/hooke " + hist))
    compare("hooke multi", run(wd, "stock_h2", data, "gran/hooke " + hist),
            run(wd, "grid_h2", data, "griddem/hooke " + hist, "fix grid all griddem cell multi"))

    # no friction: the tangential model is skipped (nothing stored, nothing evaluated)
    compare("hooke/history xmu 0", run(wd, "stock_nf", data, "gran/hooke/history " + nofric),
            run(wd, "grid_nf", data, "griddem/hooke/history " + nofric))
    compare("hooke dampflag 0", run(wd, "stock_nd", data, "gran/hooke 1e4 NULL 50 NULL 0.5 0"),
            run(wd, "grid_nd", data, "griddem/hooke 1e4 NULL 50 NULL 0.5 0"))

    # as the one sub-style of pair hybrid on every type pair, as the style alone
    compare("hooke/history as pair hybrid's one style",
            run(wd, "stock_hy", data, "hybrid gran/hooke/history " + hist, coeffs="pair_coeff * * gran/hooke/history"),
            run(wd, "grid_hy", data, "hybrid griddem/hooke/history " + hist, coeffs="pair_coeff * * griddem/hooke/history"))
    # and of hybrid/overlay, and of hybrid/scaled, which scales the forces and torques it adds;
    # overlaid with another sub-style on every pair, whose forces add to its own
    for kind, scale in (("hybrid/overlay", ""), ("hybrid/scaled", "0.5 ")):
        label = kind.replace("/", "_")
        compare("hooke/history as pair %s's one style" % kind,
                run(wd, "stock_" + label, data, "%s %sgran/hooke/history %s" % (kind, scale, hist),
                    coeffs="pair_coeff * * gran/hooke/history"),
                run(wd, "grid_" + label, data, "%s %sgriddem/hooke/history %s" % (kind, scale, hist),
                    coeffs="pair_coeff * * griddem/hooke/history"))
    overlay = "hybrid/overlay %s %s gran/hooke 1e4 NULL 50 NULL 0.5 0"
    compare("hooke/history overlaid with gran/hooke",
            run(wd, "stock_overlaid", data, overlay % ("gran/hooke/history", hist),
                coeffs="pair_coeff * * gran/hooke/history\npair_coeff * * gran/hooke"),
            run(wd, "grid_overlaid", data, overlay % ("griddem/hooke/history", hist),
                coeffs="pair_coeff * * griddem/hooke/history\npair_coeff * * gran/hooke"))

    # gran/hertz/history: the normal force and the friction scaled by sqrt(delta R_eff)
    hertz = "2e5 NULL 50 NULL 0.5 1"
    ref = run(wd, "stock_hz", data, "gran/hertz/history " + hertz)
    for cell in ["exact", "multi", "classes"]:
        compare("hertz/history cell " + cell, ref,
                run(wd, "grid_hz_" + cell, data, "griddem/hertz/history " + hertz,
                    "fix grid all griddem contacts 64 cell " + cell))
    compare("hertz/history dampflag 0 limit_damping", run(wd, "stock_hzld", data, "gran/hertz/history " + args),
            run(wd, "grid_hzld", data, "griddem/hertz/history " + args))
    compare("hertz/history xmu 0", run(wd, "stock_hznf", data, "gran/hertz/history " + nofric),
            run(wd, "grid_hznf", data, "griddem/hertz/history " + nofric))
    # Kn and Kt in pressure units, converted as stock does (units metal: nktv2p = 1.6e6)
    compare("hertz/history units metal", run(wd, "stock_hzm", data, "gran/hertz/history 2e7 NULL 5 NULL 0.5 1", units="metal"),
            run(wd, "grid_hzm", data, "griddem/hertz/history 2e7 NULL 5 NULL 0.5 1", units="metal"))

    # pairs excluded from the neighbor list do not interact, as with stock
    exclude = "group low id <= 700\nneigh_modify exclude group low low"
    compare("hooke/history neigh_modify exclude group", run(wd, "stock_ex", data, "gran/hooke/history " + hist, exclude),
            run(wd, "grid_ex", data, "griddem/hooke/history " + hist, exclude))
    # a group's pairs with itself (tested as one mask of bits) beside pairs of two groups, which overlap it
    exclude = ("group low id <= 700\ngroup mid id 500:1000\ngroup high id > 1000\n"
               "neigh_modify exclude group low low exclude group mid high exclude group high high")
    compare("hooke/history neigh_modify exclude group, three", run(wd, "stock_ex3", data, "gran/hooke/history " + hist, exclude),
            run(wd, "grid_ex3", data, "griddem/hooke/history " + hist, exclude))

    # radii 1:8: two size classes, pairs across them from the small sphere into the coarse grid
    poly = os.path.join(wd, "data.poly")
    t.write_random_spheres(poly, 1500, (4.5, 4.5, 4.5), 0.05, 0.4, seed=9, vscale=1.0, wscale=5.0)
    ref_poly = run(wd, "stock_poly", poly, "gran/hooke/history " + hist)
    compare("hooke/history 1:8, cell classes", ref_poly,
            run(wd, "grid_poly", poly, "griddem/hooke/history " + hist, "fix grid all griddem contacts 64 cell classes"))
    kernels(wd, "hooke/history 1:8", poly, "griddem/hooke/history " + hist, ref_poly,
            "fix grid all griddem contacts 64 cell classes")

    compare("hooke/history triclinic", run(wd, "stock_tri", tri, "gran/hooke/history " + hist),
            run(wd, "grid_tri", tri, "griddem/hooke/history " + hist))

    # rigid clumps: a contact takes the masses of the two bodies, as stock's
    compare("hooke/history, rigid clumps", clumps(wd, "stock_clumps", "gran/hooke/history " + hist),
            clumps(wd, "grid_clumps", "griddem/hooke/history " + hist), thermo=("c_virial[1]", "c_virial[4]", "c_virial[6]"))

    # radii that grow during the run: the grid follows the largest radius every step, not only
    # where LAMMPS reneighbors
    def growing(name, pair):
        out = t.run_ok(growing_text(data, pair, name), wd, name="in." + name)
        return t.read_dumps(os.path.join(wd, "dump." + name)), out
    compare("hooke/history, radii growing", growing("stock_grow", "gran/hooke/history " + hist),
            growing("grid_grow", "griddem/hooke/history " + hist))

    # 2d, as the stock styles run it: discs in a periodic plane with fix enforce2d; also with the
    # box's z width under 1/8 of the contact distance, which a periodic axis may not have in 3d
    # (in 2d LAMMPS makes no periodic images along z)
    plane = "fix plane all enforce2d"
    for label, zwidth in (("2d", 1.0), ("2d, z width 0.05", 0.05)):
        flat = os.path.join(wd, "data.flat")
        t.write_random_spheres(flat, 700, (8.0, 8.0, zwidth), 0.1, 0.3, seed=17, vscale=1.0, wscale=5.0, flat=True)
        for law in ("gran/hooke/history " + hist, "gran/hooke " + hist):
            name = law.split()[0].replace("/", "_") + ("_thin" if zwidth < 1.0 else "")
            compare("%s %s" % (law.split()[0].replace("gran/", ""), label),
                    run(wd, "stock_2d_" + name, flat, law, plane, dimension=2),
                    run(wd, "grid_2d_" + name, flat, law.replace("gran/", "griddem/"), plane, dimension=2))
    t.finish()


if __name__ == "__main__":
    main()
