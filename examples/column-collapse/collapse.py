#!/usr/bin/python3
"""Granular column collapse: DEM (in.collapse, griddem spheres, one process, one thread) and the 2D
mu(I) continuum (continuum.py) with the rheology learned from RVEs (../rheology), measured by one
rule (deposit.py). For each aspect ratio: run-out, final height, front over time, final profile,
wall times; the run-outs against published scaling laws. Writes results.json and figures (those
of the README's runs are in reference/).

    /usr/bin/python3 collapse.py [--lmp PATH] [--aspect 0.5,1,2,3] [--spheres 1800] [--h 0.5]
                                 [--no-continuum] [--no-plot] [--lmp-args ARGS --tag TAG]

Column: ncols = round(sqrt(0.197 N / a) / 1.1) lattice columns (width L0 = 1.1 ncols), fill height
a L0 / 0.65 (the lattice fill settles to about 0.65 of it); the measured a = H0 / L0 after settling
is what the results use. DEM results are cached in work/dem_<a>_<N>/ (ignored by git)."""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
RHEOLOGY = os.path.join(HERE, "..", "rheology")
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
sys.path.insert(0, HERE)
sys.path.insert(0, RHEOLOGY)
import deposit as D  # noqa: E402
from griddemtools import lammps, log as lammps_log  # noqa: E402
from continuum import FollowingBox, HeldMu, MuIFlow  # noqa: E402

WORK = os.path.join(HERE, "work")
W = 4.4            # periodic depth of in.collapse
DUMP_EVERY = 0.5
SERIES_SPHERES = 1800  # the aspect-ratio series; other column sizes show the size effect
DT = 0.001         # DEM time step (in.collapse's default: contact time / 23)


def geometry(a, spheres):
    ncols = max(4, int(round(math.sqrt(0.197 * spheres / a) / 1.1)))
    L0 = 1.1 * ncols
    H = a * L0 / 0.65
    H0 = 0.65 * H
    Lx = math.ceil(L0 + 2.5 * H0 + 15.0)
    tmax = math.ceil(20.0 + 5.0 * math.sqrt(H0))
    return L0, H, Lx, tmax


def lammps_times(log):
    """LAMMPS's loop times summed over the runs of a log, and the same times the CPU use it reports
    for each (the processor time: on a shared machine the loop time counts waits for a core)."""
    runs = lammps_log.loop_times(log)
    return (round(sum(r.seconds for r in runs), 1),
            round(sum(r.seconds * r.cpu_percent / 100.0 for r in runs if r.cpu_percent is not None), 1))


