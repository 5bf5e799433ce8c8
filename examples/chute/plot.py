#!/usr/bin/python3
"""Downhill velocity and number density per layer of the chute flow, griddem against stock, from
the runs' profile files (fix ave/chunk, averaged over the run): writes chute.png."""
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))


def profile(path):
    """Last block of a fix ave/chunk file: (z, vx, density) per layer."""
    with open(path) as f:
        lines = [line.split() for line in f if not line.startswith("#")]
    rows, k = [], 0
    while k < len(lines):
        count = int(lines[k][1])
        rows = [(float(r[1]), float(r[3]), float(r[4])) for r in lines[k + 1:k + 1 + count]]
        k += 1 + count
    return [r for r in rows if r[2] > 0.0]


fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 4.5), sharey=True)
for tag, style in (("griddem", "-"), ("stock", "--")):
    rows = profile(os.path.join(HERE, "profile.%s.txt" % tag))
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
