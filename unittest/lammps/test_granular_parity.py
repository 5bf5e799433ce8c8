"""griddem/granular against stock pair granular with the same pair_coeff lines: forces, torques,
virial and 20-step trajectories agree to 1e-10 relative on a dense random polydisperse (1:3)
configuration of two atom types (the unlike pair mixed from the like ones), with random linear
and angular velocities, for the example law of every row of the sub-model table
(griddem_submodels.c) that pair granular also has; together the examples name every sub-model
the style takes (unittest/core/test_submodels.c checks that). In the jkr example stock has pairs
interacting beyond contact at step 20 (separated after touching, inside the pull-off distance;
checked), so that this range is compared too. The models pair granular has and the table does
not are refused by name, bad arguments with a message naming them, and a restart file naming an
unknown sub-model stops read_restart naming it."""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from test_stock_parity import TEMPLATE, compare, run as parity_run

# stock's list is built once: a pair keeps its i/j order, so its rolling history keeps its sign
FROZEN_LIST = "neighbor 0.3 bin\nneigh_modify every 1000 delay 0 check no"

# (label, type 1 coefficients, type 2 coefficients): each row's example; the 1-2 pair is mixed
MODELS, STOCK_ONLY = t.submodel_table()
JKR = next(m for m in MODELS if m[0] == "normal jkr")


# a law with a heat model: temperatures varying across the box, conducted by fix heat/flow; each
# atom's temperature and heatflow dumped beside the forces
# (HEAT's parts: a restart defines the store and the conduction again, without the temperatures)
HEAT_STORE = "fix heat_store all property/atom temperature heatflow\n"
HEAT_TEMPERATURES = "variable temperature atom 1.0+x+0.5*y*z\nset group all temperature v_temperature\n"
HEAT_FLOW = "fix conduct all heat/flow constant 0.3\ncompute heat all property/atom temperature heatflow\n"
HEAT_DUMP = ("dump heat all custom 20 dump.heat.{name} id c_heat[1] c_heat[2]\n"
             "dump_modify heat format float %.17g sort id\n")
HEAT = HEAT_STORE + HEAT_TEMPERATURES + HEAT_FLOW + HEAT_DUMP


def run(wd, name, data, pair, c1, c2, extra=""):
    coeffs = "pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2)
    if " heat " in c1:
        extra += "\n" + HEAT.format(name=name)
    return parity_run(wd, name, data, pair, extra + "\n" + FROZEN_LIST, coeffs)


def heat_reference(data, c1, c2):
    """Each atom's heatflow at step 0 from pair granular's documented heat models, written here:
    over the pairs that overlap (minimum image in the periodic cube), radius: 2 k a (T_j - T_i),
    area: k pi a^2 (T_j - T_i), with a = sqrt(delta R_eff) (hooke and hertz), k of the like types
    and its geometric mean for unlike ones, and HEAT's temperatures."""
    with open(data) as f:
        lines = f.read().splitlines()
    side = float(next(l for l in lines if l.endswith("xlo xhi")).split()[1])
    start = lines.index("Atoms # sphere") + 2
    atoms = {}
    for line in lines[start:]:
        words = line.split()
        if not words:
            break
        x, y, z = (float(v) for v in words[4:7])
        atoms[int(words[0])] = (int(words[1]), 0.5 * float(words[2]), (x, y, z), 1.0 + x + 0.5 * y * z)
    model = c1.split(" heat ")[1].split()[0]
    k = {1: float(c1.split(" heat ")[1].split()[1]), 2: float(c2.split(" heat ")[1].split()[1])}
    ncell = int(side // 0.6)    # cells at least as wide as the longest contact (radii <= 0.3)
    h = side / ncell

    def cell(x):
        return tuple(int(v / h) % ncell for v in x)

    cells = {}
    for tag, (_, _, x, _) in atoms.items():
        cells.setdefault(cell(x), []).append(tag)
    flow = {}
    for tag, (ti, ri, xi, temp_i) in atoms.items():
        home, total = cell(xi), 0.0
        near = [((home[0] + a) % ncell, (home[1] + b) % ncell, (home[2] + c) % ncell)
                for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)]
        for other in {j for c in near for j in cells.get(c, [])} - {tag}:
            tj, rj, xj, temp_j = atoms[other]
            d = [a - b - side * round((a - b) / side) for a, b in zip(xi, xj)]
            r = math.sqrt(sum(v * v for v in d))
            if r >= ri + rj:
                continue
            a = math.sqrt((ri + rj - r) * ri * rj / (ri + rj))
            kij = k[ti] if ti == tj else math.sqrt(k[1] * k[2])
            total += 2 * kij * a * (temp_j - temp_i) if model == "radius" else kij * math.pi * a * a * (temp_j - temp_i)
        flow[tag] = total
    return flow


