#!/usr/bin/python3
"""mu(I) rheology learned from DEM: runs in.rve (build/lmp, one process, one thread) at inertial
numbers chosen adaptively where an ensemble of small NumPy MLPs disagrees, fits the
GDR MiDi / Jop form, regularises the learned curve at low I, and checks it against steady inclined
layers (in.incline) through the Bagnold profile. Writes results.json, rve_points.json, mu_I.png and
incline.png (those of the README's run are in reference/, which no call writes).

    /usr/bin/python3 learn_mu.py [--lmp PATH] [--tol 0.005] [--max-runs 6] [--uniform-levels 2]
                                 [--extra-I 0.003,0.001] [--recorded reference/rve_points.json]
                                 [--thetas 22,24,26]

The adaptive loop and the uniform comparison sample [--Ilo, --Ihi] (0.01..0.3); --extra-I adds RVEs
at the given (lower) I. All points enter the final ensemble (on [lowest I, Ihi]), the Jop fit and
the regularisation, whose cutoff I_c is then the lowest requested I.
(/usr/bin/python3: Debian's interpreter, which has NumPy, SciPy and matplotlib.) DEM results are
cached in work/ (one folder per run), so a second call only refits and redraws. --recorded FILE:
an RVE whose requested I is in FILE (a list of result dicts, e.g. rve_points.json, written by every
call; reference/rve_points.json holds the README's) is taken from there instead of being rerun when work/ has no cache of it. The inclined layers
are DEM runs (cached in work/ too); --thetas '' skips them, so that with --recorded nothing runs
DEM. A DEM run with no lmp at --lmp stops the script with a message that says so."""
import argparse
import hashlib
import json
import math
import os
import re
import resource
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import chunks, lammps, log  # noqa: E402

WORK = os.path.join(HERE, "work")
RESULT = re.compile(r"GRIDDEM rheology: result I (\S+) \+- (\S+) mu (\S+) \+- (\S+) phi (\S+) \+- (\S+)")
FAILED = "GRIDDEM rheology: pressure control failed"


# ---------------------------------------------------------------- DEM runs
def need_lmp(lmp, what):
    """stop, naming --lmp, when a DEM run is due and lmp is not an executable"""
    if not os.access(lmp, os.X_OK):
        raise SystemExit("%s: %s needs a DEM run and there is no lmp at %s: pass --lmp PATH (or set "
                         "GRIDDEM_LMP)" % (os.path.basename(sys.argv[0]), what, lmp))


def parse_rve(text):
    """The closing result line of in.rve: dict of I, dI, mu, dmu, phi, dphi; None if absent."""
    m = RESULT.search(text)
    if not m:
        return None
    v = [float(x) for x in m.groups()]
    return dict(I=v[0], dI=v[1], mu=v[2], dmu=v[3], phi=v[4], dphi=v[5])


STEADY = re.compile(r"GRIDDEM rheology: production blocks start after (\S+) strain")


def rve_log_info(text):
    """From in.rve's output or log: strain sheared before the production blocks (the steady-state
    test's exit), total strain sheared, window means of mu, and the summed LAMMPS loop times (s)."""
    wins = re.findall(r"GRIDDEM rheology: window \S+: strain (\S+) mu (\S+)", text)
    blocks = re.findall(r"GRIDDEM rheology: block \S+: mu", text)
    info = dict(loop_s=round(sum(run.seconds for run in log.loop_times(text)), 1),
                window_mu=[round(float(m), 4) for _, m in wins])
    m = STEADY.search(text)
    if m and wins:
        info["steady_strain"] = float(m.group(1))
        info["total_strain"] = round(float(m.group(1)) + float(wins[0][0]) * len(blocks), 3)
    return info


IN_RVE = os.path.join(HERE, "in.rve")
# in.rve's variables that act after the compression phase only: they do not enter the compressed state
SHEAR_ONLY = ("I", "gains", "gdotg", "emaxr", "wstrain", "tol", "ptol", "minwin", "maxwin", "nblock", "phimin", "tag")


