"""The items of a LAMMPS text dump (dump custom, dump atom, dump grid): each "ITEM: ..." header and
the lines under it, up to the next header."""


def read_items(path):
    """[(header, lines)] of a dump file in the file's order: header is the item's line after
    "ITEM:" (e.g. "ATOMS id x y z"), lines the lines under it."""
    with open(path) as f:
        lines = f.read().splitlines()
    items = []
    for line in lines:
        if line.startswith("ITEM:"):
            items.append((line[len("ITEM:"):].strip(), []))
        elif items:
            items[-1][1].append(line)
    return items