def compare_heat(label, wd, ref_name, name, reference):
    """Each atom's heatflow at step 0 against the formula (heat_reference), and its temperature
    and heatflow at step 20 (c_heat[1], c_heat[2]) against stock's. (Stock's heatflow of the setup
    step differs from the formula for the atoms within reach of a periodic face; from step 1 on it
    follows it.) Heat flows through most atoms and changes their temperatures."""
    ref = t.read_dumps(os.path.join(wd, "dump.heat." + ref_name))
    test = t.read_dumps(os.path.join(wd, "dump.heat." + name))
    t.check(len(ref) == len(test) == 2, label + ": heat dumped at steps 0 and 20")
    names, step0 = test[0]
    column = names.index("c_heat[2]")
    scale = max(abs(v) for v in reference.values())
    err = max(abs(step0[tag][column] - q) for tag, q in reference.items()) / scale
    t.check(err <= 1e-10, "%s step 0: heatflow against the formula, relative error %.3g" % (label, err))
    err = t.max_rel_diff(test[1], ref[1], ["c_heat[1]", "c_heat[2]"])
    t.check(err <= 1e-10, "%s step 20: temperature/heatflow against stock, relative error %.3g" % (label, err))
    t.check(sum(1 for q in reference.values() if q != 0) > 0.9 * len(reference), label + ": heat flows through most atoms")
    first = {tag: v[names.index("c_heat[1]")] for tag, v in step0.items()}
    moved = max(abs(v[names.index("c_heat[1]")] - first[tag]) for tag, v in test[1][1].items())
    t.check(moved > 1e-6, "%s: temperatures change over 20 steps (largest change %.3g)" % (label, moved))


# stock's pairs at step 20: the stock pair style's force for each pair in its neighbor list
LOCAL = t.PERIODIC_SPHERES + FROZEN_LIST + """
timestep 1e-5
fix integrate all nve/sphere
compute pairs all property/local patom1 patom2
compute values all pair/local dist force
dump local all local 20 dump.{name} c_pairs[1] c_pairs[2] c_values[1] c_values[2]
dump_modify local format float %.17g
run 20
"""


