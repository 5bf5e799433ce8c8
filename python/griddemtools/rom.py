"""Reduced-order DEM tooling (fix griddem/rom) shared by examples/rom-pile, rom-hopper and rom-blade
and by bench/rom.py: the model file (versions 1 to 3, doc/fix_griddem_rom.md), the ridge fits of a
model with lambda by leave-one-run-out validation, what a run is measured by (the fill height of
each voxel column, the kinematic share of the atoms in a log), and the examples' figures' accuracy
panel. Needs numpy."""
import numpy as np

from . import log
from .grid import read_grid_dump


def write_model(path, n, box, lam, weights, note="", frame=None, force=None, form="linear"):
    """weights: array [3 nvoxel, 1 + nvoxel + ncontrol] (row 3 m + d, columns bias, densities,
    controls), or with form "occupancy" [3 nvoxel, 1 + ncontrol] (columns bias, controls; the row's
    value times the voxel's density). frame: 'moving' for a box relative to fix griddem/rom's
    keyword origin; force: array [3, columns of weights], the force on a tool from the same
    features (form occupancy: bias and controls, no density). Either one makes the file format
    version 2, form occupancy version 3."""
    nvox = n[0] * n[1] * n[2]
    nrow, ncol = weights.shape
    assert nrow == 3 * nvox
    assert force is None or force.shape == (3, ncol)
    controls = ncol - 1 if form == "occupancy" else ncol - 1 - nvox
    version = 3 if form != "linear" else 1 if frame is None and force is None else 2
    with open(path, "w") as f:
        f.write("# griddem/rom model (fix griddem/rom, doc/fix_griddem_rom.md)\n")
        for line in note.splitlines():
            f.write("# " + line + "\n")
        f.write("griddem/rom %d\n" % version)
        f.write("grid %d %d %d\n" % tuple(n))
        f.write("box %s\n" % " ".join("%.17g" % b for b in box))
        if frame is not None:
            f.write("frame %s\n" % frame)
        f.write("controls %d\n" % controls)
        f.write("lambda %.6g\n" % lam)
        if form != "linear":
            f.write("form %s\n" % form)
        f.write("weights %d %d\n" % (nrow, ncol))
        for row in weights:
            f.write(" ".join("%.10g" % w for w in row) + "\n")
        if force is not None:
            f.write("force 3 %d\n" % ncol)
            for row in force:
                f.write(" ".join("%.10g" % w for w in row) + "\n")


def read_model(path):
    """The model file's grid n, box, frame (None or 'moving'), number of controls, lambda, form,
    weights and force (None without a force block), as write_model takes them."""
    with open(path) as f:
        lines = [line.split() for line in f if line.strip() and not line.startswith("#")]
    model = dict(frame=None, force=None, form="linear")
    k = 0
    while k < len(lines):
        key, rest = lines[k][0], lines[k][1:]
        if key in ("weights", "force"):
            nrow = int(rest[0])
            model[key] = np.array([[float(w) for w in row] for row in lines[k + 1:k + 1 + nrow]])
            k += 1 + nrow
            continue
        if key == "grid":
            model["n"] = tuple(int(v) for v in rest)
        elif key == "box":
            model["box"] = tuple(float(v) for v in rest)
        elif key in ("frame", "form"):
            model[key] = rest[0]
        elif key == "controls":
            model["controls"] = int(rest[0])
        elif key == "lambda":
            model["lambda"] = float(rest[0])
        k += 1
    return model


# of the median feature spread: the smallest spread a feature is scaled by
STD_FLOOR = 0.05


def fit(X, Y, lam):
    """Ridge of targets Y [frames, nout] on standardised features X [frames, nfeat] with lambda
    lam: the raw weights [nout, 1 + nfeat], the bias first."""
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
    """The targets of features X [frames, nfeat] under weights Wfull [nout, 1 + nfeat]."""
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


# the bulk density a fill height is measured in (the same for both runs compared, so an error does
# not depend on it)
RHO_BULK = 0.6