def rve_settings(extra=()):
    """in.rve's index variables: its defaults, overridden by the -var NAME VALUE pairs of extra."""
    with open(IN_RVE) as f:
        settings = dict(re.findall(r"^variable\s+(\S+)\s+index\s+(\S+)", f.read(), re.M))
    extra = list(extra)
    for k, word in enumerate(extra[:-2]):
        if word == "-var":
            settings[extra[k + 1]] = extra[k + 2]
    return settings


def state_path(statedir, extra=()):
    """The compressed state (in.rve -var save) for the settings that shape it: its name lists them,
    and ends with a hash of in.rve's text, so different settings or an edited in.rve never share one."""
    settings = rve_settings(extra)
    with open(IN_RVE, "rb") as f:
        digest = hashlib.sha1(f.read()).hexdigest()[:10]
    words = ["%s%s" % (k, re.sub(r"[^A-Za-z0-9.+-]", "-", v)) for k, v in sorted(settings.items())
             if k not in SHEAR_ONLY]
    return os.path.join(statedir, "compressed_%s_%s.restart" % ("_".join(words), digest))


def prepare_state(lmp, statedir, extra=()):
    """The compressed state of these settings in statedir, written now (in.rve -var save
    -var compress_only) unless it exists: (its path, the CPU seconds that took, 0 when it existed).
    A caller that runs RVEs on the fly prepares it ahead, so the one compression is paid with the
    start set rather than by whichever RVE comes first."""
    state = state_path(statedir, extra)
    if os.path.exists(state):
        return state, 0.0
    need_lmp(lmp, "the compressed state of the RVEs")
    os.makedirs(statedir, exist_ok=True)
    written = "%s.%d.tmp" % (state, os.getpid())
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = lammps.run(lmp, ["-in", IN_RVE, "-var", "save", written, "-var", "compress_only", "1", "-log", "none",
                            "-echo", "none"] + list(extra), statedir)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0 or "compressed state written" not in proc.stdout or not os.path.exists(written):
        if os.path.exists(written):
            os.remove(written)
        raise RuntimeError("the compressed state (in.rve -var save) failed (exit %d):\n%s"
                           % (proc.returncode, proc.stdout[-2000:]))
    os.replace(written, state)
    return state, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def run_rve(lmp, I, extra=(), workdir=None, recorded=(), statedir=None):
    """One RVE at requested inertial number I (cached in work/rve_<I>/result.json; else taken from
    recorded, a list of earlier results, when one has the same requested I). The compressed state
    is shared: the first RVE of a parameter set writes it to statedir (default: the folder above
    workdir), the others start from it and skip the compression (result key "state": written or read)."""
    workdir = workdir or os.path.join(WORK, "rve_%.5g" % I)
    cache = os.path.join(workdir, "result.json")
    if os.path.exists(cache):
        with open(cache) as f:
            res = json.load(f)
        log = os.path.join(workdir, "log.lammps")
        if "steady_strain" not in res and os.path.exists(log):
            with open(log) as f:
                res.update(rve_log_info(f.read()))
        res.setdefault("source", "work/ cache")
        return res
    for r in recorded:
        if abs(math.log(r["Irequested"] / I)) < 1e-6:
            return dict(r, source="recorded")
    need_lmp(lmp, "the RVE at I=%g (neither in work/ nor recorded)" % I)
    os.makedirs(workdir, exist_ok=True)
    state = state_path(statedir or os.path.dirname(os.path.abspath(workdir)), extra)
    written = "%s.%d.tmp" % (state, os.getpid())       # renamed once the RVE has succeeded
    start = ["-var", "state", state] if os.path.exists(state) else ["-var", "save", written]
    t0 = time.time()
    proc = lammps.run(lmp, ["-in", IN_RVE, "-var", "I", "%.6g" % I, "-log", "log.lammps",
                            "-echo", "none"] + start + list(extra), workdir)
    res = parse_rve(proc.stdout)
    if (FAILED in proc.stdout or proc.returncode != 0 or res is None) and os.path.exists(written):
        os.remove(written)
    if FAILED in proc.stdout:
        raise RuntimeError("RVE at I=%g: %s" % (I, [l for l in proc.stdout.splitlines() if FAILED in l][0]))
    if proc.returncode != 0 or res is None:
        raise RuntimeError("RVE at I=%g failed (exit %d):\n%s" % (I, proc.returncode, proc.stdout[-2000:]))
    res["Irequested"] = I
    res["steady"] = "no steady state" not in proc.stdout
    res["state"] = "read" if start[1] == "state" else "written"
    if res["state"] == "written":
        os.replace(written, state)
    with open(os.path.join(workdir, "log.lammps")) as f:
        res.update(rve_log_info(f.read()))
    res["wall_s"] = round(time.time() - t0, 1)
    res["date"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t0))
    res["lmp"] = lmp
    with open(cache, "w") as f:
        json.dump(res, f)
    return res


