#!/usr/bin/python3
"""The reduced-order model of the blade (examples/rom-blade), in a grid that moves with the blade:
ridge regression of the voxel velocities and of the force on the blade on the voxel densities and
the blade's velocity, from resolved runs.

    train_blade.py [--blade block|plates] OUT.model TAG [TAG ...]

Reads, per run TAG, in.blade's outputs, each snapshot binned in the frame of in.blade's blade
(default block, the slice's; python/griddemtools/blade.py: the files, the frames and their
binning). Features: the densities and the controls (vbx, vbz); targets: the voxel velocities, and
separately the force (x, 0, z), each fitted by griddemtools.rom's ridge (train_rom.py's) with its
own lambda (leave-one-run-out). Writes a model of format version 2 with 'frame moving' (fix
griddem/rom ... origin v_bx 0 0) and the 'force' block."""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools.blade import FRAMES, load_run  # noqa: E402
from griddemtools.rom import fit_validated, write_model  # noqa: E402


def main():
    args = sys.argv[1:]
    blade = "block"
    if args[:1] == ["--blade"] and len(args) > 1:
        blade, args = args[1], args[2:]
    if len(args) < 2 or blade not in FRAMES:
        raise SystemExit(__doc__)
    out, tags = args[0], args[1:]
    frame = FRAMES[blade]
    data = [(tag,) + load_run(tag, frame) for tag in tags]
    (W, lam), note_v = fit_validated([(d[0], d[1], d[2]) for d in data], "velocity")
    (WF, _), note_f = fit_validated([(d[0], d[1], d[3]) for d in data], "force")
    note = "trained by train_blade.py on %s\n%s\n%s" % (" ".join(tags), note_v, note_f)
    write_model(out, frame[0], frame[1], lam, W, note, frame="moving", force=WF)
    print(note)


if __name__ == "__main__":
    main()
