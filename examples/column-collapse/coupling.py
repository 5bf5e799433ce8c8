#!/usr/bin/python3
"""The continuum collapse with the rheology learned on the fly: every output interval (0.5 time
units) the solver's grain cells report their inertial numbers I to the ensemble of ../rheology
(learn_mu.Ensemble); where its spread exceeds tol (chosen above the RVE noise) a new RVE is run
(learn_mu.run_rve, in.rve) and the ensemble and the regularised curve are refitted during the run.
Above the highest sampled I the policy decides: "sample" runs RVEs on up (to I_cap), "hold" keeps
mu at its value at the highest sampled I; both are reported (largest I met, cells held).

New RVEs sit on a log grid I_ref f^k (I_ref = 0.3, f = the sampling factor): an unsure I is
snapped to the nearest grid point and each grid point is run at most once, so f sets how finely
the solver may ask. The sampled range is that of the measured I of the RVEs: an RVE whose measured
I misses the requested one by more than 10 % (a pressure control that did not hold P) is reported
and not used, and no higher I is asked for after it. Only cells at least one grain layer deep (p >= phi rho_s g d) count: at the free
surface p -> 0 and I -> infinity by construction, not by the flow.

    /usr/bin/python3 coupling.py [--lmp PATH] [--factors 1.5,2,3] [--first 1] [--others 0.5,2,3]
                                 [--tol 0.015] [--policy sample] [--I-cap 1.0] [--h 1.0] [--dt-max 0.05]

Start set: the recorded RVEs of ../rheology at I = 0.001, 0.003 (the expensive low-I plateau),
0.01, 0.0548 and 0.3 (its adaptive loop's start), and the RVEs' compressed state
(learn_mu.prepare_state), both paid once for all collapses. The first collapse (DEM column of
collapse.py's cache, work/) trains the ensemble; the other aspect ratios reuse it and report their
new RVEs. Writes coupling.json (that of the README's run is reference/coupling.json)."""
import argparse
import json
import math
import os
import resource
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
sys.path.insert(0, HERE)
import collapse as CL  # noqa: E402
import learn_mu as L  # noqa: E402  (collapse puts ../rheology on the path)
from continuum import HeldMu  # noqa: E402
from griddemtools import lammps  # noqa: E402

START = (0.001, 0.003, 0.01, 0.0548, 0.3)
I_REF = 0.3
MISS = 1.1         # an RVE whose measured I is off the requested by more than this factor missed it


