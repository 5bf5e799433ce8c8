#!/usr/bin/env python3
"""Kokkos benchmark: LAMMPS's chute scene (bench/in.chute.scaled, data.chute replicated x*y to the
given sizes) with stock gran/hooke/history/kk and GRIDDEM's kk styles, side by side in one job,
with LAMMPS's benchmark switches (-k on g 1 | t N -sf kk -pk kokkos newton off neigh half).
Appends one JSON line per run to bench/results/gpu.jsonl: atom-steps/s and peak memory (GPU:
nvidia-smi's memory.used polled every 200 ms, less its value before the run; always the lmp
process's peak host RSS). A run that fails (out of memory, a crash, a timeout) is recorded as
failed with its reason and the job goes on; a style the lmp lacks is recorded as not available,
never replaced by another. A griddem line's "driver" says what ran it: on a host back end without
--cell or --search the kk styles run the CPU engine ("engine"), else the Kokkos kernels
("kernels"; --search thread gives the kernels on a host). On a GPU without --sizes the sizes are 0.5M, 2M, 8M, 32M and the
issue's 100M, then 2x more (200M, 400M, ...) while any style still runs.

With --census each run that worked is run again with bench/kokkos_census.c (built here with cc)
as a Kokkos Tools library, and its line gets "kernels": each kernel's calls and milliseconds per
step (those of the whole run, setup included, over its steps; the tool makes Kokkos fence around
every kernel, so on a GPU too they are execution times) and "kernels_per_step".

Each line records LAMMPS's timing breakdown ("sections_pct": Pair, Neigh, Comm, Output, Modify,
Other, percent of the loop). On a GPU kernels run asynchronously and LAMMPS charges a kernel to
whichever section waits for it next, so stock's Pair share counts little more than its launch;
--launch-blocking runs with CUDA_LAUNCH_BLOCKING=1, each kernel finishing inside its own section
(slower as a whole: the line says "launch_blocking": true and is for the breakdown, not the
speed).

With --cell the griddem styles run once per fix griddem cell mode given (auto, multi, exact or
an edge, as `fix grid all griddem cell X`), each line recording its "cell"; the cell edge trades
candidates searched against cells visited, and a GPU may weigh the two otherwise than a CPU.
With --search they run once per fix griddem search given (thread, team, auto), each line
recording its "search", and with both once per pair of the two.

--scene poly runs the polydisperse scene instead: spheres of diameters log-uniform over 1:10 (0.1 to
1) on a simple cubic lattice of spacing 1, squeezed by fix deform to half the box's edge (solid
fraction about 0.6) in --prep steps, then timed for --steps at that density. Stock KOKKOS has no
multi binning, so stock kk lists every pair within the largest diameter plus the skin (0.1, the
chute's; LAMMPS's best for it is the smallest skin whose rebuilds stay rare: check yes every step).

--results PATH writes the lines there instead of bench/results/gpu.jsonl (bench/gpu_session.py
collects a session's lines in its output folder).

usage: bench/gpu.py [--lmp build-kk/lmp] [--gpu [N] | --threads N] [--sizes 32k,128k,0.5M]
                    [--steps N] [--only STYLE,...] [--cell MODE,...] [--search MODE,...] [--timeout S]
                    [--lammps-bench DIR] [--census] [--launch-blocking] [--build LABEL]
                    [--scene chute|poly] [--prep N] [--results PATH]"""
import argparse
import datetime
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
from griddemtools import log  # noqa: E402

