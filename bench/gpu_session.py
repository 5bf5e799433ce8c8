#!/usr/bin/env python3
"""One GPU session's measurements, in priority order, under one deadline, from a bundle alone.

A lent GPU machine gives minutes, not hours, and holds only what is sent to it. This script runs
from a bundle (bench/gpu_bundle.py: the lmp, the CUDA runtime it links, and every program, script
and data file the steps read) and reads nothing outside it. It runs these steps in order, each
under its own cap and all under --deadline, and writes every result as soon as it has it, so that
a session cut short still keeps what it reached:

  start    the lmp loads (ldd, with the bundle's lib/ first: no library or symbol version
           missing), on a GPU the driver is there and supports the lmp's CUDA runtime, lmp -h
           runs and names KOKKOS (its device back end on a GPU), and the lmp initialises Kokkos;
           if any of these fails the script stops, its reason recorded
  kktests  test_kokkos.py's GPU sections (KK_SECTIONS: list and row layouts, size classes,
           history rows that grow, migrate, are added and deleted and go through restart, the
           blocking synchronisations of a step, counted by unittest/kokkos_tools/sync_counter.c,
           built here with cc, the team search against the thread search), GRIDDEM_KK_GPUS=1
  chute    bench/gpu.py: stock and griddem/hooke/history/kk (fix griddem search thread and team)
           on LAMMPS's chute at 2M, 8M and 32M atoms
  bound    bench/gpu.py --launch-blocking: one stock run at 2M, for the bound on any pair style
  poly     bench/gpu.py --scene poly: the 1:10 polydisperse squeeze at 2M, stock kk and griddem
  census   bench/gpu.py --census at 8M: each kernel's time per step
  largest  the largest chute that fits, by the griddem history style's slopes from the chute
           step's two largest sizes (8M and 32M): its peak GPU memory in 90% of the device's, its
           peak host memory in 90% of the host's available memory, and its whole run (set-up
           included) in half the step's cap (an H200's 74M atoms, at 80%, ran past it); 100 steps

Each step after start checks what it needs (the bundle's files, a KOKKOS lmp, cc) and records one
line: ok, or skipped or failed with its reason; the next step runs either way. Without cc the
kktests step leaves out the synchronisation section and census is skipped, each saying so.

Out folder (--out; $OUT on the device machine): session.jsonl (one line per step: name, status,
reason, seconds, what it found), gpu.jsonl (bench/gpu.py's lines, to be appended to
bench/results/gpu.jsonl after the session), session.log (every step's output, with headers).

--cpu N runs the same steps end to end on N OpenMP threads with small sizes (a Kokkos OpenMP
lmp) and caps 10x longer, so that a GPU session never fails on a script error; bound is then
skipped (CUDA only). With an lmp without KOKKOS the dry run checks the bundle: the kk steps are
skipped, saying so.

usage: BUNDLE/bench/gpu_session.py --out DIR [--deadline 420] [--cpu N] [--only STEP,...]
"""
import argparse
import collections
import ctypes
import json
import lzma
import os
import re
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time

import gpu_bundle as bundle
from gpu import CHUTE_FILES, help_info, reason

HERE = os.path.dirname(os.path.abspath(__file__))
BUNDLE = os.path.dirname(HERE)
KK_SECTIONS = ["laws", "classes", "growth", "migration", "add_delete", "restart", "synchronisation", "search"]
SKIP = 77  # test_kokkos.py's exit code when the lmp has no KOKKOS
STOCK, HISTORY = "gran/hooke/history/kk", "griddem/hooke/history/kk"
START_CAP = 30
DRY_LARGEST_CAP = 256000  # atoms: the dry run computes the largest size but runs no more than this
DRY_CAP_FACTOR = 10       # the dry run's caps: a few CPU threads do in 10x the time what a GPU does
NO_KOKKOS = "lmp has no KOKKOS package (lmp -h)"


class Skipped(Exception):
    """A step that does not apply to this lmp or machine; its reason."""


class Failed(Exception):
    """A step that cannot run; its reason."""


