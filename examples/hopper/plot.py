#!/usr/bin/python3
"""Hopper discharge from the reference runs (their logs and reference/final.<tag>.dump): the mass
fraction left against time (griddem and stock), the steady discharge rate against Beverloo's law,
and the residual heap's angle of repose on both sides of the orifice. Writes hopper.png (the
committed figure is reference/hopper.png) and prints the numbers.
usage: plot.py [griddem|stock ...]"""
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import dump, log  # noqa: E402

RHO, D, ORIFICE, DEPTH, G = 1592.0, 0.006, 0.04, 0.04, 9.81


def beverloo_rate(phi=0.6, c=1.03, k=1.5):
    """Beverloo's law for a slot orifice (width b, length l across it): W = C rho_b sqrt(g)
    (b - k d)^(3/2) (l - k d); C ~ 1.03 for slots, k ~ 1.5, bulk density phi rho."""
    return c * phi * RHO * math.sqrt(G) * (ORIFICE - k * D) ** 1.5 * (DEPTH - k * D)


def discharge(tag):
    text = log.text_of(log.reference_log(HERE, tag, 2))
    mass0 = float(text.split("initial mass ")[-1].split()[0])
    left = log.thermo(text, "v_inhopper")
    t = log.thermo(text, "Time")[-len(left):]    # the discharge run's rows
    # steady rate: straight line through the part between 80% and 40% left
    pts = [(a, b) for a, b in zip(t, left) if 0.4 <= b <= 0.8]
    n = len(pts)
    mt = sum(p[0] for p in pts) / n
    mb = sum(p[1] for p in pts) / n
    slope = sum((p[0] - mt) * (p[1] - mb) for p in pts) / sum((p[0] - mt) ** 2 for p in pts)
    return t, left, -slope * mass0


def heap_angles(tag):
    """Angle of the heap left on each side of the reference run: top of the spheres per 5 mm
    column, fitted by a line from the wall to the orifice's edge."""
    atoms = dump.read_dump(os.path.join(HERE, "reference", "final.%s.dump" % tag))[0].atoms()
    top = {}
    for a in atoms:
        if a["z"] > 0:
            col = int(a["x"] / 0.005)
            top[col] = max(top.get(col, 0.0), a["z"] + a["radius"])
    angles = []
    for cols in (range(0, 16), range(24, 40)):    # x 0-0.08 and 0.12-0.2
        xs = [(c + 0.5) * 0.005 for c in cols if c in top]
        zs = [top[c] for c in cols if c in top]
        mx, mz = sum(xs) / len(xs), sum(zs) / len(zs)
        slope = sum((x - mx) * (z - mz) for x, z in zip(xs, zs)) / sum((x - mx) ** 2 for x in xs)
        angles.append(abs(math.degrees(math.atan(slope))))
    return angles, top


def main():
    tags = sys.argv[1:] or ["griddem", "stock"]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 4.2))
    for tag in tags:
        t, left, rate = discharge(tag)
        angles, top = heap_angles(tag)
        print("%s: discharge rate %.4f kg/s (Beverloo %.4f), mass left %.4f, heap angles %.1f and %.1f deg"
              % (tag, rate, beverloo_rate(), left[-1], angles[0], angles[1]))
        ax1.plot(t, left, label="%s: %.3f kg/s" % (tag, rate))
        cols = sorted(top)
        ax2.plot([(c + 0.5) * 0.005 for c in cols], [top[c] for c in cols], ".-",
                 label="%s: %.0f and %.0f deg" % (tag, angles[0], angles[1]))
    ax1.set_xlabel("time after opening (s)")
    ax1.set_ylabel("mass fraction left in the hopper")
    ax1.set_title("discharge; Beverloo (slot, C 1.03, k 1.5): %.3f kg/s" % beverloo_rate(), fontsize=9)
    ax1.legend(fontsize=8)
    ax2.set_xlabel("x (m)")
    ax2.set_ylabel("top of the residual heap (m)")
    ax2.set_title("residual heaps (paper: ~18 deg)", fontsize=9)
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "hopper.png"), dpi=100)


if __name__ == "__main__":
    main()
