#!/usr/bin/env python3
"""One GPU session's measurements, in priority order, under one deadline.

A lent GPU machine gives minutes, not hours: this script spends them measuring. Given a CUDA
`lmp` (built on the CPU machine, bench/README.md "A GPU session"), it runs these steps in order,
each under its own cap and all under --deadline, and writes every result as soon as it has it,
so that a session cut short still keeps what it reached:

  start    the lmp starts and initialises Kokkos on the device (ldd: no library missing)
  kktests  test_kokkos.py's GPU sections (KK_SECTIONS: list and row layouts, size classes,
           history rows that grow, migrate and go through restart, the blocking synchronisations
           of a step, counted by unittest/kokkos_tools/sync_counter.c, built here with cc,
           the team search against the thread search),
           GRIDDEM_KK_GPUS=1
  chute    bench/gpu.py: stock and griddem/hooke/history/kk (fix griddem search thread and team)
           on LAMMPS's chute at 2M, 8M and 32M atoms
  bound    bench/gpu.py --launch-blocking: one stock run at 2M, for the bound on any pair style
  poly     bench/gpu.py --scene poly: the 1:10 polydisperse squeeze at 2M, stock kk and griddem
  census   bench/gpu.py --census at 8M: each kernel's time per step
  largest  the largest chute that the griddem history style's memory slope (peak GPU memory at
           8M and 32M from the chute step) says fits in 90% of the device's memory, 100 steps

Out folder (--out; $OUT on the device machine): session.jsonl (one line per step: name, status,
seconds, what it found), gpu.jsonl (bench/gpu.py's lines, to be appended to
bench/results/gpu.jsonl after the session), session.log (every step's output, with headers).

--cpu N runs the same steps end to end on N OpenMP threads with small sizes (a Kokkos OpenMP
build) and caps 10x longer, so that a GPU session never fails on a script error; bound is then
skipped (CUDA only).

usage: bench/gpu_session.py --lmp LMP[.xz] --out DIR [--deadline 420] [--cpu N] [--only STEP,...]
                            [--lammps-bench DIR]
"""
import argparse
import json
import lzma
import os
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
GPU_PY = os.path.join(HERE, "gpu.py")
KK_SECTIONS = "laws,classes,growth,migration,add_delete,restart,synchronisation,search"
STOCK, HISTORY = "gran/hooke/history/kk", "griddem/hooke/history/kk"
# (step, cap in seconds, GPU sizes, CPU dry-run sizes)
STEPS = [
    ("start", 30, None, None),
    ("kktests", 120, None, None),
    ("chute", 170, "2M,8M,32M", "32k,64k,128k"),
    ("bound", 25, "2M", None),
    ("poly", 60, "2M", "16k"),
    ("census", 60, "8M", "64k"),
    ("largest", 90, None, None),
]
DRY_LARGEST_CAP = 256000  # atoms: the dry run computes the largest size but runs no more than this
DRY_CAP_FACTOR = 10       # the dry run's caps: a few CPU threads do in 10x the time what a GPU does


class Session:
    def __init__(self, out, deadline):
        self.out, self.end = out, time.time() + deadline
        self.log = open(os.path.join(out, "session.log"), "a")

    def left(self):
        return self.end - time.time()

    def record(self, line):
        print(json.dumps(line), flush=True)
        with open(os.path.join(self.out, "session.jsonl"), "a") as f:
            f.write(json.dumps(line) + "\n")

    def run(self, name, cmd, cap, env=None):
        """Run cmd (its output to session.log) for at most min(cap, time left): (exit code or
        None if it was stopped at its cap or the deadline, seconds)."""
        limit = max(1.0, min(cap, self.left()))
        self.log.write("\n===== %s: %s (at most %.0f s)\n" % (name, " ".join(cmd), limit))
        self.log.flush()
        start = time.time()
        proc = subprocess.Popen(cmd, stdout=self.log, stderr=subprocess.STDOUT, cwd=TOP,
                                env=dict(os.environ, **(env or {})), start_new_session=True)
        try:
            rc = proc.wait(timeout=limit)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # gpu.py and the lmp it runs
            proc.wait()
            rc = None
        self.log.flush()
        return rc, round(time.time() - start, 1)