# ---------------------------------------------------------------- ensemble of small MLPs
class MLP:
    """1 input (scaled log I) -> H tanh units -> 2 outputs (scaled mu, phi): one member of an
    Ensemble, trained with the others by train_members."""

    def __init__(self, hidden, seed):
        rng = np.random.default_rng(seed)
        self.W1 = rng.normal(0, 1.5, (1, hidden))
        self.b1 = rng.normal(0, 1.0, hidden)
        self.W2 = rng.normal(0, 1.0 / math.sqrt(hidden), (hidden, 2))
        self.b2 = np.zeros(2)
        self.rng = rng

    def forward(self, x):
        h = np.tanh(x[:, None] @ self.W1 + self.b1)
        return h, h @ self.W2 + self.b2


def train_members(nets, x, ys, w, iters=3000, lr=0.01, decay=1e-4):
    """Adam on each member's squared error weighted by w (loss = sum w r^2 / 2n), member k on its own
    targets ys[k]. The members are independent; they are trained as one stack of arrays (a leading
    member axis) because a refit during a coupled run waits for them, and small NumPy operations
    cost their call, not their size."""
    W1, b1, W2, b2 = (np.array([getattr(n, name) for n in nets]) for name in ("W1", "b1", "W2", "b2"))
    params = [W1, b1, W2, b2]
    m = [np.zeros_like(p) for p in params]
    v = [np.zeros_like(p) for p in params]
    beta1, beta2, eps = 0.9, 0.999, 1e-8
    xs = x[None, :, None]                                  # (1, n, 1)
    for t in range(1, iters + 1):
        h = np.tanh(xs * W1 + b1[:, None, :])              # (members, n, H)
        out = h @ W2 + b2[:, None, :]
        r = (out - ys) * w / len(x)                        # d(loss)/d(out)
        gW2 = h.transpose(0, 2, 1) @ r + decay * W2
        gb2 = r.sum(1)
        dh = (r @ W2.transpose(0, 2, 1)) * (1 - h * h)
        gW1 = (xs * dh).sum(1, keepdims=True) + decay * W1
        gb1 = dh.sum(1)
        for k, (p, g) in enumerate(zip(params, [gW1, gb1, gW2, gb2])):
            m[k] = beta1 * m[k] + (1 - beta1) * g
            v[k] = beta2 * v[k] + (1 - beta2) * g * g
            p -= lr * (m[k] / (1 - beta1 ** t)) / (np.sqrt(v[k] / (1 - beta2 ** t)) + eps)
    for k, n in enumerate(nets):
        n.W1, n.b1, n.W2, n.b2 = W1[k], b1[k], W2[k], b2[k]


