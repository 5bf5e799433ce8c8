"""LAMMPS dump grid text files written by one process (cells in order, x fastest, then y, z):
each frame's step, box, grid size and per-cell columns."""

from .items import read_items


class GridFrame:
    """One frame: step, box (xlo xhi ylo yhi zlo zhi), n (nx, ny, nz), names (the GRID CELLS
    item's column names, e.g. c_cg:grid:density) and columns ({name after its last ':': the cells'
    values}, in the names' order)."""
    __slots__ = ("step", "box", "n", "names", "columns")

    def __init__(self, step, box, n, names, columns):
        self.step, self.box, self.n, self.names, self.columns = step, box, n, names, columns


def short_name(name):
    """c_cg:grid:density -> density; f_avg:grid:data[1] -> data[1]."""
    return name.split(":")[-1]


def read_grid_dump(path):
    """The frames of a dump grid text file, in the file's order. Two columns whose names end alike
    (c_a:grid:vx, c_b:grid:vx) are an error: their short names would clash."""
    frames = []
    step = box = n = None
    for header, lines in read_items(path):
        if header.startswith("TIMESTEP"):
            step = int(lines[0])
        elif header.startswith("BOX BOUNDS"):
            box = [float(v) for row in lines[:3] for v in row.split()[:2]]
        elif header.startswith("GRID SIZE"):
            n = tuple(int(v) for v in lines[0].split())
        elif header.startswith("GRID CELLS"):
            names = header.split()[2:]
            short = [short_name(c) for c in names]
            if len(set(short)) != len(short):
                raise ValueError("%s: columns %s share a short name" % (path, " ".join(names)))
            cells = n[0] * n[1] * n[2]
            rows = [[float(v) for v in row.split()] for row in lines[:cells]]
            if len(rows) != cells or any(len(r) != len(names) for r in rows):
                raise ValueError("%s: the frame of step %s has not %d cells of %d values"
                                 % (path, step, cells, len(names)))
            columns = {s: [r[j] for r in rows] for j, s in enumerate(short)}
            frames.append(GridFrame(step, box, n, names, columns))
    return frames
