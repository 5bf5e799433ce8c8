"""Stability at the extremes, each case asserting numbers:
- time step across the NN4DEM limit pi/5 sqrt(m/k): below it, no warning and the energy error of
  an undamped elastic gas stays small and shrinks as dt^2; above it, a warning naming the limit;
- displacement rule dx/v_max: an atom crossing more than one NN4DEM cell per step stops the run
  with its ID, just below that the run goes on;
- stiffness from 1e2 to 1e9 (velocities scaled with sqrt(k), dt with 1/sqrt(k)): the same
  relative energy error at every stiffness;
- polydispersity 1:4 in the exact (NN4DEM) cells: forces and trajectories equal stock's;
- density from a dilute gas (grid coarsened, with a warning) to a jammed bed with overlaps:
  energy conserved, no atom lost, forces equal stock's, no NaN.
(Precision: the channels are double only, so there is no single-precision drift to measure.)"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from test_stock_parity import compare, run as parity_run

GAS = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
pair_style griddem/hooke/history {kn} NULL 0.0 NULL 0.0 0
pair_coeff * *
timestep {dt}
fix integrate all nve/sphere
compute rot all erotate/sphere
compute trans all ke
variable etotal equal c_trans+c_rot+f_GRIDDEM[7]
thermo_style custom step atoms f_GRIDDEM[5] v_etotal
thermo_modify format float %.17g norm no lost error
thermo {every}
run {steps}
"""


