#!/usr/bin/python3
"""Height of the ball over time from the reference logs, with the analytic apex heights:
writes free-fall.png (matplotlib, headless; the committed figure is reference/free-fall.png)."""
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import analytic, log  # noqa: E402

m = 2700 * 4.0 / 3.0 * math.pi * 0.05 ** 3
fig, ax = plt.subplots(figsize=(7, 4))
for label, eta, style in [("undamped", 0.0, "-"), ("damped", 0.5, "-"), ("stock", 0.5, ":")]:
    path = log.reference_log(HERE, label)
    name = {"undamped": "griddem, eta = 0", "damped": "griddem, eta = 0.5",
            "stock": "stock granular, eta = 0.5"}[label]
    ax.plot(log.thermo(path, "Time"), log.thermo(path, "v_h"), style, label=name)
for h in analytic.bounce_apexes(0.95, 5e4, 0.5, m, 4):
    ax.axhline(h, color="grey", lw=0.5)
ax.set_xlabel("time (s)")
ax.set_ylabel("height above the floor (m)")
ax.set_title("NN4DEM set I free fall; grey: analytic apexes (eta = 0.5)")
ax.legend(loc="lower left")
fig.tight_layout()
fig.savefig(os.path.join(HERE, "free-fall.png"), dpi=100)