def beyond_contact(wd, data, c1, c2):
    """(pairs with a force, pairs with a force whose distance exceeds the sum of the radii) in
    stock's step 20."""
    radius = {}
    with open(data) as f:
        lines = f.read().splitlines()
    start = lines.index("Atoms # sphere") + 2
    for line in lines[start:]:
        words = line.split()
        if not words:
            break
        radius[int(words[0])] = 0.5 * float(words[2])
    coeffs = "pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2)
    t.run_ok(LOCAL.format(data=data, pair="granular", coeffs=coeffs, name="local"), wd, name="in.local")
    with open(os.path.join(wd, "dump.local")) as f:
        lines = f.read().splitlines()
    start = max(k for k, line in enumerate(lines) if line.startswith("ITEM: ENTRIES")) + 1
    forced, beyond = 0, 0
    for line in lines[start:]:
        words = line.split()
        if not words or words[0] == "ITEM:":
            break
        a, b, dist, force = int(words[0]), int(words[1]), float(words[2]), float(words[3])
        if force != 0.0:
            forced += 1
            beyond += dist > radius[a] + radius[b]
    return forced, beyond


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.dense")
    t.write_random_spheres(data, 1500, (4.5, 4.5, 4.5), 0.1, 0.3, seed=17, vscale=1.0, wscale=5.0,
                           ntypes=2)
    for k, (label, c1, c2) in enumerate(MODELS):
        ref = run(wd, "stock_%d" % k, data, "granular", c1, c2)
        reference = heat_reference(data, c1, c2) if " heat " in c1 else None
        for cell in ["exact", "multi", "classes"]:
            compare("granular %s, cell %s" % (label, cell), ref,
                    run(wd, "grid_%d_%s" % (k, cell), data, "griddem/granular", c1, c2,
                        "fix grid all griddem contacts 64 cell " + cell))
            if " heat " in c1:
                compare_heat("granular %s, cell %s" % (label, cell), wd, "stock_%d" % k,
                             "grid_%d_%s" % (k, cell), reference)
        if " heat " in c1:    # on 2 ranks and 2 threads (contacts with ghosts), as on one
            for nprocs, threads, tag in ((2, None, "np2"), (1, 2, "omp2")):
                name = "grid_%d_%s" % (k, tag)
                text = TEMPLATE.format(data=data, pair="griddem/granular", name=name,
                                       coeffs="pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2),
                                       extra=HEAT.format(name=name) + "\n" + FROZEN_LIST)
                t.run_ok(text, wd, nprocs=nprocs, name="in." + name, threads=threads)
                one = t.read_dumps(os.path.join(wd, "dump.heat.grid_%d_exact" % k))
                other = t.read_dumps(os.path.join(wd, "dump.heat." + name))
                err = max(t.max_rel_diff(a, b, ["c_heat[1]", "c_heat[2]"]) for a, b in zip(other, one)) \
                    if len(other) == len(one) == 2 else 1.0
                t.check(err <= 1e-10, "granular %s, %s vs 1 rank: temperature/heatflow relative error %.3g" % (label, tag, err))

    # the JKR case compares pairs beyond contact: stock has a visible number of them at step 20
    forced, beyond = beyond_contact(wd, data, JKR[1], JKR[2])
    t.check(forced > 1000 and beyond >= 0.01 * forced,
            "jkr: stock has pairs interacting beyond contact at step 20 (%d of %d)" % (beyond, forced))

    # type pairs with different history: each lays out its own values (rolling on type 1, a
    # 4-value mindlin_rescale with twisting on type 2, none between them), as pair granular allows
    mixed = ("pair_coeff 1 1 hertz 1e5 20 tangential linear_history 3e4 0.5 0.5 rolling sds 500 5 0.1\n"
             "pair_coeff 2 2 hertz 2e5 10 tangential mindlin_rescale 2e4 0.6 0.4 twisting sds 100 0.005 0.2\n"
             "pair_coeff 1 2 hooke 1.5e4 30 damping mass_velocity tangential linear_nohistory 0.5 0.5")
    ref = parity_run(wd, "stock_mixed", data, "granular", FROZEN_LIST, mixed)
    for cell in ["exact", "classes"]:
        compare("granular, a history layout per type pair, cell " + cell, ref,
                parity_run(wd, "grid_mixed_" + cell, data, "griddem/granular",
                           FROZEN_LIST + "\nfix grid all griddem contacts 64 cell " + cell, mixed))

    label, c1, c2 = next(m for m in MODELS if m[0] == "normal hertz")
    compare("granular %s, neigh_modify exclude type 1 2" % label,
            run(wd, "stock_ex", data, "granular", c1, c2, "neigh_modify exclude type 1 2"),
            run(wd, "grid_ex", data, "griddem/granular", c1, c2, "neigh_modify exclude type 1 2\nfix grid all griddem contacts 64"))

    # pair granular's models that the table does not evaluate: stock knows each name, and
    # griddem/granular refuses it by name (at the name, before its coefficients are read)
    t.check(len(STOCK_ONLY) > 0, "the table lists pair granular's models it does not evaluate")
    for keyword, name in STOCK_ONLY:
        coeff = name if keyword == "normal" else "hooke 1e4 5 %s %s" % (keyword, name)
        text = ("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\n"
                "pair_style {pair}\npair_coeff * * %s\n" % coeff)
        rc, out = t.run_lmp(text.format(pair="granular"), wd, name="in.stock_only")
        t.check("Illegal model type" not in out, "pair granular knows %s %s: %s" % (
            keyword, name, t.errors(out)[:1]))
        rc, out = t.run_lmp(text.format(pair="griddem/granular"), wd, name="in.bad")
        t.check(rc != 0 and "does not support %s model %s" % (keyword, name) in out,
                "unsupported %s %s refused by name: %s" % (keyword, name, out.strip().splitlines()[-1:]))

    # bad arguments: each stops with a message naming what is wrong (run 0 reaches the checks
    # made when coefficients are mixed and converted)
    tangential = "tangential linear_history 1 1 1"
    for style, coeffs, expect in [
            ("1 2", "* * hooke 1e4 5 " + tangential, "takes at most one argument"),
            ("-1", "* * hooke 1e4 5 " + tangential, "cutoff must be > 0, not -1"),
            ("", "* * hooke 1e4", "hooke needs 2 coefficients"),
            ("", "* * hooke -1 5 " + tangential, "hooke coefficient 1 must be >= 0, not -1"),
            ("", "* * hertz/material 0 0.5 0.3 " + tangential, "hertz/material needs E > 0"),
            ("", "* * hooke 1e4 5 tangential", "tangential needs a model name"),
            ("", "* * hooke 1e4 5 cutoff -2 " + tangential, "cutoff must be > 0, not -2"),
            ("", "* * hooke 1e4 5 %s bogus 1" % tangential, "unknown keyword bogus"),
            # an unknown keyword last (a newer LAMMPS's synchronized_verlet) named as unknown
            ("", "* * hooke 1e4 5 %s synchronized_verlet" % tangential, "unknown keyword synchronized_verlet"),
            ("", "* * hooke 1e4 5 %s cutoff" % tangential, "cutoff needs a value"),
            ("", "* * hooke 1e4 5 damping foo " + tangential, "unknown damping model foo"),
            ("", "* * hooke 1e4 5", "a tangential model is required"),
            ("", "1 1 hooke 1e4 5 %s\npair_coeff 2 2 hertz 1e4 5 %s" % (tangential, tangential),
             "set pair_coeff 1 2 explicitly"),
            ("", "* * hooke 1e4 5 tangential linear_history 0 1 0.5", "linear_history with kt = 0"),
            ("", "* * hooke 1e4 5 %s rolling sds 0 1 0.1" % tangential, "rolling sds with k_roll = 0"),
            ("", "* * hooke 1e4 5 %s twisting sds 1 1" % tangential, "sds needs 3 coefficients"),
            # what stock refuses too: Mindlin's k from material properties the normal model lacks,
            # and damping that cannot hold a cohesive contact
            ("", "* * hooke 1e4 5 tangential mindlin NULL 1 0.5", "k NULL needs a normal model with material properties"),
            ("", "* * jkr 1e4 5 0.3 1 %s limit_damping" % tangential,
             "limit_damping cannot be used with the cohesive normal model jkr"),
            ("", "* * dmt 1e4 5 0.3 1 damping tsuji " + tangential, "damping tsuji cannot be used with a cohesive normal model"),
            ("", "* * jkr 1e4 5 0.3 1 damping coeff_restitution " + tangential,
             "damping coeff_restitution cannot be used with a cohesive normal model")]:
        rc, out = t.run_lmp("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 2 b\n"
                            "comm_modify vel yes\npair_style griddem/granular %s\npair_coeff %s\nrun 0\n"
                            % (style, coeffs), wd, name="in.bad")
        t.check(rc != 0 and "ERROR" in out and expect in out,
                "'%s' refused with '%s': %s" % (coeffs.splitlines()[0], expect, out.strip().splitlines()[-1:]))
    heat_settings(wd)
    heat_restart(wd, data)
    unknown_in_restart(wd)
    t.finish()


