#!/usr/bin/python3
"""Resolved against reduced-order run of the same scene:
    compare.py RESOLVED_TAG ROM_TAG      (reads cg.TAG.txt and log.TAG)
- speed-up: LAMMPS loop time of the resolved run / of the reduced run;
- surface height: per voxel column (x), the mass-equivalent fill height of the container
  h = (mass above the plate, z > 0, per unit area) / (rho_bulk), rho_bulk = 0.6 (the same for both
  runs, so the error is independent of it); accuracy = 1 - mean over frames (second half of the
  run) and columns of |h_rom - h_res| / mean h_res;
- velocity field: time-averaged (second half) voxel velocities (vx, vz) where the resolved mean
  density exceeds 0.05; error = ||<v>_rom - <v>_res|| / ||<v>_res|| (L2 over those voxels)."""
import re
import sys

import numpy as np

from romtools import read_grid_dump

RHO_BULK = 0.6


def loop_time(tag):
    with open("log." + tag) as f:
        times = re.findall(r"Loop time of ([0-9.eE+-]+) on", f.read())
    return float(times[-1])


def heights(frame):
    step, box, n, cols = frame
    nx, ny, nz = n
    hz = (box[5] - box[4]) / nz
    zc = box[4] + (np.arange(nz) + 0.5) * hz
    rho = cols["density"].reshape(nz, ny, nx)
    inside = zc > 0
    return (rho[inside].sum(axis=(0, 1)) * hz / ny) / RHO_BULK


def main():
    res_tag, rom_tag = sys.argv[1], sys.argv[2]
    res, rom = read_grid_dump("cg.%s.txt" % res_tag), read_grid_dump("cg.%s.txt" % rom_tag)
    nf = min(len(res), len(rom))
    half = range(nf // 2, nf)
    hr = np.array([heights(res[k]) for k in half])
    hm = np.array([heights(rom[k]) for k in half])
    height_acc = 1.0 - np.mean(np.abs(hm - hr)) / np.mean(hr)
    final_acc = 1.0 - np.mean(np.abs(hm[-1] - hr[-1])) / np.mean(hr[-1])
    rho = np.mean([res[k][3]["density"] for k in half], axis=0)
    mask = rho > 0.05
    vr = np.array([np.mean([res[k][3][c] for k in half], axis=0)[mask] for c in ("vx", "vz")])
    vm = np.array([np.mean([rom[k][3][c] for k in half], axis=0)[mask] for c in ("vx", "vz")])
    verr = np.linalg.norm(vm - vr) / np.linalg.norm(vr)
    tr, tm = loop_time(res_tag), loop_time(rom_tag)
    print("loop time resolved %.2f s, reduced %.2f s: speed-up %.2f" % (tr, tm, tr / tm))
    print("surface (fill) height accuracy %.3f over the second half, %.3f at the end" % (height_acc, final_acc))
    print("final fill heights resolved %s" % np.round(hr[-1], 2))
    print("final fill heights reduced  %s" % np.round(hm[-1], 2))
    print("time-averaged velocity field error %.3f (relative L2 over %d voxels)" % (verr, mask.sum()))


if __name__ == "__main__":
    main()