def unpacked(lmp, scratch):
    """lmp itself, or lmp.xz decompressed into scratch and made executable."""
    if not lmp.endswith(".xz"):
        return os.path.abspath(lmp)
    path = os.path.join(scratch, "lmp")
    with lzma.open(lmp) as src, open(path, "wb") as dst:
        shutil.copyfileobj(src, dst)
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
    return path


def missing_libraries(lmp):
    out = subprocess.run(["ldd", lmp], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True).stdout
    return [line.split()[0] for line in out.splitlines() if "not found" in line]


def bench_lines(path, **match):
    """gpu.jsonl lines whose fields equal match."""
    if not os.path.exists(path):
        return []
    with open(path) as f:
        lines = [json.loads(l) for l in f if l.strip()]
    return [l for l in lines if all(l.get(k) == v for k, v in match.items())]


def device_memory_mib(cpu):
    """Memory the runs can fill: the GPU's total (nvidia-smi), or the host's available memory."""
    if cpu:
        with open("/proc/meminfo") as f:
            return float(next(l.split()[1] for l in f if l.startswith("MemAvailable"))) / 1024.0
    out = subprocess.run(["nvidia-smi", "--query-gpu=memory.total", "--format=csv,noheader,nounits", "-i", "0"],
                         stdout=subprocess.PIPE, universal_newlines=True).stdout
    return float(out.split()[0])


