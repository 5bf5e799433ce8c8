"""griddemplugin.so in a LAMMPS built without GRIDDEM (GRIDDEM_LMP, with GRIDDEM_PLUGIN): that LAMMPS
knows no griddem style by itself; "plugin load" registers every style the package's headers declare
(PairStyle/FixStyle/ComputeStyle lines, the list LAMMPS compiles in; kk ones when the host has
KOKKOS), each once, and a second load adds nothing; a plugin compiled for other integer sizes
(GRIDDEM_PLUGIN_OTHER_SIZES, the registration alone) is refused with an error. The styles' numbers through the plugin are
checked by the suite's own tests run with GRIDDEM_PLUGIN set (lammps.plugin.*)."""
import glob
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

PKG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "src", "PKG-GRIDDEM")


def declared_styles(with_kokkos):
    """(kind, name) of every style declared in the package's headers."""
    headers = glob.glob(os.path.join(PKG, "*.h"))
    if with_kokkos:
        headers += glob.glob(os.path.join(PKG, "kokkos", "*.h"))
    styles = set()
    for h in headers:
        with open(h) as f:
            for kind, name in re.findall(r"^(Pair|Fix|Compute)Style\(([^,]+),", f.read(), re.M):
                styles.add((kind.lower(), name))
    return styles


def section(help_text, title):
    """The words of one '* title' section of lmp -h."""
    return help_text.split("* " + title)[1].split("\n* ")[0].split()


def main():
    plugin = t.PLUGIN
    if not plugin:
        raise SystemExit("set GRIDDEM_PLUGIN to build/griddemplugin.so")
    help_text = subprocess.run([t.LMP, "-h"], stdout=subprocess.PIPE, universal_newlines=True).stdout
    packages = help_text.split("Installed packages:")[1].split("List of individual")[0].split()
    t.check("PLUGIN" in packages and "GRANULAR" in packages, "the host has PLUGIN and GRANULAR")
    t.check("GRIDDEM" not in packages, "the host was built without GRIDDEM")
    t.check("KSPACE" not in packages, "the host has no KSPACE: compute griddem/cg uses the plugin's FFT")
    kokkos = "KOKKOS" in packages
    expected = declared_styles(kokkos)
    t.check(len(expected) >= (19 if kokkos else 7), "%d styles declared in the headers" % len(expected))
    for kind, title in [("pair", "Pair styles"), ("fix", "Fix styles"), ("compute", "Compute styles")]:
        built_in = set(section(help_text, title))
        t.check(not {n for k, n in expected if k == kind} & built_in,
                "no griddem %s style built into the host" % kind)
    t.check("gran/hooke/history" in section(help_text, "Pair styles"),
            "the host lists its own pair styles (gran/hooke/history)")

    wd = t.workdir()
    # run_lmp puts "plugin load" first; the second load must register nothing new
    rc, out = t.run_lmp("plugin load %s\nplugin list\n" % plugin, wd)
    t.check(rc == 0, "plugin load and plugin list run (exit %d)" % rc)
    listed = re.findall(r"^\s*\d+: (\w+) style plugin (\S+)$", out, re.M)
    t.check(len(listed) == len(set(listed)), "each style registered once: %s" % listed)
    t.check(set(listed) == expected, "registered %s, declared %s" % (sorted(set(listed)), sorted(expected)))
    t.check(len(re.findall(r"^Ignoring load of", out, re.M)) == len(expected),
            "the second load is ignored for each of the %d styles" % len(expected))

    other = os.environ.get("GRIDDEM_PLUGIN_OTHER_SIZES")
    t.check(bool(other), "GRIDDEM_PLUGIN_OTHER_SIZES names the plugin built for other LAMMPS_SIZES")
    if other:
        rc, out = t.run_lmp("plugin load %s\nplugin list\n" % other, wd, name="in.sizes")
        t.check(rc != 0 and any("GRIDDEM plugin was compiled with 8-byte tagint" in line or
                                "GRIDDEM plugin was compiled with 4-byte tagint" in line for line in t.errors(out)),
                "a plugin for other integer sizes is refused:\n" + out[-1500:])
    t.finish()


if __name__ == "__main__":
    main()
