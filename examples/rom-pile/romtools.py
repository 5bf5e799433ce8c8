"""Reading LAMMPS `dump grid` text files (one process: cells in x-fastest order) and the
griddem/rom model file format (versions 1 and 2, doc/fix_griddem_rom.md)."""
import numpy as np


def read_grid_dump(path):
    """Frames of a dump grid text file: list of (step, box[6], n[3], {column: array[nvoxel]})."""
    frames = []
    with open(path) as f:
        lines = f.read().splitlines()
    k = 0
    while k < len(lines):
        if lines[k].startswith("ITEM: TIMESTEP"):
            step = int(lines[k + 1])
            k += 2
            continue
        if lines[k].startswith("ITEM: BOX BOUNDS"):
            box = [float(v) for line in lines[k + 1:k + 4] for v in line.split()[:2]]
            k += 4
            continue
        if lines[k].startswith("ITEM: GRID SIZE"):
            n = [int(v) for v in lines[k + 1].split()]
            k += 2
            continue
        if lines[k].startswith("ITEM: GRID CELLS"):
            cols = lines[k].split()[3:]
            m = n[0] * n[1] * n[2]
            data = np.array([[float(v) for v in line.split()] for line in lines[k + 1:k + 1 + m]])
            names = [c.split(":")[-1] for c in cols]
            frames.append((step, box, n, {name: data[:, j] for j, name in enumerate(names)}))
            k += 1 + m
            continue
        k += 1
    return frames


def write_model(path, n, box, lam, weights, note="", frame=None, force=None):
    """weights: array [3 nvoxel, 1 + nvoxel + ncontrol] (row 3 m + d, columns bias, densities,
    controls). frame: 'moving' for a box relative to fix griddem/rom's keyword origin; force:
    array [3, 1 + nvoxel + ncontrol], the force on a tool from the same features. Either one
    makes the file format version 2."""
    nvox = n[0] * n[1] * n[2]
    nrow, ncol = weights.shape
    assert nrow == 3 * nvox
    assert force is None or force.shape == (3, ncol)
    with open(path, "w") as f:
        f.write("# griddem/rom model (fix griddem/rom, doc/fix_griddem_rom.md)\n")
        for line in note.splitlines():
            f.write("# " + line + "\n")
        f.write("griddem/rom %d\n" % (1 if frame is None and force is None else 2))
        f.write("grid %d %d %d\n" % tuple(n))
        f.write("box %s\n" % " ".join("%.17g" % b for b in box))
        if frame is not None:
            f.write("frame %s\n" % frame)
        f.write("controls %d\n" % (ncol - 1 - nvox))
        f.write("lambda %.6g\n" % lam)
        f.write("weights %d %d\n" % (nrow, ncol))
        for row in weights:
            f.write(" ".join("%.10g" % w for w in row) + "\n")
        if force is not None:
            f.write("force 3 %d\n" % ncol)
            for row in force:
                f.write(" ".join("%.10g" % w for w in row) + "\n")