def energy_run(wd, name, data, kn, dt, steps):
    rc, out = t.run_lmp(GAS.format(data=data, kn=kn, dt=dt, every=max(1, steps // 20), steps=steps), wd,
                        name="in." + name)
    e = t.thermo_values(out, "v_etotal")
    contacts = t.thermo_values(out, "f_GRIDDEM[5]")
    drift = max(abs(x - e[0]) for x in e) / e[0] if rc == 0 and e else float("inf")
    return rc, out, drift, max(contacts) if contacts else 0


def lightest(rmin, density=1.0):
    return density * 4.0 / 3.0 * math.pi * rmin ** 3


def timestep_sweep(wd):
    data = os.path.join(wd, "data.gas")
    t.write_random_spheres(data, 216, (6.6, 6.6, 6.6), 0.3, 0.45, seed=5, lattice=1.1)
    limit = math.pi / 5 * math.sqrt(lightest(0.3) / 1e4)
    drifts = {}
    for frac in (0.25, 0.5, 1.0, 1.5):
        rc, out, drift, contacts = energy_run(wd, "dt%g" % frac, data, 1e4, frac * limit, int(2.0 / (frac * limit)))
        warned = "exceeds the stability limit pi/5*sqrt(m/Kn)" in out
        drifts[frac] = drift
        t.check(rc == 0 and contacts > 0, "dt %.2f x limit: ran with contacts (%s)" % (frac, contacts))
        if frac <= 1.0:
            t.check(not warned, "dt %.2f x limit: no warning" % frac)
            t.check(drift <= 1e-2, "dt %.2f x limit: energy error %.3g <= 1e-2" % (frac, drift))
        else:
            t.check(warned, "dt %.2f x limit: stability warning printed" % frac)
    # velocity Verlet: the error of a collision grows as (omega dt)^2
    ratio = drifts[0.5] / drifts[0.25]
    t.check(2.5 <= ratio <= 8.0, "energy error grows as dt^2: x%.2f when dt doubles" % ratio)
    t.check(drifts[1.5] > drifts[1.0], "above the limit the energy error grows (%.3g > %.3g)" % (drifts[1.5], drifts[1.0]))


def displacement_rule(wd):
    # two spheres of diameter 1: a cell is 1/sqrt(3); the fast one moves v*dt per step
    base = """
units lj
atom_style sphere
atom_modify map array
boundary p p p
comm_modify vel yes
region box block 0 20 0 20 0 20
create_box 1 box
create_atoms 1 single 5 5 5
create_atoms 1 single 12 5 5
set type 1 diameter 1.0
velocity all set 0 0 0
set atom 2 vx {v}
pair_style griddem/hooke/history 1e4 NULL 0 NULL 0 0
pair_coeff * *
timestep 0.01
fix integrate all nve/sphere
run 10
"""
    allowed = 1.0 / math.sqrt(3.0)
    rc, out = t.run_lmp(base.format(v=0.95 * allowed / 0.01), wd, name="in.slow")
    t.check(rc == 0, "0.95 of a cell per step: runs")
    rc, out = t.run_lmp(base.format(v=1.05 * allowed / 0.01), wd, name="in.fast")
    t.check(rc != 0 and "atom 2 moves" in out and "%.5f" % allowed in out,
            "1.05 of a cell per step: stops naming atom 2 and the allowed %.5f" % allowed)


def stiffness_sweep(wd):
    drifts = []
    for kn in (1e2, 1e5, 1e9):
        scale = math.sqrt(kn / 1e4)
        data = os.path.join(wd, "data.k%g" % kn)
        t.write_random_spheres(data, 216, (6.6, 6.6, 6.6), 0.3, 0.45, seed=5, vscale=scale, wscale=scale, lattice=1.1)
        dt = 0.25 * math.pi / 5 * math.sqrt(lightest(0.3) / kn)
        rc, out, drift, contacts = energy_run(wd, "k%g" % kn, data, kn, dt, int(2.0 / (0.25 * math.pi / 5 * math.sqrt(lightest(0.3) / 1e4))))
        t.check(rc == 0 and contacts > 0, "kn %g: ran with contacts" % kn)
        drifts.append(drift)
    spread = max(drifts) / min(drifts)
    t.check(max(drifts) <= 1e-3 and spread <= 1.5,
            "kn 1e2..1e9: relative energy errors %s, the same at every stiffness" % ["%.3g" % d for d in drifts])


def polydispersity(wd):
    data = os.path.join(wd, "data.poly4")
    t.write_random_spheres(data, 1200, (4.5, 4.5, 4.5), 0.1, 0.4, seed=23, vscale=1.0, wscale=3.0)
    hist = "1e4 NULL 50 NULL 0.5 1"
    ref = parity_run(wd, "stock_p4", data, "gran/hooke/history " + hist)
    compare("polydispersity 1:4, exact cells", ref,
            parity_run(wd, "grid_p4", data, "griddem/hooke/history " + hist, "fix grid all griddem contacts 80 cell exact"))


def densities(wd):
    # dilute: 40 spheres in a box 2000 diameters wide; the grid over them is coarsened
    data = os.path.join(wd, "data.dilute")
    t.write_random_spheres(data, 40, (500.0, 500.0, 500.0), 0.2, 0.3, seed=9, vscale=20.0)
    rc, out, drift, contacts = energy_run(wd, "dilute", data, 1e4, 1e-3, 2000)
    t.check(rc == 0 and drift <= 1e-12, "dilute gas: runs, energy kept to %.3g" % drift)
    t.check("cell edge enlarged" in out, "dilute gas: the grid is coarsened, with a warning")
    # jammed: solid fraction ~0.9 of random overlapping spheres
    data = os.path.join(wd, "data.jammed")
    t.write_random_spheres(data, 1500, (4.8, 4.8, 4.8), 0.2, 0.3, seed=31, vscale=0.1, wscale=0.1)
    hist = "1e4 NULL 50 NULL 0.5 1"
    ref = parity_run(wd, "stock_j", data, "gran/hooke/history " + hist)
    test = parity_run(wd, "grid_j", data, "griddem/hooke/history " + hist, "fix grid all griddem contacts 80 cell multi")
    compare("jammed with overlaps (solid fraction ~0.9)", ref, test)
    values = [v for snap in test[0] for row in snap[1].values() for v in row]
    t.check(all(math.isfinite(v) for v in values), "jammed: every dumped value finite")
    fsum = [sum(row[snap[0].index(c)] for row in snap[1].values()) for snap in test[0] for c in ("fx", "fy", "fz")]
    fmax = max(abs(row[test[0][0][0].index("fx")]) for row in test[0][0][1].values())
    t.check(max(abs(f) for f in fsum) <= 1e-9 * fmax * 1500, "jammed: forces sum to zero (%.3g)" % max(abs(f) for f in fsum))


def main():
    wd = t.workdir()
    timestep_sweep(wd)
    displacement_rule(wd)
    stiffness_sweep(wd)
    polydispersity(wd)
    densities(wd)
    t.finish()


if __name__ == "__main__":
    main()
