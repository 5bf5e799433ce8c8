"""The examples that run in under a minute run as shipped and give the numbers they are about:
free-fall (NN4DEM set I) apex heights against the analytic e^2 per bounce (0.1%) and against
stock pair granular (1e-8); sliding distance against the solution for the curved floor (0.1%);
the default pour scene's packing fraction against stock gran/hooke/history (0.01, a chaotic
pour) and a random packing's range; the 2d pour's area fraction against stock's (0.01) and a
random packing of discs' range; the heat-bed's steady heat flux and temperature against the
linear profile (1e-5) and its transient against stock pair granular (1e-10). Each also against the
reference log in the example (1e-6 for the single particles, 0.005 for the pours, 1e-8 for the
heat). Every example's reference log echoes its current
input."""
import glob
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(os.path.dirname(HERE))
EXAMPLES = os.path.join(TOP, "examples")
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(TOP, "python"))
import griddem_testlib as t
# the examples' analytic references and griddemtools' plain log readers (the logs' numbers are
# what is checked, not the readers: python.griddemtools checks those)
from griddemtools import analytic, echo
from griddemtools.log import reference_log, thermo


def run_example(name, wd, *variables):
    src = os.path.join(EXAMPLES, name, "in." + name)
    args = []
    for var in variables:
        args += ["-var"] + var.split()
    with open(src) as f:
        text = f.read()
    rc, out = t.run_lmp(text, wd, name="in." + name, extra=args)
    if rc != 0:
        print(out[-3000:], file=sys.stderr)
        raise SystemExit("example %s failed" % name)
    return out


def close(a, b, rel):
    return abs(a - b) <= rel * abs(b)


def free_fall(wd):
    m = 2700 * 4.0 / 3.0 * math.pi * 0.05 ** 3
    runs = {}
    for label, eta, style in [("damped", 0.5, "griddem/granular"), ("undamped", 0.0, "griddem/granular"),
                              ("stock", 0.5, "granular")]:
        out = run_example("free-fall", wd, "eta %g" % eta, "style " + style)
        runs[label] = analytic.apexes(thermo(out, "v_h"))
        ref = analytic.apexes(thermo(reference_log(os.path.join(EXAMPLES, "free-fall"), label), "v_h"))
        t.check(len(runs[label]) == 4 and len(ref) == 4, "free-fall %s: four bounces (%s)" % (label, runs[label]))
        t.check(all(close(a, b, 1e-6) for a, b in zip(runs[label], ref)),
                "free-fall %s: apexes %s match the reference log %s" % (label, runs[label], ref))
        exact = analytic.bounce_apexes(0.95, 5e4, eta, m, 4)
        t.check(all(close(a, b, 1e-3) for a, b in zip(runs[label], exact)),
                "free-fall %s: apexes %s, analytic %s" % (label, runs[label], exact))
    t.check(all(close(a, b, 1e-8) for a, b in zip(runs["damped"], runs["stock"])),
            "free-fall: griddem/granular %s equals stock granular %s" % (runs["damped"], runs["stock"]))


def sliding(wd):
    out = run_example("sliding", wd)
    x = thermo(out, "v_x")[-1]
    v = thermo(out, "v_v")[-1]
    ref = thermo(reference_log(os.path.join(EXAMPLES, "sliding")), "v_x")[-1]
    expected = analytic.slide_on_sphere(1.414, 0.5, 9.81, 50.05)
    t.check(abs(v) < 1e-3, "sliding: the ball stopped (v = %.3g m/s)" % v)
    t.check(close(x, expected, 1e-3), "sliding: stopped after %.6f m, curved-floor solution %.6f m" % (x, expected))
    t.check(close(x, ref, 1e-6), "sliding: %.6f m, reference log %.6f m" % (x, ref))
    t.check(close(x, 1.414 ** 2 / (2 * 0.5 * 9.81), 0.01), "sliding: within 1%% of the flat-floor 0.2038 m (%.4f)" % x)


def pour(wd):
    pattern = r"packing fraction of the lower half ([0-9.]+)"
    phi = float(re.findall(pattern, run_example("pour", wd))[-1])
    with open(os.path.join(EXAMPLES, "pour", "in.pour")) as f:
        stock_text = f.read().replace("griddem/hooke/history", "gran/hooke/history")
    stock_text = stock_text.replace(" f_GRIDDEM[5] f_GRIDDEM[2]", "").replace(", $(f_GRIDDEM[5]) contacts", "")
    out = t.run_ok(stock_text, wd, name="in.pour.stock")
    check_packing("pour", pattern, phi, float(re.findall(pattern, out)[-1]), (0.58, 0.66), "packing fraction",
                  "a random packing of spheres")


