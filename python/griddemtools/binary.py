"""LAMMPS binary dumps (dump custom and dump grid to a file named *.bin; LAMMPS's format revision 2,
as tools/binary2txt reads it): each frame's header and its values, read without formatting them
as text, which costs a run more than its own steps when frames are frequent and the run is short."""
import struct
from array import array

KINDS = (b"DUMPCUSTOM", b"DUMPGRID")


def is_binary(path):
    """Whether path starts as a binary dump of this format: a negative length, then its magic string."""
    with open(path, "rb") as f:
        head = f.read(8 + max(len(k) for k in KINDS))
    if len(head) < 8:
        return False
    marker = struct.unpack("<q", head[:8])[0]
    return marker < 0 and head[8:8 - marker] in KINDS


class Frame:
    """One frame: kind (b"DUMPCUSTOM" or b"DUMPGRID"), step, count (atoms; 0 for a grid), box
    (xlo xhi ylo yhi zlo zhi), tilt (xy xz yz, or None), n (nx, ny, nz of a grid, else None),
    columns (the column names), chunks (one array of doubles per writing process, size_one values a
    row)."""
    __slots__ = ("kind", "step", "count", "box", "tilt", "n", "columns", "chunks")


def read_frames(path):
    """The frames of a binary dump file, in the file's order."""
    with open(path, "rb") as f:
        data = f.read()
    at = 0

    def take(fmt):
        nonlocal at
        values = struct.unpack_from("<" + fmt, data, at)
        at += struct.calcsize("<" + fmt)
        return values

    def text():
        (length,) = take("i")
        nonlocal at
        s = data[at:at + length].decode()
        at += length
        return s

    frames = []
    while at < len(data):
        (marker,) = take("q")
        if marker >= 0:
            raise ValueError("%s: at byte %d, a frame of the old binary format (no magic string)" % (path, at - 8))
        kind = data[at:at - marker]
        at -= marker
        if kind not in KINDS:
            raise ValueError("%s: at byte %d, unknown dump kind %r" % (path, at, kind))
        endian, revision = take("ii")
        if endian != 1 or revision != 2:
            raise ValueError("%s: endian %d, revision %d (this reader knows 1 and 2)" % (path, endian, revision))
        fr = Frame()
        fr.kind = kind
        fr.step, fr.count = take("qq")
        (triclinic,) = take("i")
        take("6i")    # boundary flags
        fr.box = list(take("6d"))
        fr.tilt = list(take("3d")) if triclinic else None
        fr.n = None
        if kind == b"DUMPGRID":
            take("i")    # dimension
            fr.n = take("3i")
            fr.count = 0
        (size_one,) = take("i")
        text()    # units (written in the first frame only, when asked for)
        (has_time,) = take("b")
        if has_time:
            take("d")
        fr.columns = text().split()
        if len(fr.columns) != size_one:
            raise ValueError("%s: step %d has %d column names for %d values a row" % (path, fr.step, len(fr.columns), size_one))
        (nchunk,) = take("i")
        fr.chunks = []
        for _ in range(nchunk):
            (nvalues,) = take("i")
            chunk = array("d")
            chunk.frombytes(data[at:at + 8 * nvalues])
            at += 8 * nvalues
            fr.chunks.append(chunk)
        frames.append(fr)
    return frames
