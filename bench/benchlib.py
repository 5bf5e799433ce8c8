"""Shared by the benchmark harnesses: the machine's name, LAMMPS's loop time and timing breakdown."""
import os
import platform
import re


def device():
    """CPU model and core count, as recorded with every result."""
    name = platform.processor()
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                name = line.split(":", 1)[1].strip()
                break
    return "%s, %d cores" % (name, os.cpu_count())


def loop_time(out, what):
    """(loop seconds, steps, atoms) of the last run in LAMMPS's screen output."""
    found = re.findall(r"Loop time of ([0-9.e+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", out)
    if not found:
        print(out[-3000:])
        raise SystemExit("no loop time for " + what)
    loop, _, steps, atoms = found[-1]
    return float(loop), int(steps), int(atoms)


def timing_sections(out):
    """{section: percent of the loop} from the last run's "MPI task timing breakdown" (Pair, Neigh,
    Comm, Output, Modify, Other); {} if there is none."""
    table = out.rpartition("MPI task timing breakdown:")[2].split("\n\n")[0]
    return {k: float(v) for k, v in re.findall(r"^(\w+)\s*\|.*\|\s*([0-9.]+)\s*$", table, re.M)}


def run_lmp(lmp, wd, text, ranks, threads=1, extra=(), env=None):
    """Run an input text with lmp on `ranks` MPI ranks and `threads` OpenMP threads each, with the
    command-line switches `extra` (Kokkos's, say) and the variables `env` added to the
    environment; returns (loop seconds, steps, atoms, screen output) of its last run."""
    import subprocess
    with open(os.path.join(wd, "in.run"), "w") as f:
        f.write(text)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMP_NUM_THREADS=str(threads), **(env or {}))
    cmd = [lmp] + list(extra) + ["-in", "in.run", "-log", "none"]
    if ranks > 1:
        cmd = ["mpirun", "-np", str(ranks), "--bind-to", "core", "-x", "OMP_NUM_THREADS"] + cmd
    out = subprocess.run(cmd, cwd=wd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True).stdout
    return loop_time(out, "%s on %d ranks" % (text.splitlines()[0], ranks)) + (out,)


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
