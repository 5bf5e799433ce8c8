#!/usr/bin/python3
"""Side view of a one-sphere-thick slice through the middle of the poured bed, coloured by
speed, from the last snapshot of dump.pour (run in.pour first): writes pour.png
(the committed figure is reference/pour.png)."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import dump, plot  # noqa: E402

atoms = dump.last_snapshot(sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "dump.pour")).atoms()
fig, ax = plt.subplots(figsize=(4, 7))
coll = plot.draw_slice(ax, atoms, 5.0, 0.5, lambda a: a["z"], "viridis")
ax.set_xlim(0, 10)
ax.set_ylim(0, 18)
ax.set_xlabel("x")
ax.set_ylabel("z")
ax.set_title("pour: slice 4.5 < y < 5.5, by height", fontsize=9)
fig.tight_layout()
fig.savefig(os.path.join(HERE, "pour.png"), dpi=90)
