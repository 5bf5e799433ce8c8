#!/usr/bin/env python3
"""A GPU session's bundle: the one folder that bench/gpu_session.py needs on a bare machine.

A lent GPU machine holds only what is sent to it, so the bundle carries the lmp and every program,
script and data file the session's steps read; the scripts and sources keep their paths in this
repository, so that they import each other unchanged:

  lmp, or lmp.xz with --xz                the Kokkos lmp (a CUDA lmp is larger than one carry)
  lib/                                    the CUDA runtime the lmp links (each libcudart that
                                          ldd resolves; none for a CPU lmp)
  unittest/core/list_submodels            the sub-model table test_granular_parity reads
  lammps-bench/data.chute, in.chute.scaled  LAMMPS's chute (bench/gpu.py --lammps-bench)
  bench/gpu_session.py and what it runs   gpu.py, benchlib.py, kokkos_census.c, this file
  python/griddemtools/                    the readers and runner benchlib.py and gpu.py import
  unittest/lammps/*.py                    test_kokkos.py and the test modules it imports
  unittest/kokkos_tools/sync_counter.c    the synchronisation counter, built there with cc

Then, wherever DIR is copied: python3 DIR/bench/gpu_session.py --out OUT (bench/README.md).

usage: bench/gpu_bundle.py --lmp LMP --out DIR [--xz] [--list-submodels PROGRAM] [--lammps-bench DIR]
"""
import argparse
import glob
import lzma
import os
import shutil
import subprocess
import sys

from gpu import CHUTE_FILES, LAMMPS_BENCH as DOWNLOADED_BENCH

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)

# the bundle's layout, relative to its folder
LMP = "lmp"
LIB = "lib"
LIST_SUBMODELS = os.path.join("unittest", "core", "list_submodels")
LAMMPS_BENCH = "lammps-bench"
SYNC_COUNTER_SOURCE = os.path.join("unittest", "kokkos_tools", "sync_counter.c")
KK_TESTS = os.path.join("unittest", "lammps", "test_kokkos.py")
GPU_PY = os.path.join("bench", "gpu.py")
CENSUS_SOURCE = os.path.join("bench", "kokkos_census.c")
SCRIPTS = [os.path.join("bench", name) for name in
           ("gpu_session.py", "gpu_bundle.py", "gpu.py", "benchlib.py", "kokkos_census.c")] + [SYNC_COUNTER_SOURCE]
TEST_MODULES = os.path.join("unittest", "lammps", "*.py")
TOOLS_MODULES = os.path.join("python", "griddemtools", "*.py")
# libraries carried with the lmp: the CUDA runtime, which a machine with only the driver lacks
CARRIED_LIBRARIES = ("libcudart.so",)


def ldd(program, lib_dir=None):
    """({library: path} that the loader resolves for program, [what it cannot: a library not
    found, a symbol version missing]), with lib_dir searched first as LD_LIBRARY_PATH."""
    env = dict(os.environ)
    if lib_dir:
        env["LD_LIBRARY_PATH"] = os.pathsep.join(p for p in (lib_dir, env.get("LD_LIBRARY_PATH")) if p)
    out = subprocess.run(["ldd", program], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, env=env).stdout
    resolved, problems = {}, []
    for line in out.splitlines():
        if "not found" in line:
            problems.append(line.strip())
        elif " => /" in line:
            name, path = line.split(" => ")
            resolved[name.strip()] = path.split(" (")[0].strip()
    return resolved, problems


def bundled_lmp(bundle):
    """The bundle's lmp: its path, compressed or not."""
    for name in (LMP, LMP + ".xz"):
        if os.path.exists(os.path.join(bundle, name)):
            return os.path.join(bundle, name)
    return None


def place(path, out, rel):
    """Copy the file at path to out/rel."""
    os.makedirs(os.path.join(out, os.path.dirname(rel)), exist_ok=True)
    shutil.copy2(path, os.path.join(out, rel))


def make(lmp, out, xz, list_submodels, lammps_bench):
    inputs = [lmp, list_submodels] + [os.path.join(lammps_bench, name) for name in CHUTE_FILES]
    absent = [path for path in inputs if not os.path.isfile(path)]
    if absent:
        raise SystemExit("gpu_bundle.py: no %s (--lmp, --list-submodels, --lammps-bench)" % ", ".join(absent))
    if os.path.exists(out):
        if not os.path.exists(os.path.join(out, "bench", "gpu_bundle.py")):
            raise SystemExit("gpu_bundle.py: %s exists and is not a bundle; name a new folder" % out)
        shutil.rmtree(out)
    modules = glob.glob(os.path.join(TOP, TEST_MODULES)) + glob.glob(os.path.join(TOP, TOOLS_MODULES))
    for rel in SCRIPTS + [os.path.relpath(p, TOP) for p in modules]:
        place(os.path.join(TOP, rel), out, rel)
    place(list_submodels, out, LIST_SUBMODELS)
    for name in CHUTE_FILES:
        place(os.path.join(lammps_bench, name), out, os.path.join(LAMMPS_BENCH, name))
    if xz:
        with open(lmp, "rb") as src, lzma.open(os.path.join(out, LMP + ".xz"), "wb") as dst:
            shutil.copyfileobj(src, dst)
    else:
        place(lmp, out, LMP)
    resolved, problems = ldd(lmp)
    carried = sorted(path for name, path in resolved.items() if name.startswith(CARRIED_LIBRARIES))
    os.makedirs(os.path.join(out, LIB))
    for path in carried:
        place(path, out, os.path.join(LIB, os.path.basename(path)))
    print("bundle %s: %s, libraries carried: %s" % (out, os.path.basename(bundled_lmp(out)),
                                                   " ".join(map(os.path.basename, carried)) or "none"))
    if problems:
        print("gpu_bundle.py: on this machine ldd says of %s: %s" % (lmp, "; ".join(problems)))


def main():
    sys.path.insert(0, os.path.join(TOP, "python"))
    from griddemtools.lammps import list_submodels_program
    ap = argparse.ArgumentParser()
    ap.add_argument("--lmp", required=True, help="a Kokkos lmp (CUDA for a GPU session)")
    ap.add_argument("--out", required=True, help="the bundle's folder (replaced if it is a bundle)")
    ap.add_argument("--xz", action="store_true", help="store the lmp as lmp.xz")
    ap.add_argument("--list-submodels", default=None,
                    help="unittest/core/list_submodels (default: GRIDDEM_LIST_SUBMODELS, else beside the lmp's build)")
    ap.add_argument("--lammps-bench", default=DOWNLOADED_BENCH, help="folder of LAMMPS's data.chute and in.chute.scaled")
    args = ap.parse_args()
    make(os.path.abspath(args.lmp), os.path.abspath(args.out), args.xz,
         args.list_submodels or list_submodels_program(args.lmp), args.lammps_bench)


if __name__ == "__main__":
    main()
