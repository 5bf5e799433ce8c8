"""How the examples' and the benchmarks' scripts start LAMMPS: which lmp, its environment (OpenMP
threads; Open MPI's consent to run as root) and its command line, alone or under mpirun."""
import os
import subprocess

TOP = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Open MPI refuses to start as root unless both are set
ROOT_CONSENT = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1"}


def default_lmp():
    """GRIDDEM_LMP if set, else this repository's build/lmp."""
    return os.environ.get("GRIDDEM_LMP") or os.path.join(TOP, "build", "lmp")


def environment(threads=1, extra=None):
    """This process's environment with OMP_NUM_THREADS = threads, Open MPI's root consent and the
    variables extra adds."""
    return dict(os.environ, OMP_NUM_THREADS=str(threads), **ROOT_CONSENT, **(extra or {}))


def command(lmp, args, ranks=1, mpirun_args=()):
    """lmp's command line with args; on more than one rank under mpirun -np ranks, with
    mpirun_args (e.g. --bind-to core) before the program."""
    cmd = [lmp] + list(args)
    if ranks > 1:
        cmd = ["mpirun", "-np", str(ranks)] + list(mpirun_args) + cmd
    return cmd


def run(lmp, args, cwd, ranks=1, threads=1, mpirun_args=(), env=None, output=True, check=False, timeout=None):
    """Run lmp with args in cwd (see command and environment). output: capture the screen output
    (stdout and stderr together, as the result's stdout text); False sends it to /dev/null, None
    leaves it to this process's. check: raise CalledProcessError on a nonzero exit. Returns the
    CompletedProcess."""
    stdout = subprocess.PIPE if output else subprocess.DEVNULL if output is False else None
    return subprocess.run(command(lmp, args, ranks, mpirun_args), cwd=cwd, env=environment(threads, env),
                          stdout=stdout, stderr=subprocess.STDOUT if output else None,
                          universal_newlines=True, check=check, timeout=timeout)


def list_submodels_program(lmp):
    """unittest/core/list_submodels (the sub-model table's printer): GRIDDEM_LIST_SUBMODELS (set by
    ctest), else the one in the build folder of lmp."""
    return os.environ.get("GRIDDEM_LIST_SUBMODELS") or os.path.join(
        os.path.dirname(os.path.abspath(lmp)), "unittest", "core", "list_submodels")