def pour_2d(wd):
    pattern = r"area fraction ([0-9.]+)"
    phi = float(re.findall(pattern, run_example("pour-2d", wd))[-1])
    phi_stock = float(re.findall(pattern, run_example("pour-2d", wd, "style gran/hooke/history", "tag stock"))[-1])
    # between random loose packing of frictional discs and random close packing of polydisperse ones
    check_packing("pour-2d", pattern, phi, phi_stock, (0.77, 0.85), "area fraction", "a random packing of discs")


def check_packing(name, pattern, phi, phi_stock, bounds, what, packing):
    """A pour's packing fraction phi in its range, against stock gran/hooke/history's (0.01, a
    chaotic pour) and the last the example's reference log prints by pattern (0.005)."""
    with open(reference_log(os.path.join(EXAMPLES, name))) as f:
        phi_ref = float(re.findall(pattern, f.read())[-1])
    t.check(bounds[0] <= phi <= bounds[1], "%s: %s %.3f of %s" % (name, what, phi, packing))
    t.check(abs(phi - phi_stock) <= 0.01, "%s: %.3f, stock gran/hooke/history %.3f" % (name, phi, phi_stock))
    t.check(abs(phi - phi_ref) <= 0.005, "%s: %.3f, reference log %.3f" % (name, phi, phi_ref))


def heat_bed(wd):
    """The heat-bed's steady state against the linear profile: the flux per column G / 7 (G = 2 k a,
    a = sqrt(0.02 R_eff)) and layer 3 at 2 - 3/7 (1e-5 relative); the flux through the transient
    against stock pair granular's, step by step (1e-10), and the reference log's (1e-8)."""
    pattern = r"flux per column ([0-9.]+) \(steady state ([0-9.]+)\), layer 3 at ([0-9.]+)"
    out = run_example("heat-bed", wd)
    flux, steady, layer3 = (float(v) for v in re.findall(pattern, out)[-1])
    expected = 2 * 1.0 * math.sqrt(0.02 * 0.51 * 0.51 / 1.02) / 7
    t.check(abs(steady - expected) <= 1e-7 * expected, "heat-bed: the script's steady flux %.8g is G/7 %.8g" % (steady, expected))
    t.check(abs(flux - expected) <= 1e-5 * expected, "heat-bed: flux per column %.8g, steady state %.8g" % (flux, expected))
    t.check(abs(layer3 - (2 - 3 / 7)) <= 1e-5, "heat-bed: layer 3 at %.8g, steady state %.8g" % (layer3, 2 - 3 / 7))
    stock = run_example("heat-bed", wd, "style granular", "tag stock")
    with open(reference_log(os.path.join(EXAMPLES, "heat-bed"))) as f:
        logged = f.read()
    ours = thermo(out, "v_flux")
    t.check(len(ours) == 13 and ours[6] > 0.5 * expected, "heat-bed: flux printed through the transient (%s)" % ours[:3])
    for other, what, tolerance in ((thermo(stock, "v_flux"), "stock pair granular", 1e-10),
                                   (thermo(logged, "v_flux"), "the reference log", 1e-8)):
        worst = max(abs(a - b) for a, b in zip(ours, other)) / expected if len(ours) == len(other) else 1.0
        t.check(worst <= tolerance, "heat-bed: flux against %s, relative difference %.3g" % (what, worst))


def reference_logs_echo_inputs():
    """Every reference log in examples/ (log.DATE.NAME[.variant].N) is the output of the current
    examples/NAME/in.NAME: it echoes each of its commands in order and no other."""
    # log.lammps: LAMMPS's own name, written where an example is run in its folder
    logs = sorted(p for p in glob.glob(os.path.join(EXAMPLES, "*", "log.*")) if not p.endswith("log.lammps"))
    t.check(len(logs) > 0, "reference logs found in %s" % EXAMPLES)
    for log in logs:
        name = os.path.basename(os.path.dirname(log))
        t.check(re.match(r"log\.\d{1,2}[A-Z][a-z][a-z]\d\d\.%s(\.[^.]+)*\.\d+$" % re.escape(name),
                         os.path.basename(log)), "%s named log.DATE.%s[.variant].N" % (log, name))
        with open(log) as f:
            fault = echo.echo_fault(os.path.join(EXAMPLES, name, "in." + name), f.read())
        t.check(fault is None, "%s echoes in.%s (%s)" % (log, name, fault))


def main():
    wd = t.workdir()
    reference_logs_echo_inputs()
    free_fall(wd)
    sliding(wd)
    pour(wd)
    pour_2d(wd)
    heat_bed(wd)
    t.finish()


if __name__ == "__main__":
    main()
