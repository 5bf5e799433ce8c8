#!/usr/bin/python3
"""Position and velocity of the sliding ball from the reference log, with the stopping distance
of the curved floor and of a flat one: writes sliding.png (matplotlib, headless; the committed
figure is reference/sliding.png)."""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import analytic, log  # noqa: E402

path = log.reference_log(HERE)
t = log.thermo(path, "Time")
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(t, log.thermo(path, "v_x"), label="x (m), griddem")
ax.plot(t, log.thermo(path, "v_v"), label="v (m/s), griddem")
ax.axhline(analytic.slide_on_sphere(1.414, 0.5, 9.81, 50.05), color="grey", lw=0.8,
           label="stop, floor of radius 50 m")
ax.axhline(1.414 ** 2 / (2 * 0.5 * 9.81), color="grey", ls=":", lw=0.8, label="stop, flat floor 0.2038 m")
ax.set_xlabel("time (s)")
ax.set_title("NN4DEM set I sliding, mu = 0.5, v0 = 1.414 m/s")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(HERE, "sliding.png"), dpi=100)
