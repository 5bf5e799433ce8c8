"""The force on the blade (examples/rom-blade): force.TAG.txt holds, every 100 steps, the means over
those steps of the force the run measures on the blade (Fx, Fz: minus the blade's contact forces
on the spheres), of the force the reduced run's model predicts (Fx, Fz of fix griddem/rom's
f_rom[14], f_rom[16]; 0 in a resolved run).
Force accuracy = 1 - time-mean |F - F_resolved| / time-mean |F_resolved| (|.|: the norm of (Fx, Fz),
means over all rows of the run)."""
import numpy as np


def read_force(tag):
    """Array of rows: step, Fx, Fz, predicted Fx, predicted Fz."""
    return np.loadtxt("force.%s.txt" % tag, comments="#")


def force_accuracy(res_tag, tag, which):
    """{'force_accuracy_WHICH': value}: which = 'measured' (the force tag's run measures) or
    'predicted' (its model's prediction), against the force resolved run res_tag measures."""
    res, other = read_force(res_tag), read_force(tag)
    n = min(len(res), len(other))
    cols = [1, 2] if which == "measured" else [3, 4]
    err = np.linalg.norm(other[:n][:, cols] - res[:n][:, [1, 2]], axis=1)
    ref = np.linalg.norm(res[:n][:, [1, 2]], axis=1)
    return {"force_accuracy_" + which: float(1.0 - err.mean() / ref.mean())}
