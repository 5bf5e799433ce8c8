"""Writing and reading the griddem/rom model file format (versions 1 to 3, doc/fix_griddem_rom.md)."""
import numpy as np


def write_model(path, n, box, lam, weights, note="", frame=None, force=None, form="linear"):
    """weights: array [3 nvoxel, 1 + nvoxel + ncontrol] (row 3 m + d, columns bias, densities,
    controls), or with form "occupancy" [3 nvoxel, 1 + ncontrol] (columns bias, controls; the row's
    value times the voxel's density). frame: 'moving' for a box relative to fix griddem/rom's
    keyword origin; force: array [3, 1 + nvoxel + ncontrol], the force on a tool from the same
    features. Either one makes the file format version 2, form occupancy version 3."""
    nvox = n[0] * n[1] * n[2]
    nrow, ncol = weights.shape
    assert nrow == 3 * nvox
    assert force is None or (form == "linear" and force.shape == (3, ncol))
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
