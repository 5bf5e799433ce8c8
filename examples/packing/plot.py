#!/usr/bin/python3
"""Side view of a one-sphere-thick slice through the middle of the settled bed, coloured by the
layer each sphere was poured with, griddem beside stock, from the runs' last dump snapshots:
writes packing.png (matplotlib, headless; the committed figure is reference/packing.png).
usage: plot.py dump.packing.griddem dump.packing.stock"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import dump, plot  # noqa: E402


fig, axes = plt.subplots(1, 2, figsize=(10, 5), sharey=True)
for ax, path, title in zip(axes, sys.argv[1:3], ["griddem/granular", "stock granular"]):
    plot.draw_slice(ax, dump.last_snapshot(path).atoms(), 2.5, 0.05, lambda a: (a["id"] - 1) // 14406, "tab10", (0, 9))
    ax.set_xlim(0, 5)
    ax.set_ylim(0, 2.6)
    ax.set_title("%s: slice 2.45 < y < 2.55 m" % title, fontsize=9)
    ax.set_xlabel("x (m)")
axes[0].set_ylabel("z (m)")
fig.suptitle("NN4DEM Case I: 72,029 spheres poured in five layers (colours), settled", fontsize=10)
fig.tight_layout()
fig.savefig(os.path.join(HERE, "packing.png"), dpi=90)
