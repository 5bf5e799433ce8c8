"""fix ave/chunk files: blocks of per-chunk rows, each after a line 'step nchunks total'."""


def read_ave_chunk(path):
    """[(step, rows)]: each block's step and its rows, each row all of the line's numbers as
    floats (the chunk's index first, then the file's columns: Coord1 ..., Ncount, the values)."""
    with open(path) as f:
        lines = [line.split() for line in f if not line.startswith("#") and line.strip()]
    blocks, k = [], 0
    while k < len(lines):
        step, count = int(lines[k][0]), int(lines[k][1])
        rows = [[float(v) for v in row] for row in lines[k + 1:k + 1 + count]]
        if len(rows) != count:
            raise ValueError("%s: the block of step %d has %d of its %d rows" % (path, step, len(rows), count))
        blocks.append((step, rows))
        k += 1 + count
    return blocks


def last_block(path):
    """The rows of the file's last block."""
    blocks = read_ave_chunk(path)
    if not blocks:
        raise ValueError("%s: no block" % path)
    return blocks[-1][1]
