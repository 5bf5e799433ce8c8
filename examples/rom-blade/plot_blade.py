#!/usr/bin/python3
"""Figure of the blade study (run where its files are):

    plot_blade.py RESOLVED_TAG ROM_TAG [NOISE_TAG] OUT.png

Top: snapshots at step 7,500 (mid-push; atoms.TAG.bin), resolved and reduced, the reduced one
coloured kinematic (blue) / dynamic (red), the blade grey. Middle: surface-height accuracy of each
frame against the resolved run (and of the resolved run with another seed: the noise floor); the
kinematic share and the share within reach of a dynamic atom. Bottom: the force on the blade
(x, z), resolved, reduced (measured on the blade) and the reduced run's model prediction."""
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))  # griddemtools
from griddemtools.blade import ATOMS, FIELDS, read_force, read_snapshots, read_table  # noqa: E402
from griddemtools.rom import accuracy_panel, kinematic_series, run_tags  # noqa: E402

STEP = 7500


def main():
    res_tag, rom_tag, noise_tag, out = run_tags(sys.argv[1:], __doc__)
    fig = plt.figure(figsize=(12, 11))
    for row, (tag, title) in enumerate(((res_tag, "resolved"), (rom_tag, "reduced"))):
        ax = fig.add_subplot(4, 1, 1 + row)
        a = dict(read_snapshots(ATOMS % tag))[STEP]
        d = (a["mass"] / (np.pi / 6.0)) ** (1.0 / 3.0)
        kin = a["v_kin"] > 0.5
        ax.scatter(a["x"], a["z"], s=(11 * 72 / 20.0 * d) ** 2, c=np.where(kin, "tab:blue", "tab:red"), linewidths=0)
        bx, bz = read_table("controls.%s.txt" % tag)[STEP][:2]
        ax.add_patch(Rectangle((bx - 0.2, bz), 0.2, 3.0, color="grey"))
        ax.set_xlim(0, 20)
        ax.set_ylim(0, 4.5)
        ax.set_aspect("equal")
        ax.set_title("%s, step %d: %d spheres%s" % (title, STEP, len(d),
                                                     ", %d kinematic (blue)" % kin.sum() if row else ""))
    accuracy_panel(fig.add_subplot(4, 2, 5), res_tag, rom_tag, noise_tag, 0.65, 0.6, "lower left", FIELDS)
    ax = fig.add_subplot(4, 2, 6)
    for column, label in (("v_nkin", "kinematic"), ("v_nnear", "kinematic within reach (move every step)")):
        steps, frac = kinematic_series("log.%s" % rom_tag, column)
        ax.plot(steps, frac, label=label)
    ax.set_xlabel("step")
    ax.set_ylabel("share of the spheres")
    ax.set_ylim(0, 1)
    ax.legend(loc="lower left")
    fr, fm = read_force(res_tag), read_force(rom_tag)
    fn = read_force(noise_tag) if noise_tag else None
    for k, axis in enumerate("xz"):
        ax = fig.add_subplot(4, 2, 7 + k)
        ax.plot(fr[:, 0], fr[:, 1 + k], label="resolved")
        if fn is not None:
            ax.plot(fn[:, 0], fn[:, 1 + k], ":", label="resolved, other seed")
        ax.plot(fm[:, 0], fm[:, 1 + k], label="reduced, measured")
        ax.plot(fm[:, 0], fm[:, 3 + k], "--", label="reduced, model's prediction")
        ax.set_xlabel("step")
        ax.set_ylabel("force on the blade, %s (mean over 100 steps)" % axis)
        ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    print("wrote", out)


if __name__ == "__main__":
    main()
