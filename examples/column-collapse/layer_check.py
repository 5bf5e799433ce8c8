#!/usr/bin/python3
"""The 2D solver (continuum.py) on the steady inclined layer: periodic in x, a grain layer of depth H
under a layer of air, gravity tilted by theta, marched from rest to steady state and compared with
the analytic Bagnold profile, on several grids (convergence in h).

Analytic: the weight above depth y (grains and air) sets both stresses, tau = sin(theta) q(y) g and
p = cos(theta) q(y) g, q(y) = rho_g (H - y) + rho_air A (A = air depth), so mu(I) = tan(theta) and I
is uniform (I = mu^-1(tan theta)); the shear rate I sqrt(p / rho_s) / d integrates to
    u(y) = (I/d) sqrt(g cos(theta) / rho_s) (2 / (3 rho_g)) (q(0)^1.5 - q(y)^1.5)   (no slip at y = 0).

    /usr/bin/python3 layer_check.py            # grids of 5, 10, 20, 40 cells over H; writes layer_check.json
(the README's run: reference/layer_check.json)"""
import json
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from continuum import MuIFlow  # noqa: E402

JOP = (math.tan(math.radians(20.9)), math.tan(math.radians(32.76)), 0.279)   # Jop et al. 2006


def mu_jop(I, mu_s=JOP[0], mu_2=JOP[1], I_0=JOP[2]):
    I = np.asarray(I, float)
    return mu_s + (mu_2 - mu_s) / (1.0 + I_0 / np.maximum(I, 1e-300))


def bagnold_air(y, H, A, theta, I, phi, rho_air, g=1.0, rho_s=1.0, d=1.0):
    q = lambda yy: phi * rho_s * (H - np.minimum(yy, H)) + rho_air * A
    return (I / d) * math.sqrt(g * math.cos(theta) / rho_s) * 2.0 / (3.0 * phi * rho_s) * \
        (q(0.0) ** 1.5 - q(np.asarray(y, float)) ** 1.5)


def run_layer(cells_over_H, H=10.0, A=2.0, theta_deg=25.0, phi=0.6, t_end=400.0, dt=0.5, nx=2, passes=1):
    """March the layer from rest; returns dict with the relative rms and surface errors of u in the
    grain layer against bagnold_air, and the largest relative change of u over the last 10 time units.
    One viscosity pass per step: the steady state does not depend on it."""
    theta = math.radians(theta_deg)
    h = H / cells_over_H
    ny = int(round((H + A) / h))
    f = MuIFlow(nx, ny, h, mu_jop, phi, gravity=(math.sin(theta), -math.cos(theta)), periodic_x=True)
    f.set_layer(H)
    mu_s, mu_2, I_0 = JOP
    t = math.tan(theta)
    I = I_0 * (t - mu_s) / (mu_2 - t)
    steps = int(round(t_end / dt))
    t0 = time.time()
    u_prev = None
    for k in range(steps):
        f.step(dt, passes)
        if k == steps - int(round(10.0 / dt)) - 1:
            u_prev = f.u_full()[0][0].copy()
    u = f.u_full()[0][0]                                       # u at the faces x = 0, cell centres in y
    y = (np.arange(ny) + 0.5) * h
    grain = y < H
    exact = bagnold_air(y, H, A, theta, I, phi, f.rho_air)
    us = float(exact[grain].max())
    return dict(cells_over_H=cells_over_H, h=h, I=I, u_surface_exact=us,
                u_surface=float(u[grain].max()),
                rms_rel=float(np.sqrt(np.mean((u[grain] - exact[grain]) ** 2)) / us),
                surface_rel=float(abs(u[grain].max() - us) / us),
                drift_last_10=float(np.max(np.abs(u - u_prev)) / us),
                wall_s=round(time.time() - t0, 2), y=y[grain].tolist(), u=u[grain].tolist(),
                exact=exact[grain].tolist())


def main():
    out = []
    for n in (5, 10, 20, 40):
        r = run_layer(n)
        print("cells over H %2d: surface u %.4f exact %.4f  rms error %.2e  surface error %.2e  drift %.1e  %.1f s"
              % (n, r["u_surface"], r["u_surface_exact"], r["rms_rel"], r["surface_rel"], r["drift_last_10"],
                 r["wall_s"]), flush=True)
        out.append(r)
    with open(os.path.join(HERE, "layer_check.json"), "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
