"""LAMMPS text dumps of atoms (dump custom, dump atom): each snapshot's step, box and per-atom rows."""

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
    """The snapshots of a dump file, in the file's order. Items other than TIMESTEP, NUMBER OF
    ATOMS, BOX BOUNDS and ATOMS (dump_modify time, units) are passed over."""
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