class Session:
    def __init__(self, out, deadline, cpu):
        self.out, self.end, self.cpu = out, time.time() + deadline, cpu
        self.log = open(os.path.join(out, "session.log"), "a")
        self.scratch = tempfile.mkdtemp(prefix="griddem-session-")
        self.results = os.path.join(out, "gpu.jsonl")
        self.lmp = self.api = None

    def left(self):
        return self.end - time.time()

    def record(self, line):
        print(json.dumps(line), flush=True)
        with open(os.path.join(self.out, "session.jsonl"), "a") as f:
            f.write(json.dumps(line) + "\n")

    def run(self, name, cmd, cap, env=None):
        """Run cmd in the scratch folder (its output to session.log) for at most min(cap, time
        left): (exit code or None if it was stopped, seconds, its output, what would stop it)."""
        limit = max(1.0, min(cap, self.left()))
        self.log.write("\n===== %s: %s (at most %.0f s)\n" % (name, " ".join(cmd), limit))
        self.log.flush()
        begin, start = self.log.tell(), time.time()
        proc = subprocess.Popen(cmd, stdout=self.log, stderr=subprocess.STDOUT, cwd=self.scratch,
                                env=dict(os.environ, **(env or {})), start_new_session=True)
        try:
            rc = proc.wait(timeout=limit)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)  # gpu.py and the lmp it runs
            proc.wait()
            rc = None
        self.log.flush()
        with open(self.log.name, "rb") as f:
            f.seek(begin)
            out = f.read().decode(errors="replace")
        return rc, round(time.time() - start, 1), out, "its cap" if limit == cap else "the deadline"

    def kk_switches(self):
        return ["-k", "on"] + (["t", str(self.cpu)] if self.cpu else ["g", "1"])

    def need(self, *paths):
        """Fail the step if the bundle lacks one of paths (relative to it)."""
        absent = [p for p in paths if not os.path.exists(os.path.join(BUNDLE, p))]
        if absent:
            raise Failed("the bundle has no %s" % ", ".join(absent))

    def need_kokkos(self):
        if not self.api:
            raise Skipped(NO_KOKKOS)


def cuda_version(library, function):
    """A CUDA version number (13000 is 13.0) that library's function gives, or the reason it
    gives none."""
    try:
        value = ctypes.c_int()
        rc = getattr(ctypes.CDLL(library), function)(ctypes.byref(value))
    except (OSError, AttributeError) as e:
        return None, str(e)
    return (value.value, None) if rc == 0 else (None, "%s returned %d" % (function, rc))


