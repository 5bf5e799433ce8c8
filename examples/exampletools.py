"""Shared by the examples' checks and plots: read thermo columns from a LAMMPS log, and the
analytic references of the NN4DEM single-particle scenes."""
import math


def thermo(path_or_text, column):
    """Values of a thermo column in a log file (or log text), all runs concatenated."""
    text = path_or_text
    if "\n" not in path_or_text:
        with open(path_or_text) as f:
            text = f.read()
    values, header = [], None
    for line in text.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            header = words
        elif header and words[:1] == ["Loop"]:
            header = None
        elif header and len(words) == len(header):
            try:
                values.append(float(words[header.index(column)]))
            except ValueError:
                header = None
    return values


def apexes(heights, floor=0.01):
    """Local maxima of a height series above floor: the apex after each bounce."""
    return [heights[k] for k in range(1, len(heights) - 1)
            if heights[k] >= heights[k - 1] and heights[k] > heights[k + 1] and heights[k] > floor]


def bounce_apexes(drop, k, eta, m, count):
    """Apex heights of a sphere dropped from drop onto an infinitely heavy partner: linear spring k,
    absolute damping eta: each bounce keeps e^2 of the height, e = exp(-pi z / sqrt(1 - z^2)),
    z = eta / (2 sqrt(k m))."""
    z = eta / (2.0 * math.sqrt(k * m))
    e = math.exp(-math.pi * z / math.sqrt(1.0 - z * z))
    return [drop * e ** (2 * n) for n in range(1, count + 1)]


def slide_on_sphere(v0, mu, g, rc, dt=1e-6):
    """Distance along x a non-rotating sphere slides before it stops, starting at the top of a
    sphere of radius rc (centre distance) at speed v0 with Coulomb friction mu."""
    th, w = 0.0, v0 / rc
    while w > 0:
        normal = g * math.cos(th) - rc * w * w
        w += (g * math.sin(th) - mu * normal) / rc * dt
        th += w * dt
    return rc * math.sin(th)


def last_snapshot(path):
    """Atoms of the last snapshot of a dump custom file, as dicts by column name."""
    with open(path) as f:
        lines = f.read().splitlines()
    start = max(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    names = lines[start].split()[2:]
    return [dict(zip(names, map(float, line.split()))) for line in lines[start + 1:] if line.strip()]


def draw_slice(ax, atoms, y0, half_width, colour, cmap, clim=None):
    """Spheres whose centres lie within half_width of the plane y = y0, drawn as their x-z
    circles, coloured by colour(atom)."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    inside = [a for a in atoms if abs(a["y"] - y0) < half_width]
    coll = PatchCollection([Circle((a["x"], a["z"]), a["radius"]) for a in inside], cmap=cmap)
    coll.set_array([colour(a) for a in inside])
    if clim:
        coll.set_clim(*clim)
    ax.add_collection(coll)
    ax.set_aspect("equal")
    return coll
