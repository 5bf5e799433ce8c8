"""Deposit measures shared by the DEM dumps and the continuum's VOF field, so that both follow one rule.

Thickness h(x): grain volume per unit area of base over the column's packing fraction phi0, i.e. the
height the grains would have at phi0, in columns of width 1 d, then averaged over 3 neighbouring
columns (a window of 3 d: the settled packing keeps columns of spheres 1.1 d apart from its lattice
fill, which a single 1 d column aliases by +-10 %). DEM: each sphere's volume split exactly between
the columns its slab crosses, over the depth W; continuum: sum of the VOF fraction c over the cells
of a column times the cell size.
Run-out / front: the farthest x where h >= 1 d, linear between column centres (the crossing of
h = 1 d after the last column with h >= 1 d). Final height: the largest h."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))  # griddemtools
from griddemtools import dump  # noqa: E402


def front(x, h, thick=1.0):
    """Farthest x where the thickness profile h (at column centres x) is >= thick, interpolated to the
    crossing with the next column; 0 if no column is that thick."""
    x, h = np.asarray(x, float), np.asarray(h, float)
    idx = np.nonzero(h >= thick)[0]
    if idx.size == 0:
        return 0.0
    k = idx[-1]
    if k + 1 >= len(h):
        return float(x[k])
    return float(x[k] + (x[k + 1] - x[k]) * (h[k] - thick) / (h[k] - h[k + 1]))


def read_dump(path):
    """LAMMPS dump custom (id x z radius): list of (timestep, array N x 3 of x, z, radius)."""
    frames = []
    for s in dump.read_dump(path):
        data = np.array(s.rows, float).reshape(s.natoms, len(s.columns))
        frames.append((s.step, data[:, [s.columns.index(c) for c in ("x", "z", "radius")]]))
    return frames


def smooth(h):
    """Mean over each column and its two neighbours (two at the ends)."""
    h = np.asarray(h, float)
    s = np.convolve(h, np.ones(3), mode="same")
    n = np.convolve(np.ones_like(h), np.ones(3), mode="same")
    return s / n


def dem_thickness(xzr, W, phi0, Lx, bin_width=1.0):
    """Column centres and thickness h(x) of a DEM frame (rows x, z, radius)."""
    edges = np.arange(0.0, Lx + bin_width, bin_width)
    nb = len(edges) - 1
    x, r = xzr[:, 0], xzr[:, 2]

    def below(t):          # sphere volume on the side x - x_centre < t
        t = np.clip(t, -r, r)
        return math.pi * (r * r * t - t ** 3 / 3.0 + 2.0 * r ** 3 / 3.0)
    vol = np.zeros(nb)
    first = np.floor((x - r) / bin_width).astype(int)
    for k in range(int(math.ceil(2 * r.max() / bin_width)) + 1):
        b = first + k
        ok = (b >= 0) & (b < nb)
        part = below(edges[np.clip(b + 1, 0, nb)] - x) - below(edges[np.clip(b, 0, nb)] - x)
        np.add.at(vol, b[ok], part[ok])
    return 0.5 * (edges[:-1] + edges[1:]), smooth(vol / (bin_width * W * phi0))


def settled_column(xzr, W, L0):
    """Packing fraction phi0 of the settled column (spheres with centres inside [1, L0 - 1] x
    [2, z_top - 2], z_top the 99th percentile of centre heights) and its height at phi0, H0 = total
    sphere volume / (L0 W phi0)."""
    x, z, r = xzr.T
    vol = 4.0 / 3.0 * math.pi * r ** 3
    ztop = float(np.percentile(z, 99))
    inside = (x > 1.0) & (x < L0 - 1.0) & (z > 2.0) & (z < ztop - 2.0)
    phi0 = float(vol[inside].sum() / ((L0 - 2.0) * W * (ztop - 4.0)))
    return phi0, float(vol.sum() / (L0 * W * phi0))
