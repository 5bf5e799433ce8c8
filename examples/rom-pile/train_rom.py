#!/usr/bin/python3
"""Ridge regression of the voxel velocity field on the voxel density field and the controls,
from resolved runs' coarse-grained fields (dump grid of compute griddem/cg density vx vy vz).

    train_rom.py [--form occupancy] [--components xz] OUT.model DUMP:CONTROLS [DUMP:CONTROLS ...]

CONTROLS: the run's control values, CONTROL[,CONTROL...] (constant), or @FILE for controls that
change during the run: FILE has rows "UNTIL_STEP CONTROL [CONTROL...]", in increasing
UNTIL_STEP; a frame at step s takes the first row with s <= UNTIL_STEP (the values in effect
during step s, when its fields were dumped).

Features per frame: the densities of all voxels and the controls, each standardised over the
training frames (a spread below 5% of the median spread counts as that: a voxel the training
runs almost never fill gets no huge weight); targets: vx, vy, vz of every voxel. Closed form: W = (X'X + lambda I)^-1 X'Y on
centred data. lambda is chosen by leave-one-run-out validation (mean squared velocity error
over the held-out run's frames) from a logarithmic grid, then the model is refitted on all runs
and written with the scaling folded in (plain weights on raw densities and controls).

--form occupancy: each voxel's velocity is its own density times a linear function of [1,
controls] (the model file's form occupancy); fitted voxel by voxel by least squares weighted by
the density, as the velocity error is: W_m = (A'DA + lambda s I)^-1 A'DY_m with A = density_m [1,
controls] over the frames, D their densities and s the scale of a voxel full of dense material
(the 95th percentile density) in every frame; lambda by leave-one-run-out validation of the
density-weighted error.

--components: the velocity components the model predicts (default xyz); the others' weights are
zero (a quasi-2D slice between walls: xz, so that no driven atom drifts into the walls with the
slice-averaged vy, which is noise)."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))  # griddemtools
from griddemtools.grid import read_grid_dump  # noqa: E402
from romtools import write_model  # noqa: E402


STD_FLOOR = 0.05    # of the median feature spread: the smallest spread a feature is scaled by


def control_values(controls, step):
    """The controls in effect at a step: constant (comma-separated) or from an @FILE schedule."""
    if not controls.startswith("@"):
        return [float(v) for v in controls.split(",")]
    with open(controls[1:]) as f:
        for line in f:
            w = line.split()
            if w and not w[0].startswith("#") and step <= int(w[0]):
                return [float(v) for v in w[1:]]
    raise SystemExit("%s: no control row for step %d" % (controls[1:], step))


def load(specs):
    runs, n, box = [], None, None
    for spec in specs:
        path, controls = spec.rsplit(":", 1)
        X, Y = [], []
        for frame in read_grid_dump(path):
            b, nn, cols = frame.box, frame.n, frame.columns
            c = control_values(controls, frame.step)
            if n is None:
                n, box = nn, b
            if nn != n or not np.allclose(b, box):
                raise SystemExit("%s: grid %s box %s differ from the first run's %s %s" % (path, nn, b, n, box))
            X.append(np.concatenate([cols["density"], c]))
            Y.append(np.stack([cols["vx"], cols["vy"], cols["vz"]], axis=1).ravel())
        runs.append((path, np.array(X), np.array(Y)))
    return runs, n, box


def fit(X, Y, lam):
    """Ridge on standardised features; returns (raw weights with bias column, scaling)."""
    xm, xs = X.mean(0), X.std(0)
    # a voxel that training runs almost never fill has a tiny spread; dividing by it would make
    # its raw weight huge, and a test run that fills it would get an absurd field (measured: 1e9)
    floor = STD_FLOOR * np.median(xs[xs > 0]) if np.any(xs > 0) else 1.0
    xs = np.maximum(xs, floor)
    ym = Y.mean(0)
    Z = (X - xm) / xs
    A = Z.T @ Z + lam * np.eye(Z.shape[1])
    B = np.linalg.solve(A, Z.T @ (Y - ym))      # [nfeat, nout]
    W = (B / xs[:, None]).T                      # raw weights [nout, nfeat]
    bias = ym - W @ xm
    return np.hstack([bias[:, None], W])


def predict(Wfull, X):
    return Wfull[:, 0][None, :] + X @ Wfull[:, 1:].T


def occupancy_fit(nvox):
    """fit(X, Y, lam), predict(W, X) and the validation's weights (the densities) of the occupancy
    form for features X = [densities of nvox voxels, controls] and targets Y = [vx, vy, vz of every
    voxel]."""
    def controls(X):
        return np.hstack([np.ones((len(X), 1)), X[:, nvox:]])

    def fit(X, Y, lam):
        # least squares weighted by the density, as the velocity error is: the dilute, fast
        # material (the feed stream) that DEM resolves counts little; one ridge scale for every
        # voxel, that of a voxel full of dense material in every frame, so a voxel the training
        # runs only saw dilute gets weights near zero, not of order velocity / density
        F = controls(X)
        dense = np.percentile(X[:, :nvox], 95)
        scale = len(X) * dense ** 3 * np.mean(np.sum(F ** 2, axis=1))
        W = np.zeros((Y.shape[1], F.shape[1]))
        for m in range(nvox):
            root = np.sqrt(X[:, m:m + 1])
            A = root * X[:, m:m + 1] * F
            W[3 * m:3 * m + 3] = np.linalg.solve(A.T @ A + lam * scale * np.eye(F.shape[1]),
                                                 A.T @ (root * Y[:, 3 * m:3 * m + 3])).T
        return W

    def densities(X):
        """each voxel's density under its three velocity components"""
        return np.repeat(X[:, :nvox], 3, axis=1)

    def predict_occupancy(W, X):
        return (controls(X) @ W.T) * densities(X)
    return fit, predict_occupancy, densities