def heat_restart(wd, data):
    """The heat model survives a restart: 10 steps, write_restart, read_restart and 10 more (the
    property/atom and heat/flow fixes defined again with their IDs) give each atom's temperature
    and heatflow of the run that wrote the file and went on for 10 steps (a new run's setup step
    reads the contact history without advancing it, so the reference has one too), bit for bit."""
    label, c1, c2 = next(m for m in MODELS if m[0] == "heat radius")
    head = t.PERIODIC_SPHERES.format(data=data, pair="griddem/granular",
                                     coeffs="pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2))
    integrate = "fix integrate all nve/sphere\ntimestep 1e-5\n"
    t.run_ok(head + HEAT.format(name="whole") + integrate + "run 10\nwrite_restart restart.heat\nrun 10\n", wd,
             name="in.heat_whole")
    t.run_ok("read_restart restart.heat\ncomm_modify vel yes\n" + HEAT_STORE + HEAT_FLOW + HEAT_DUMP.format(name="second") +
             integrate + "run 10\n", wd, name="in.heat_second")
    whole = t.read_dumps(os.path.join(wd, "dump.heat.whole"))[-1]
    second = t.read_dumps(os.path.join(wd, "dump.heat.second"))[-1]
    t.check(second[1] == whole[1], "heat radius across a restart: temperature and heatflow at step 20 identical")
    t.check(any(v[1] != 0.0 for v in whole[1].values()), "heat radius across a restart: heat flows")


def heat_settings(wd):
    """A heat model needs the atoms' temperature and heatflow (refused naming the missing one, in
    pair granular's words), and type pairs left without one are warned of."""
    box = "units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 2 b\ncomm_modify vel yes\n"
    heat = "pair_style griddem/granular\npair_coeff * * hooke 1e4 5 tangential linear_nohistory 1 1 heat area 1.0\n"
    for store, missing in (("", "temperature"), ("fix store all property/atom temperature\n", "heatflow")):
        rc, out = t.run_lmp(box + store + heat + "run 0\n", wd, name="in.heat_store")
        t.check(rc != 0 and any("Heat conduction in pair style griddem/granular requires atom style with %s property"
                                % missing in l for l in t.errors(out)),
                "heat without %s refused naming it: %s" % (missing, t.errors(out)[:1]))
    rc, out = t.run_lmp(box + "fix store all property/atom temperature heatflow\n" + heat +
                        "pair_coeff 1 2 hooke 1e4 5 tangential linear_nohistory 1 1\nrun 0\n", wd, name="in.heat_some")
    t.check(rc == 0 and "2 type pairs given in pair_coeff have a heat model and 1 do not" in out,
            "a type pair without a heat model among ones with it is warned of: %s" % out.strip().splitlines()[-1:])


def unknown_in_restart(wd):
    """The restart file stores the sub-model names and coefficient counts; a name changed in the
    file (same length, so the layout is unchanged) stops read_restart with an error naming it, and
    so does a coefficient count that is not the sub-model's."""
    t.run_ok("""
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 single 1 1 1
create_atoms 1 single 1.9 1 1
set type 1 diameter 1.0
pair_style griddem/granular
pair_coeff * * hertz 1e4 5 tangential mindlin 1e3 1 0.5 rolling sds 100 1 0.2
fix integrate all nve/sphere
run 2
write_restart restart.mindlin
""", wd, name="in.write_mindlin")
    with open(os.path.join(wd, "restart.mindlin"), "rb") as f:
        data = f.read()
    t.check(data.count(b"mindlin") >= 1, "restart file holds the sub-model name mindlin")
    with open(os.path.join(wd, "restart.mindlix"), "wb") as f:
        f.write(data.replace(b"mindlin", b"mindlix"))
    read = "read_restart restart.{name}\ncomm_modify vel yes\nfix integrate all nve/sphere\nrun 2\n"
    rc, out = t.run_lmp(read.format(name="mindlin"), wd, name="in.read_mindlin")
    t.check(rc == 0, "restart with tangential mindlin read and continued (exit %d): %s" % (
        rc, t.errors(out)[:1]))
    rc, out = t.run_lmp(read.format(name="mindlix"), wd, name="in.read_mindlix")
    errors = t.errors(out)
    t.check(rc != 0 and any("restart file" in l and "mindlix" in l for l in errors),
            "restart naming an unknown sub-model mindlix stops read_restart naming it: %s" % errors[:1])
    # rolling sds written as name length 3, "sds", 3 coefficients (native ints): claim 2
    count = struct.pack("i", 3) + b"sds" + struct.pack("i", 3)
    t.check(data.count(count) == 1, "restart file holds rolling sds with its 3 coefficients")
    with open(os.path.join(wd, "restart.sds2"), "wb") as f:
        f.write(data.replace(count, struct.pack("i", 3) + b"sds" + struct.pack("i", 2)))
    rc, out = t.run_lmp(read.format(name="sds2"), wd, name="in.read_sds2")
    errors = t.errors(out)
    t.check(rc != 0 and any("restart file gives 2 coefficients for rolling model sds, which takes 3" in l for l in errors),
            "restart with a wrong coefficient count stops read_restart naming the sub-model: %s" % errors[:1])


if __name__ == "__main__":
    main()
