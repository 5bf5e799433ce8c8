"""tools/install-deps never removes a package, and keeps Debian's ParaView (python3-paraview
conflicts with python3-vtk9, and ships the VTK modules the project needs).

1. The plan on made-up machines: dpkg-query and apt-get replaced by stand-ins on PATH (the
   stand-in dpkg-query reports installed every package but those in STUB_MISSING; apt-get records
   its arguments), so the case runs anywhere:
   - ParaView's Python installed, python3-vtk9 and python3-scipy missing: installs python3-scipy
     with --no-remove, and not python3-vtk9 (which would remove ParaView);
   - neither installed: installs python3-vtk9, with --no-remove.
2. The plan on this machine, by apt itself: `install-deps --simulate` (apt-get -s install
   --no-remove of every package wanted) succeeds and removes nothing. With python3-paraview
   installed, asking for python3-vtk9 would make apt refuse (exit 100)."""
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "lammps"))
import griddem_testlib as t  # noqa: E402  (the suite's check and closing line)

INSTALL_DEPS = os.path.join(HERE, "..", "..", "tools", "install-deps")

STUBS = {
    "dpkg-query": '#!/bin/sh\n'
                  'for pkg; do :; done\n'
                  'case " $STUB_MISSING " in *" $pkg "*) exit 1 ;; esac\n'
                  'printf "install ok installed"\n',
    "apt-get": '#!/bin/sh\necho "$*" >> "$STUB_LOG"\n',
    "sudo": '#!/bin/sh\nexec "$@"\n',
}

def planned_installs(stubs, missing):
    """The apt-get install commands install-deps runs where the packages in missing are not
    installed: a list of argument lists."""
    log = os.path.join(stubs, "apt.log")
    if os.path.exists(log):
        os.remove(log)
    env = dict(os.environ, PATH=stubs + os.pathsep + os.environ["PATH"], STUB_MISSING=" ".join(missing),
               STUB_LOG=log)
    proc = subprocess.run([INSTALL_DEPS], env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True)
    t.check(proc.returncode == 0, "install-deps with %s missing: exit %d %s" % (missing, proc.returncode, proc.stdout))
    if not os.path.exists(log):
        return []
    with open(log) as f:
        return [line.split() for line in f if line.split()[:1] != ["update"]
                and "install" in line.split()]


def check_made_up_machines():
    stubs = tempfile.mkdtemp(prefix="griddem-stubs-")
    try:
        for name, text in STUBS.items():
            path = os.path.join(stubs, name)
            with open(path, "w") as f:
                f.write(text)
            os.chmod(path, 0o755)

        plans = planned_installs(stubs, ["python3-vtk9", "python3-scipy"])
        print("ParaView's Python installed: %s" % plans)
        t.check(len(plans) == 1, "ParaView installed: one apt-get install (%s)" % plans)
        for plan in plans:
            t.check("--no-remove" in plan, "ParaView installed: apt-get install --no-remove (%s)" % plan)
            t.check("python3-scipy" in plan, "ParaView installed: the missing python3-scipy is installed (%s)" % plan)
            t.check("python3-vtk9" not in plan, "ParaView installed: python3-vtk9, which would remove it, is not "
                  "installed (%s)" % plan)

        plans = planned_installs(stubs, ["python3-vtk9", "python3-paraview", "python3-scipy"])
        print("no VTK: %s" % plans)
        t.check(len(plans) == 1, "no VTK: one apt-get install (%s)" % plans)
        for plan in plans:
            t.check("--no-remove" in plan, "no VTK: apt-get install --no-remove (%s)" % plan)
            t.check("python3-vtk9" in plan and "python3-scipy" in plan,
                  "no VTK: python3-vtk9 and python3-scipy are installed (%s)" % plan)
    finally:
        shutil.rmtree(stubs)


def check_this_machine():
    if not shutil.which("apt-get"):
        print("this machine: no apt-get, apt's own plan not checked")
        return
    proc = subprocess.run([INSTALL_DEPS, "--simulate"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True)
    removals = [line for line in proc.stdout.splitlines() if line.startswith("Remv ")]
    paraview = subprocess.run(["dpkg-query", "-W", "-f=${Status}", "python3-paraview"], stdout=subprocess.PIPE,
                              stderr=subprocess.DEVNULL, universal_newlines=True).stdout == "install ok installed"
    print("this machine (python3-paraview %s): apt-get -s exit %d, %d removals"
          % ("installed" if paraview else "not installed", proc.returncode, len(removals)))
    t.check(proc.returncode == 0, "install-deps --simulate: apt accepts the plan (exit %d): %s"
          % (proc.returncode, proc.stdout[-1500:]))
    t.check(not removals, "install-deps --simulate: apt removes nothing (%s)" % removals)


check_made_up_machines()
check_this_machine()
t.finish()
