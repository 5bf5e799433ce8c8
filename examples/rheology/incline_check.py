#!/usr/bin/python3
"""The continuum check of the learned rheology against DEM inclined layers (in.incline):
(1) steady layers: momentum balance fixes mu = tan(theta) at every depth, so each layer gives
    points (I(z), tan theta) with I(z) = gdot(z) d / sqrt(P(z)/rho), gdot from the block-averaged
    velocity profile, P(z) = rho g cos(theta) * integral of the solid fraction above z; compared
    with the RVE points and the learned curve (a base-slip-free test: only gradients enter);
(2) a decelerating layer: the steady layer at theta1 with the slope lowered to theta2 at t = 0,
    DEM (vcm(flow,x)) against the 1D depth-resolved solver (layer_solver.py) with the regularised
    mu(I), plus a grid/time-step refinement of the solver.
Reads the RVE points from a results.json of learn_mu.py (by default reference/results.json, the
README's run), rebuilds the same ensemble and regularised curve, runs the inclines (cached in
work/incline_<theta>/), writes incline_check.json and incline_check.png, decel.png.

    /usr/bin/python3 incline_check.py [--lmp PATH] [--results results.json] [--thetas 22,24,26]
                                      [--theta1 24 --theta2 16]"""
import argparse
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))  # griddemtools
import learn_mu as L  # noqa: E402
import layer_solver as S  # noqa: E402
from griddemtools import chunks, lammps  # noqa: E402

HERE = L.HERE
EDGE = 2.0     # layers within this distance (d) of the base or the surface are left out


def read_chunks(path):
    """All blocks of a fix ave/chunk file: (timesteps, array [block, chunk, (z, count, rho, vx)])."""
    blocks = chunks.read_ave_chunk(path)
    return np.array([step for step, _ in blocks]), np.array([[r[1:] for r in rows] for _, rows in blocks])


def read_series(path):
    a = np.loadtxt(path, comments="#")
    return a[:, 0], a[:, 1]


def local_inertial(z, phi, vx, theta, dz=0.5, rho=1.0, g=1.0, d=1.0):
    """I(z) on the layers: gdot by central differences of vx, P = rho g cos(theta) * the solid
    fraction integrated from the top (phi = mass density / rho for particle density rho)."""
    above = np.cumsum(phi[::-1])[::-1] * dz - 0.5 * phi * dz        # integral from z to the top
    P = rho * g * math.cos(theta) * above
    gdot = np.gradient(vx, dz)
    return gdot * d / np.sqrt(np.maximum(P, 1e-12) / rho), P


