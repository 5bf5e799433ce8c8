#!/usr/bin/python3
"""Side view of a one-sphere-thick slice through the middle of the settled bed, coloured by the
layer each sphere was poured with, griddem beside stock, from the runs' last dump snapshots:
writes packing.png (matplotlib, headless).
usage: plot.py dump.griddem dump.stock"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.collections import PatchCollection
from matplotlib.patches import Circle

HERE = os.path.dirname(os.path.abspath(__file__))


def last_snapshot(path):
    with open(path) as f:
        lines = f.read().splitlines()
    start = max(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    names = lines[start].split()[2:]
    return [dict(zip(names, map(float, line.split()))) for line in lines[start + 1:] if line.strip()]


fig, axes = plt.subplots(1, 2, figsize=(10, 5), sharey=True)
for ax, path, title in zip(axes, sys.argv[1:3], ["griddem/granular", "stock granular"]):
    atoms = [a for a in last_snapshot(path) if abs(a["y"] - 2.5) < 0.05]
    patches = [Circle((a["x"], a["z"]), a["radius"]) for a in atoms]
    coll = PatchCollection(patches, cmap="tab10")
    coll.set_array([(a["id"] - 1) // 14406 for a in atoms])
    coll.set_clim(0, 9)
    ax.add_collection(coll)
    ax.set_xlim(0, 5)
    ax.set_ylim(0, 2.6)
    ax.set_aspect("equal")
    ax.set_title("%s: slice 2.45 < y < 2.55 m" % title, fontsize=9)
    ax.set_xlabel("x (m)")
axes[0].set_ylabel("z (m)")
fig.suptitle("NN4DEM Case I: 72,029 spheres poured in five layers (colours), settled", fontsize=10)
fig.tight_layout()
fig.savefig(os.path.join(HERE, "packing.png"), dpi=90)