def run_dem(lmp, a, spheres, extra=(), tag=""):
    L0, H, Lx, tmax = geometry(a, spheres)
    wd = os.path.join(WORK, "dem_%g_%d%s" % (a, spheres, tag))
    res_path = os.path.join(wd, "dem.json")
    if os.path.exists(res_path):
        with open(res_path) as f:
            res = json.load(f)
        log = os.path.join(wd, "log.lammps")
        if os.path.exists(log):         # (a record kept without its log keeps the times it recorded)
            res["loop_s"], res["loop_cpu_s"] = lammps_times(log)
        return res
    os.makedirs(wd, exist_ok=True)
    t0 = time.time()
    log = os.path.join(wd, "log.lammps")
    finished = os.path.exists(log) and "GRIDDEM collapse: released" in open(log).read()
    if not finished:       # (a finished run whose analysis was interrupted is analysed, not rerun)
        args = ["-in", os.path.join(HERE, "in.collapse"), "-var", "L0", "%g" % L0, "-var", "H", "%g" % H,
                "-var", "Lx", "%g" % Lx, "-var", "tmax", "%g" % tmax, "-var", "dump_every", "%g" % DUMP_EVERY,
                "-var", "dt", "%g" % DT, "-log", "log.lammps", "-echo", "none"] + list(extra)
        p = lammps.run(lmp, args, wd)
        if p.returncode != 0 or "GRIDDEM collapse: released" not in p.stdout:
            raise RuntimeError("in.collapse failed (exit %d):\n%s" % (p.returncode, p.stdout[-2000:]))
    wall = time.time() - t0
    settled = D.read_dump(os.path.join(wd, "settled.dump"))[0][1]
    phi0, H0 = D.settled_column(settled, W, L0)
    frames = D.read_dump(os.path.join(wd, "collapse.dump"))
    times, fronts, heights = [], [], []
    for step, xzr in frames:
        xc, h = D.dem_thickness(xzr, W, phi0, Lx)
        times.append(step * DT)
        fronts.append(D.front(xc, h))
        heights.append(float(h.max()))
    xc, h = D.dem_thickness(frames[-1][1], W, phi0, Lx)
    loop, loop_cpu = lammps_times(log)
    res = dict(a_target=a, spheres_requested=spheres, spheres=int(len(settled)), L0=L0, H_fill=H, Lx=Lx, phi0=phi0, H0=H0, a=H0 / L0,
               t=times, front=fronts, height=heights, runout=fronts[-1], final_height=heights[-1],
               x=xc.tolist(), profile=h.tolist(), wall_s=round(wall, 1) if not finished else None, loop_s=loop, loop_cpu_s=loop_cpu,
               stopped_at=times[-1], date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t0)),
               lmp=lmp, extra=list(extra))
    with open(res_path, "w") as f:
        json.dump(res, f)
    return res


def learned_mu():
    """The regularised mu(I) of ../rheology (its final ensemble refitted to its reference
    rve_points.json, the procedure of learn_mu.main), held at its value at the highest sampled I
    above it."""
    import learn_mu as L
    with open(os.path.join(RHEOLOGY, "reference", "rve_points.json")) as f:
        pts = json.load(f)
    Ilo, Ihi = min(p["Irequested"] for p in pts), max(p["Irequested"] for p in pts)
    ens = L.Ensemble(Ilo, Ihi).fit(pts)
    Ig = np.logspace(math.log10(Ilo), math.log10(Ihi), 60)
    mu_reg = L.regularise(Ig, ens.predict(Ig)[0][:, 0], I_c=Ilo)
    return HeldMu(mu_reg, mu_reg.params["I_max"]), ens