class Ensemble:
    """members MLPs on x = log10 I scaled to [-1, 1] over [Ilo, Ihi]; mu and phi scaled by the data.
    Each member sees its own copy of the targets perturbed by their error bars, so the spread carries
    the data noise as well as the fit's; the weights are 1/(error^2 + floor^2)."""

    def __init__(self, Ilo, Ihi, members=8, hidden=6, seed=12345):
        self.a, self.b = math.log10(Ilo), math.log10(Ihi)
        self.members, self.hidden, self.seed = members, hidden, seed

    def x(self, I):
        return 2 * (np.log10(np.asarray(I, float)) - self.a) / (self.b - self.a) - 1

    def fit(self, points, floor=0.003):
        I = np.array([p["I"] for p in points])
        Y = np.array([[p["mu"], p["phi"]] for p in points])
        E = np.array([[p["dmu"], p["dphi"]] for p in points])
        self.mean, self.scale = Y.mean(0), np.maximum(Y.std(0), 0.02)
        w = 1.0 / ((E / self.scale) ** 2 + (floor / self.scale) ** 2)
        w = w / w.mean(0)
        self.nets = [MLP(self.hidden, self.seed + k) for k in range(self.members)]
        ys = np.array([(Y + E * n.rng.normal(size=Y.shape) - self.mean) / self.scale for n in self.nets])
        train_members(self.nets, self.x(I), ys, w)
        return self

    def predict(self, I, extrapolate=False):
        """(mean, std) over members, each of shape (len(I), 2): columns mu, phi. An I outside the
        sampled range [Ilo, Ihi] is an error unless extrapolate is asked for."""
        if not extrapolate:
            outside = [v for v in np.atleast_1d(np.asarray(I, float))
                       if not 10 ** self.a * (1 - 1e-9) <= v <= 10 ** self.b * (1 + 1e-9)]
            if outside:
                raise ValueError("I = %.4g is outside the sampled range [%.4g, %.4g]: the learned rheology is not "
                                 "extrapolated" % (outside[0], 10 ** self.a, 10 ** self.b))
        outs = np.array([n.forward(self.x(I))[1] * self.scale + self.mean for n in self.nets])
        return outs.mean(0), outs.std(0)


def adaptive(run, Ilo, Ihi, tol, max_runs, grid=60, **ens):
    """Start from Ilo, Ihi and their geometric middle; while the ensemble's std of mu anywhere on a
    log grid of [Ilo, Ihi] exceeds tol, run the RVE at the grid point of largest std.
    Returns (points, history of (runs, max std))."""
    Ig = np.logspace(math.log10(Ilo), math.log10(Ihi), grid)
    points = [run(I) for I in (Ilo, math.sqrt(Ilo * Ihi), Ihi)]
    history = []
    while True:
        e = Ensemble(Ilo, Ihi, **ens).fit(points)
        std = e.predict(Ig)[1][:, 0]
        history.append((len(points), float(std.max())))
        if std.max() <= tol or len(points) >= max_runs:
            return points, history, e
        # never the same I twice (a cached rerun adds no information): mask sampled grid points
        done = np.array([any(abs(math.log(x / p["Irequested"])) < 1e-6 for p in points) for x in Ig])
        if np.all(done):
            return points, history, e
        points.append(run(float(Ig[int(np.argmax(np.where(done, -1.0, std)))])))


def uniform(run, Ilo, Ihi, tol, max_level=3, grid=60, **ens):
    """Nested uniform log grids of 3, 5, 9, ... points until the max std of mu is below tol."""
    Ig = np.logspace(math.log10(Ilo), math.log10(Ihi), grid)
    history = []
    for level in range(1, max_level + 1):
        n = 2 ** level + 1
        points = [run(float(I)) for I in np.logspace(math.log10(Ilo), math.log10(Ihi), n)]
        e = Ensemble(Ilo, Ihi, **ens).fit(points)
        s = float(e.predict(Ig)[1][:, 0].max())
        history.append((n, s))
        if s <= tol:
            break
    return points, history, e


# ---------------------------------------------------------------- closed forms and regularisation
def mu_jop(I, mu_s, mu_2, I_0):
    """GDR MiDi / Jop et al. (2006): mu = mu_s + (mu_2 - mu_s) / (1 + I_0 / I)."""
    I = np.asarray(I, float)
    return mu_s + (mu_2 - mu_s) / (1.0 + I_0 / I)


def fit_jop(I, mu, dmu=None):
    """Weighted least squares of mu_jop (scipy curve_fit): ((mu_s, mu_2, I_0), their std errors)."""
    from scipy.optimize import curve_fit
    I, mu = np.asarray(I, float), np.asarray(mu, float)
    p0 = (mu.min(), mu.max() + 0.1, math.sqrt(I.min() * I.max()))
    p, cov = curve_fit(mu_jop, I, mu, p0=p0, sigma=dmu, absolute_sigma=dmu is not None,
                       bounds=([0, 0, 1e-6], [2, 5, 100]), maxfev=20000)
    return p, np.sqrt(np.diag(cov))


