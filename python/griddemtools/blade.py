"""The blade of examples/rom-blade, measured: each snapshot binned in the blade's frame (the features
and targets its model is trained on: train_blade.py), and the force on the blade.

Run TAG's files (in.blade's outputs, ATOMS and FIELDS named by TAG): atoms.TAG.bin (binary
snapshots: id x y z vx vy vz mass ...), cg.TAG.bin (the voxel fields),
controls.TAG.txt (step, the blade's front face bx and bottom bz, then the controls of both sets
of CONTROLS, each column named in the title line: velocity vbx vbz, cut cutx cutz depth) and
force.TAG.txt (fix ave/time's file: every 100 steps, the means over those steps of the contact
forces of the blade's walls on the spheres, x and z of each wall (c_onspheres[1], [2], then the
second plate's [3], [4]), and of the force the reduced run's model predicts (fix griddem/rom's
f_rom[14], f_rom[16]; absent in a resolved run); read_force makes the blade's force of them: minus
the walls' sum).

A snapshot is binned in the blade's frame (FRAMES, by in.blade's blade), x relative to bx, y
periodic over the frame's (the box's) width, by the cloud-in-cell weights and boundary rule of fix
griddem/rom (griddem_rom_weights: weights beyond a non-periodic boundary go to the boundary voxel,
along the periodic y they wrap; atoms outside the box are left out), density = mass / voxel
volume, velocity = momentum / mass (0 in an empty voxel; vy 0 in a slice one voxel deep): written
out here, apart from the fix's C code, which unittest/lammps/test_rom.py checks against it.
Force accuracy = 1 - time-mean |F - F_resolved| / time-mean |F_resolved| (|.|: the norm of (Fx, Fz),
means over all rows of the run)."""
import numpy as np

from . import dump

# the frames (voxels, box), x relative to the blade's cutting edge, by in.blade's blade. block (the
# slice): x from 6 behind to 18 ahead (the whole bed for every blade position of the study), the
# slice's depth (y periodic, one voxel), z from the floor to 4. plates (the method's paper's 3D
# blade): the grid around the blade that the paper's model drives, x from 1.5 behind to 3.5 ahead
# (the heap it pushes), the bed's whole width (periodic, 8 voxels of 0.4), z from the floor to 2.5
FRAMES = {"block": ((48, 1, 8), (-6.0, 18.0, 0.0, 1.0, 0.0, 4.0)),
          "plates": ((10, 8, 5), (-1.5, 3.5, 0.0, 3.2, 0.0, 2.5))}

# in.blade's dumps of run TAG (binary; the readers take text too)
ATOMS, FIELDS = "atoms.%s.bin", "cg.%s.bin"

# the model's controls by in.blade's -var controls, as controls.TAG.txt names them: the blade's
# velocity, or its cut (velocity times the depth below the bed's surface, and that depth)
CONTROLS = {"velocity": ("vbx", "vbz"), "cut": ("cutx", "cutz", "depth")}


def read_snapshots(path):
    """[(step, {column: array over the atoms})] of a LAMMPS dump (text or binary)."""
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


def bin_frame(x, y, z, vx, vy, vz, mass, n, box):
    """Density, vx, vy, vz on the frame's voxels n over box (x relative to the blade's cutting edge,
    y periodic over the box's width; vy 0 where the frame is one voxel deep)."""
    nx, ny, nz = n
    xlo, xhi, ylo, yhi, zlo, zhi = box
    inside = (x >= xlo) & (x < xhi) & (z >= zlo) & (z < zhi)
    x, y, z, vx, vy, vz, mass = (a[inside] for a in (x, y, z, vx, vy, vz, mass))
    ix, wx = cic_axis(x, xlo, xhi, nx, False)
    iy, wy = cic_axis(y, ylo, yhi, ny, True)
    iz, wz = cic_axis(z, zlo, zhi, nz, False)
    vol = np.prod([(box[2 * d + 1] - box[2 * d]) / n[d] for d in range(3)])
    m, px, py, pz = (np.zeros(nx * ny * nz) for _ in range(4))
    for a in range(2):
        for b in range(2):
            for c in range(2):
                voxel = ix[:, a] + nx * (iy[:, b] + ny * iz[:, c])
                w = wx[:, a] * wy[:, b] * wz[:, c] * mass
                np.add.at(m, voxel, w)
                np.add.at(px, voxel, w * vx)
                np.add.at(py, voxel, w * vy)
                np.add.at(pz, voxel, w * vz)
    safe = np.where(m > 0, m, 1.0)
    uy = np.where(m > 0, py / safe, 0.0) if ny > 1 else np.zeros_like(m)
    return m / vol, np.where(m > 0, px / safe, 0.0), uy, np.where(m > 0, pz / safe, 0.0)


