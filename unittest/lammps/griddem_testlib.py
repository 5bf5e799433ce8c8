"""Helpers for GRIDDEM's LAMMPS-level tests: run build/lmp on an input text (optionally under
mpirun), read dump files and thermo columns (with python/griddemtools's plain readers, which
python.griddemtools checks), make random polydisperse sphere configurations, compare numbers.
Standard library only."""
import atexit
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from griddemtools import dump, lammps, log  # noqa: E402
from griddemtools.spheres import write_random_spheres  # noqa: E402,F401 (the tests' scenes)

LMP = os.path.abspath(os.environ.get("GRIDDEM_LMP", "lmp")) if os.sep in os.environ.get("GRIDDEM_LMP", "lmp") else os.environ.get("GRIDDEM_LMP", "lmp")
# with GRIDDEM_PLUGIN set (a griddemplugin.so), every input starts by loading it: the tests then
# run GRIDDEM's styles through a LAMMPS built without them
PLUGIN = os.path.abspath(os.environ["GRIDDEM_PLUGIN"]) if os.environ.get("GRIDDEM_PLUGIN") else None
_failures = []
_passed = 0
# the temporary folder of a process, and where Open MPI 4 puts its session directories
TMP_VARIABLES = ("TMPDIR", "OMPI_MCA_orte_tmpdir_base")


def _own_tmpdir():
    """Give everything this test starts (lmp, mpirun, the examples' scripts) a temporary folder
    of its own, removed at exit. Open MPI 4 keeps its session directory in
    <TMPDIR>/ompi.<host>.<uid>, made by every start and removed by every end: a program that
    starts or ends beside ours in the same folder can stop ours from starting ("mkdir ...: File
    exists"). tempfile has chosen the folder of this test's own workdir()s by then: they stay
    where they were. The MCA setting overrides a site's own."""
    folder = tempfile.mkdtemp(prefix="griddem-tmp-")
    callers = {k: os.environ[k] for k in TMP_VARIABLES if k in os.environ}
    os.environ.update({k: folder for k in TMP_VARIABLES})
    atexit.register(shutil.rmtree, folder, True)
    return folder, callers


TMPDIR, _callers_tmp_environment = _own_tmpdir()

# What Open MPI prints when a process could not start (its runtime, or MPI_Init)
MPI_START_FAILED = ("It looks like orte_init failed", "It looks like opal_init failed",
                    "It looks like MPI_INIT failed", "before MPI_INIT completed")


class MPIStartError(RuntimeError):
    """Open MPI could not start a run: a fault of the machine's MPI, not of the input."""