BASE = 32000  # atoms in data.chute
# LAMMPS's chute files (./tools/build downloads the LAMMPS source into .deps)
LAMMPS_BENCH = os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench")
CHUTE_FILES = ("data.chute", "in.chute.scaled")
# (pair style as written in the input, note); all with the chute's coefficients
STYLES = [
    ("gran/hooke/history/kk", "stock, LAMMPS's Kokkos chute benchmark"),
    ("griddem/hooke/history/kk", "GRIDDEM, twin of gran/hooke/history"),
    ("griddem/hooke/kk", "GRIDDEM, twin of gran/hooke (no tangential history)"),
    ("gran/hooke/kk", "stock, like for like with griddem/hooke/kk"),
]
GPU_SIZES = ["0.5M", "2M", "8M", "32M", "100M"]
# the polydisperse scene, squeezed from a lattice; kn and the step resolve the smallest spheres'
# contacts (diameter 0.1, density 1: a contact lasts about 18 steps)
POLY = """units lj
atom_style sphere
boundary p p p
newton off
comm_modify vel yes
region box block 0 {n} 0 {n} 0 {nz}
create_box 1 box
lattice sc 1.0
create_atoms 1 box
variable d atom 0.1*10^random(0,1,4711)
set group all diameter v_d
set group all density 1.0
pair_style {style} 20000.0 NULL 50.0 NULL 0.5 0
pair_coeff * *
{fix}neighbor 0.1 bin
neigh_modify every 1 delay 0 check yes
timestep 0.00002
fix 1 all nve/sphere
fix squeeze all deform 1 x scale 0.5 y scale 0.5 z scale 0.5 remap x
thermo_style custom step atoms ke press
thermo_modify norm no
thermo 100
run {prep}
unfix squeeze
run {steps}
"""
CPU_SIZES = ["32k", "128k"]


def atoms(text):
    m = re.fullmatch(r"([0-9.]+)([kKmM]?)", text.strip())
    return int(round(float(m.group(1)) * {"": 1, "k": 1e3, "m": 1e6}[m.group(2).lower()]))


def replicas(natoms):
    """x, y with x*y copies of data.chute nearest natoms, as square as divides evenly."""
    n = max(1, int(round(natoms / BASE)))
    y = max(d for d in range(1, int(math.isqrt(n)) + 1) if n % d == 0)
    return n // y, y


def poly_lattice(natoms):
    """n, nz: an n x n x nz simple cubic lattice nearest natoms, as cubic as it goes."""
    n = max(2, int(round(natoms ** (1.0 / 3.0))))
    return n, max(2, int(round(natoms / float(n * n))))


def scene_layout(scene, natoms):
    """(atoms, fields naming the scene's shape in a line) of the scene nearest natoms."""
    if scene == "poly":
        n, nz = poly_lattice(natoms)
        return n * n * nz, {"lattice": "%d %d %d" % (n, n, nz)}
    x, y = replicas(natoms)
    return BASE * x * y, {"replicate": "%d %d 1" % (x, y)}


def scene_input(args, scaled, style, variant, natoms):
    """(input text, lmp's -var switches) of one run of the scene with this pair style, and with
    `fix grid all griddem cell <cell> search <search>` after its pair_coeff line when variant
    (cell, search) gives either."""
    cell, search = variant
    options = "".join(" %s %s" % (key, value) for key, value in (("cell", cell), ("search", search)) if value)
    fix = "fix grid all griddem%s\n" % options if options else ""
    if args.scene == "poly":
        n, nz = poly_lattice(natoms)
        return POLY.format(n=n, nz=nz, style=style, fix=fix, prep=args.prep, steps=args.steps), []
    text = scaled.replace("gran/hooke/history ", style + " ")
    if fix:
        text, found = re.subn(r"^(pair_coeff.*)$", lambda m: m.group(1) + "\n" + fix.rstrip(), text, flags=re.M)
        if found != 1:
            raise SystemExit("in.chute.scaled: no single pair_coeff line to put fix griddem after")
    x, y = replicas(natoms)
    return re.sub(r"run\s+100", "run %d" % args.steps, text), ["-var", "x", str(x), "-var", "y", str(y)]


