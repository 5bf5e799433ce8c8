"""The suite's MPI tests beside another LAMMPS MPI run, and a failed MPI start reported as such.

1. Three rounds of an MPI test of the suite (SUITE_TESTS) pass while another LAMMPS run,
   `mpirun -np 2 lmp` on a tiny input, starts and stops in a loop beside them. Everything shares
   one temporary folder, as programs on one machine share /tmp: Open MPI 4 makes its session
   directory <TMPDIR>/ompi.<host>.<uid> at each start and removes it, when empty, at each end, and
   a start that meets another program's end fails ("mkdir ...: File exists", or "No such file or
   directory" one level down). Two LAMMPS runs meet too rarely for a test of a minute to see it,
   so with Open MPI 4 a third neighbour makes and removes that directory as fast as it can, as
   Open MPI's starts and ends do: then a test that shares the folder fails in most rounds.
   griddem_testlib gives each test a folder of its own, and none of its starts can meet the
   neighbours'.
2. A run whose MPI cannot start (Open MPI's session directory under a plain file) raises
   MPIStartError quoting Open MPI's message, on 1 and 2 ranks, instead of returning an exit code
   a test would read as the input's fault."""
import errno
import os
import socket
import subprocess
import sys
import threading
import time

import griddem_testlib as t

HERE = os.path.dirname(os.path.abspath(__file__))
SUITE_TESTS = ("history_lifecycle",)
ROUNDS = 3
# between two runs of the loop beside: back to back they would hold Open MPI's session directory
# almost all the time, and the churn could seldom remove it
PAUSE = 0.5
TINY = """
units lj
atom_style sphere
lattice sc 1.0
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
"""


def mpirun(nprocs):
    return ["mpirun", "-np", str(nprocs), "--oversubscribe"] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])


class BesideLoop(threading.Thread):
    """mpirun -np 2 lmp on TINY, again and again until stopped; counts runs and failures."""

    def __init__(self, wd, env):
        super().__init__()
        self.cmd = mpirun(2) + [os.path.abspath(t.LMP), "-in", "in.tiny", "-log", "none"]
        self.wd, self.env = wd, env
        self.stop = threading.Event()
        self.runs, self.failed, self.first_failure = 0, 0, ""
        with open(os.path.join(wd, "in.tiny"), "w") as f:
            f.write(TINY)

    def run(self):
        while not self.stop.is_set():
            proc = subprocess.run(self.cmd, cwd=self.wd, env=self.env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, universal_newlines=True)
            self.runs += 1
            if proc.returncode != 0:
                self.failed += 1
                self.first_failure = self.first_failure or proc.stdout[:3000]
            self.stop.wait(PAUSE)


class SessionDirChurn(threading.Thread):
    """Makes Open MPI 4's top session directory in folder and removes it, in a loop, until
    stopped; counts the removals, and the times it held another program's session (not empty)."""

    def __init__(self, folder):
        super().__init__()
        self.path = os.path.join(folder, "ompi.%s.%d" % (socket.gethostname().split(".")[0], os.getuid()))
        self.stop = threading.Event()
        self.removed, self.held = 0, 0

    def run(self):
        while not self.stop.is_set():
            try:
                os.mkdir(self.path)
            except FileExistsError:
                pass
            try:
                os.rmdir(self.path)
                self.removed += 1
            except OSError as e:
                self.held += e.errno == errno.ENOTEMPTY


def check_beside_another_run():
    shared = t.workdir()
    # the caller's environment with one temporary folder for all; the tests take their own in it
    env = {k: v for k, v in os.environ.items() if k not in t.TMP_VARIABLES}
    env["TMPDIR"] = shared
    # the churn makes Open MPI 4's name; with another version, the LAMMPS loop alone
    open_mpi_4 = "(Open MPI) 4." in subprocess.run(["mpirun", "--version"], stdout=subprocess.PIPE,
                                                   universal_newlines=True).stdout
    neighbours = [BesideLoop(t.workdir(), env)] + ([SessionDirChurn(shared)] if open_mpi_4 else [])
    loop = neighbours[0]
    for neighbour in neighbours:
        neighbour.start()
    start = time.time()
    try:
        for round_ in range(1, ROUNDS + 1):
            for name in SUITE_TESTS:
                before = loop.runs
                proc = subprocess.run([sys.executable, os.path.join(HERE, "test_%s.py" % name)], env=env,
                                      stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)
                print("round %d: test_%s exit %d, %d runs of the loop beside it"
                      % (round_, name, proc.returncode, loop.runs - before))
                t.check(proc.returncode == 0, "round %d: test_%s passes beside the loop: %s"
                        % (round_, name, proc.stdout[-3000:]))
                t.check(loop.runs > before, "round %d: the LAMMPS run beside started and stopped during test_%s"
                        % (round_, name))
    finally:
        for neighbour in neighbours:
            neighbour.stop.set()
            neighbour.join()
    print("beside: %d LAMMPS runs in %.0f s (%d failed to start)" % (loop.runs, time.time() - start, loop.failed))
    for churn in neighbours[1:]:
        print("beside: %s removed %d times, held by a run %d times" % (churn.path, churn.removed, churn.held))
        t.check(churn.removed > 0 and churn.held > 0, "the neighbour removed the directory Open MPI's runs make")


def check_start_failure_reported():
    wd = t.workdir()
    plain_file = os.path.join(wd, "not-a-folder")
    open(plain_file, "w").close()
    session = {k: os.environ.get(k) for k in t.TMP_VARIABLES if k != "TMPDIR"}
    os.environ.update({k: plain_file for k in session})
    try:
        for nprocs in (1, 2):
            try:
                rc, out = t.run_lmp(TINY, wd, nprocs=nprocs)
                said = "returned exit %d: %s" % (rc, out[:300])
            except t.MPIStartError as e:
                said = str(e)
            print("session directory under a file, %d rank(s): %s" % (nprocs, said.splitlines()[0]))
            t.check(said.startswith("Open MPI could not start") and plain_file in said,
                    "%d rank(s): MPIStartError quoting Open MPI's message on %s: %s" % (nprocs, plain_file, said))
    finally:
        for k, v in session.items():
            if v is None:
                os.environ.pop(k)
            else:
                os.environ[k] = v


check_beside_another_run()
check_start_failure_reported()
t.finish()