def isotonic(y, w=None):
    """Pool-adjacent-violators: the non-decreasing sequence closest to y in weighted least squares."""
    y = np.asarray(y, float)
    w = np.ones_like(y) if w is None else np.asarray(w, float)
    blocks = []                                            # [value, weight, count]
    for yi, wi in zip(y, w):
        blocks.append([yi, wi, 1])
        while len(blocks) > 1 and blocks[-2][0] > blocks[-1][0]:
            v2, w2, c2 = blocks.pop()
            v1, w1, c1 = blocks.pop()
            blocks.append([(v1 * w1 + v2 * w2) / (w1 + w2), w1 + w2, c1 + c2])
    return np.concatenate([[v] * c for v, w_, c in blocks])


def regularise(I_grid, mu_grid, I_c):
    """The regularised mu(I): above the cutoff I_c, the isotonic (non-decreasing) version of mu_grid
    (linear in log I between grid points); below I_c, Barker & Gray's (2017) well-posed low-I form
        mu(I) = sqrt(alpha / ln(A / I)),   alpha = mu_c^3 / (2 I_c mu'_c),  A = I_c exp(alpha / mu_c^2),
    which matches the value mu_c and slope mu'_c at I_c (C1), increases monotonically and tends to 0
    as I -> 0. mu'_c: slope of the isotonic curve over the first half decade above I_c, at least 1e-3
    of mu_c per unit ln I. Returns a function of I."""
    lg = np.log(np.asarray(I_grid, float))
    mono = isotonic(mu_grid)
    keep = lg >= math.log(I_c)
    lg, mono = lg[keep], mono[keep]
    mu_c = float(np.interp(math.log(I_c), lg, mono))
    span = lg <= math.log(I_c) + math.log(10 ** 0.5)
    slope_ln = max(np.polyfit(lg[span], mono[span], 1)[0] if span.sum() >= 2 else 0.0, 1e-3 * mu_c)
    dmu_c = slope_ln / I_c                                  # d mu / d I at I_c
    alpha = mu_c ** 3 / (2 * I_c * dmu_c)
    A = I_c * math.exp(alpha / mu_c ** 2)

    I_max = float(np.exp(lg[-1]))

    def mu(I, extrapolate=False):
        I = np.asarray(I, float)
        if not extrapolate and np.any(I > I_max * (1 + 1e-9)):
            raise ValueError("I = %.4g is above the sampled range (up to %.4g): the regularised mu(I) is not "
                             "extrapolated there" % (float(np.max(I)), I_max))
        with np.errstate(divide="ignore"):        # I = 0 (no shear): A / I = inf gives the limit mu = 0
            low = np.sqrt(alpha / np.log(A / np.minimum(I, I_c)))
        high = np.interp(np.log(np.maximum(I, I_c)), lg, mono)
        return np.where(I < I_c, low, high)
    mu.params = dict(I_c=I_c, mu_c=mu_c, dmu_c=dmu_c, alpha=alpha, A=A, I_max=I_max)
    return mu


def invert(mu, target, Ilo=1e-8, Ihi=None):
    """I with mu(I) = target for a non-decreasing mu (bisection in log I); None outside its range
    (up to a regularised curve's I_max, else Ihi or 10)."""
    if Ihi is None:
        Ihi = getattr(mu, "params", {}).get("I_max", 10.0)
    a, b = math.log(Ilo), math.log(Ihi)
    if not (float(mu(math.exp(a))) <= target <= float(mu(math.exp(b)))):
        return None
    for _ in range(100):
        c = 0.5 * (a + b)
        if float(mu(math.exp(c))) < target:
            a = c
        else:
            b = c
    return math.exp(0.5 * (a + b))


