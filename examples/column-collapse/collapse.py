#!/usr/bin/python3
"""Granular column collapse: DEM (in.collapse, griddem spheres, one process, one thread) and the 2D
mu(I) continuum (continuum.py) with the rheology learned from RVEs (../rheology), measured by one
rule (deposit.py). For each aspect ratio: run-out, final height, front over time, final profile,
wall times; the run-outs against published scaling laws. Writes results.json and figures.

    /usr/bin/python3 collapse.py [--lmp PATH] [--aspect 0.5,1,2,3] [--spheres 1800] [--h 0.5]
                                 [--style griddem/hooke/history] [--sf kk] [--no-continuum]

Column: ncols = round(sqrt(0.197 N / a) / 1.1) lattice columns (width L0 = 1.1 ncols), fill height
a L0 / 0.65 (the lattice fill settles to about 0.65 of it); the measured a = H0 / L0 after settling
is what the results use. DEM results are cached in work/dem_<a>_<N>/ (ignored by git)."""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
RHEOLOGY = os.path.join(HERE, "..", "rheology")
sys.path.insert(0, HERE)
sys.path.insert(0, RHEOLOGY)
import deposit as D  # noqa: E402
from continuum import HeldMu, MuIFlow  # noqa: E402

WORK = os.path.join(HERE, "work")
W = 4.4            # periodic depth of in.collapse
DUMP_EVERY = 0.5


def default_lmp():
    return os.environ.get("GRIDDEM_LMP", os.path.join(HERE, "..", "..", "build", "lmp"))


def geometry(a, spheres):
    ncols = max(4, int(round(math.sqrt(0.197 * spheres / a) / 1.1)))
    L0 = 1.1 * ncols
    H = a * L0 / 0.65
    H0 = 0.65 * H
    Lx = math.ceil(L0 + 2.5 * H0 + 15.0)
    tmax = math.ceil(20.0 + 5.0 * math.sqrt(H0))
    return L0, H, Lx, tmax


def run_dem(lmp, a, spheres, extra=(), tag=""):
    L0, H, Lx, tmax = geometry(a, spheres)
    wd = os.path.join(WORK, "dem_%g_%d%s" % (a, spheres, tag))
    res_path = os.path.join(wd, "dem.json")
    if os.path.exists(res_path):
        with open(res_path) as f:
            return json.load(f)
    os.makedirs(wd, exist_ok=True)
    t0 = time.time()
    cmd = [lmp, "-in", os.path.join(HERE, "in.collapse"), "-var", "L0", "%g" % L0, "-var", "H", "%g" % H,
           "-var", "Lx", "%g" % Lx, "-var", "tmax", "%g" % tmax, "-var", "dump_every", "%g" % DUMP_EVERY,
           "-log", "log.lammps", "-echo", "none"] + list(extra)
    p = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    if p.returncode != 0 or "GRIDDEM collapse: released" not in p.stdout:
        raise RuntimeError("in.collapse failed (exit %d):\n%s" % (p.returncode, p.stdout[-2000:]))
    wall = time.time() - t0
    settled = D.read_dump(os.path.join(wd, "settled.dump"))[0][1]
    phi0, H0 = D.settled_column(settled, W, L0)
    frames = D.read_dump(os.path.join(wd, "collapse.dump"))
    dt = float(next(l.split()[1] for l in open(os.path.join(wd, "log.lammps")) if l.startswith("timestep")))
    times, fronts, heights = [], [], []
    for step, xzr in frames:
        xc, h = D.dem_thickness(xzr, W, phi0, Lx)
        times.append(step * dt)
        fronts.append(D.front(xc, h))
        heights.append(float(h.max()))
    xc, h = D.dem_thickness(frames[-1][1], W, phi0, Lx)
    loop = sum(float(l.split()[3]) for l in p.stdout.splitlines() if l.startswith("Loop time of"))
    res = dict(a_target=a, spheres_requested=spheres, spheres=int(len(settled)), L0=L0, H_fill=H, Lx=Lx, phi0=phi0, H0=H0, a=H0 / L0,
               t=times, front=fronts, height=heights, runout=fronts[-1], final_height=heights[-1],
               x=xc.tolist(), profile=h.tolist(), wall_s=round(wall, 1), loop_s=round(loop, 1),
               stopped_at=times[-1], date=time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t0)),
               lmp=lmp, extra=list(extra))
    with open(res_path, "w") as f:
        json.dump(res, f)
    return res