def run_continuum(dem, mu, h=0.5, t_end=None, ke_stop=1e-5, on_output=None, dt_max=0.05, passes=2, full_box=False,
                  dt_rest=0.5, rest_fraction=1e-2, margin_x=16, air_density=0.01, air_viscosity=0.01, box_extra=0.0):
    """The continuum on the DEM's measured column (L0, H0, phi0), the same box length; front and
    height by the DEM's rule (thickness binned in columns of 1 d) every DUMP_EVERY; there also the
    largest I of the deep grain cells (MuIFlow.grain_inertial_numbers) and how many were above
    mu.I_max, the highest sampled I (held there), and on_output(flow) is called (the on-the-fly coupling).
    The solver follows the grains (continuum.FollowingBox: its top, and its length to margin_x cells
    beyond the front, open to the air beyond; margin_x None: the whole length) unless full_box.
    The step is at most dt_max,
    and at most dt_rest once the kinetic energy (read every DUMP_EVERY) has fallen below rest_fraction
    of its peak: dt_max is set by the start of the flow (the lagged viscosity of a column at rest), and
    the deposit's creep afterwards moves a few hundredths of d in tens of time units. The air (density
    relative to the grains' bulk density, viscosity) stands for the DEM's vacuum; box_extra lengthens
    the box beyond the DEM's (the margin study of the README)."""
    L0, H0, phi0, Lx = dem["L0"], dem["H0"], dem["phi0"], dem["Lx"] + box_extra
    # the deposit rule's columns of 1 d: per_bin cells each (h <= 1), or each cell split into
    # per_cell of them (h a whole number of d)
    per_bin, per_cell = max(1, int(round(1.0 / h))), max(1, int(round(h)))
    if abs(h * per_bin / per_cell - 1) > 1e-9:
        raise ValueError("h = %g d: the cells must tile columns of 1 d (h = 1/k or k d)" % h)
    nx = int(round(Lx / h)) // per_bin * per_bin
    ny = int(math.ceil((H0 + 2.0) / h))
    air = dict(air_density=air_density, air_viscosity=air_viscosity)
    f = MuIFlow(nx, ny, h, mu, phi0, **air) if full_box else FollowingBox(nx, ny, h, mu, phi0, margin_x=margin_x, **air)
    f.set_column(L0, H0)

    def thickness_in_columns():
        return D.smooth(np.repeat(f.thickness(), per_cell).reshape(-1, per_bin).mean(axis=1))
    pe0 = float(np.sum(f.c * phi0 * ((np.arange(ny) + 0.5) * h)[None, :]) * h * h)
    mass0 = float(f.c.sum())
    t_end = t_end or dem["stopped_at"]
    t0, cpu0 = time.time(), time.process_time()
    times, fronts, heights = [], [], []
    next_out, steps = 0.0, 0
    I_seen, held, cells = 0.0, 0, 0
    ke_peak, step_max = 0.0, dt_max
    xc = np.arange(nx * per_cell // per_bin) + 0.5
    while True:
        if f.t >= next_out - 1e-9:
            thick = thickness_in_columns()
            times.append(f.t); fronts.append(D.front(xc, thick)); heights.append(float(thick.max()))
            next_out += DUMP_EVERY
            I_cells = f.grain_inertial_numbers()
            if I_cells.size:
                I_seen = max(I_seen, float(I_cells.max()))
                held += int((I_cells > mu.I_max).sum())
                cells += I_cells.size
            if on_output is not None:
                on_output(f)
            # stopped: kinetic energy per unit grain volume below ke_stop of the initial potential energy
            ke = f.kinetic_energy()
            if f.t > 5.0 and ke < ke_stop * pe0:
                break
            ke_peak = max(ke_peak, ke)
            if ke < rest_fraction * ke_peak:
                step_max = max(dt_max, dt_rest)
        if f.t >= t_end:
            break
        f.step(min(f.stable_dt(dt_max=step_max), next_out - f.t), passes)
        steps += 1
    thick = thickness_in_columns()
    return dict(h=h, dt_max=dt_max, dt_rest=dt_rest, rest_fraction=rest_fraction, passes=passes, full_box=full_box,
                margin_x=None if full_box else margin_x, air_density=air_density, air_viscosity=air_viscosity,
                box_extra=box_extra, nx=nx, ny=ny, t=times, front=fronts, height=heights, runout=fronts[-1],
                final_height=heights[-1], x=xc.tolist(), profile=thick.tolist(), steps=steps,
                wall_s=round(time.time() - t0, 1), cpu_s=round(time.process_time() - cpu0, 1), mass_rel_change=float(f.c.sum() / mass0 - 1),
                c_min=float(f.c.min()), c_max=float(f.c.max()), I_max_seen=I_seen, held_cells=held,
                deep_grain_cells=cells)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=lammps.default_lmp())
    ap.add_argument("--aspect", default="0.5,1,2,3")
    ap.add_argument("--spheres", type=int, default=SERIES_SPHERES, help="spheres per column (the fits and the "
                    "speed-ups take the %d-sphere series; other sizes are drawn apart)" % SERIES_SPHERES)
    ap.add_argument("--h", type=float, default=0.5, help="continuum cell size (d)")
    ap.add_argument("--dt-max", type=float, default=0.05, help="continuum: largest time step")
    ap.add_argument("--dt-rest", type=float, default=0.5, help="continuum: largest time step once the kinetic "
                    "energy is below 1 %% of its peak (the deposit's creep)")
    ap.add_argument("--passes", type=int, default=2, help="continuum: Picard passes per step")
    ap.add_argument("--full-box", action="store_true", help="continuum: solve on the whole box (no FollowingBox)")
    ap.add_argument("--margin-x", type=int, default=16, help="continuum: the solver's box ends this many cells "
                    "beyond the front, open to the air beyond (0: the box's whole length, closed)")
    ap.add_argument("--air-density", type=float, default=0.01, help="continuum: the air's density, relative to "
                    "the grains' bulk density")
    ap.add_argument("--air-viscosity", type=float, default=0.01, help="continuum: the air's viscosity")
    ap.add_argument("--box-extra", type=float, default=0.0, help="continuum: lengthen the box by this many d")
    ap.add_argument("--no-continuum", action="store_true")
    ap.add_argument("--no-plot", action="store_true")
    ap.add_argument("--out", default=os.path.join(HERE, "results.json"))
    ap.add_argument("--lmp-args", default="", help="extra LAMMPS arguments, e.g. '-var seed 1234' or the "
                    "Kokkos switches '-k on t 2 -sf kk -pk kokkos newton off neigh half'")
    ap.add_argument("--tag", default="", help="suffix of the DEM cache directory (work/dem_<a>_<N><tag>)")
    a = ap.parse_args()
    lmp = os.path.abspath(a.lmp)
    mu = None if a.no_continuum else learned_mu()[0]
    out = dict(cases=[])
    if os.path.exists(a.out):
        with open(a.out) as f:
            out = json.load(f)
    for asp in [float(x) for x in a.aspect.split(",")]:
        dem = run_dem(lmp, asp, a.spheres, a.lmp_args.split(), a.tag)
        print("DEM a %.2f (target %g): N %d L0 %.1f H0 %.2f phi0 %.3f run-out %.2f (dL/L0 %.2f) final height %.2f "
              "stopped t %.1f, LAMMPS loop time %.0f s (CPU %.0f s)" % (dem["a"], asp, dem["spheres"], dem["L0"], dem["H0"], dem["phi0"],
                                              dem["runout"], (dem["runout"] - dem["L0"]) / dem["L0"],
                                              dem["final_height"], dem["stopped_at"], dem["loop_s"], dem["loop_cpu_s"]), flush=True)
        case = dict(dem=dem)
        if mu is not None:
            con = run_continuum(dem, mu, h=a.h, dt_max=a.dt_max, dt_rest=a.dt_rest, passes=a.passes, full_box=a.full_box,
                                 margin_x=a.margin_x or None, air_density=a.air_density,
                                 air_viscosity=a.air_viscosity, box_extra=a.box_extra)
            print("   continuum h %.2f: run-out %.2f (dL/L0 %.2f) final height %.2f, %d steps, wall %.0f s (CPU %.0f s), "
                  "mass change %.1e, largest I (deep grain cells) %.3g, %d of %d cell samples held at I_max"
                  % (con["h"], con["runout"], (con["runout"] - dem["L0"]) / dem["L0"], con["final_height"],
                     con["steps"], con["wall_s"], con["cpu_s"], con["mass_rel_change"], con["I_max_seen"], con["held_cells"], con["deep_grain_cells"]),
                  flush=True)
            case["continuum"] = con
        out["cases"] = [c for c in out["cases"] if abs(c["dem"]["a_target"] - asp) > 1e-9 or
                        c["dem"]["spheres_requested"] != a.spheres] + [case]
        summarise(out)
        with open(a.out, "w") as f:
            json.dump(out, f, indent=1)
    if not a.no_plot:
        plot(out)



