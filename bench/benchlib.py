"""Shared by the benchmark harnesses: the machine's name, the last run's loop time, one input run on
ranks and threads, one result recorded, LAMMPS's chute with a law of pair granular."""
import os
import platform
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))  # griddemtools
from griddemtools import lammps, log  # noqa: E402


def device():
    """CPU model and core count, as recorded with every result."""
    name = platform.processor()
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                name = line.split(":", 1)[1].strip()
                break
    return "%s, %d cores" % (name, os.cpu_count())


def commit(dirty=False):
    """The repository's commit (short), the build a result names unless told another; dirty: with
    -dirty where the work tree differs from it. "unknown" outside a git checkout."""
    top = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    args = ["describe", "--always", "--dirty"] if dirty else ["rev-parse", "--short", "HEAD"]
    try:
        return subprocess.run(["git", "-C", top] + args, stdout=subprocess.PIPE, universal_newlines=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def loop_time(out, what):
    """(loop seconds, steps, atoms) of the last run in LAMMPS's screen output."""
    runs = log.loop_times(out)
    if not runs:
        print(out[-3000:])
        raise SystemExit("no loop time for " + what)
    return runs[-1].seconds, runs[-1].steps, runs[-1].atoms


def run_lmp(lmp, wd, text, ranks, threads=1, extra=(), env=None):
    """Run an input text with lmp on `ranks` MPI ranks and `threads` OpenMP threads each, with the
    command-line switches `extra` (Kokkos's, say) and the variables `env` added to the
    environment; returns (loop seconds, steps, atoms, screen output) of its last run."""
    with open(os.path.join(wd, "in.run"), "w") as f:
        f.write(text)
    out = lammps.run(lmp, list(extra) + ["-in", "in.run", "-log", "none"], wd, ranks, threads,
                     ["--bind-to", "core", "-x", "OMP_NUM_THREADS"], env).stdout
    return loop_time(out, "%s on %d ranks" % (text.splitlines()[0], ranks)) + (out,)


def run_rounds(lmp, wd, runs, rounds, path, scene, build, fields=None):
    """Each run of runs, a tuple (label, input text, ranks, threads), `rounds` times in turn (the
    first round of every run, then the second, ...), so that the machine's swings fall on every
    variant alike; each run recorded in path (build, its round, and fields(screen output)'s items),
    then per rank count each label's median loop time and stock's median over it printed: the
    job's ratio."""
    loops = {}
    for r in range(rounds):
        for label, text, ranks, threads in runs:
            loop, steps, atoms, out = run_lmp(lmp, wd, text, ranks, threads)
            record(path, scene, label, ranks, threads, loop, steps, atoms, build=build, round=r + 1, rounds=rounds,
                   **(fields(out) if fields else {}))
            loops.setdefault((ranks, label), []).append(loop)
    for (ranks, label), times in loops.items():
        ratio = ""
        if label != "stock" and (ranks, "stock") in loops:
            stock = statistics.median(loops[(ranks, "stock")])
            ratio = ", %.2fx of stock's speed (stock %.3f s)" % (stock / statistics.median(times), stock)
        print("%s, %d rank(s): %s median %.3f s of %d runs%s" % (scene, ranks, label, statistics.median(times),
                                                                 len(times), ratio))


def record(path, scene, style, ranks, threads, loop, steps, atoms, **extra):
    """One JSON line for a run (date, machine, scene, style, speed), printed and appended to path."""
    import datetime
    import json
    line = {"date": datetime.date.today().isoformat(), "device": device(), "scene": scene,
            "natoms": atoms, "steps": steps, "ranks": ranks, "threads": threads, "style": style}
    line.update(extra)
    line.update({"loop_s": loop, "atom_steps_per_s": atoms * steps / loop})
    print(json.dumps(line))
    with open(path, "a") as f:
        f.write(json.dumps(line) + "\n")


# The composed laws of the examples' pair granular scenes, with the stiffness and friction of
# LAMMPS's chute: "rolling" is examples/rom-blade's and rom-hopper's set of sub-models,
# "nohistory" that of examples/hopper, packing and sliding.
GRANULAR_LAWS = {
    "rolling": "hooke 200000 0.01 damping coeff_restitution tangential linear_history 100000 1.0 0.5 "
               "rolling sds 100000 0.1 0.2",
    "nohistory": "hooke 200000 50 damping velocity tangential linear_nohistory 1.0 0.5"}
# each gran/hooke/history style's pair granular twin
GRANULAR_TWIN = {"gran/hooke/history": "granular", "griddem/hooke/history": "griddem/granular"}


def chute_granular(text, law):
    """LAMMPS's chute input (bench/in.chute) with each pair style's pair granular twin and
    GRANULAR_LAWS[law] for every type pair."""
    def twin(m):
        return "pair_style      %s\npair_coeff      * * %s" % (GRANULAR_TWIN[m.group(1)], GRANULAR_LAWS[law])
    return re.sub(r"pair_style\s+(\S+).*\npair_coeff\s+\* \*", twin, text)
