#!/usr/bin/python3
"""Figures of a reduced against a resolved run (run where their files are):

    plot_rom.py RESOLVED_TAG ROM_TAG [NOISE_TAG] OUT.png

Top: the last snapshots (atoms.TAG.txt: id x z kinematic [diameter]), resolved and reduced, the reduced one coloured kinematic
(blue) / dynamic (red). Bottom left: surface-height accuracy of each frame against the resolved
run (and of a resolved run with another seed, NOISE_TAG: the chaotic noise floor). Bottom right:
the kinematic fraction after each classification (thermo of log.ROM_TAG)."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))  # griddemtools
from griddemtools import dump  # noqa: E402
from griddemtools.rom import accuracy_panel, kinematic_series, run_tags  # noqa: E402


def main():
    res_tag, rom_tag, noise_tag, out = run_tags(sys.argv[1:], __doc__)
    fig = plt.figure(figsize=(10, 8))
    for col, (tag, title) in enumerate(((res_tag, "resolved"), (rom_tag, "reduced"))):
        ax = fig.add_subplot(2, 2, 1 + col)
        snapshot = dump.last_snapshot("atoms.%s.txt" % tag)
        step, a = snapshot.step, np.array(snapshot.rows)
        colour = np.where(a[:, 3] > 0.5, "tab:blue", "tab:red")
        # a fifth column holds diameters: markers of about the spheres' size (a panel is ~4.5 in)
        size = (4.5 * 72 / np.ptp(a[:, 1]) * a[:, 4]) ** 2 if a.shape[1] > 4 else 6
        ax.scatter(a[:, 1], a[:, 2], s=size, c=colour, linewidths=0)
        nkin = int((a[:, 3] > 0.5).sum())
        ax.set_title("%s, step %d: %d atoms%s" % (title, step, len(a),
                                                   ", %d kinematic (blue)" % nkin if col else ""))
        ax.set_aspect("equal")
        ax.set_xlabel("x / d")
        ax.set_ylabel("z / d")
    accuracy_panel(fig.add_subplot(2, 2, 3), res_tag, rom_tag, noise_tag, 0.9, 0.5, "lower right")
    ax = fig.add_subplot(2, 2, 4)
    steps, frac = kinematic_series("log.%s" % rom_tag)
    ax.plot(steps, frac)
    ax.set_xlabel("step")
    ax.set_ylabel("kinematic fraction (after a classification)")
    ax.set_ylim(0, 1)
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    print("wrote", out)


if __name__ == "__main__":
    main()
