#!/usr/bin/python3
"""Chute profiles from in.chute-cg: the downhill velocity coarse-grained by compute griddem/cg
(averaged over x, y and the dumps from step 1000 on) against fix ave/chunk's layer averages, and
the coarse-grained stress against the weight of the material above each height (steady flow:
pzz(z) = g cos(26 deg) * integral of the density above z, and -pxz(z) the same with sin; the
stress is positive in compression as in compute pressure). Reads chute-cg.fields.*.txt and
chute-cg.bins.txt, writes chute-cg.png (the committed figure is reference/chute-cg.png) and prints
the largest differences below the free surface."""
import glob
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import chunks, grid  # noqa: E402

THETA = math.radians(26.0)


def grid_dump(path):
    """(step, zlo, zhi, per-z-plane means of each column) of one dump grid file's frame."""
    frame = grid.read_grid_dump(path)[0]
    nx, ny, nz = frame.n
    planes = []
    for k in range(nz):
        cells = slice(k * nx * ny, (k + 1) * nx * ny)
        planes.append([sum(values[cells]) / (nx * ny) for values in frame.columns.values()])
    return frame.step, frame.box[4], frame.box[5], planes


def bins():
    """Last block of chute-cg.bins.txt: (z, vx, mass density) per layer."""
    return [(r[1], r[3], r[4]) for r in chunks.last_block(os.path.join(HERE, "chute-cg.bins.txt"))]


dumps = sorted((grid_dump(p) for p in glob.glob(os.path.join(HERE, "chute-cg.fields.*.txt"))), key=lambda d: d[0])
dumps = [d for d in dumps if d[0] >= 1000]
nz = len(dumps[0][3])
zlo, zhi = dumps[-1][1], dumps[-1][2]
dz = (zhi - zlo) / nz
z = [zlo + (k + 0.5) * dz for k in range(nz)]
mean = [[sum(d[3][k][j] for d in dumps) / len(dumps) for j in range(4)] for k in range(nz)]
rho, vx, pzz, pxz = ([m[j] for m in mean] for j in range(4))
# weight of the material above each grid plane, from the coarse-grained density itself
above = [sum(rho[k + 1:]) * dz + 0.5 * rho[k] * dz for k in range(nz)]
weight_z = [a * math.cos(THETA) for a in above]
weight_x = [a * math.sin(THETA) for a in above]

layers = bins()
surface = max(r[0] for r in layers if r[2] > 0.3 * max(q[2] for q in layers))
inside = [k for k in range(nz) if 2.0 < z[k] < surface - 2.0]
scale = max(weight_z)
print("below the free surface (z in 2..%.1f): |pzz - weight| <= %.3g, |-pxz - weight| <= %.3g (of %.3g)"
      % (surface - 2.0, max(abs(pzz[k] - weight_z[k]) for k in inside),
         max(abs(-pxz[k] - weight_x[k]) for k in inside), scale))

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 4.5), sharey=True)
ax1.plot([r[1] for r in layers], [r[0] for r in layers], "o", ms=3, label="fix ave/chunk layers")
ax1.plot(vx, z, "-", label="griddem/cg, W = 1")
ax1.set_xlabel("downhill velocity vx")
ax1.set_ylabel("height z")
ax1.legend()
ax2.plot(pzz, z, "-", label="griddem/cg pzz")
ax2.plot(weight_z, z, "--", label="g cos26 x mass above")
ax2.plot([-p for p in pxz], z, "-", label="griddem/cg -pxz")
ax2.plot(weight_x, z, "--", label="g sin26 x mass above")
ax2.set_xlabel("stress")
ax2.legend()
fig.tight_layout()
fig.savefig(os.path.join(HERE, "chute-cg.png"), dpi=100)
