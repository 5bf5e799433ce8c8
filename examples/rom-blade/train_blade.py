#!/usr/bin/python3
"""The reduced-order model of the blade (examples/rom-blade), in a grid that moves with the blade:
ridge regression of the voxel velocities and of the force on the blade on the voxel densities and
the blade's velocity, from resolved runs.

    train_blade.py OUT.model TAG [TAG ...]

Reads, per run TAG (in.blade's outputs): atoms.TAG.txt (snapshots: id x z vx vz mass ...),
controls.TAG.txt (step, the blade's front face bx and bottom bz, its velocity vbx vbz) and
force.TAG.txt (the force on the blade, means over the 100 steps up to each step). Each snapshot
is binned in the blade's frame, x relative to bx: FRAME_N voxels over FRAME_BOX, by the
cloud-in-cell weights and boundary rule of fix griddem/rom (griddem_rom_weights: weights beyond a
non-periodic boundary go to the boundary voxel; atoms outside the box are left out), density =
mass / voxel volume, velocity = momentum / mass (0 in an empty voxel). Features: the densities and
the controls (vbx, vbz); targets: the voxel velocities, and separately the force (x, 0, z), each
fitted by griddemtools.rom's ridge (train_rom.py's) with its own lambda (leave-one-run-out). Writes a model of format
version 2 with 'frame moving' (fix griddem/rom ... origin v_bx 0 0) and the 'force' block."""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))  # griddemtools
from griddemtools import dump  # noqa: E402
from griddemtools.rom import fit_validated, write_model  # noqa: E402

# the frame: x from 6 behind the blade's front face to 18 ahead of it (the whole bed for every
# blade position of the study), the slice's depth (y periodic, one voxel), z from the floor to 4
FRAME_N = (48, 1, 8)
FRAME_BOX = (-6.0, 18.0, 0.0, 1.0, 0.0, 4.0)


def read_snapshots(path):
    """[(step, {column: array over the atoms})] of a LAMMPS text dump."""
    frames = []
    for s in dump.read_dump(path):
        data = np.array(s.rows, dtype=float).reshape(s.natoms, len(s.columns))
        frames.append((s.step, {c: data[:, k] for k, c in enumerate(s.columns)}))
    return frames


def read_table(path):
    """{step: row of numbers} of a file of rows 'step value ...' ('#' comments)."""
    rows = {}
    with open(path) as f:
        for line in f:
            w = line.split()
            if w and not w[0].startswith("#"):
                rows[int(w[0])] = [float(v) for v in w[1:]]
    return rows


def cic_axis(x, lo, hi, n, periodic):
    """Indices (2 per point) and weights of cloud-in-cell along one axis (griddem_cg_cic)."""
    h = (hi - lo) / n
    u = (x - lo) / h - 0.5
    below = np.floor(u)
    f = u - below
    idx = np.stack([below, below + 1], axis=1).astype(int)
    idx = idx % n if periodic else np.clip(idx, 0, n - 1)
    return idx, np.stack([1.0 - f, f], axis=1)


def bin_frame(x, z, vx, vz, mass, n=FRAME_N, box=FRAME_BOX):
    """Density, vx, vy (0), vz on the frame's voxels (x relative to the blade's front face; one
    voxel along the periodic y)."""
    nx, ny, nz = n
    assert ny == 1
    xlo, xhi, _, _, zlo, zhi = box
    inside = (x >= xlo) & (x < xhi) & (z >= zlo) & (z < zhi)
    x, z, vx, vz, mass = x[inside], z[inside], vx[inside], vz[inside], mass[inside]
    ix, wx = cic_axis(x, xlo, xhi, nx, False)
    iz, wz = cic_axis(z, zlo, zhi, nz, False)
    vol = np.prod([(box[2 * d + 1] - box[2 * d]) / n[d] for d in range(3)])
    m, px, pz = (np.zeros(nx * ny * nz) for _ in range(3))
    for a in range(2):
        for c in range(2):
            voxel = ix[:, a] + nx * iz[:, c]
            w = wx[:, a] * wz[:, c] * mass
            np.add.at(m, voxel, w)
            np.add.at(px, voxel, w * vx)
            np.add.at(pz, voxel, w * vz)
    safe = np.where(m > 0, m, 1.0)
    return m / vol, np.where(m > 0, px / safe, 0.0), np.zeros_like(m), np.where(m > 0, pz / safe, 0.0)


def load_run(tag):
    """Features, velocity targets and force targets of one resolved run's snapshots."""
    controls, force = read_table("controls.%s.txt" % tag), read_table("force.%s.txt" % tag)
    X, Y, F = [], [], []
    for step, a in read_snapshots("atoms.%s.txt" % tag):
        if step not in controls or step not in force:
            continue
        bx, _, vbx, vbz = controls[step]
        rho, ux, uy, uz = bin_frame(a["x"] - bx, a["z"], a["vx"], a["vz"], a["mass"])
        X.append(np.concatenate([rho, [vbx, vbz]]))
        Y.append(np.stack([ux, uy, uz], axis=1).ravel())
        F.append([force[step][0], 0.0, force[step][1]])
    return np.array(X), np.array(Y), np.array(F)


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    out, tags = sys.argv[1], sys.argv[2:]
    data = [(tag,) + load_run(tag) for tag in tags]
    (W, lam), note_v = fit_validated([(d[0], d[1], d[2]) for d in data], "velocity")
    (WF, _), note_f = fit_validated([(d[0], d[1], d[3]) for d in data], "force")
    note = "trained by train_blade.py on %s\n%s\n%s" % (" ".join(tags), note_v, note_f)
    write_model(out, FRAME_N, FRAME_BOX, lam, W, note, frame="moving", force=WF)
    print(note)


if __name__ == "__main__":
    main()