def main():
    args = sys.argv[1:]
    options = dict(form="linear", components="xyz")
    while args[:1] in (["--form"], ["--components"]) and len(args) > 1:
        options[args[0][2:]], args = args[1], args[2:]
    form, components = options["form"], options["components"]
    if len(args) < 2 or form not in ("linear", "occupancy") or not components or set(components) - set("xyz"):
        raise SystemExit(__doc__)
    out, specs = args[0], args[1:]
    runs, n, box = load(specs)
    if form == "occupancy":
        W, note = fit_validated(runs, "velocity", *occupancy_fit(n[0] * n[1] * n[2]),
                                lams=10.0 ** np.arange(-6, 1.01, 0.5))
    else:
        W, note = fit_validated(runs, "velocity")
    model_weights = W[0].copy()
    for d, c in enumerate("xyz"):
        if c not in components:
            model_weights[d::3] = 0.0
    write_model(out, n, box, W[1], model_weights, "trained by train_rom.py (form %s, components %s) on %s\n%s"
                % (form, components, " ".join(specs), note), form=form)
    print(note)


def fit_validated(runs, what, fit=fit, predict=predict, weights=None, lams=10.0 ** np.arange(-3, 5.01, 0.5)):
    """Ridge fit of runs [(name, X, Y)] with lambda chosen by leave-one-run-out validation from the
    logarithmic grid lams (fit and predict: the model's form; weights(X): the weight of each
    squared error, default 1); returns ((weights, lambda), a note on the fit)."""
    def mean_square(P, Y, X):
        w = weights(X) if weights else np.ones_like(Y)
        return np.sum(w * (P - Y) ** 2) / np.sum(w)

    rms = "density-weighted rms" if weights else "rms"
    scores = []
    for lam in lams:
        err = []
        for k, (path, Xv, Yv) in enumerate(runs):
            Xt = np.vstack([r[1] for j, r in enumerate(runs) if j != k])
            Yt = np.vstack([r[2] for j, r in enumerate(runs) if j != k])
            err.append(mean_square(predict(fit(Xt, Yt, lam), Xv), Yv, Xv))
        scores.append(np.mean(err))
        print("lambda %-10.4g leave-one-run-out %s %s error %.5f" % (lam, rms, what, np.sqrt(scores[-1])))
    best = lams[int(np.argmin(scores))]
    X = np.vstack([r[1] for r in runs])
    Y = np.vstack([r[2] for r in runs])
    W = fit(X, Y, best)
    train_rms = np.sqrt(mean_square(predict(W, X), Y, X))
    zero_rms = np.sqrt(mean_square(0.0 * Y, Y, X))
    note = ("%s: %d frames; lambda %.4g by leave-one-run-out validation: %s %.5f; training %.5f; of the data %.5f"
            % (what, len(X), best, rms, np.sqrt(min(scores)), train_rms, zero_rms))
    return (W, best), note


if __name__ == "__main__":
    main()
