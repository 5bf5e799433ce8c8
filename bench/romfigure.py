#!/usr/bin/python3
"""The errors of a reduced-order study over time, as the method's paper draws them: one panel per
error (velocity, surface height, granular temperature where the dumps have it), the reduced run
against the griddem resolved run of its seed, the do-nothing run against the same, and the noise
floor (each pair of stock resolved runs with different seeds) as grey lines. Reads the series that
bench/rom.py writes into a study's work folder (errors.TAG.vs.REF.txt).

usage: bench/romfigure.py WORK_FOLDER OUT.png [--title TEXT]"""
import argparse
import glob
import os
import textwrap

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

NAMES = {"velocity": "velocity error", "height": "surface-height error", "temperature": "granular-temperature error"}


def read_series(path):
    """{column name: values} of one errors file (its header names the columns after 'step')."""
    with open(path) as f:
        header = f.readline().split()
    names = header[1:header.index("errors")]
    data = np.loadtxt(path, ndmin=2)
    return dict(zip(names, data.T))


def draw(work, out, title=""):
    """The figure of the study in folder work, written to out; returns the curves drawn."""
    def series(tag, ref):
        path = os.path.join(work, "errors.%s.vs.%s.txt" % (tag, ref))
        return read_series(path) if os.path.exists(path) else None

    refs = sorted(glob.glob(os.path.join(work, "errors.test.rom.r0.vs.*.txt")))
    if not refs:
        raise SystemExit("%s: no errors.test.rom.r0.vs.*.txt (run bench/rom.py first)" % work)
    ref = os.path.basename(refs[0])[len("errors.test.rom.r0.vs."):-len(".txt")]
    curves = [("reduced", series("test.rom.r0", ref), dict(color="C0", lw=1.6)),
              ("do-nothing", series("test.donothing", ref), dict(color="C3", lw=1.2, ls="--"))]
    floor = sorted(glob.glob(os.path.join(work, "errors.test.stock.seed*.vs.test.stock.seed*.txt")))
    curves += [("noise floor (stock seeds)" if k == 0 else None, read_series(p), dict(color="0.6", lw=0.8))
               for k, p in enumerate(floor)]
    panels = [n for n in NAMES if curves[0][1] is not None and n in curves[0][1]]
    fig, axes = plt.subplots(len(panels), 1, figsize=(6.4, 2.2 * len(panels)), sharex=True, squeeze=False)
    for ax, name in zip(axes[:, 0], panels):
        for label, s, style in curves:
            if s is not None and name in s:
                ax.plot(s["step"], s[name], label=label, **style)
        ax.set_ylabel(NAMES[name])
        ax.set_ylim(bottom=0.0)
    axes[0, 0].legend(fontsize=8)
    axes[-1, 0].set_xlabel("step")
    if title:
        axes[0, 0].set_title(textwrap.fill(title, 80), fontsize=9)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return [c[0] for c in curves if c[1] is not None]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("work")
    ap.add_argument("out")
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    draw(a.work, a.out, a.title)


if __name__ == "__main__":
    main()
