"""build/lmp -h lists the package's styles, next to the stock granular ones."""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

out = subprocess.run([t.LMP, "-h"], stdout=subprocess.PIPE, universal_newlines=True).stdout
words = out.split()
for style in ["griddem/hooke/history", "griddem/hooke", "griddem/hertz/history", "gran/hooke/history", "gran/hooke"]:
    t.check(style in words, "pair style %s listed by lmp -h" % style)
t.check("griddem" in out.split("* Fix styles")[1].split("* ")[0].split(),
        "fix style griddem listed by lmp -h")
t.check("GRIDDEM" in out.split("Installed packages:")[1].split("List of individual")[0],
        "GRIDDEM among the installed packages")
t.finish()
