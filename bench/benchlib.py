"""Shared by the benchmark harnesses: the machine's name and LAMMPS's loop time."""
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