def lmp_info(lmp):
    return help_info(subprocess.run([lmp, "-h"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                    universal_newlines=True).stdout)


def help_info(text):
    """(the KOKKOS package API, None without KOKKOS; the set of pair styles) from lmp -h's text."""
    api = re.search(r"KOKKOS package API:\s*(.*)", text)
    pairs = text.split("* Pair styles:", 1)[-1].split("* Bond styles:", 1)[0].split()
    return (api.group(1).strip() if api else None), set(pairs)


def gpu_name():
    try:
        out = subprocess.run(["nvidia-smi", "--query-gpu=name", "--format=csv,noheader", "-i", "0"],
                             stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, universal_newlines=True)
    except OSError:
        return None
    return out.stdout.strip() if out.returncode == 0 and out.stdout.strip() else None


def gpu_mem_used():
    out = subprocess.run(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits",
                          "-i", "0"], stdout=subprocess.PIPE, universal_newlines=True).stdout
    return float(out.split()[0])


def run(cmd, cwd, timeout, gpu, env_extra=None):
    """(exit code or -signal, output, peak host RSS MiB, peak GPU MiB above idle or None, timed out,
    seconds from start to end)"""
    log = open(os.path.join(cwd, "out.txt"), "w+")
    poll = None
    if gpu:
        idle = gpu_mem_used()
        poll = subprocess.Popen(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits",
                                 "-i", "0", "-lms", "200"], stdout=subprocess.PIPE, universal_newlines=True)
    env = dict(os.environ)
    env.setdefault("OMP_PROC_BIND", "spread")  # as Kokkos advises
    env.setdefault("OMP_PLACES", "threads")
    env.update(env_extra or {})
    p = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=log, stderr=subprocess.STDOUT)
    start, timed_out = time.time(), False
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if time.time() - start > timeout and not timed_out:
            timed_out = True
            p.kill()
        time.sleep(0.1)
    p.returncode = os.waitstatus_to_exitcode(status)
    wall = time.time() - start
    gpu_peak = None
    if poll:
        poll.terminate()
        used = [float(v) for v in poll.communicate()[0].split() if re.fullmatch(r"[0-9.]+", v)]
        gpu_peak = max(used + [gpu_mem_used()]) - idle
    log.seek(0)
    out = log.read()
    log.close()
    return p.returncode, out, usage.ru_maxrss / 1024.0, gpu_peak, timed_out, wall


def build_census(wd):
    """bench/kokkos_census.c as a shared library in wd."""
    lib = os.path.join(wd, "kokkos_census.so")
    subprocess.run(["cc", "-O2", "-shared", "-fPIC", os.path.join(HERE, "kokkos_census.c"), "-o", lib],
                   check=True)
    return lib


def census(cmd, wd, timeout, gpu, lib, steps):
    """{kernel: [calls per step, ms per step]} of one run under the census library (kernels of at
    least 0.5% of the kernels' time), and the kernels launched per step; None if the run failed."""
    table = os.path.join(wd, "census.txt")
    if os.path.exists(table):
        os.remove(table)
    rc, out = run(cmd, wd, timeout, gpu, {"KOKKOS_TOOLS_LIBS": lib, "GRIDDEM_CENSUS": table})[:2]
    if rc != 0 or not os.path.exists(table):
        return None, None
    rows = []
    with open(table) as f:
        for line in f:
            if line.startswith("#"):
                continue
            kind, calls, seconds, name = line.rstrip("\n").split(" ", 3)
            if kind in "FRS":
                rows.append((name, int(calls), float(seconds)))
    total = sum(r[2] for r in rows) or 1.0
    kernels = {name: [round(calls / steps, 3), round(1e3 * seconds / steps, 4)]
               for name, calls, seconds in sorted(rows, key=lambda r: -r[2]) if seconds >= 0.005 * total}
    return kernels, round(sum(r[1] for r in rows) / steps, 2)