def heights(frame):
    """Per voxel column (x, y; x fastest) of a dump grid frame: the mass-equivalent fill height, the
    mass above z = 0 per unit area over RHO_BULK."""
    nx, ny, nz = frame.n
    box = frame.box
    hz = (box[5] - box[4]) / nz
    zc = box[4] + (np.arange(nz) + 0.5) * hz
    rho = np.asarray(frame.columns["density"]).reshape(nz, ny, nx)
    inside = zc > 0
    return (rho[inside].sum(axis=0) * hz).ravel() / RHO_BULK


def height_accuracy_series(res, rom):
    """(steps, accuracy of each frame): 1 - mean |h_rom - h_res| / mean h_res."""
    nf = min(len(res), len(rom))
    acc = []
    for k in range(nf):
        hr, hm = heights(res[k]), heights(rom[k])
        acc.append(1.0 - np.mean(np.abs(hm - hr)) / np.mean(hr))
    return np.array([res[k].step for k in range(nf)]), np.array(acc)


def kinematic_series(log_path, column="v_nkin"):
    """(steps, share of the atoms) at the thermo rows of a reduced run's log with atoms: column
    v_nkin the kinematic atoms, v_nnear those of them moving at DEM's step; empty for a run without
    them. The share is of the scene's atoms, column v_natoms (fix griddem/rom's f_rom[18]: LAMMPS's
    atoms and those its store holds) where the log has it, else of LAMMPS's atoms (Atoms)."""
    total = "v_natoms" if log.thermo_table(log_path, "Step", "v_natoms") else "Atoms"
    rows = [r for r in log.thermo_table(log_path, "Step", total, column) if r[1] > 0]
    return np.array([int(r[0]) for r in rows]), np.array([r[2] / r[1] for r in rows])


def kinematic_fraction(log_path):
    """Mean over the thermo rows of the kinematic share of the atoms, 0 for a resolved run."""
    frac = kinematic_series(log_path)[1]
    return float(np.mean(frac)) if frac.size else 0.0


def near_fraction(log_path):
    """Mean over the thermo rows of the share of the atoms that are kinematic and move at DEM's
    step (within reach of a dynamic atom)."""
    frac = kinematic_series(log_path, "v_nnear")[1]
    return float(np.mean(frac)) if frac.size else 0.0


def counters(log_path):
    """The fix's counters the examples print at the end of a reduced run (ROM-COUNTS name value ...)."""
    with open(log_path) as f:
        for line in f:
            if line.startswith("ROM-COUNTS"):
                w = line.split()[1:]
                return {w[k]: float(w[k + 1]) for k in range(0, len(w), 2)}
    return {}


def accuracy_panel(ax, res_tag, rom_tag, noise_tag, bar, bottom, legend_at, fields="cg.%s.txt"):
    """Draw on matplotlib axes ax the surface-height accuracy of each frame (the field dump FIELDS
    of a tag, in the working folder) of the reduced run against the resolved one, of a resolved run
    with another seed (NOISE_TAG, the noise floor; None: not drawn), and the goal's bar."""
    res = read_grid_dump(fields % res_tag)
    steps, acc = height_accuracy_series(res, read_grid_dump(fields % rom_tag))
    ax.plot(steps, acc, label="reduced vs resolved")
    if noise_tag:
        steps, acc = height_accuracy_series(res, read_grid_dump(fields % noise_tag))
        ax.plot(steps, acc, "--", label="resolved, other seed (noise floor)")
    ax.axhline(bar, color="grey", lw=0.5)
    ax.set_xlabel("step")
    ax.set_ylabel("surface-height accuracy")
    ax.set_ylim(bottom, 1.0)
    ax.legend(loc=legend_at)


def run_tags(args, usage):
    """A figure script's RESOLVED_TAG ROM_TAG [NOISE_TAG] OUT.png: (res, rom, noise or None, out)."""
    if len(args) not in (3, 4):
        raise SystemExit(usage)
    return args[0], args[1], args[2] if len(args) == 4 else None, args[-1]