def bagnold(z, H, I, phi, theta, g=1.0, d=1.0):
    """Steady uniform layer of depth H on a slope theta: P = phi rho g cos(theta) (H - z), I constant,
    so u(z) = (2/3) (I / d) sqrt(phi g cos theta) (H^{3/2} - (H - z)^{3/2}) (no slip at z = 0)."""
    z = np.clip(np.asarray(z, float), 0, H)
    return 2.0 / 3.0 * I / d * math.sqrt(phi * g * math.cos(theta)) * (H ** 1.5 - (H - z) ** 1.5)


# ---------------------------------------------------------------- inclined layers
def run_incline(lmp, theta, steps, theta2=None, steps2=0):
    """in.incline at slope theta (degrees) for steps, then with steps2 at slope theta2 for steps2
    more (the decelerating layer), in work/incline_<theta>; cached: run only when an output this
    call reads is absent (profile and vcm files; with steps2 the decel file). Returns the folder."""
    workdir = os.path.join(WORK, "incline_%g" % theta)
    outputs = ["profile.%g.txt", "vcm.%g.txt"] + (["decel.%g.txt"] if steps2 else [])
    if not all(os.path.exists(os.path.join(workdir, name % theta)) for name in outputs):
        need_lmp(lmp, "the inclined layer at %g degrees (not in work/; --thetas '' skips the layers)" % theta)
        os.makedirs(workdir, exist_ok=True)
        args = ["-in", os.path.join(HERE, "in.incline"), "-var", "theta", "%g" % theta, "-var", "steps", str(steps),
                "-var", "tag", "%g" % theta, "-log", "log.lammps", "-echo", "none"]
        if steps2:
            args += ["-var", "theta2", "%g" % theta2, "-var", "steps2", str(steps2)]
        lammps.run(lmp, args, workdir, output=False, check=True)
    return workdir


def read_profile(path):
    """Last block of a fix ave/chunk file: arrays z, mass density, vx (layers with mass only)."""
    a = np.array([r[1:] for r in chunks.last_block(path) if r[2] > 0])
    return a[:, 0], a[:, 2], a[:, 3]


Z_BASE = 0.625    # flow starts at the base spheres' mean top: centre jitter U(0,0.25) mean 0.125 + radius 0.5


def compare_incline(z, rho, vx, theta_deg, mu_reg, phi_of_I, dz=0.5):
    """Bagnold prediction from the learned rheology against a DEM profile; no fitted parameter: I
    from mu_reg(I) = tan theta, phi = phi(I), H = DEM mass per area / (phi rho_p) above Z_BASE."""
    theta = math.radians(theta_deg)
    I = invert(mu_reg, math.tan(theta))
    if I is None:
        return None
    try:
        phi = float(phi_of_I(I))
    except ValueError as e:    # I below the sampled range (the regularised tail): no phi there
        print("theta %g: %s" % (theta_deg, e))
        return None
    H = float(rho[z > Z_BASE].sum() * dz / phi)
    inside = (z > Z_BASE + 0.5) & (z < Z_BASE + H - 1.0)
    u = bagnold(z - Z_BASE, H, I, phi, theta)
    usurf = float(vx[inside].max())
    err = float(np.sqrt(np.mean((vx[inside] - u[inside]) ** 2)) / usurf)
    slip = float(vx[inside][0] - u[inside][0])
    err_slip = float(np.sqrt(np.mean((vx[inside] - u[inside] - slip) ** 2)) / usurf)
    return dict(theta=theta_deg, I=I, phi=phi, H=H, rms_rel=err, rms_rel_slip=err_slip,
                u_surface_dem=usurf, u_surface_bagnold=float(u[inside].max()),
                z=z.tolist(), vx=vx.tolist(), u=u.tolist(), slip=slip)


