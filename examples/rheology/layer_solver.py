"""Depth-resolved 1D granular layer on a slope with a local mu(I) rheology (NumPy/SciPy):

    rho phi du/dt = rho phi g sin(theta) + d tau/dz,   tau = mu(I) P sign(du/dz),
    P = rho phi g cos(theta) (H - z),   I = d |du/dz| / sqrt(P / rho),

u(0) = 0 (no slip at the base), tau(H) = 0 (stress-free surface), phi constant over depth.

Grid: nodes z_i = i H/n (i = 0..n, u_0 = 0), stresses on the faces z_{i+1/2}, so P > 0 wherever
mu(I) is read; the surface node carries half a cell's mass. Summing the discrete balance gives the
steady solution exactly: tau/P = tan(theta) on every face, i.e. I uniform (the Bagnold profile
integrated with the midpoint rule).

Time: backward Euler. The shear stress is written tau = eta (du/dz) with the secant viscosity
eta = mu(I) P / max(|du/dz|, gdot_floor); each step is solved by Picard (Kacanov) iteration on eta,
a tridiagonal solve per iteration. For a non-decreasing mu(I) with mu/I decreasing (both hold for
the regularised curve of learn_mu.py and for mu_jop), the step is a convex minimisation and this
iteration converges from any start; with mu(I) non-monotone the implicit step could have several
solutions (the ill-posedness that the regularisation removes). gdot_floor = I_floor sqrt(P/rho)/d
(I_floor = 1e-9) bounds eta in a static region: for a constant mu it is the usual Bingham
regularisation (a creep of I ~ I_floor below the yield stress)."""
import math

import numpy as np
from scipy.linalg import solve_banded


class Layer:
    """A layer of depth H, solid fraction phi, grain diameter d, on n cells; mu: function of I
    (array in, array out)."""

    def __init__(self, mu, H, phi, n, d=1.0, rho=1.0, g=1.0, I_floor=1e-9):
        self.mu, self.H, self.phi, self.n, self.d, self.rho, self.g = mu, H, phi, n, d, rho, g
        self.dz = H / n
        self.z = np.arange(n + 1) * self.dz                 # nodes, z[0] = 0 is the base
        self.zf = (np.arange(n) + 0.5) * self.dz            # faces between node k and k+1
        self.m = np.full(n, rho * phi * self.dz)            # mass per area of nodes 1..n
        self.m[-1] *= 0.5
        self.I_floor = I_floor

    def pressure(self, theta):
        return self.rho * self.phi * self.g * math.cos(theta) * (self.H - self.zf)

    def stress(self, u, theta):
        """Shear stress on the faces for node velocities u (length n + 1, u[0] = 0)."""
        P = self.pressure(theta)
        gd = np.diff(u) / self.dz
        I = self.d * np.abs(gd) / np.sqrt(P / self.rho)
        return np.sign(gd) * self.mu(I) * P

    def steady(self, theta, I):
        """The discrete steady solution for mu(I) = tan(theta) (I given): midpoint-rule Bagnold."""
        gd = I * np.sqrt(self.pressure(theta) / self.rho) / self.d
        return np.concatenate([[0.0], np.cumsum(gd) * self.dz])

    def mean(self, u):
        """Depth-averaged velocity (trapezoid rule, the nodes' masses)."""
        return float(np.dot(self.m, u[1:]) / (self.rho * self.phi * self.H))

    def step(self, u, theta, dt, tol=1e-6, max_iter=5000):
        """One backward Euler step of length dt from u; returns (u_new, Picard iterations).
        Converged when no node velocity changes by more than tol times the largest one."""
        n, dz = self.n, self.dz
        P = self.pressure(theta)
        gd_floor = self.I_floor * np.sqrt(P / self.rho) / self.d
        rhs = self.m * (u[1:] / dt + self.g * math.sin(theta))
        new = u.copy()
        for it in range(1, max_iter + 1):
            gd = np.maximum(np.abs(np.diff(new)) / dz, gd_floor)
            c = self.mu(self.d * gd / np.sqrt(P / self.rho)) * P / gd / dz   # eta / dz on each face
            ab = np.zeros((3, n))
            ab[1] = self.m / dt + c                                  # face below each node
            ab[1, :-1] += c[1:]                                      # face above (none at the surface)
            ab[0, 1:] = -c[1:]
            ab[2, :-1] = -c[1:]
            sol = solve_banded((1, 1), ab, rhs)
            change = np.max(np.abs(sol - new[1:]))
            new[1:] = sol
            if change <= tol * max(np.max(np.abs(sol)), 1e-12):
                return new, it
        raise RuntimeError("layer_solver: Picard iteration did not converge in %d iterations" % max_iter)

    def run(self, u0, theta, t_end, dt, record=None):
        """March from u0 on slope theta (radians) to t_end. Returns dict t, mean, surface (every
        step) and profiles {t: u} at the times in record (nearest step), max Picard iterations."""
        u = np.array(u0, float)
        steps = int(round(t_end / dt))
        t = np.arange(steps + 1) * dt
        mean, surf = [self.mean(u)], [u[-1]]
        want = sorted(record or [])
        profiles, iters = {}, 0
        if want and want[0] <= 0.5 * dt:
            profiles[want.pop(0)] = u.copy()
        for k in range(1, steps + 1):
            u, it = self.step(u, theta, dt)
            iters = max(iters, it)
            mean.append(self.mean(u))
            surf.append(u[-1])
            while want and abs(want[0] - t[k]) <= 0.5 * dt:
                profiles[want.pop(0)] = u.copy()
        return dict(t=t, mean=np.array(mean), surface=np.array(surf), profiles=profiles, iters=iters)


def stop_time(t, v, frac=0.02):
    """First time v falls below frac of v[0] (linear interpolation); None if it never does."""
    v = np.asarray(v, float)
    below = np.nonzero(v < frac * v[0])[0]
    if below.size == 0:
        return None
    k = below[0]
    if k == 0:
        return float(t[0])
    level = frac * v[0]
    return float(t[k - 1] + (t[k] - t[k - 1]) * (v[k - 1] - level) / (v[k - 1] - v[k]))
