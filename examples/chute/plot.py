#!/usr/bin/python3
"""Downhill velocity and number density per layer of the chute flow, griddem against stock, from
the profile files (fix ave/chunk, averaged over the run) of the reference runs
(reference/profile.<tag>.txt) or of the runs given: writes chute.png (the committed figure is
reference/chute.png).
usage: plot.py [profile.griddem.txt profile.stock.txt]"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import chunks  # noqa: E402


def profile(path):
    """Last block of a fix ave/chunk file: (z, vx, density) per layer."""
    rows = [(r[1], r[3], r[4]) for r in chunks.last_block(path)]
    return [r for r in rows if r[2] > 0.0]


fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 4.5), sharey=True)
paths = sys.argv[1:3] or [os.path.join(HERE, "reference", "profile.%s.txt" % tag)
                          for tag in ("griddem", "stock")]
for path, tag, style in zip(paths, ("griddem", "stock"), ("-", "--")):
    rows = profile(path)
    z = [r[0] for r in rows]
    ax1.plot([r[1] for r in rows], z, style, label=tag)
    ax2.plot([r[2] for r in rows], z, style, label=tag)
ax1.set_xlabel("downhill velocity vx (lj units)")
ax1.set_ylabel("height z (layer of 1 diameter)")
ax2.set_xlabel("number density")
ax1.legend()
fig.suptitle("LAMMPS chute, 32,000 spheres, 26 degrees: profiles averaged over 5000 steps", fontsize=10)
fig.tight_layout()
fig.savefig(os.path.join(HERE, "chute.png"), dpi=100)