def read_columns(path):
    """{step: {name: value}} of a file of rows 'step value ...' whose columns the title line
    '# step NAME ...' names."""
    with open(path) as f:
        title = f.readline().split()
    if title[:2] != ["#", "step"]:
        raise ValueError("%s: no title line '# step NAME ...' naming its columns" % path)
    return {step: dict(zip(title[2:], row)) for step, row in read_table(path).items()}


def load_run(tag, frame, controls):
    """Features (the densities, then the controls named, one of CONTROLS' lists), velocity targets
    and force targets of one resolved run's snapshots (run TAG's files in the working folder),
    binned in frame (voxels, box)."""
    table = read_columns("controls.%s.txt" % tag)
    named = next(iter(table.values()), {})    # every row holds the names of the title line
    missing = [c for c in controls if c not in named]
    if table and missing:
        raise ValueError("controls.%s.txt has no column %s (an earlier in.blade's run: run it again)"
                         % (tag, " ".join(missing)))
    force = {int(row[0]): row[1:] for row in read_force(tag)}
    X, Y, F = [], [], []
    for step, a in read_snapshots(ATOMS % tag):
        if step not in table or step not in force:
            continue
        row = table[step]
        rho, ux, uy, uz = bin_frame(a["x"] - row["bx"], a["y"], a["z"], a["vx"], a["vy"], a["vz"], a["mass"],
                                    *frame)
        X.append(np.concatenate([rho, [row[c] for c in controls]]))
        Y.append(np.stack([ux, uy, uz], axis=1).ravel())
        F.append([force[step][0], 0.0, force[step][1]])
    return np.array(X), np.array(Y), np.array(F)


def read_force(tag):
    """Array of rows: step, Fx, Fz, predicted Fx, predicted Fz (force.TAG.txt in the working folder,
    its columns by the names of its header line '# TimeStep NAME ...')."""
    path = "force.%s.txt" % tag
    names = None
    with open(path) as f:
        for line in f:
            if line.startswith("# TimeStep"):
                names = line.split()[2:]
                break
    if names is None:
        raise ValueError("%s: no '# TimeStep' header naming its columns" % path)
    data = np.atleast_2d(np.loadtxt(path, comments="#"))
    out = np.zeros((len(data), 5))
    out[:, 0] = data[:, 0]
    for k, name in enumerate(names):
        column = data[:, 1 + k]
        if name.startswith("c_onspheres["):    # wall force on the spheres: x at odd, z at even index
            out[:, 1 if int(name[12:-1]) % 2 else 2] -= column
        elif name in ("f_rom[14]", "f_rom[16]"):
            out[:, 3 if name == "f_rom[14]" else 4] = column
        else:
            raise ValueError("%s: column %s is not a wall's force or the model's" % (path, name))
    return out


def force_accuracy(res_tag, tag, which):
    """{'force_accuracy_WHICH': value}: which = 'measured' (the force tag's run measures) or
    'predicted' (its model's prediction), against the force resolved run res_tag measures."""
    res, other = read_force(res_tag), read_force(tag)
    n = min(len(res), len(other))
    cols = [1, 2] if which == "measured" else [3, 4]
    err = np.linalg.norm(other[:n][:, cols] - res[:n][:, [1, 2]], axis=1)
    ref = np.linalg.norm(res[:n][:, [1, 2]], axis=1)
    return {"force_accuracy_" + which: float(1.0 - err.mean() / ref.mean())}
