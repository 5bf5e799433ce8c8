"""cmake --install <build> --prefix P: P/bin/lmp runs and has GRIDDEM; P/lib*/lammps/plugins holds
griddemplugin.so, which LAMMPS auto-loads from LAMMPS_PLUGIN_PATH (checked when GRIDDEM_PLAIN_LMP
names a LAMMPS without GRIDDEM); P/share/doc/griddem holds doc/ and README.md; the potentials are in
P/share/lammps/potentials, next to LAMMPS's own, where LAMMPS's etc/profile.d/lammps.sh points
LAMMPS_POTENTIALS. Usage: test_install.py <cmake> <build folder> plugin|no-plugin (whether the
build makes griddemplugin.so)."""
import filecmp
import glob
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def same_files(src, dst, label):
    names = sorted(os.listdir(src))
    missing = [n for n in names if not os.path.isfile(os.path.join(dst, n))]
    t.check(not missing, "%s: every file installed (missing %s)" % (label, missing))
    differ = [n for n in names if n not in missing and not filecmp.cmp(os.path.join(src, n), os.path.join(dst, n), shallow=False)]
    t.check(not differ, "%s: installed files equal the sources (differ: %s)" % (label, differ))


def main():
    cmake, build, with_plugin = sys.argv[1], sys.argv[2], sys.argv[3] == "plugin"
    prefix = t.workdir()
    proc = subprocess.run([cmake, "--install", build, "--prefix", prefix], stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True)
    t.check(proc.returncode == 0, "cmake --install exits 0:\n" + proc.stdout[-3000:])

    lmp = os.path.join(prefix, "bin", "lmp")
    help_text = subprocess.run([lmp, "-h"], stdout=subprocess.PIPE, universal_newlines=True).stdout if os.path.isfile(lmp) else ""
    t.check("GRIDDEM" in help_text.split("Installed packages:")[-1].split("List of individual")[0],
            "installed bin/lmp runs and has GRIDDEM")
    plugins = glob.glob(os.path.join(prefix, "lib*", "lammps", "plugins", "griddemplugin.so"))
    t.check(len(plugins) == (1 if with_plugin else 0), "griddemplugin.so installed in lib*/lammps/plugins: %s" % plugins)
    same_files(os.path.join(ROOT, "doc"), os.path.join(prefix, "share", "doc", "griddem"), "doc/")
    t.check(os.path.isfile(os.path.join(prefix, "share", "doc", "griddem", "README.md")), "README.md installed")
    same_files(os.path.join(ROOT, "potentials"), os.path.join(prefix, "share", "lammps", "potentials"), "potentials/")
    t.check(os.path.isfile(os.path.join(prefix, "share", "man", "man1", "lmp.1")), "LAMMPS's man page installed")

    plain = os.environ.get("GRIDDEM_PLAIN_LMP")
    if plain and plugins:
        wd = t.workdir()
        with open(os.path.join(wd, "in.list"), "w") as f:
            f.write("plugin list\n")
        env = dict(os.environ, LAMMPS_PLUGIN_PATH=os.path.dirname(plugins[0]))
        out = subprocess.run([plain, "-in", "in.list", "-log", "none"], cwd=wd, env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT, universal_newlines=True).stdout
        t.check("Loaded 1 plugins from %s" % os.path.dirname(plugins[0]) in out and
                "pair style plugin griddem/hooke/history" in out,
                "a LAMMPS without GRIDDEM auto-loads the installed plugin from LAMMPS_PLUGIN_PATH:\n" + out[-2000:])
        shutil.rmtree(wd)
    shutil.rmtree(prefix)
    t.finish()


if __name__ == "__main__":
    main()