def learned_mu():
    """The regularised mu(I) of ../rheology (its final ensemble refitted to rve_points.json, the
    procedure of learn_mu.main), held at its value at the highest sampled I above it."""
    import learn_mu as L
    with open(os.path.join(RHEOLOGY, "rve_points.json")) as f:
        pts = json.load(f)
    Ilo, Ihi = min(p["Irequested"] for p in pts), max(p["Irequested"] for p in pts)
    ens = L.Ensemble(Ilo, Ihi).fit(pts)
    Ig = np.logspace(math.log10(Ilo), math.log10(Ihi), 60)
    mu_reg = L.regularise(Ig, ens.predict(Ig)[0][:, 0], I_c=Ilo)
    return HeldMu(mu_reg, mu_reg.params["I_max"]), ens


def run_continuum(dem, mu, h=0.5, t_end=None, ke_stop=1e-5):
    """The continuum on the DEM's measured column (L0, H0, phi0), the same box length; front and
    height by the DEM's rule (thickness binned in columns of 1 d) every DUMP_EVERY."""
    L0, H0, phi0, Lx = dem["L0"], dem["H0"], dem["phi0"], dem["Lx"]
    per_bin = int(round(1.0 / h))
    nx = int(round(Lx / h)) // per_bin * per_bin
    ny = int(math.ceil((H0 + 2.0) / h))
    f = MuIFlow(nx, ny, h, mu, phi0)
    f.set_column(L0, H0)
    pe0 = float(np.sum(f.c * phi0 * ((np.arange(ny) + 0.5) * h)[None, :]) * h * h)
    mass0 = float(f.c.sum())
    t_end = t_end or dem["stopped_at"]
    t0 = time.time()
    times, fronts, heights = [], [], []
    next_out, steps = 0.0, 0
    xc = (np.arange(nx // per_bin) + 0.5) * per_bin * h
    while True:
        if f.t >= next_out - 1e-9:
            thick = f.thickness().reshape(-1, per_bin).mean(axis=1)
            times.append(f.t); fronts.append(D.front(xc, thick)); heights.append(float(thick.max()))
            next_out += DUMP_EVERY
            # stopped: kinetic energy per unit grain volume below ke_stop of the initial potential energy
            if f.t > 5.0 and f.kinetic_energy() < ke_stop * pe0:
                break
        if f.t >= t_end:
            break
        f.step(min(f.stable_dt(), next_out - f.t))
        steps += 1
    thick = f.thickness().reshape(-1, per_bin).mean(axis=1)
    return dict(h=h, nx=nx, ny=ny, t=times, front=fronts, height=heights, runout=fronts[-1],
                final_height=heights[-1], x=xc.tolist(), profile=thick.tolist(), steps=steps,
                wall_s=round(time.time() - t0, 1), mass_rel_change=float(f.c.sum() / mass0 - 1),
                c_min=float(f.c.min()), c_max=float(f.c.max()), I_max_seen=mu.I_seen_max, held_evaluations=mu.held)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=default_lmp())
    ap.add_argument("--aspect", default="0.5,1,2,3")
    ap.add_argument("--spheres", type=int, default=1800)
    ap.add_argument("--h", type=float, default=0.5, help="continuum cell size (d)")
    ap.add_argument("--no-continuum", action="store_true")
    ap.add_argument("--out", default=os.path.join(HERE, "results.json"))
    a = ap.parse_args()
    lmp = os.path.abspath(a.lmp)
    mu = None if a.no_continuum else learned_mu()[0]
    out = dict(cases=[])
    if os.path.exists(a.out):
        with open(a.out) as f:
            out = json.load(f)
    for asp in [float(x) for x in a.aspect.split(",")]:
        dem = run_dem(lmp, asp, a.spheres)
        print("DEM a %.2f (target %g): N %d L0 %.1f H0 %.2f phi0 %.3f run-out %.2f (dL/L0 %.2f) final height %.2f "
              "stopped t %.1f wall %.0f s" % (dem["a"], asp, dem["spheres"], dem["L0"], dem["H0"], dem["phi0"],
                                              dem["runout"], (dem["runout"] - dem["L0"]) / dem["L0"],
                                              dem["final_height"], dem["stopped_at"], dem["wall_s"]), flush=True)
        case = dict(dem=dem)
        if mu is not None:
            mu.I_seen_max, mu.held = 0.0, 0
            con = run_continuum(dem, mu, h=a.h)
            print("   continuum h %.2f: run-out %.2f (dL/L0 %.2f) final height %.2f, %d steps, wall %.0f s, "
                  "mass change %.1e, largest I %.3g (%d evaluations held at I_max)"
                  % (con["h"], con["runout"], (con["runout"] - dem["L0"]) / dem["L0"], con["final_height"],
                     con["steps"], con["wall_s"], con["mass_rel_change"], con["I_max_seen"], con["held_evaluations"]),
                  flush=True)
            case["continuum"] = con
        out["cases"] = [c for c in out["cases"] if abs(c["dem"]["a_target"] - asp) > 1e-9 or
                        c["dem"]["spheres_requested"] != a.spheres] + [case]
        with open(a.out, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