class AdaptiveRheology:
    """mu(I) for the solver, refined on the fly. run(I) -> RVE result dict (learn_mu.run_rve)."""

    def __init__(self, run, points, factor, tol, policy="sample", I_cap=1.0, members=8):
        self.run_rve, self.points, self.members = run, list(points), members
        self.factor, self.tol, self.policy, self.I_cap = factor, tol, policy, I_cap
        self.runs = []                     # new RVEs: dicts I, source, wall_s, reason
        self.failed = []                   # grid points whose RVE failed or missed (not retried)
        self.unreachable = math.inf        # requested I from which the RVE missed its target
        self.refit()

    def grid_point(self, I):
        k = round(math.log(I / I_REF) / math.log(self.factor))
        return I_REF * self.factor ** k

    def sampled(self, I):
        return any(abs(math.log(I / J)) < 1e-6 for J in [p["Irequested"] for p in self.points] + self.failed)

    def refit(self):
        """Ensemble and regularised curve on the measured I of the points (the sampled range)."""
        Imeas = [p["I"] for p in self.points]
        self.Ilo, self.Ihi = min(Imeas), max(Imeas)
        self.ens = L.Ensemble(self.Ilo, self.Ihi, members=self.members).fit(self.points)
        Ig = np.logspace(math.log10(self.Ilo), math.log10(self.Ihi), 60)
        curve = L.regularise(Ig, self.ens.predict(Ig)[0][:, 0], I_c=self.Ilo)
        self.mu = HeldMu(curve, curve.params["I_max"])

    def __call__(self, I):
        return self.mu(I)

    @property
    def I_max(self):
        return self.Ihi

    def candidate(self, I_cells):
        """The next RVE the cells ask for, or None: the unsure I of largest spread inside the sampled
        range (snapped, not yet run), else with policy "sample" the first grid point above the
        sampled range, if cells reach it (up to I_cap)."""
        I_cells = np.asarray(I_cells, float)
        inside = I_cells[(I_cells >= self.Ilo) & (I_cells <= self.Ihi)]
        if inside.size:
            Iu = np.unique(np.round(np.log(inside), 2))          # distinct I to 1 % (cheap prediction)
            std = self.ens.predict(np.exp(Iu).clip(self.Ilo, self.Ihi))[1][:, 0]
            for k in np.argsort(-std):
                if std[k] <= self.tol:
                    break
                g = self.grid_point(math.exp(Iu[k]))
                if not self.sampled(g) and self.Ilo < g < self.Ihi:
                    return g, "ensemble std %.4f at I %.3g" % (std[k], math.exp(Iu[k]))
        if self.policy == "sample" and I_cells.size and I_cells.max() > self.Ihi:
            k = math.floor(math.log(self.Ihi / I_REF) / math.log(self.factor) + 1e-9) + 1
            g = I_REF * self.factor ** k
            while self.sampled(g) and g < self.I_cap:    # run, but measured a little below the grid point
                k += 1
                g = I_REF * self.factor ** k
            if g <= self.I_cap * (1 + 1e-9) and g < self.unreachable and not self.sampled(g) and \
                    I_cells.max() >= self.grid_point(g) / math.sqrt(self.factor):
                return g, "cells at I up to %.3g above the sampled %.3g" % (I_cells.max(), self.Ihi)
        return None

    def update(self, I_cells):
        """Run the RVE the cells ask for (at most one per call), refit; returns it or None."""
        c = self.candidate(I_cells)
        if c is None:
            return None
        I, why = c
        t0 = time.time()
        try:
            r = self.run_rve(I)
        except RuntimeError as e:          # e.g. the RVE's pressure control cannot hold a dilute flow
            self.failed.append(I)
            self.runs.append(dict(I=I, failed=str(e).splitlines()[0], wall_s=round(time.time() - t0, 1), reason=why))
            return self.runs[-1]
        run = dict(I=I, I_measured=r["I"], mu=r["mu"], dmu=r["dmu"], phi=r["phi"], source=r.get("source", "run"),
                   wall_s=round(time.time() - t0, 1), rve_wall_s=r.get("wall_s"), reason=why)
        if abs(math.log(r["I"] / I)) > math.log(MISS):
            # the RVE's pressure control could not hold P (its dilation rate is capped): the point is
            # not steady at the requested rate, so it is not used, and no higher I is asked for
            run["missed"] = "measured I %.3g for %.3g requested: not used" % (r["I"], I)
            self.failed.append(I)
            self.unreachable = min(self.unreachable, I)
            self.runs.append(run)
            return run
        self.points.append(r)
        self.runs.append(run)
        self.refit()
        return run


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=lammps.default_lmp())
    ap.add_argument("--factors", default="1.5,2,3")
    ap.add_argument("--first", type=float, default=1.0)
    ap.add_argument("--others", default="0.5,2,3")
    ap.add_argument("--spheres", type=int, default=1800)
    ap.add_argument("--tol", type=float, default=0.015)
    ap.add_argument("--policy", default="sample", choices=("sample", "hold"))
    ap.add_argument("--I-cap", type=float, default=1.0)
    ap.add_argument("--h", type=float, default=1.0)
    ap.add_argument("--dt-max", type=float, default=0.05)
    a = ap.parse_args()
    lmp = os.path.abspath(a.lmp)
    with open(os.path.join(CL.RHEOLOGY, "reference", "rve_points.json")) as f:
        recorded = json.load(f)
    start = [r for r in recorded if any(abs(math.log(r["Irequested"] / I)) < 1e-3 for I in START)]
    rve_dir = os.path.join(CL.WORK, "rve")
    state, state_cpu = L.prepare_state(lmp, rve_dir)
    print("compressed state of the RVEs: %s (%.1f s of CPU now, once for all collapses)" % (state, state_cpu), flush=True)

    def run(I):
        r = L.run_rve(lmp, I, workdir=os.path.join(rve_dir, "rve_%.5g" % I), recorded=recorded)
        print("   RVE I=%.4g: mu %.4f +- %.4f, %s, %s s" % (I, r["mu"], r["dmu"], r.get("source", "run"),
                                                          r.get("wall_s")), flush=True)
        return r

    out = dict(tol=a.tol, policy=a.policy, I_cap=a.I_cap, h=a.h, dt_max=a.dt_max, start=list(START),
               state_cpu_s=round(state_cpu, 1), factors=[])
    for fac in [float(x) for x in a.factors.split(",")]:
        rheo = AdaptiveRheology(run, start, fac, a.tol, a.policy, a.I_cap)
        rec = dict(factor=fac, collapses=[])
        for asp in [a.first] + [float(x) for x in a.others.split(",") if x.strip()]:
            dem = CL.run_dem(lmp, asp, a.spheres)
            n_before = len(rheo.runs)

            def on_output(flow):
                I = flow.grain_inertial_numbers()
                while rheo.update(I) is not None:
                    pass

            t0, children0 = time.time(), resource.getrusage(resource.RUSAGE_CHILDREN)
            con = CL.run_continuum(dem, rheo, h=a.h, on_output=on_output, dt_max=a.dt_max)
            children = resource.getrusage(resource.RUSAGE_CHILDREN)
            rve_cpu = max(0.0, children.ru_utime + children.ru_stime - children0.ru_utime - children0.ru_stime)
            held_note = "held above the final sampled I = %.3g" % rheo.Ihi
            new = rheo.runs[n_before:]
            rec["collapses"].append(dict(a=dem["a"], a_target=asp, new_rves=new, n_new=len(new),
                                         n_failed=sum("failed" in r for r in new),
                                         n_missed=sum("missed" in r for r in new),
                                         n_cached=sum(r.get("source") == "work/ cache" for r in new),
                                         sampled_range=[rheo.Ilo, rheo.Ihi], runout=con["runout"],
                                         dem_runout=dem["runout"], final_height=con["final_height"],
                                         wall_s=round(time.time() - t0, 1), cpu_s=con["cpu_s"],
                                         rve_cpu_s=round(rve_cpu, 1),
                                         rve_wall_s=round(sum(r["wall_s"] for r in new), 1),
                                         I_max_seen=con["I_max_seen"], held_cells=con["held_cells"],
                                         deep_grain_cells=con["deep_grain_cells"], held_note=held_note))
            print("factor %g, a %.2f: %d new RVEs %s, run-out %.2f (DEM %.2f), wall %.0f s (RVEs %.0f s), CPU: "
                  "continuum and refits %.1f s, RVEs %.1f s; largest I of the deep grain cells %.3g (%s)"
                  % (fac, dem["a"], len(new), [round(r["I"], 4) for r in new], con["runout"], dem["runout"],
                     time.time() - t0, rec["collapses"][-1]["rve_wall_s"], con["cpu_s"], rve_cpu,
                     con["I_max_seen"], held_note),
                  flush=True)
        rec["points"] = [dict(I=p["I"], mu=p["mu"], dmu=p["dmu"], Irequested=p["Irequested"]) for p in rheo.points]
        out["factors"].append(rec)
        with open(os.path.join(HERE, "coupling.json"), "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