def version_text(number):
    return "%d.%d" % (number // 1000, number % 1000 // 10)


def unpacked(scratch):
    """The bundle's lmp, or its lmp.xz decompressed into scratch and made executable."""
    lmp = bundle.bundled_lmp(BUNDLE)
    if lmp is None:
        raise Failed("no lmp or lmp.xz in %s: make the bundle with bench/gpu_bundle.py" % BUNDLE)
    if not lmp.endswith(".xz"):
        return lmp
    path = os.path.join(scratch, "lmp")
    with lzma.open(lmp) as src, open(path, "wb") as dst:
        shutil.copyfileobj(src, dst)
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
    return path


def start(s, line):
    """Raises Failed unless the lmp loads, finds its device and initialises Kokkos."""
    s.lmp = unpacked(s.scratch)
    resolved, problems = bundle.ldd(s.lmp, os.path.join(BUNDLE, bundle.LIB))
    if problems:
        raise Failed("%sldd: %s" % ("no NVIDIA driver: " if any("libcuda.so" in p for p in problems) else "",
                                    "; ".join(problems)))
    runtime = [path for name, path in resolved.items() if name.startswith(bundle.CARRIED_LIBRARIES)]
    line["cuda_runtime"] = runtime[0] if runtime else None
    if not s.cpu:
        driver, why = cuda_version("libcuda.so.1", "cuDriverGetVersion")
        if driver is None:
            raise Failed("no NVIDIA driver: %s" % why)
        line["driver_cuda"] = version_text(driver)
        if runtime:
            needed, why = cuda_version(runtime[0], "cudaRuntimeGetVersion")
            if needed is None:
                raise Failed("the CUDA runtime %s gives no version: %s" % (runtime[0], why))
            line["runtime_cuda"] = version_text(needed)
            if driver < needed:
                raise Failed("the driver supports CUDA %s, older than the lmp's runtime %s (%s)" % (
                    version_text(driver), version_text(needed), runtime[0]))
    rc, _, out, _ = s.run("start: lmp -h", [s.lmp, "-h"], START_CAP)
    if rc != 0:
        raise Failed("lmp -h: %s" % ("stopped at %d s" % START_CAP if rc is None else reason(rc, out, False, 0)))
    s.api = help_info(out)[0]
    line["kokkos"] = s.api
    if not s.api:
        if not s.cpu:
            raise Failed(NO_KOKKOS)
        line["note"] = NO_KOKKOS + ": the kk steps are skipped"
        return
    if not s.cpu and "CUDA" not in s.api.split():
        raise Failed("lmp's Kokkos has no CUDA back end (%s)" % s.api)
    rc, seconds, out, _ = s.run("start", [s.lmp] + s.kk_switches() + ["-sf", "kk", "-in", "/dev/null", "-log", "none"],
                                START_CAP)
    line["seconds"] = seconds
    if rc != 0:
        raise Failed("Kokkos does not start: %s" % (
            "stopped at %d s" % START_CAP if rc is None else reason(rc, out, False, 0)))


def sync_counter(s):
    """(the sync counter library built here, or None; why not)."""
    cc = shutil.which("cc")
    if not cc:
        return None, "no C compiler (cc) to build %s" % bundle.SYNC_COUNTER_SOURCE
    lib = os.path.join(s.scratch, "griddem_sync_counter.so")
    built = subprocess.run([cc, "-O2", "-shared", "-fPIC", "-o", lib, os.path.join(BUNDLE, bundle.SYNC_COUNTER_SOURCE)],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
    if built.returncode != 0:
        return None, "cc failed on %s: %s" % (bundle.SYNC_COUNTER_SOURCE, (built.stdout.strip().splitlines() or ["?"])[0])
    return lib, None


def kktests(s, line, cap, sizes):
    s.need(bundle.KK_TESTS, bundle.LIST_SUBMODELS, bundle.SYNC_COUNTER_SOURCE)
    env = {"GRIDDEM_LMP": s.lmp, "GRIDDEM_LIST_SUBMODELS": os.path.join(BUNDLE, bundle.LIST_SUBMODELS)}
    env.update({"OMP_NUM_THREADS": str(s.cpu)} if s.cpu else {"GRIDDEM_KK_GPUS": "1"})
    sections = list(KK_SECTIONS)
    counter, why = sync_counter(s)
    if counter:
        env["GRIDDEM_SYNC_COUNTER"] = counter
    else:
        sections.remove("synchronisation")
        line["not_run"] = {"synchronisation": why}
    line["sections"] = ",".join(sections)
    ran = s.run("kktests", [sys.executable, os.path.join(BUNDLE, bundle.KK_TESTS), "--only", line["sections"]], cap, env)
    out = ran[2]
    tally = re.findall(r"^\d+ passed, \d+ failed$", out, re.M)
    line["result"] = tally[-1] if tally else None
    if ran[0] == SKIP:  # the test's own skip: it found no KOKKOS in the lmp
        raise Skipped(next((l for l in out.splitlines() if l.startswith("SKIPPED")), "test_kokkos.py exit 77")[:300])
    return ran


def bench(s, line, cap, args, on_chute=True, compiles=None):
    """bench/gpu.py with args (on the chute unless on_chute is False; building the bundle's source
    compiles with cc if given), its lines to gpu.jsonl; line gets how many runs ended how."""
    chute_files = [os.path.join(bundle.LAMMPS_BENCH, name) for name in CHUTE_FILES] if on_chute else []
    s.need(bundle.GPU_PY, *chute_files + ([compiles] if compiles else []))
    s.need_kokkos()
    if compiles and not shutil.which("cc"):
        raise Skipped("no C compiler (cc) to build %s" % compiles)
    before = len(bench_lines(s.results))
    device = ["--threads", str(s.cpu)] if s.cpu else ["--gpu"]
    ran = s.run(line["step"], [sys.executable, os.path.join(BUNDLE, bundle.GPU_PY), "--lmp", s.lmp,
                               "--results", s.results, "--lammps-bench", os.path.join(BUNDLE, bundle.LAMMPS_BENCH)]
                + device + args, cap)
    line["runs"] = dict(collections.Counter(l["status"] for l in bench_lines(s.results)[before:]))
    return ran


def chute(s, line, cap, sizes):
    return bench(s, line, cap, ["--sizes", sizes, "--only", ",".join([STOCK, HISTORY]), "--search", "thread,team"])


def bound(s, line, cap, sizes):
    if s.cpu:
        raise Skipped("CUDA_LAUNCH_BLOCKING needs a GPU")
    return bench(s, line, cap, ["--sizes", sizes, "--only", STOCK, "--launch-blocking"])


def poly(s, line, cap, sizes):
    return bench(s, line, cap, ["--scene", "poly", "--sizes", sizes, "--only", ",".join([STOCK, HISTORY])] + (
        ["--prep", "500"] if s.cpu else []), on_chute=False)


def census(s, line, cap, sizes):
    return bench(s, line, cap, ["--sizes", sizes, "--census", "--only", ",".join([STOCK, HISTORY])],
                 compiles=bundle.CENSUS_SOURCE)


def largest(s, line, cap, sizes):
    s.need_kokkos()
    atoms, how = largest_size(s.results, s.cpu, cap)
    line["how"] = how
    if atoms is None:
        raise Skipped(how)
    line["fits_atoms"] = atoms
    if s.cpu:
        atoms = min(atoms, DRY_LARGEST_CAP)
    return bench(s, line, cap, ["--sizes", str(atoms), "--only", HISTORY, "--timeout", str(int(cap))])


# (step, cap in seconds, GPU sizes, CPU dry-run sizes) in order, after start; the kk tests are
# many small runs, each paying the device's start-up: their cap counts on no speed-up over the
# CPU dry run (bench/README.md)
STEPS = [
    (kktests, 300, None, None),
    (chute, 170, "2M,8M,32M", "32k,64k,128k"),
    (bound, 25, "2M", None),
    (poly, 60, "2M", "16k"),
    (census, 60, "8M", "64k"),
    (largest, 90, None, None),
]
STEP_NAMES = [step[0].__name__ for step in STEPS]


def bench_lines(path, **match):
    """gpu.jsonl lines whose fields equal match."""
    if not os.path.exists(path):
        return []
    with open(path) as f:
        lines = [json.loads(l) for l in f if l.strip()]
    return [l for l in lines if all(l.get(k) == v for k, v in match.items())]


def gpu_memory_mib():
    """The GPU's memory (nvidia-smi)."""
    out = subprocess.run(["nvidia-smi", "--query-gpu=memory.total", "--format=csv,noheader,nounits", "-i", "0"],
                         stdout=subprocess.PIPE, universal_newlines=True).stdout
    return float(out.split()[0])


def host_memory_mib():
    """The host's available memory."""
    with open("/proc/meminfo") as f:
        return float(next(l.split()[1] for l in f if l.startswith("MemAvailable"))) / 1024.0


def largest_size(results, cpu, cap):
    """(atoms, how): the most atoms of a chute of the griddem history style that the chute step's
    two largest sizes say fits, linearly in the atoms, in 90% of the GPU's memory (not on a dry
    run), in 90% of the host's available memory, and in half of cap seconds, the whole run; how
    names each bound."""
    # per quantity, its growth through (n1, n2): the most of each size's runs (one a search mode)
    keys = [("gpu_peak_mem_mib", None if cpu else gpu_memory_mib(), 0.9, "GPU MiB"),
            ("host_peak_rss_mib", host_memory_mib(), 0.9, "host MiB"),
            ("wall_s", cap, 0.5, "s")]
    runs = [l for l in bench_lines(results, scene="chute", style=HISTORY, status="ok")
            if not l.get("kernels") and not l.get("launch_blocking")]
    fits, hows = [], []
    for key, whole, share, unit in keys:
        if whole is None:
            continue
        most = {}
        for l in runs:
            if l.get(key):
                most[l["natoms"]] = max(most.get(l["natoms"], 0.0), l[key])
        ok = sorted(most.items())
        if len(ok) < 2:
            return None, "fewer than two chute sizes with griddem/hooke/history/kk's %s measured" % key
        (n1, m1), (n2, m2) = ok[-2], ok[-1]
        slope = (m2 - m1) / float(n2 - n1)
        if slope <= 0:
            return None, "%s did not grow from %d to %d atoms" % (key, n1, n2)
        fits.append(int((share * whole - (m2 - slope * n2)) / slope))
        hows.append("%d atoms: %.4g %s per million atoms from %d to %d, %d%% of %.0f %s" % (
            fits[-1], slope * 1e6, unit, n1, n2, round(100 * share), whole, unit))
    return min(fits), "; ".join(hows)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", required=True, help="folder for session.jsonl, gpu.jsonl and session.log")
    ap.add_argument("--deadline", type=float, default=420.0, help="seconds for all steps together")
    ap.add_argument("--cpu", type=int, default=None, metavar="N",
                    help="dry run on N OpenMP threads with small sizes (a Kokkos OpenMP lmp)")
    ap.add_argument("--only", default=None, help="comma-separated steps to run after start (default: all, in order)")
    args = ap.parse_args()
    only = args.only.split(",") if args.only else STEP_NAMES
    unknown = [name for name in only if name not in STEP_NAMES]
    if unknown:
        raise SystemExit("gpu_session.py --only: no step %s (steps: %s)" % (",".join(unknown), ",".join(STEP_NAMES)))
    # nothing from outside the bundle: no test settings of the caller's, the bundle's libraries first
    for key in [k for k in os.environ if k.startswith("GRIDDEM_") or k == "KOKKOS_TOOLS_LIBS"]:
        del os.environ[key]
    os.environ["LD_LIBRARY_PATH"] = os.pathsep.join(
        p for p in (os.path.join(BUNDLE, bundle.LIB), os.environ.get("LD_LIBRARY_PATH")) if p)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    s = Session(out, args.deadline, args.cpu)
    s.record({"step": "session", "bundle": BUNDLE, "deadline_s": args.deadline,
              "mode": "cpu %d threads" % args.cpu if args.cpu else "gpu", "steps": ["start"] + only,
              "date": time.strftime("%Y-%m-%d %H:%M:%S")})
    line = {"step": "start"}
    try:
        start(s, line)
        line["status"] = "ok"
    except Failed as e:
        line.update(status="failed", reason=str(e))
    except Exception as e:  # an lmp.xz that does not unpack, a fault of this script
        line.update(status="failed", reason="gpu_session.py: %s: %s" % (type(e).__name__, e))
    s.record(line)
    if line["status"] != "ok":
        shutil.rmtree(s.scratch, ignore_errors=True)
        sys.exit(1)
    for step, cap, gpu_sizes, cpu_sizes in STEPS:
        if step.__name__ not in only:
            continue
        line = {"step": step.__name__}
        if s.left() < 5:
            line.update(status="not reached", reason="deadline")
            s.record(line)
            continue
        try:
            rc, seconds, out_text, limit = step(s, line, cap * (DRY_CAP_FACTOR if s.cpu else 1),
                                                cpu_sizes if s.cpu else gpu_sizes)
            line["seconds"] = seconds
            if rc == 0:
                line["status"] = "ok"
            elif rc is None:
                line.update(status="stopped", reason="stopped at %s after %.0f s" % (limit, seconds))
            else:
                line.update(status="failed", reason=reason(rc, out_text, False, 0))
        except Skipped as e:
            line.update(status="skipped", reason=str(e))
        except Failed as e:
            line.update(status="failed", reason=str(e))
        except Exception as e:  # a fault of this script in one step: the next still runs
            line.update(status="failed", reason="gpu_session.py: %s: %s" % (type(e).__name__, e))
        s.record(line)
    shutil.rmtree(s.scratch, ignore_errors=True)


if __name__ == "__main__":
    main()