# ---------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=lammps.default_lmp())
    ap.add_argument("--Ilo", type=float, default=0.01, help="lowest I run (1e-3 requested: see README)")
    ap.add_argument("--Ihi", type=float, default=0.3)
    ap.add_argument("--tol", type=float, default=0.005, help="max ensemble std of mu")
    ap.add_argument("--max-runs", type=int, default=6)
    ap.add_argument("--thetas", default="22,24,26")
    ap.add_argument("--incline-steps", type=int, default=300000)
    ap.add_argument("--no-uniform", action="store_true", help="skip the uniform-sampling comparison")
    ap.add_argument("--uniform-levels", type=int, default=2, help="nested uniform grids of 3, 5, 9.. points: how many")
    ap.add_argument("--extra-I", default="", help="comma list of further RVEs (e.g. 0.003,0.001 below Ilo)")
    ap.add_argument("--recorded", default="", help="JSON list of earlier RVE results to reuse (rve_points.json)")
    a = ap.parse_args()
    lmp = os.path.abspath(a.lmp)
    recorded = []
    if a.recorded:
        with open(a.recorded) as f:
            recorded = json.load(f)
    measured = {}                                          # requested I -> result, all distinct RVEs

    def run(I):
        r = run_rve(lmp, I, recorded=recorded)
        measured.setdefault("%.6g" % r["Irequested"], r)
        print("RVE I=%.4g: I %.4g +- %.2g  mu %.4f +- %.4f  phi %.4f +- %.4f  steady after %s strain (%s)" %
              (I, r["I"], r["dI"], r["mu"], r["dmu"], r["phi"], r["dphi"], r.get("steady_strain", "?"),
               r.get("source", "run")), flush=True)
        return r

    pts, hist, ens = adaptive(run, a.Ilo, a.Ihi, a.tol, a.max_runs)
    print("adaptive: runs and max std of mu:", hist)
    out = dict(adaptive=dict(runs=len(pts), history=hist, tol=a.tol, Ilo=a.Ilo, Ihi=a.Ihi))
    if not a.no_uniform:
        upts, uhist, _ = uniform(run, a.Ilo, a.Ihi, a.tol, max_level=a.uniform_levels)
        print("uniform: runs and max std of mu:", uhist)
        out["uniform"] = dict(runs=len(upts), history=uhist)
    extra = [float(x) for x in a.extra_I.split(",") if x.strip()]
    for x in extra:
        run(x)
    P = sorted(measured.values(), key=lambda p: p["I"])
    with open(os.path.join(HERE, "rve_points.json"), "w") as f:
        json.dump([{k: v for k, v in p.items() if k != "source"} for p in P], f, indent=1)
    I = np.array([p["I"] for p in P]); mu = np.array([p["mu"] for p in P]); dmu = np.array([p["dmu"] for p in P])
    pj, pe = fit_jop(I, mu, np.maximum(dmu, 1e-3))
    out["points"] = P
    out["jop_fit"] = dict(mu_s=pj[0], mu_2=pj[1], I_0=pj[2], err=pe.tolist())
    print("fit mu_s %.4f +- %.4f  mu_2 %.4f +- %.4f  I_0 %.4f +- %.4f" % (pj[0], pe[0], pj[1], pe[1], pj[2], pe[2]))
    # the final ensemble spans every measured point; the regularisation cutoff is the lowest one
    Ilo = min([a.Ilo] + extra)
    out["ensemble"] = dict(Ilo=Ilo, Ihi=a.Ihi)
    final = Ensemble(Ilo, a.Ihi).fit(P)
    Ig = np.logspace(math.log10(Ilo), math.log10(a.Ihi), 60)
    mean, std = final.predict(Ig)
    mu_reg = regularise(Ig, mean[:, 0], I_c=Ilo)
    out["regularised"] = mu_reg.params
    old = None
    if Ilo < a.Ilo:
        # the extrapolation the low-I points replace: the same procedure on the points >= a.Ilo only
        hi = [p for p in P if p["Irequested"] >= a.Ilo * (1 - 1e-6)]
        Ih = np.logspace(math.log10(a.Ilo), math.log10(a.Ihi), 60)
        old = regularise(Ih, Ensemble(a.Ilo, a.Ihi).fit(hi).predict(Ih)[0][:, 0], I_c=a.Ilo)
        out["extrapolation_check"] = dict(params=old.params, points=[
            dict(I=p["I"], mu=p["mu"], dmu=p["dmu"], mu_barker_gray=float(old(p["I"])),
                 diff_in_errors=(p["mu"] - float(old(p["I"]))) / p["dmu"])
            for p in P if p["Irequested"] < a.Ilo * (1 - 1e-6)])
        for c in out["extrapolation_check"]["points"]:
            print("I %.4g: measured mu %.4f +- %.4f, Barker-Gray extrapolation from I_c = %g: %.4f (%+.1f errors)"
                  % (c["I"], c["mu"], c["dmu"], a.Ilo, c["mu_barker_gray"], c["diff_in_errors"]))

    def phi_of_I(x):
        return final.predict([x])[0][0, 1]
    inc = []
    for t in [float(s) for s in a.thetas.split(",") if s.strip()]:
        z, rho, vx = read_profile(os.path.join(run_incline(lmp, t, a.incline_steps), "profile.%g.txt" % t))
        c = compare_incline(z, rho, vx, t, mu_reg, phi_of_I)
        if c is None:
            print("theta %g: tan theta outside the learned mu range: no steady Bagnold layer" % t)
            continue
        print("theta %g: I %.4f phi %.3f H %.2f  u_surface DEM %.3f Bagnold %.3f  rms error %.3f (%.3f after the slip offset)"
              % (t, c["I"], c["phi"], c["H"], c["u_surface_dem"], c["u_surface_bagnold"], c["rms_rel"], c["rms_rel_slip"]))
        inc.append(c)
    out["incline"] = inc
    with open(os.path.join(HERE, "results.json"), "w") as f:
        json.dump(out, f, indent=1)
    plot(out, Ig, mean, std, mu_reg, pj, old)


