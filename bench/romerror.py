"""The errors of a reduced-order run's fields against a resolved run's, as the method's paper defines
them, frame by frame (functions of time), over the reduced region: the voxels of the coarse-graining
grid (compute griddem/cg, dump grid), each weighted by its resolved mass density, so that empty
voxels do not count.

- velocity error e_v(t) = sum_m rho_m |v'_m - v_m| / (V_c sum_m rho_m): the model run's mean field
  v' against the coarse-grained resolved field v, relative to a characteristic speed V_c (the
  resolved run's density-weighted RMS speed over the region and the run);
- granular-temperature error e_T(t) = sum_m rho_m |T'_m - T_m| / (T_c sum_m rho_m), T_c the
  resolved run's density-weighted mean temperature over the region and the run;
- surface-height error e_h(t) = sum_c |h'_c - h_c| / sum_c (h_c - h_ref,c): the area integral of
  |h' - h| over the volume between the resolved surface h and the reference surface h_ref, here the
  container's floor and walls. Per voxel column h - h_ref is the mass-equivalent thickness of the
  material above z = 0 (griddemtools.rom's heights: mass per area over one bulk
  density), which is the height of the surface above the floor and walls it rests on.

An accuracy is one minus an error; a run's is reported as the time mean and as the mean over the
worst tenth of its frames (at least one)."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))  # griddemtools
from griddemtools.rom import heights  # noqa: E402


def velocity_error(rho, v_res, v_rom, speed):
    """e_v of one frame: rho [m], v_res, v_rom [m, d] (d components), speed V_c > 0."""
    rho = np.asarray(rho, float)
    diff = np.linalg.norm(np.asarray(v_rom, float) - np.asarray(v_res, float), axis=1)
    return float(np.sum(rho * diff) / (speed * np.sum(rho)))


def temperature_error(rho, t_res, t_rom, temperature):
    """e_T of one frame: rho, t_res, t_rom [m], the characteristic temperature T_c > 0."""
    rho = np.asarray(rho, float)
    return float(np.sum(rho * np.abs(np.asarray(t_rom, float) - np.asarray(t_res, float))) /
                 (temperature * np.sum(rho)))


def height_error(h_res, h_rom):
    """e_h of one frame: h_res, h_rom [column] the surface heights above the reference surface."""
    h_res = np.asarray(h_res, float)
    return float(np.sum(np.abs(np.asarray(h_rom, float) - h_res)) / np.sum(h_res))


def characteristic_speed(rho, v):
    """V_c: sqrt(sum rho |v|^2 / sum rho) over frames and voxels; rho [t, m], v [t, m, d]."""
    rho = np.asarray(rho, float)
    return float(np.sqrt(np.sum(rho * np.sum(np.asarray(v, float) ** 2, axis=-1)) / np.sum(rho)))


def characteristic_temperature(rho, t):
    """T_c: sum rho T / sum rho over frames and voxels; rho, t [t, m]."""
    rho = np.asarray(rho, float)
    return float(np.sum(rho * np.asarray(t, float)) / np.sum(rho))


def summary(errors):
    """(time mean, mean over the worst tenth of the frames, at least one) of an error series."""
    e = np.sort(np.asarray(errors, float))[::-1]
    return float(np.mean(e)), float(np.mean(e[:max(1, len(e) // 10)]))


def _fields(frame):
    c = frame.columns
    return (np.asarray(c["density"], float), np.stack([np.asarray(c[k], float) for k in ("vx", "vy", "vz")], axis=1),
            np.asarray(c["temperature"], float) if "temperature" in c else None)


def error_series(res, rom):
    """Frames of a resolved and of another run (read_grid_dump; the first min(len) frames, the same
    steps) -> dict: steps, velocity, height and (when both runs dumped it) temperature error
    series, and the characteristic speed and temperature they are relative to."""
    nf = min(len(res), len(rom))
    if nf == 0:
        raise ValueError("no frames to compare")
    steps = [res[k].step for k in range(nf)]
    if steps != [rom[k].step for k in range(nf)]:
        raise ValueError("the runs' frames are not at the same steps")
    fr = [_fields(res[k]) for k in range(nf)]
    fm = [_fields(rom[k]) for k in range(nf)]
    # frames with no resolved mass in the grid (a run that starts empty) have no error to measure
    use = [k for k in range(nf) if np.sum(fr[k][0]) > 0]
    speed = characteristic_speed([fr[k][0] for k in use], [fr[k][1] for k in use])
    out = dict(steps=[steps[k] for k in use], characteristic_speed=speed,
               velocity=[velocity_error(fr[k][0], fr[k][1], fm[k][1], speed) for k in use],
               height=[height_error(heights(res[k]), heights(rom[k])) for k in use])
    if all(f[2] is not None for f in fr + fm):
        temp = characteristic_temperature([fr[k][0] for k in use], [fr[k][2] for k in use])
        out["characteristic_temperature"] = temp
        out["temperature"] = [temperature_error(fr[k][0], fr[k][2], fm[k][2], temp) for k in use]
    return out


def accuracies(series, prefix=""):
    """{PREFIXvelocity_accuracy, PREFIXvelocity_accuracy_worst10, ... height, temperature}: one
    minus the time mean and one minus the worst tenth's mean of each error series."""
    out = {}
    for name in ("velocity", "height", "temperature"):
        if name in series:
            mean, worst = summary(series[name])
            out["%s%s_accuracy" % (prefix, name)] = 1.0 - mean
            out["%s%s_accuracy_worst10" % (prefix, name)] = 1.0 - worst
    return out


def write_series(path, series):
    """The error series as columns (step, velocity, height, temperature if present), for figures."""
    names = [n for n in ("velocity", "height", "temperature") if n in series]
    with open(path, "w") as f:
        f.write("# step %s errors (bench/romerror.py); V_c %.6g\n"
                % (" ".join(names), series["characteristic_speed"]))
        for k, step in enumerate(series["steps"]):
            f.write("%d %s\n" % (step, " ".join("%.6g" % series[n][k] for n in names)))