def steady_layer(workdir, theta_deg, mu_reg, mu_std, rve_points, last=5):
    """Local I in the interior of one layer from the last `last` profile blocks: per-block interior
    mean of I, their mean and standard error; the mu offset mu_reg(I_DEM) - tan(theta) and the
    velocity factors of a curve lower by 1 and 2 ensemble std (mu_std(I))."""
    theta = math.radians(theta_deg)
    steps, B = read_chunks(os.path.join(workdir, "blocks.%g.txt" % theta_deg))
    B = B[-last:]
    z = B[0, :, 0]
    H = float((B[:, :, 2].mean(0))[z > L.Z_BASE].sum() * 0.5 / np.mean(
        [np.mean(b[(z > L.Z_BASE + EDGE) & (z < L.Z_BASE + 6), 2]) for b in B]))
    inside = (z > L.Z_BASE + EDGE) & (z < L.Z_BASE + H - EDGE)
    Ib = []
    for b in B:
        I, _ = local_inertial(z, b[:, 2], b[:, 3], theta)
        Ib.append(I[inside])
    Ib = np.array(Ib)
    per_block = Ib.mean(1)
    I_mean, I_err = float(per_block.mean()), float(per_block.std(ddof=1) / math.sqrt(len(per_block)))
    phi_mean = B[:, :, 2].mean(0)
    vx_mean = B[:, :, 3].mean(0)
    I_z, P_z = local_inertial(z, phi_mean, vx_mean, theta)
    tan = math.tan(theta)
    # I_DEM may lie above the RVE range (flagged above_data and printed): extrapolated knowingly
    mu_of = lambda x: float(mu_reg(x, extrapolate=True))
    I_pred = L.invert(mu_reg, tan)
    offset = mu_of(I_mean) - tan
    # sensitivity: the Bagnold velocity is proportional to I, and a curve lower by s (the ensemble
    # std at I_pred) needs I = mu_reg^-1(tan theta + s); slope = local d mu_reg / dI at I_pred
    s = float(mu_std(I_pred))
    slope = (mu_of(1.1 * I_pred) - mu_of(I_pred / 1.1)) / (I_pred * (1.1 - 1 / 1.1))
    factors = [L.invert(mu_reg, tan + k * s) for k in (1, 2)]
    factors = [f / I_pred if f else None for f in factors]          # None: above the curve's range
    slip = float(vx_mean[np.argmin(abs(z - (L.Z_BASE + 0.25)))])
    return dict(theta=theta_deg, H=H, I_dem=I_mean, I_dem_err=I_err, I_dem_blocks=per_block.tolist(),
                I_pred=I_pred, ratio=I_mean / I_pred, mu_offset=offset, dmu_dI=slope, ens_std=s,
                offset_in_std=offset / s, velocity_factor_1std=factors[0], velocity_factor_2std=factors[1],
                above_data=I_mean > max(p["I"] for p in rve_points),
                slip=slip, u_surface=float(vx_mean[inside][-1]),
                z=z[inside].tolist(), I_z=I_z[inside].tolist(), P_z=P_z[inside].tolist(),
                phi_interior=float(phi_mean[inside].mean()))


def steadiness(workdir, theta_deg):
    t, v = read_series(os.path.join(workdir, "vcm.%g.txt" % theta_deg))
    t = t * 1e-3
    thirds = [float(v[(t > a) & (t <= a + t[-1] / 3)].mean()) for a in (0, t[-1] / 3, 2 * t[-1] / 3)]
    last = v[t > 2 * t[-1] / 3]
    return dict(t=t.tolist(), vcm=v.tolist(), thirds=thirds, last_min=float(last.min()),
                last_max=float(last.max()), last_std=float(last.std()))


