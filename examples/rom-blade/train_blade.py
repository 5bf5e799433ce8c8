#!/usr/bin/python3
"""The reduced-order model of the blade (examples/rom-blade), in a grid that moves with the blade:
ridge regression of the voxel velocities and of the force on the blade on the voxel densities and
the blade's controls, from resolved runs.

    train_blade.py [--blade block|plates] [--controls cut|velocity] [--form occupancy|linear]
                   OUT.model TAG [TAG ...]

Reads, per run TAG, in.blade's outputs, each snapshot binned in the frame of in.blade's blade
(default block, the slice's; python/griddemtools/blade.py: the files, the frames and their
binning). Features: the densities and the controls (in.blade's -var controls: default cut, the
blade's velocity times its depth below the bed's surface, and that depth; velocity: vbx, vbz).
Form occupancy (the default): each voxel's velocity its density times a linear function of the
controls, the force a linear function of the controls; linear: each voxel's velocity a linear
function of every density and the controls, the force of the same features. Each fitted by
griddemtools.rom's ridge (train_rom.py's) with its own lambda (leave-one-run-out). Writes a model
with 'frame moving' (fix griddem/rom ... origin v_bx 0 0) and the 'force' block."""
import argparse
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools.blade import CONTROLS, FRAMES, load_run  # noqa: E402
from griddemtools.rom import fit_validated, occupancy_fit, write_model  # noqa: E402


def main():
    ap = argparse.ArgumentParser(usage=__doc__)
    ap.add_argument("--blade", choices=sorted(FRAMES), default="block")
    ap.add_argument("--controls", choices=sorted(CONTROLS), default="cut")
    ap.add_argument("--form", choices=("linear", "occupancy"), default="occupancy")
    ap.add_argument("out")
    ap.add_argument("tags", nargs="+")
    a = ap.parse_args()
    frame = FRAMES[a.blade]
    nvox = frame[0][0] * frame[0][1] * frame[0][2]
    data = [(tag,) + load_run(tag, frame, CONTROLS[a.controls]) for tag in a.tags]
    velocity = [(d[0], d[1], d[2]) for d in data]
    if a.form == "occupancy":
        fit, predict, weights = occupancy_fit(nvox)
        (W, lam), note_v = fit_validated(velocity, "velocity", fit=fit, predict=predict, weights=weights)
        force = [(d[0], d[1][:, nvox:], d[3]) for d in data]    # the controls alone
    else:
        (W, lam), note_v = fit_validated(velocity, "velocity")
        force = [(d[0], d[1], d[3]) for d in data]
    (WF, _), note_f = fit_validated(force, "force")
    note = "trained by train_blade.py --controls %s --form %s on %s\n%s\n%s" % (
        a.controls, a.form, " ".join(a.tags), note_v, note_f)
    write_model(a.out, frame[0], frame[1], lam, W, note, frame="moving", force=WF, form=a.form)
    print(note)


if __name__ == "__main__":
    main()