def largest_size(results, cpu):
    """(atoms, how) from the griddem history style's chute memory at its two largest sizes."""
    key = "host_peak_rss_mib" if cpu else "gpu_peak_mem_mib"
    most = {}    # per size, the most memory of its runs (one a search mode)
    for l in bench_lines(results, scene="chute", style=HISTORY, status="ok"):
        if l.get(key) and not l.get("kernels") and not l.get("launch_blocking"):
            most[l["natoms"]] = max(most.get(l["natoms"], 0.0), l[key])
    ok = sorted(most.items())
    if len(ok) < 2:
        return None, "fewer than two chute sizes with griddem/hooke/history/kk measured"
    (n1, m1), (n2, m2) = ok[-2], ok[-1]
    slope = (m2 - m1) / float(n2 - n1)  # MiB per atom
    if slope <= 0:
        return None, "memory did not grow from %d to %d atoms" % (n1, n2)
    room = 0.9 * device_memory_mib(cpu)
    atoms = int((room - (m2 - slope * n2)) / slope)
    how = "%.0f B/atom from %d to %d atoms; 90%% of %.0f MiB" % (slope * 2**20, n1, n2, room / 0.9)
    return atoms, how


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lmp", required=True, help="a Kokkos lmp (CUDA for a GPU session), or lmp.xz")
    ap.add_argument("--out", required=True, help="folder for session.jsonl, gpu.jsonl and session.log")
    ap.add_argument("--deadline", type=float, default=420.0, help="seconds for all steps together")
    ap.add_argument("--cpu", type=int, default=None, metavar="N",
                    help="dry run on N OpenMP threads with small sizes (a Kokkos OpenMP build)")
    ap.add_argument("--only", default=None, help="comma-separated steps to run (default: all, in order)")
    ap.add_argument("--lammps-bench", default=os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench"),
                    help="folder of LAMMPS's data.chute and in.chute.scaled")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    session = Session(args.out, args.deadline)
    scratch = tempfile.mkdtemp(prefix="griddem-session-")
    lmp = unpacked(args.lmp, scratch)
    results = os.path.join(os.path.abspath(args.out), "gpu.jsonl")
    device = ["--threads", str(args.cpu)] if args.cpu else ["--gpu"]
    gpu_py = [sys.executable, GPU_PY, "--lmp", lmp, "--results", results,
              "--lammps-bench", os.path.abspath(args.lammps_bench)] + device
    only = args.only.split(",") if args.only else [s[0] for s in STEPS]
    session.record({"step": "session", "lmp": args.lmp, "deadline_s": args.deadline,
                    "mode": "cpu %d threads" % args.cpu if args.cpu else "gpu", "steps": only,
                    "date": time.strftime("%Y-%m-%d %H:%M:%S")})
    for name, cap, gpu_sizes, cpu_sizes in STEPS:
        if name not in only:
            continue
        line = {"step": name}
        if session.left() < 5:
            line.update(status="not reached", reason="deadline")
            session.record(line)
            continue
        sizes = cpu_sizes if args.cpu else gpu_sizes
        rc, env = None, {}
        if name == "start":
            missing = missing_libraries(lmp)
            line["missing_libraries"] = missing
            kk = ["-k", "on"] + (["t", str(args.cpu)] if args.cpu else ["g", "1"])
            cmd = [lmp] + kk + ["-sf", "kk", "-in", "/dev/null", "-log", "none"]
        elif name == "kktests":
            counter = os.path.join(scratch, "griddem_sync_counter.so")
            subprocess.run(["cc", "-O2", "-shared", "-fPIC", "-o", counter,
                            os.path.join(TOP, "unittest", "kokkos_tools", "sync_counter.c")])
            env = {"GRIDDEM_LMP": lmp, "GRIDDEM_SYNC_COUNTER": counter}
            env.update({"OMP_NUM_THREADS": str(args.cpu)} if args.cpu else {"GRIDDEM_KK_GPUS": "1"})
            cmd = [sys.executable, os.path.join(TOP, "unittest", "lammps", "test_kokkos.py"), "--only", KK_SECTIONS]
            line["sections"] = KK_SECTIONS
        elif name == "chute":
            cmd = gpu_py + ["--sizes", sizes, "--only", ",".join([STOCK, HISTORY]), "--search", "thread,team"]
        elif name == "bound":
            if args.cpu:
                line.update(status="skipped", reason="CUDA_LAUNCH_BLOCKING needs a GPU")
                session.record(line)
                continue
            cmd = gpu_py + ["--sizes", sizes, "--only", STOCK, "--launch-blocking"]
        elif name == "poly":
            cmd = gpu_py + ["--scene", "poly", "--sizes", sizes, "--only", ",".join([STOCK, HISTORY])] + (
                ["--prep", "500"] if args.cpu else [])
        elif name == "census":
            cmd = gpu_py + ["--sizes", sizes, "--census", "--only", ",".join([STOCK, HISTORY])]
        elif name == "largest":
            atoms, how = largest_size(results, args.cpu)
            line["how"] = how
            if atoms is None:
                line.update(status="skipped", reason=how)
                session.record(line)
                continue
            line["fits_atoms"] = atoms
            if args.cpu:
                atoms = min(atoms, DRY_LARGEST_CAP)
            cmd = gpu_py + ["--sizes", str(atoms), "--only", HISTORY, "--timeout", str(int(cap))]
        before = len(bench_lines(results))
        rc, seconds = session.run(name, cmd, cap * (DRY_CAP_FACTOR if args.cpu else 1), env)
        line.update(status="ok" if rc == 0 else "stopped at %.0f s" % seconds if rc is None else "exit %d" % rc,
                    seconds=seconds)
        if name == "start":
            line["started"] = rc == 0 and not line["missing_libraries"]
        if name == "kktests":
            with open(os.path.join(args.out, "session.log")) as f:
                tail = [l for l in f.read().splitlines() if " passed, " in l and " failed" in l]
            line["result"] = tail[-1] if tail else None
        if cmd[:2] == [sys.executable, GPU_PY]:
            line["bench_lines"] = len(bench_lines(results)) - before
        session.record(line)
    shutil.rmtree(scratch, ignore_errors=True)


main()
