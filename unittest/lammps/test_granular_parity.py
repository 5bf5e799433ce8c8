"""griddem/granular against stock pair granular with the same pair_coeff lines: forces, torques,
virial and 20-step trajectories agree to 1e-10 relative on a dense random polydisperse (1:3)
configuration of two atom types (the unlike pair mixed from the like ones), with random linear
and angular velocities, for every supported normal, damping, tangential and rolling sub-model;
unsupported sub-models are refused by name."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from test_stock_parity import compare, run as parity_run

# stock's list is built once: a pair keeps its i/j order, so its rolling history keeps its sign
FROZEN_LIST = "neighbor 0.3 bin\nneigh_modify every 1000 delay 0 check no"

# (label, type 1 coefficients, type 2 coefficients); the 1-2 pair is mixed
MODELS = [
    ("hooke mass_velocity linear_history",
     "hooke 1e4 50 damping mass_velocity tangential linear_history 3e3 0.5 0.5",
     "hooke 2e4 30 damping mass_velocity tangential linear_history 5e3 0.4 0.3"),
    ("hertz viscoelastic linear_history rolling sds",
     "hertz 1e5 20 damping viscoelastic tangential linear_history 3e4 0.5 0.5 rolling sds 500 5 0.1",
     "hertz 2e5 10 tangential linear_history 2e4 0.6 0.4 rolling sds 300 3 0.2"),
    ("hertz/material tsuji linear_nohistory limit_damping",
     "hertz/material 1e6 0.8 0.3 damping tsuji tangential linear_nohistory 1.0 0.5 limit_damping",
     "hertz/material 5e5 0.6 0.25 damping tsuji tangential linear_nohistory 0.8 0.3 limit_damping"),
    ("hooke velocity linear_nohistory rolling sds",
     "hooke 1e4 5 damping velocity tangential linear_nohistory 0.5 0.5 rolling sds 200 1 0.2",
     "hooke 3e4 5 damping velocity tangential linear_nohistory 0.5 0.5 rolling sds 100 2 0.1"),
]


def run(wd, name, data, pair, c1, c2, extra=""):
    coeffs = "pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2)
    return parity_run(wd, name, data, pair, extra + "\n" + FROZEN_LIST, coeffs)


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.dense")
    t.write_random_spheres(data, 1500, (4.5, 4.5, 4.5), 0.1, 0.3, seed=17, vscale=1.0, wscale=5.0,
                           ntypes=2)
    for k, (label, c1, c2) in enumerate(MODELS):
        ref = run(wd, "stock_%d" % k, data, "granular", c1, c2)
        for cell in ["exact", "multi"]:
            compare("granular %s, cell %s" % (label, cell), ref,
                    run(wd, "grid_%d_%s" % (k, cell), data, "griddem/granular", c1, c2,
                        "fix grid all griddem contacts 64 cell " + cell))

    label, c1, c2 = MODELS[1]
    compare("granular %s, neigh_modify exclude type 1 2" % label,
            run(wd, "stock_ex", data, "granular", c1, c2, "neigh_modify exclude type 1 2"),
            run(wd, "grid_ex", data, "griddem/granular", c1, c2, "neigh_modify exclude type 1 2\nfix grid all griddem contacts 64"))

    # unsupported sub-models: refused with their name
    for coeff, name in [("dmt 1e4 5 0.3 0.1 tangential linear_history 1 1 1", "dmt"),
                        ("hooke 1e4 5 tangential mindlin NULL 1 0.5", "mindlin"),
                        ("hooke 1e4 5 tangential linear_history 1 1 1 twisting marshall", "marshall"),
                        ("hooke 1e4 5 damping coeff_restitution tangential linear_history 1 1 1", "coeff_restitution"),
                        ("hooke 1e4 5 tangential linear_history 1 1 1 heat area 1", "area")]:
        rc, out = t.run_lmp("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\n"
                            "pair_style griddem/granular\npair_coeff * * %s\n" % coeff, wd, name="in.bad")
        t.check(rc != 0 and "does not support" in out and name in out,
                "unsupported %s refused by name: %s" % (name, out.strip().splitlines()[-1:]))

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
             "types 1 and 2 use different sub-models; set pair_coeff 1 2 explicitly"),
            ("", "* * hooke 1e4 5 tangential linear_history 0 1 0.5", "linear_history with kt = 0"),
            ("", "* * hooke 1e4 5 %s rolling sds 0 1 0.1" % tangential, "rolling sds with k_roll = 0")]:
        rc, out = t.run_lmp("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 2 b\n"
                            "comm_modify vel yes\npair_style griddem/granular %s\npair_coeff %s\nrun 0\n"
                            % (style, coeffs), wd, name="in.bad")
        t.check(rc != 0 and "ERROR" in out and expect in out,
                "'%s' refused with '%s': %s" % (coeffs.splitlines()[0], expect, out.strip().splitlines()[-1:]))
    t.finish()


if __name__ == "__main__":
    main()