# ---------------------------------------------------------------- published scaling and figures
# Read through the search tool (abstracts): Balmforth & Kerswell (JFM 538, 2005), experiments in
# rectangular channels: (l_inf - L)/L ~ a^(0.9 +- 0.1) in wide channels, a^(0.65 +- 0.05) in narrow
# slots; H/h_inf ~ a^0.6 (wide), a^0.5 (narrow); the prefactors depend on the material. Larrieu,
# Staron & Hinch (JFM 554, 2006): run-out ~ a^0.65 for planar collapses (shallow-water model,
# matching experiments). Second hand (K. Kumar, PhD thesis, Cambridge 2015, chapter 2, its LaTeX
# source), for the quasi-2D channel of Lajeunesse et al. (2005): (L - L0)/L0 ~ 1.2 a below a = 2.3,
# 1.9 a^(2/3) above; h_inf/L0 ~ a below 0.7, a^(1/3) above.
PUBLISHED_EXPONENTS = dict(runout_wide=(0.9, 0.1), runout_narrow=(0.65, 0.05), height_wide=0.6, height_narrow=0.5)
SMALL_A, LARGE_A = 3.5, 3.0      # the two branches fitted separately (a <= 3.5 and a >= 3)


def power_fit(a, y):
    """Least squares of log y = log k + n log a: (k, n, standard error of n)."""
    A = np.vstack([np.ones(len(a)), np.log(a)]).T
    coef, res, _, _ = np.linalg.lstsq(A, np.log(y), rcond=None)
    dof = max(len(a) - 2, 1)
    s2 = float(np.sum((A @ coef - np.log(y)) ** 2)) / dof
    cov = s2 * np.linalg.inv(A.T @ A)
    return float(math.exp(coef[0])), float(coef[1]), float(math.sqrt(cov[1, 1]))