# the start of an input on a read_data configuration, for format(data=, pair=, coeffs=)
PERIODIC_SPHERES = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
pair_style {pair}
{coeffs}
"""

# an empty periodic box of edge 6 for spheres of one type, with an atom map
PERIODIC_BOX6 = """
units lj
atom_style sphere
atom_modify map array
boundary p p p
comm_modify vel yes
region box block 0 6 0 6 0 6
create_box 1 box
"""
# 125 spheres of density 1 on a simple cubic lattice of spacing 1 in it, for format(diameter=)
LATTICE_SPHERES = PERIODIC_BOX6 + """lattice sc 1.0
region fill block 0.5 5.5 0.5 5.5 0.5 5.5
create_atoms 1 region fill
set type 1 diameter {diameter}
set type 1 density 1.0
"""


def submodel_table():
    """The sub-model table (griddem_submodels.c) as unittest/core/list_submodels prints it:
    ([(label, type 1 arguments, type 2 arguments)] of the rows' examples, [(keyword, name)] of
    pair granular's models that the table does not evaluate)."""
    lines = subprocess.run([lammps.list_submodels_program(LMP)], stdout=subprocess.PIPE, universal_newlines=True,
                           check=True).stdout.splitlines()
    rows = [line.split("\t") for line in lines]
    return ([tuple(r[1:]) for r in rows if r[0] == "example"],
            [tuple(r[1:]) for r in rows if r[0] == "stock_only"])


def require_modules(modules, message, skip):
    """Return if this Python imports every module; else run this script again, once, under
    Debian's /usr/bin/python3 (CMake may have found another Python, pyenv's, without Debian's
    packages); else print message and exit 77 (reported as skipped) if skip, 1 if not."""
    import importlib
    try:
        for name in modules:
            importlib.import_module(name)
        return
    except ImportError:
        pass
    if os.path.exists("/usr/bin/python3") and os.environ.get("GRIDDEM_REEXEC") != "1":
        # the new process makes a temporary folder of its own, in the caller's
        shutil.rmtree(TMPDIR, True)
        env = {k: v for k, v in os.environ.items() if k not in TMP_VARIABLES}
        env.update(_callers_tmp_environment, GRIDDEM_REEXEC="1")
        os.execve("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv, env)
    print(message, file=sys.stderr)
    sys.exit(77 if skip else 1)


def check(cond, message):
    """Record one assertion; report it if it fails."""
    global _passed
    if cond:
        _passed += 1
    else:
        _failures.append(message)
        print("FAILED: " + message, file=sys.stderr)


def finish():
    print("%d passed, %d failed" % (_passed, len(_failures)))
    sys.exit(1 if _failures or _passed == 0 else 0)


def workdir():
    return tempfile.mkdtemp(prefix="griddem-test-")


def run_lmp(text, cwd, nprocs=1, name="in.test", extra=(), threads=None, timeout=900):
    """Run an input (with threads OpenMP threads if given); returns (exit code, screen output).
    Raises subprocess.TimeoutExpired after timeout seconds, MPIStartError with Open MPI's
    message where MPI did not start."""
    path = os.path.join(cwd, name)
    with open(path, "w") as f:
        if PLUGIN:
            f.write("plugin load %s\n" % PLUGIN)
        f.write(text)
    cmd = [LMP, "-in", name, "-log", "none", "-echo", "screen"] + list(extra)
    if nprocs > 1:
        env_root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
        cmd = ["mpirun", "-np", str(nprocs), "--oversubscribe"] + env_root + cmd
    env = dict(os.environ, OMP_NUM_THREADS=str(threads)) if threads else None
    proc = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=timeout, env=env)
    if proc.returncode != 0 and any(m in proc.stdout for m in MPI_START_FAILED):
        raise MPIStartError("Open MPI could not start %s in %s (exit %d); its output:\n%s"
                            % (" ".join(cmd), cwd, proc.returncode, proc.stdout[:6000]))
    return proc.returncode, proc.stdout


def errors(out):
    """The ERROR lines of a run's screen output."""
    return [line for line in out.splitlines() if "ERROR" in line]


def run_ok(text, cwd, nprocs=1, name="in.test", threads=None):
    rc, out = run_lmp(text, cwd, nprocs, name, threads=threads)
    if rc != 0:
        print(out[-4000:], file=sys.stderr)
        raise SystemExit("lmp failed (exit %d) on %s" % (rc, name))
    return out


def read_dumps(path):
    """Snapshots of a dump custom file, each (column names but id, {id: [values...]})."""
    return [([c for c in s.columns if c != "id"], s.by_id()) for s in dump.read_dump(path)]


def read_dump(path):
    """Last snapshot of a dump custom file."""
    return read_dumps(path)[-1]


def max_rel_diff(a, b, columns):
    """dump.max_rel_diff, the two dumps checked to hold the same atom IDs first."""
    check(sorted(a[1]) == sorted(b[1]), "same atom IDs in both dumps")
    return dump.max_rel_diff(a, b, columns)


def thermo_values(out, column):
    """All values of a thermo column printed to the screen."""
    return log.thermo(out, column)


def write_rom_model(path, n, box, controls=0, bias=(0.0, 0.0, 0.0), version=1, nrow=None, ncol=None,
                    control_weight=None, frame=None, vx_of_voxel=None, force=None):
    """A model whose field is the uniform bias (plus control_weight * control 1 on vx; plus
    vx_of_voxel(m) on vx of voxel m). frame: a 'frame' line's word (version 2: 'moving'); force:
    3 rows of the 'force' block (version 2)."""
    nvox = n[0] * n[1] * n[2]
    nrow = 3 * nvox if nrow is None else nrow
    ncol = 1 + nvox + controls if ncol is None else ncol
    with open(path, "w") as f:
        f.write("# test model\ngriddem/rom %s\ngrid %d %d %d\nbox %s\n"
                % (version, n[0], n[1], n[2], " ".join("%.17g" % b for b in box)))
        if frame is not None:
            f.write("frame %s\n" % frame)
        f.write("controls %d\nlambda 0.001\n" % controls)
        f.write("weights %d %d\n" % (nrow, ncol))
        for r in range(nrow):
            row = [0.0] * ncol
            row[0] = bias[r % 3]
            if vx_of_voxel is not None and r % 3 == 0:
                row[0] += vx_of_voxel(r // 3)
            if control_weight is not None and r % 3 == 0:
                row[ncol - 1] = control_weight
            f.write(" ".join("%.17g" % w for w in row) + "\n")
        if force is not None:
            f.write("force %d %d\n" % (len(force), len(force[0])))
            for row in force:
                f.write(" ".join("%.17g" % w for w in row) + "\n")