def reason(rc, out, timed_out, timeout):
    if timed_out:
        return "timed out after %d s" % timeout
    if rc < 0:
        sig = signal.Signals(-rc).name
        return "killed by %s%s" % (sig, " (out of host memory?)" if sig == "SIGKILL" else "")
    lines = [l.strip() for l in out.splitlines() if l.strip()]
    for l in lines:
        if re.search(r"ERROR|Exception|[Oo]ut of memory|failed to allocate|terminate called|what\(\)", l):
            return l[:300]
    return (lines[-1][:300] if lines else "no output") + " (exit %d)" % rc


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lmp", default=os.path.join(TOP, "build-kk", "lmp"))
    ap.add_argument("--gpu", type=int, nargs="?", const=1, default=None,
                    help="run on N GPUs (only 1 supported; default when nvidia-smi and a GPU lmp are found)")
    ap.add_argument("--threads", type=int, default=None, help="OpenMP threads on the CPU (default: all cores)")
    ap.add_argument("--sizes", default=None, help="atoms, e.g. 32k,128k,0.5M,2M (rounded to copies of 32,000)")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--only", default=None, help="comma-separated pair styles to run")
    ap.add_argument("--timeout", type=int, default=1800, help="seconds per run")
    ap.add_argument("--lammps-bench", default=LAMMPS_BENCH)
    ap.add_argument("--cell", default=None,
                    help="fix griddem cell modes for the griddem styles, e.g. auto,0.5 (default: none given)")
    ap.add_argument("--search", default=None,
                    help="fix griddem search modes for the griddem styles, e.g. thread,team (default: none given)")
    ap.add_argument("--launch-blocking", action="store_true",
                    help="GPU: CUDA_LAUNCH_BLOCKING=1, so that LAMMPS's timing breakdown charges each kernel to its section")
    ap.add_argument("--build", default=None, help="a label for the lmp's source, recorded in each line")
    ap.add_argument("--census", action="store_true",
                    help="run each again under bench/kokkos_census.c and record time per kernel")
    ap.add_argument("--scene", choices=("chute", "poly"), default="chute")
    ap.add_argument("--prep", type=int, default=2000, help="poly: steps of the squeeze before the timed run")
    ap.add_argument("--results", default=os.path.join(HERE, "results", "gpu.jsonl"),
                    help="the JSON lines file to append to")
    args = ap.parse_args()
    args.lmp = os.path.abspath(args.lmp)    # runs happen in a scratch folder
    if not os.access(args.lmp, os.X_OK):
        raise SystemExit("gpu.py: no lmp at %s: build one (README, 'Building with KOKKOS') and name it with --lmp" % args.lmp)

    api, have = lmp_info(args.lmp)
    if not api:
        raise SystemExit("%s has no KOKKOS package" % args.lmp)
    device_api = [b for b in ("CUDA", "HIP", "SYCL") if b in api.split()]
    gpu = args.gpu if args.gpu is not None else (1 if device_api and gpu_name() and args.threads is None else None)
    if gpu:
        if not device_api:
            raise SystemExit("%s was built for Kokkos %s, not for a GPU" % (args.lmp, api))
        if gpu != 1:
            raise SystemExit("only --gpu 1 is supported (one rank)")
        kk = ["-k", "on", "g", "1"]
        device = "%s, Kokkos %s" % (gpu_name() or "unknown GPU", device_api[0])
    else:
        threads = args.threads or os.cpu_count()
        kk = ["-k", "on", "t", str(threads)]
        device = "%s, Kokkos %s, %d threads" % (benchlib.device(), api.split()[0], threads)
    kk += ["-sf", "kk", "-pk", "kokkos", "newton", "off", "neigh", "half"]
    if args.launch_blocking and not gpu:
        raise SystemExit("--launch-blocking is for a GPU run")
    blocking = {"CUDA_LAUNCH_BLOCKING": "1"} if args.launch_blocking else None
    sizes = [atoms(s) for s in (args.sizes.split(",") if args.sizes else GPU_SIZES if gpu else CPU_SIZES)]
    grow = gpu and not args.sizes

    chute = [os.path.join(args.lammps_bench, name) for name in CHUTE_FILES]
    if args.scene == "chute" and not all(os.path.exists(path) for path in chute):
        raise SystemExit("gpu.py: no %s: name the folder of LAMMPS's data.chute and in.chute.scaled with "
                         "--lammps-bench DIR (./tools/build downloads it into .deps)" % " or ".join(
                             path for path in chute if not os.path.exists(path)))
    wd = tempfile.mkdtemp(prefix="griddem-gpu-")
    scaled = None
    if args.scene == "chute":
        shutil.copy(chute[0], wd)
        with open(chute[1]) as f:
            scaled = f.read()
    census_lib = build_census(wd) if args.census else None
    out_path = args.results
    only = args.only.split(",") if args.only else None
    variants = [(cell, search) for cell in (args.cell.split(",") if args.cell else [None])
                for search in (args.search.split(",") if args.search else [None])]
    styles = [(s, note, variant) for s, note in STYLES if not only or s in only
              for variant in (variants if s.startswith("griddem/") else [(None, None)])]
    failed = set()
    i = 0
    while i < len(sizes):
        natoms, shape = scene_layout(args.scene, sizes[i])
        ran = False
        for style, note, variant in styles:
            record = {"date": datetime.date.today().isoformat(), "device": device, "scene": args.scene,
                      "natoms": natoms, "steps": args.steps, "style": style, "note": note}
            record.update(shape)
            if args.scene == "poly":
                record["prep_steps"] = args.prep
            for key, value in zip(("cell", "search"), variant):
                if value:
                    record[key] = value
            if style.startswith("griddem/"):
                # on a host back end without a fix griddem in the script, the CPU engine
                record["driver"] = "kernels" if gpu or any(variant) else "engine"
            if blocking:
                record["launch_blocking"] = True
            if args.build:
                record["build"] = args.build
            if style not in have:
                record.update(status="not available", reason="%s is not in %s" % (style, args.lmp))
            elif (style, variant) in failed:
                continue  # failed at a smaller size
            else:
                text, variables = scene_input(args, scaled, style, variant, natoms)
                with open(os.path.join(wd, "in.run"), "w") as f:
                    f.write(text)
                cmd = [args.lmp] + kk + variables + ["-in", "in.run", "-log", "none"]
                rc, out, rss, gpu_mem, timed_out, wall = run(cmd, wd, args.timeout, gpu, blocking)
                runs = log.loop_times(out)
                if rc == 0 and runs:
                    loop, steps, n = runs[-1].seconds, runs[-1].steps, runs[-1].atoms
                    sections = log.timing_sections(out)
                    record.update(status="ok", natoms=n, steps=steps, loop_s=loop,
                                  atom_steps_per_s=n * steps / loop, pair_pct=sections.get("Pair"),
                                  sections_pct=sections)
                    ran = True
                    if census_lib:
                        record["kernels"], record["kernels_per_step"] = census(
                            cmd, wd, args.timeout, gpu, census_lib, steps)
                else:
                    record.update(status="failed", reason=reason(rc, out, timed_out, args.timeout))
                    failed.add((style, variant))
                record["host_peak_rss_mib"] = round(rss, 1)
                record["wall_s"] = round(wall, 2)
                if gpu:
                    record["gpu_peak_mem_mib"] = gpu_mem
                    record["gpu_mem_how"] = "nvidia-smi memory.used, polled every 200 ms, less the idle value"
            print(json.dumps(record), flush=True)
            with open(out_path, "a") as f:
                f.write(json.dumps(record) + "\n")
        i += 1
        if grow and i == len(sizes) and ran:
            sizes.append(sizes[-1] * 2)
    shutil.rmtree(wd, ignore_errors=True)


if __name__ == "__main__":
    main()