def series(out, spheres=SERIES_SPHERES):
    """The cases of the aspect-ratio series of columns of about that many spheres, by a."""
    return sorted([c for c in out["cases"] if c["dem"]["spheres_requested"] == spheres], key=lambda c: c["dem"]["a"])


def summarise(out):
    """Fits and differences of the series (out["summary"]), and the same for each other column size
    (out["summary_by_size"][N])."""
    out["summary"] = summary_of(series(out))
    sizes = sorted({c["dem"]["spheres_requested"] for c in out["cases"]} - {SERIES_SPHERES})
    out["summary_by_size"] = {str(n): summary_of(series(out, n)) for n in sizes}
    return out["summary"]


def summary_of(cases):
    a = np.array([c["dem"]["a"] for c in cases])
    summ = dict(a=a.tolist())
    for who in ("dem", "continuum"):
        have = [c for c in cases if who in c]
        if not have:
            continue
        a = np.array([c["dem"]["a"] for c in have])
        L0 = np.array([c["dem"]["L0"] for c in have])
        H0 = np.array([c["dem"]["H0"] for c in have])
        run = np.array([c[who]["runout"] for c in have])
        hf = np.array([c[who]["final_height"] for c in have])
        s = dict(a=a.tolist(), dL_over_L0=((run - L0) / L0).tolist(), H0_over_hf=(H0 / hf).tolist())
        if len(a) >= 2:
            s["runout_fit"] = power_fit(a, (run - L0) / L0)
            s["height_fit"] = power_fit(a, H0 / hf)
        for branch, sel in (("small_a", a <= SMALL_A), ("large_a", a >= LARGE_A)):
            if sel.sum() >= 3:
                s["runout_fit_" + branch] = power_fit(a[sel], ((run - L0) / L0)[sel])
                s["height_fit_" + branch] = power_fit(a[sel], (H0 / hf)[sel])
        summ[who] = s
    both = [c for c in cases if "continuum" in c]
    if both:
        summ["runout_rel_diff"] = [(c["continuum"]["runout"] - c["dem"]["runout"]) / c["dem"]["runout"] for c in both]
        summ["speedup_loop"] = [c["dem"]["loop_s"] / c["continuum"]["wall_s"] for c in both]
        if all("loop_cpu_s" in c["dem"] and "cpu_s" in c["continuum"] for c in both):
            summ["speedup_cpu"] = [c["dem"]["loop_cpu_s"] / c["continuum"]["cpu_s"] for c in both]
    return summ


