#!/usr/bin/python3
"""Resolved against reduced-order run of the same scene:
    compare.py [--log PATTERN] RESOLVED_TAG ROM_TAG
reads cg.TAG.txt and the run's log, log.TAG (or PATTERN with {} for the tag:
run_all.sh's 'log.2Dec26.rom-pile.{}.1'):
- speed-up: LAMMPS loop time of the resolved run / of the reduced run (summed over the runs of a
  log: a run in segments, examples/rom-hopper, has several);
- surface height: per voxel column (x), the mass-equivalent fill height of the container
  h = (mass above the plate, z > 0, per unit area) / (rho_bulk), rho_bulk = 0.6 (the same for both
  runs, so the error is independent of it); accuracy = 1 - mean over frames (second half of the
  run) and columns of |h_rom - h_res| / mean h_res;
- velocity field: time-averaged (second half) voxel velocities (vx, vz) where the resolved mean
  density exceeds 0.05; error = ||<v>_rom - <v>_res|| / ||<v>_res|| (L2 over those voxels);
- granular temperature: the same with the voxels' time-averaged granular temperature (compute
  griddem/cg temperature: velocity variance about the voxel mean), when the dumps have it;
- reduction: the mean fraction of kinematic atoms (thermo's v_nkin over atoms)."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))  # griddemtools
from griddemtools import log  # noqa: E402
from griddemtools.grid import read_grid_dump  # noqa: E402
from griddemtools.rom import counters, heights, kinematic_fraction, near_fraction  # noqa: E402

LOG = "log.{}"


def log_of(tag):
    return LOG.format(tag)


def loop_time(tag):
    return sum(run.seconds for run in log.loop_times(log_of(tag)))


def compare(res_tag, rom_tag):
    """Speed-up, accuracies and the last frames' fill heights of a reduced against a resolved run."""
    res, rom = read_grid_dump("cg.%s.txt" % res_tag), read_grid_dump("cg.%s.txt" % rom_tag)
    nf = min(len(res), len(rom))
    half = range(nf // 2, nf)
    hr = np.array([heights(res[k]) for k in half])
    hm = np.array([heights(rom[k]) for k in half])
    rho = np.mean([res[k].columns["density"] for k in half], axis=0)
    mask = rho > 0.05
    vr = np.array([np.mean([res[k].columns[c] for k in half], axis=0)[mask] for c in ("vx", "vz")])
    vm = np.array([np.mean([rom[k].columns[c] for k in half], axis=0)[mask] for c in ("vx", "vz")])
    tr, tm = loop_time(res_tag), loop_time(rom_tag)
    rom_log = log_of(rom_tag)
    extra = {}
    if "temperature" in res[0].columns and "temperature" in rom[0].columns:
        Tr = np.mean([res[k].columns["temperature"] for k in half], axis=0)[mask]
        Tm = np.mean([rom[k].columns["temperature"] for k in half], axis=0)[mask]
        extra["temperature_error"] = float(np.linalg.norm(Tm - Tr) / np.linalg.norm(Tr))
    return dict(**extra,loop_resolved_s=tr, loop_reduced_s=tm, speedup=tr / tm,
                height_accuracy=float(1.0 - np.mean(np.abs(hm - hr)) / np.mean(hr)),
                final_height_accuracy=float(1.0 - np.mean(np.abs(hm[-1] - hr[-1])) / np.mean(hr[-1])),
                velocity_error=float(np.linalg.norm(vm - vr) / np.linalg.norm(vr)), voxels=int(mask.sum()),
                kinematic_fraction=kinematic_fraction(rom_log), near_fraction=near_fraction(rom_log),
                **{"n_" + k: v for k, v in counters(rom_log).items()}, heights_resolved=hr[-1], heights_reduced=hm[-1])


def main():
    global LOG
    ap = argparse.ArgumentParser()
    ap.add_argument("--log", default=LOG, help="a run's log name, {} for its tag")
    ap.add_argument("resolved")
    ap.add_argument("reduced")
    args = ap.parse_args()
    LOG = args.log
    c = compare(args.resolved, args.reduced)
    print("loop time resolved %.2f s, reduced %.2f s: speed-up %.2f" % (c["loop_resolved_s"], c["loop_reduced_s"],
                                                                       c["speedup"]))
    print("mean kinematic fraction %.3f" % c["kinematic_fraction"])
    print("surface (fill) height accuracy %.3f over the second half, %.3f at the end"
          % (c["height_accuracy"], c["final_height_accuracy"]))
    print("final fill heights resolved %s" % np.round(c["heights_resolved"], 2))
    print("final fill heights reduced  %s" % np.round(c["heights_reduced"], 2))
    print("time-averaged velocity field error %.3f (relative L2 over %d voxels)" % (c["velocity_error"], c["voxels"]))
    if "temperature_error" in c:
        print("time-averaged granular temperature error %.3f" % c["temperature_error"])


if __name__ == "__main__":
    main()
