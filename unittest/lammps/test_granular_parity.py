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
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from test_stock_parity import compare, run as parity_run

# stock's list is built once: a pair keeps its i/j order, so its rolling history keeps its sign
FROZEN_LIST = "neighbor 0.3 bin\nneigh_modify every 1000 delay 0 check no"

# (label, type 1 coefficients, type 2 coefficients): each row's example; the 1-2 pair is mixed
MODELS, STOCK_ONLY = t.submodel_table()
JKR = next(m for m in MODELS if m[0] == "normal jkr")


def run(wd, name, data, pair, c1, c2, extra=""):
    coeffs = "pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2)
    return parity_run(wd, name, data, pair, extra + "\n" + FROZEN_LIST, coeffs)


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
        for cell in ["exact", "multi", "classes"]:
            compare("granular %s, cell %s" % (label, cell), ref,
                    run(wd, "grid_%d_%s" % (k, cell), data, "griddem/granular", c1, c2,
                        "fix grid all griddem contacts 64 cell " + cell))

    # the JKR case compares pairs beyond contact: stock has a visible number of them at step 20
    forced, beyond = beyond_contact(wd, data, JKR[1], JKR[2])
    t.check(forced > 1000 and beyond >= 0.01 * forced,
            "jkr: stock has pairs interacting beyond contact at step 20 (%d of %d)" % (beyond, forced))

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
            ("", "* * hooke 1e4 5 damping foo " + tangential, "unknown damping model foo"),
            ("", "* * hooke 1e4 5", "a tangential model is required"),
            ("", "1 1 hooke 1e4 5 %s\npair_coeff 2 2 hooke 1e4 5 tangential linear_nohistory 1 1" % tangential,
             "all type pairs must share it"),
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
    unknown_in_restart(wd)
    t.finish()


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