def plot(out, path=HERE):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases = series(out)
    others = [c for c in out["cases"] if c not in cases]
    summ = out["summary"]
    a = np.array(summ["a"])
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for who, st in (("dem", "ko"), ("continuum", "bs")):
        if who in summ:
            k, n, dn = summ[who]["runout_fit"] if "runout_fit" in summ[who] else (None, None, None)
            a1.plot(summ[who]["a"], summ[who]["dL_over_L0"], st, label="%s%s" % (who, "" if k is None else
                    ": %.2f a^(%.2f +- %.2f)" % (k, n, dn)))
            a2.plot(summ[who]["a"], summ[who]["H0_over_hf"], st, label=who)
    for n, s in out.get("summary_by_size", {}).items():     # the same material in larger columns: the size effect
        for who, st in (("dem", "r^"), ("continuum", "mv")):
            if who in s:
                lab = "%s, about %s spheres" % (who, n)
                a1.plot(s[who]["a"], s[who]["dL_over_L0"], st, label=lab)
                a2.plot(s[who]["a"], s[who]["H0_over_hf"], st, label=lab)
    aa = np.linspace(a.min(), a.max(), 50)
    if "dem" in summ and "runout_fit" in summ["dem"]:
        k0 = summ["dem"]["dL_over_L0"][0] / a[0] ** 0.9
        a1.plot(aa, k0 * aa ** 0.9, "g--", lw=1, label="slope a^0.9 (B&K 2005 wide)")
        k1 = summ["dem"]["dL_over_L0"][0] / a[0] ** 0.65
        a1.plot(aa, k1 * aa ** 0.65, "m:", lw=1, label="slope a^0.65 (B&K 2005 narrow)")
        k2 = summ["dem"]["H0_over_hf"][0] / a[0] ** 0.6
        a2.plot(aa, k2 * aa ** 0.6, "g--", lw=1, label="slope a^0.6 (B&K wide)")
        k3 = summ["dem"]["H0_over_hf"][0] / a[0] ** 0.5
        a2.plot(aa, k3 * aa ** 0.5, "m:", lw=1, label="slope a^0.5 (B&K narrow)")
        a1.plot(aa, np.where(aa < 2.3, 1.2 * aa, 1.9 * aa ** (2 / 3)), "r-", lw=0.8,
                label="1.2 a | 1.9 a^(2/3) (Lajeunesse 2005, 2nd hand)")
        a2.plot(aa, np.where(aa < 0.7, 1.0, aa ** (2 / 3)), "r-", lw=0.8, label="1 | a^(2/3) (same)")
    for ax, lab in ((a1, "(L_inf - L0) / L0"), (a2, "H0 / h_inf")):
        ax.set_xscale("log"); ax.set_yscale("log"); ax.set_xlabel("a = H0 / L0"); ax.set_ylabel(lab)
        ax.legend(fontsize=7)
    fig.tight_layout(); fig.savefig(os.path.join(path, "runout.png"), dpi=70)
    rows = cases + others
    fig, axes = plt.subplots(len(rows), 2, figsize=(10, 2.3 * len(rows)), squeeze=False)
    for (ax, bx), c in zip(axes, rows):
        d = c["dem"]
        ax.plot(d["x"], d["profile"], "k-", label="DEM")
        bx.plot(d["t"], d["front"], "k-", label="DEM")
        if "continuum" in c:
            ax.plot(c["continuum"]["x"], c["continuum"]["profile"], "b--", label="continuum")
            bx.plot(c["continuum"]["t"], c["continuum"]["front"], "b--", label="continuum")
        ax.set_xlim(0, max(d["runout"], c.get("continuum", d)["runout"]) * 1.15)
        ax.set_ylabel("h (a = %.2f, N %d)" % (d["a"], d["spheres"]), fontsize=8); bx.set_ylabel("front")
        ax.legend(fontsize=7)
    axes[-1][0].set_xlabel("x (final deposit)"); axes[-1][1].set_xlabel("t")
    fig.tight_layout(); fig.savefig(os.path.join(path, "profiles.png"), dpi=60)


if __name__ == "__main__":
    main()
