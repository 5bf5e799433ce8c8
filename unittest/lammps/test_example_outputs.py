"""Every example writes its outputs under names of its own: no file that an example's LAMMPS
inputs, Python scripts or shell scripts write matches a file git tracks in its folder (committed
references live in reference/, which none of them writes), and no two of them write the same name.

The names are read from the sources, with each input's variables at their defaults (index and
string variables; a name with a variable that has no default is left out): LAMMPS's dump,
write_dump, write_restart, write_data, log and the file keyword of fix ave/* and fix print;
Python's savefig(os.path.join(DIR, NAME)), open(os.path.join(HERE, NAME), "w") and --out
defaults; the shell's -log FILE, after the script's cd. A '*' or '%' in a dump name (per step,
per process) matches any text. A new way of writing a file needs its pattern here. Commands
written only in a README (bench/rom.py --plot ...) are not read.
Exits 77 (skipped) without git."""
import fnmatch
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

TOP = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(TOP, "examples")

LAMMPS_WRITES = [re.compile(p) for p in (
    r"^\s*dump\s+\S+\s+\S+\s+\S+\s+\S+\s+(\S+)",
    r"^\s*write_dump\s+\S+\s+\S+\s+(\S+)",
    r"^\s*write_(?:restart|data)\s+(\S+)",
    r"^\s*log\s+(\S+)",
    r"^\s*fix\s+\S+\s+\S+\s+(?:ave/\S+|print)\s.*?\sfile\s+(\S+)",
)]
PYTHON_WRITES = [re.compile(p) for p in (
    r"savefig\(os\.path\.join\(\w+,\s*\"([^\"]+)\"\)",
    r"open\(os\.path\.join\(HERE,\s*\"([^\"]+)\"\),\s*\"w\"\)",
    r"add_argument\(\"--out\",\s*default=os\.path\.join\(HERE,\s*\"([^\"]+)\"\)",
)]
SHELL_LOG = re.compile(r"-log\s+(\S+)")
SHELL_CD = re.compile(r"^\s*cd\s+(\S+)\s*$")


def commands(text):
    """Each line of a LAMMPS input, continuations joined and comments cut, and the quoted
    commands within it (if ... then "command")."""
    for line in text.replace("&\n", " ").splitlines():
        quoted, kept = False, ""
        for c in line:
            if c == "\"":
                quoted = not quoted
            elif c == "#" and not quoted:
                break
            kept += c
        yield kept
        yield from re.findall(r"\"([^\"]*)\"", kept)


def expand(name, defaults):
    """name with ${v} and $v replaced by the variables' defaults, as long as any is known."""
    for _ in range(10):
        new = re.sub(r"\$\{(\w+)\}|\$(\w)", lambda m: defaults.get(m.group(1) or m.group(2), m.group(0)), name)
        if new == name:
            break
        name = new
    return name


def lammps_names(path):
    """Files a LAMMPS input writes, relative to its folder, variables at their defaults."""
    with open(path) as f:
        lines = list(commands(f.read()))
    defaults = {}
    for line in lines:
        words = line.split()
        if len(words) >= 4 and words[0] == "variable" and words[2] in ("index", "string"):
            defaults.setdefault(words[1], words[3].strip("\"'"))
    names = []
    for line in lines:
        for pattern in LAMMPS_WRITES:
            for name in pattern.findall(line):
                name = expand(name.strip("\"'"), defaults)
                if "$" not in name:
                    names.append(name)
    return names


def python_names(path):
    with open(path) as f:
        text = f.read()
    return [name for pattern in PYTHON_WRITES for name in pattern.findall(text)]


def shell_names(path):
    """-log files of a shell script, in the folder its cd lines lead to."""
    names, where = [], ""
    with open(path) as f:
        for line in f:
            cd = SHELL_CD.match(line)
            if cd:
                where = os.path.normpath(os.path.join(where, cd.group(1)))
            names += [os.path.normpath(os.path.join(where, re.sub(r"\$\{?\w+\}?", "*", n)))
                      for n in SHELL_LOG.findall(line)]
    return names


def writers(folder, files):
    """{source file: [names it writes]} of an example folder."""
    out = {}
    for name in files:
        if "/" in name:
            continue
        path = os.path.join(folder, name)
        if name.startswith("in."):
            out[name] = lammps_names(path)
        elif name.endswith(".py"):
            out[name] = python_names(path)
        elif name.endswith(".sh"):
            out[name] = shell_names(path)
    return out


def pattern(name):
    return name.replace("%", "*")


def overlap(a, b):
    """Whether two written names (with * and % wildcards) can name the same file."""
    return fnmatch.fnmatchcase(a, pattern(b)) or fnmatch.fnmatchcase(b, pattern(a))


def main():
    if not shutil.which("git") or subprocess.run(["git", "-C", TOP, "rev-parse"], capture_output=True).returncode:
        print("no git, or not a git work tree: the committed files are unknown; skipped", file=sys.stderr)
        sys.exit(77)
    tracked = subprocess.run(["git", "-C", TOP, "ls-files", "examples"], capture_output=True, text=True,
                             check=True).stdout.split()
    examples = sorted({p.split("/")[1] for p in tracked if p.count("/") >= 2})
    for example in examples:
        folder = os.path.join(EXAMPLES, example)
        files = [p[len("examples/%s/" % example):] for p in tracked if p.startswith("examples/%s/" % example)]
        written = writers(folder, files)
        print("%s: %s" % (example, "; ".join("%s %s" % (w, " ".join(n)) for w, n in sorted(written.items()) if n)))
        for writer, names in sorted(written.items()):
            for name in names:
                hits = [f for f in files if fnmatch.fnmatchcase(f, pattern(name))]
                t.check(not hits, "examples/%s: %s writes %s over the committed %s" % (example, writer, name, hits))
        pairs = sorted(written.items())
        for i, (w1, n1) in enumerate(pairs):
            for w2, n2 in pairs[i + 1:]:
                both = [(a, b) for a in n1 for b in n2 if overlap(a, b)]
                t.check(not both, "examples/%s: %s and %s write the same files %s" % (example, w1, w2, both))
    t.finish()


if __name__ == "__main__":
    main()
