"""LAMMPS dump grid files, text or binary (*.bin), written by one process (cells in order, x
fastest, then y, z): each frame's step, box, grid size and per-cell columns."""

from . import binary
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


def columns_by_short_name(path, names, rows):
    """{short name: the cells' values} of rows (a list of values per cell, in names' order)."""
    short = [short_name(c) for c in names]
    if len(set(short)) != len(short):
        raise ValueError("%s: columns %s share a short name" % (path, " ".join(names)))
    return {s: [r[j] for r in rows] for j, s in enumerate(short)}


def binary_frame(path, frame):
    """A GridFrame of a dump grid binary frame; a frame of several processes' bricks is an error
    (its cells are not in order)."""
    if frame.kind != b"DUMPGRID":
        raise ValueError("%s: step %d is a %s frame, not a grid" % (path, frame.step, frame.kind.decode()))
    if len(frame.chunks) != 1:
        raise ValueError("%s: step %d was written by %d processes (a brick each): cells not in order"
                         % (path, frame.step, len(frame.chunks)))
    cells, width = frame.n[0] * frame.n[1] * frame.n[2], len(frame.columns)
    values = frame.chunks[0]
    if len(values) != cells * width:
        raise ValueError("%s: the frame of step %d has not %d cells of %d values" % (path, frame.step, cells, width))
    rows = [values[k:k + width] for k in range(0, len(values), width)]
    return GridFrame(frame.step, frame.box, tuple(frame.n), frame.columns,
                     columns_by_short_name(path, frame.columns, rows))


def read_grid_dump(path):
    """The frames of a dump grid file, text or binary, in the file's order. Two columns whose names
    end alike (c_a:grid:vx, c_b:grid:vx) are an error: their short names would clash."""
    if binary.is_binary(path):
        return [binary_frame(path, f) for f in binary.read_frames(path)]
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
            cells = n[0] * n[1] * n[2]
            rows = [[float(v) for v in row.split()] for row in lines[:cells]]
            if len(rows) != cells or any(len(r) != len(names) for r in rows):
                raise ValueError("%s: the frame of step %s has not %d cells of %d values"
                                 % (path, step, cells, len(names)))
            frames.append(GridFrame(step, box, n, names, columns_by_short_name(path, names, rows)))
    return frames
