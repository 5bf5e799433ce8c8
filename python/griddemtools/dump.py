"""LAMMPS dumps of atoms (dump custom, dump atom as text; dump custom binary, *.bin): each
snapshot's step, box and per-atom rows."""

from . import binary
from .items import read_items


class Snapshot:
    """One snapshot: step, natoms, box (rows of the BOX BOUNDS item: [lo, hi] or [lo, hi, tilt]),
    columns (the names of the ATOMS item) and rows (per atom, floats in the columns' order, in the
    file's order)."""
    __slots__ = ("step", "natoms", "box", "columns", "rows")

    def __init__(self, step, natoms, box, columns, rows):
        self.step, self.natoms, self.box, self.columns, self.rows = step, natoms, box, columns, rows

    def column(self, name):
        """One column's values, atom by atom."""
        k = self.columns.index(name)
        return [row[k] for row in self.rows]

    def atoms(self):
        """The atoms as dicts by column name."""
        return [dict(zip(self.columns, row)) for row in self.rows]

    def by_id(self):
        """{id: the atom's other values, in the columns' order without id}."""
        k = self.columns.index("id")
        return {int(row[k]): row[:k] + row[k + 1:] for row in self.rows}


def read_dump(path):
    """The snapshots of a dump file, text or binary, in the file's order. Items other than TIMESTEP,
    NUMBER OF ATOMS, BOX BOUNDS and ATOMS (dump_modify time, units) are passed over."""
    if binary.is_binary(path):
        return [binary_snapshot(path, f) for f in binary.read_frames(path)]
    snapshots = []
    step = natoms = box = None
    for header, lines in read_items(path):
        if header.startswith("TIMESTEP"):
            step = int(lines[0])
        elif header.startswith("NUMBER OF ATOMS"):
            natoms = int(lines[0])
        elif header.startswith("BOX BOUNDS"):
            box = [[float(v) for v in row.split()] for row in lines[:3]]
        elif header.startswith("ATOMS"):
            columns = header.split()[1:]
            rows = [[float(v) for v in row.split()] for row in lines[:natoms]]
            if len(rows) != natoms or any(len(r) != len(columns) for r in rows):
                raise ValueError("%s: the snapshot of step %s has not %d rows of %d values"
                                 % (path, step, natoms, len(columns)))
            snapshots.append(Snapshot(step, natoms, box, columns, rows))
    return snapshots


def binary_snapshot(path, frame):
    """A Snapshot of a dump custom binary frame (the box as the text dump's rows: [lo, hi] or
    [lo, hi, tilt])."""
    if frame.kind != b"DUMPCUSTOM":
        raise ValueError("%s: step %d is a %s frame, not atoms" % (path, frame.step, frame.kind.decode()))
    width = len(frame.columns)
    values = [v for chunk in frame.chunks for v in chunk]
    if len(values) != frame.count * width:
        raise ValueError("%s: the snapshot of step %d has not %d rows of %d values" % (path, frame.step, frame.count, width))
    box = [frame.box[2 * d:2 * d + 2] + ([frame.tilt[d]] if frame.tilt else []) for d in range(3)]
    rows = [values[k:k + width] for k in range(0, len(values), width)]
    return Snapshot(frame.step, frame.count, box, frame.columns, rows)


def last_snapshot(path):
    """The last snapshot of a dump file."""
    snapshots = read_dump(path)
    if not snapshots:
        raise ValueError("%s: no snapshot" % path)
    return snapshots[-1]


def max_rel_diff(a, b, columns):
    """Largest |a - b| over the atoms of b and the given columns, relative to the largest |b| per
    column; a and b are (columns, {id: values}) (Snapshot.columns without id, Snapshot.by_id())."""
    worst = 0.0
    names_a, da = a
    names_b, db = b
    for col in columns:
        ia, ib = names_a.index(col), names_b.index(col)
        scale = max(abs(v[ib]) for v in db.values()) or 1.0
        for tag, vb in db.items():
            worst = max(worst, abs(da[tag][ia] - vb[ib]) / scale)
    return worst