def decelerating(workdir, theta1, theta2, mu_reg, phi, shift, grids=((20, 0.2), (40, 0.1), (80, 0.05))):
    """DEM vcm(flow,x) after the slope change against the 1D solver, started from the DEM's own
    steady profile (its last profile blocks, base slip removed: the solver has no slip) and from
    the continuum's steady (Bagnold) profile, and (finest grid, DEM start) with mu_reg lowered by
    shift (the steady layers' mean offset) to test whether one offset explains both; stopping time = first time the mean velocity is below
    2 % of its start."""
    steps, v = read_series(os.path.join(workdir, "decel.%g.txt" % theta1))
    t_dem = steps * 1e-3
    _, B = read_chunks(os.path.join(workdir, "blocks.%g.txt" % theta1))
    B = B[-5:]
    z = B[0, :, 0]
    rho_z, vx = B[:, :, 2].mean(0), B[:, :, 3].mean(0)
    H = float(rho_z[z > L.Z_BASE].sum() * 0.5 / phi)
    th1, th2 = math.radians(theta1), math.radians(theta2)
    out = dict(theta1=theta1, theta2=theta2, H=H, phi=phi, t_dem=t_dem.tolist(), v_dem=v.tolist(),
               t_stop_dem=S.stop_time(t_dem, v), runs=[])
    T = float(t_dem[-1])
    I1 = L.invert(mu_reg, math.tan(th1))
    # near the free surface P -> 0, so the continuum's I leaves the sampled range there whatever
    # the flow: the solver holds mu at its top value, knowingly, and the largest I met is reported
    seen = [0.0]

    def mu_held(x):
        seen[0] = max(seen[0], float(np.max(x)))
        return mu_reg(x, extrapolate=True)
    for n, dt in grids:
        lay = S.Layer(mu_held, H, phi, n)
        keep = (z > L.Z_BASE)
        u_dem = np.interp(lay.z, z[keep] - L.Z_BASE, vx[keep] - vx[keep][0])
        u_dem[0] = 0.0
        cases = [("dem", u_dem, lay), ("bagnold", lay.steady(th1, I1), lay)]
        if (n, dt) == grids[-1]:
            cases.append(("dem, mu_reg - %.3f" % shift, u_dem, S.Layer(lambda x: np.maximum(mu_held(x) - shift, 0.0), H, phi, n)))
        for start, u0, solver in cases:
            r = solver.run(u0, th2, T, dt)
            vd = np.interp(r["t"], t_dem, v)
            rms = float(np.sqrt(np.mean((r["mean"] - vd) ** 2)) / v[0])
            out["runs"].append(dict(n=n, dt=dt, start=start, t=r["t"][::max(1, int(0.2 / dt))].tolist(),
                                    mean=r["mean"][::max(1, int(0.2 / dt))].tolist(),
                                    t_stop=S.stop_time(r["t"], r["mean"]), mean0=float(r["mean"][0]),
                                    rms_vs_dem=rms, final=float(r["mean"][-1]), iters=r["iters"]))
    out["I_max_met"] = seen[0]
    out["I_max_sampled"] = mu_reg.params["I_max"]
    print("decelerating layer: the continuum met I up to %.3g (the top cells), mu held at its value at I = %.3g above"
          % (seen[0], mu_reg.params["I_max"]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=lammps.default_lmp())
    ap.add_argument("--results", default=os.path.join(HERE, "reference", "results.json"),
                    help="learn_mu.py's results.json whose RVE points make the curve")
    ap.add_argument("--thetas", default="22,24,26")
    ap.add_argument("--steps", type=int, default=300000)
    ap.add_argument("--theta1", type=float, default=24.0, help="steady layer of the decelerating run")
    ap.add_argument("--theta2", type=float, default=16.0, help="slope after t = 0 (tan below mu_s)")
    ap.add_argument("--steps2", type=int, default=60000)
    a = ap.parse_args()
    lmp = os.path.abspath(a.lmp)
    with open(a.results) as f:
        res = json.load(f)
    P = res["points"]
    rng = res.get("ensemble", res["adaptive"])          # the final ensemble's span (learn_mu.py)
    Ilo, Ihi = rng["Ilo"], rng["Ihi"]
    ens = L.Ensemble(Ilo, Ihi).fit(P)
    Ig = np.logspace(math.log10(Ilo), math.log10(Ihi), 60)
    mean, std = ens.predict(Ig)
    mu_reg = L.regularise(Ig, mean[:, 0], I_c=Ilo)
    out = dict(layers=[], steady=[])
    for t in [float(s) for s in a.thetas.split(",")]:
        first = t == a.theta1
        wd = L.run_incline(lmp, t, a.steps, a.theta2 if first else None, a.steps2 if first else 0)
        c = steady_layer(wd, t, mu_reg, lambda x: ens.predict([x], extrapolate=True)[1][0, 0], P)
        s = steadiness(wd, t)
        c["vcm_thirds"] = s["thirds"]
        print("theta %g: I_DEM %.4f +- %.4f (blocks %s), I from mu_reg = tan theta %.4f, ratio %.2f; mu_reg(I_DEM) - tan theta "
              "= %+.4f (%.1f ensemble std of %.4f%s), dmu_reg/dI %.3f; curve lower by 1, 2 std: Bagnold velocity x%s, x%s; "
              "vcm by thirds %s, slip %.3f of surface %.3f"
              % (t, c["I_dem"], c["I_dem_err"], np.round(c["I_dem_blocks"], 3), c["I_pred"], c["ratio"], c["mu_offset"],
                 c["offset_in_std"], c["ens_std"], ", I_DEM above the RVE range" if c["above_data"] else "",
                 c["dmu_dI"], *["%.2f" % f if f else "(beyond the data)" for f in (c["velocity_factor_1std"], c["velocity_factor_2std"])],
                 np.round(s["thirds"], 3), c["slip"], c["u_surface"]), flush=True)
        out["layers"].append(c)
        out["steady"].append(s)
    decel = [c for c in out["layers"] if c["theta"] == a.theta1]
    if decel:
        c = decel[0]
        wd = os.path.join(L.WORK, "incline_%g" % a.theta1)
        phi = float(ens.predict([c["I_pred"]])[0][0, 1])
        shift = float(np.mean([l["mu_offset"] for l in out["layers"]]))
        out["decel"] = dcl = decelerating(wd, a.theta1, a.theta2, mu_reg, phi, shift)
        print("decelerating %g -> %g: DEM mean velocity %.3f -> below 2%% at t = %.2f" %
              (a.theta1, a.theta2, dcl["v_dem"][0], dcl["t_stop_dem"]))
        for r in dcl["runs"]:
            print("  solver n %d dt %g from %s: start %.3f, stop %.2f, rms vs DEM %.3f of its start, final %.2g, max Picard %d"
                  % (r["n"], r["dt"], r["start"], r["mean0"], r["t_stop"] or float("nan"), r["rms_vs_dem"],
                     r["final"], r["iters"]))
    with open(os.path.join(HERE, "incline_check.json"), "w") as f:
        json.dump(out, f, indent=1)
    plot(out, P, Ig, mean, std, mu_reg)


def plot(out, P, Ig, mean, std, mu_reg):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4.2))
    a1.errorbar([p["I"] for p in P], [p["mu"] for p in P], xerr=[p["dI"] for p in P],
                yerr=[p["dmu"] for p in P], fmt="ko", ms=4, label="RVE")
    a1.plot(Ig, mean[:, 0], "b-", lw=1, label="MLP ensemble ±2 std")
    a1.fill_between(Ig, mean[:, 0] - 2 * std[:, 0], mean[:, 0] + 2 * std[:, 0], color="b", alpha=0.15)
    Il = np.logspace(-3, math.log10(0.3), 100)
    a1.plot(Il, mu_reg(Il), "g--", lw=1, label="regularised")
    for c, col in zip(out["layers"], "mrc"):
        tan = math.tan(math.radians(c["theta"]))
        a1.plot(c["I_z"], [tan] * len(c["I_z"]), col + ".", ms=4, alpha=0.5)
        a1.errorbar([c["I_dem"]], [tan], xerr=[c["I_dem_err"]], fmt=col + "s", ms=6,
                    label="incline %g° (interior layers, mean)" % c["theta"])
        a1.plot([c["I_pred"]], [tan], col + "x", ms=8)
    a1.set_xscale("log"); a1.set_xlabel("I"); a1.set_ylabel("mu")
    a1.set_title("x: I where mu_reg = tan theta", fontsize=8); a1.legend(fontsize=7)
    for s, c, col in zip(out["steady"], out["layers"], "mrc"):
        a2.plot(s["t"], s["vcm"], col + "-", lw=0.8, label="%g°" % c["theta"])
    a2.set_xlabel("time"); a2.set_ylabel("vcm(flow, x)"); a2.legend(fontsize=7)
    a2.set_title("steadiness: mean downhill velocity (profiles: last third)", fontsize=8)
    fig.tight_layout(); fig.savefig(os.path.join(HERE, "incline_check.png"), dpi=80)
    if "decel" in out:
        dcl = out["decel"]
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        ax.plot(dcl["t_dem"], dcl["v_dem"], "k-", label="DEM vcm(flow,x)")
        for r, sty in zip([r for r in dcl["runs"] if r["n"] == 80], ["b--", "g:", "r-."]):
            ax.plot(r["t"], r["mean"], sty, label="1D solver, start: %s profile" % r["start"])
        ax.set_xlabel("time after the slope change"); ax.set_ylabel("mean downhill velocity")
        ax.set_title("%g° -> %g°" % (dcl["theta1"], dcl["theta2"]), fontsize=9); ax.legend(fontsize=7)
        fig.tight_layout(); fig.savefig(os.path.join(HERE, "decel.png"), dpi=80)


if __name__ == "__main__":
    main()
