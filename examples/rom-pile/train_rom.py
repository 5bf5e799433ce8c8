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
from griddemtools.rom import fit_validated, occupancy_fit, write_model  # noqa: E402


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


if __name__ == "__main__":
    main()