def plot(out, Ig, mean, std, mu_reg, pj, old=None):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    P = out["points"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4.2))
    a1.errorbar([p["I"] for p in P], [p["mu"] for p in P], xerr=[p["dI"] for p in P],
                yerr=[p["dmu"] for p in P], fmt="ko", ms=4, label="DEM RVE (block averages)")
    a1.plot(Ig, mean[:, 0], "b-", label="MLP ensemble mean")
    a1.fill_between(Ig, mean[:, 0] - 2 * std[:, 0], mean[:, 0] + 2 * std[:, 0], color="b", alpha=0.2, label="±2 std")
    Il = np.logspace(math.log10(min(1e-3, Ig[0] / 3)), math.log10(Ig[-1]), 100)
    a1.plot(Il, mu_reg(Il), "g--", label="regularised (Barker-Gray below I_c = %.3g)" % mu_reg.params["I_c"])
    if old is not None:
        Io = Il[Il <= old.params["I_c"]]
        a1.plot(Io, old(Io), color="0.5", ls="--", lw=1,
                label="earlier extrapolation from I_c = %.3g" % old.params["I_c"])
    a1.plot(Il, mu_jop(Il, *pj), "r:", label="fit mu_s=%.3f mu_2=%.3f I_0=%.3f" % tuple(pj))
    a1.plot(Il, mu_jop(Il, math.tan(math.radians(20.9)), math.tan(math.radians(32.76)), 0.279), "m-.",
            lw=1, label="Jop et al. 2006 (glass beads)")
    a1.set_xscale("log"); a1.set_xlabel("I"); a1.set_ylabel("mu"); a1.legend(fontsize=7)
    a2.errorbar([p["I"] for p in P], [p["phi"] for p in P], yerr=[p["dphi"] for p in P], fmt="ko", ms=4)
    a2.plot(Ig, mean[:, 1], "b-"); a2.set_xscale("log"); a2.set_xlabel("I"); a2.set_ylabel("solid fraction phi")
    fig.tight_layout(); fig.savefig(os.path.join(HERE, "mu_I.png"), dpi=80)
    if out["incline"]:
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        for c, col in zip(out["incline"], "bgrcm"):
            z = np.array(c["z"])
            ax.plot(c["vx"], z, col + "o", ms=3, label="DEM %g°" % c["theta"])
            ax.plot(c["u"], z, col + "-", label="Bagnold, rms %.2f" % c["rms_rel"])
        ax.set_xlabel("downhill velocity"); ax.set_ylabel("z"); ax.legend(fontsize=7)
        fig.tight_layout(); fig.savefig(os.path.join(HERE, "incline.png"), dpi=80)


if __name__ == "__main__":
    main()
