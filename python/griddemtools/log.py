"""A LAMMPS log or screen output: thermo columns, the loop time of each run and its timing
breakdown; and the reference logs an example keeps (log.DATE.NAME[.variant].N)."""
import collections
import glob
import os
import re

# one run's "Loop time of ..." line, and its "% CPU use ..." line (None where there is none)
LoopTime = collections.namedtuple("LoopTime", "seconds procs steps atoms cpu_percent")
_LOOP = re.compile(r"^Loop time of (\S+) on (\d+) procs for (\d+) steps with (\d+) atoms", re.M)
_CPU = re.compile(r"^([0-9.]+)% CPU use", re.M)


def text_of(path_or_text):
    """A log's text: the argument itself if it has a newline or is empty, else the file it names."""
    if "\n" in path_or_text or not path_or_text:
        return path_or_text
    with open(path_or_text) as f:
        return f.read()


def thermo_table(path_or_text, *columns):
    """Rows of thermo columns, each a tuple of the columns' values, from every table that has all
    of them, in order. A table starts at a line whose first word is Step and ends at a Loop line
    or at a row of its width that is not all numbers; WARNING lines and lines of another width
    inside it are passed over."""
    rows, at = [], None
    for line in text_of(path_or_text).splitlines():
        words = line.split()
        if words[:1] == ["WARNING:"]:
            continue
        if words[:1] == ["Step"]:
            at = [words.index(c) for c in columns] if all(c in words for c in columns) else None
            width = len(words)
        elif at and words[:1] == ["Loop"]:
            at = None
        elif at and len(words) == width:
            try:
                rows.append(tuple(float(words[k]) for k in at))
            except ValueError:
                at = None
    return rows


def thermo(path_or_text, column):
    """Values of one thermo column, the rows of all tables that have it, in order."""
    return [row[0] for row in thermo_table(path_or_text, column)]


def loop_times(path_or_text):
    """A LoopTime per run, in order."""
    text = text_of(path_or_text)
    matches = list(_LOOP.finditer(text))
    runs = []
    for k, m in enumerate(matches):
        after = text[m.end():matches[k + 1].start() if k + 1 < len(matches) else len(text)]
        cpu = _CPU.search(after)
        runs.append(LoopTime(float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4)),
                             float(cpu.group(1)) if cpu else None))
    return runs


def timing_sections(path_or_text):
    """{section: percent of the loop} from the last run's "MPI task timing breakdown" (Pair, Neigh,
    Comm, Output, Modify, Other); {} if there is none."""
    table = text_of(path_or_text).rpartition("MPI task timing breakdown:")[2].split("\n\n")[0]
    return {k: float(v) for k, v in re.findall(r"^(\w+)\s*\|.*\|\s*([0-9.]+)\s*$", table, re.M)}


def reference_logs(folder, variant=None, ranks=1):
    """An example's reference logs of one run, log.DATE.NAME[.variant].N with any date."""
    name = ".".join(["log", "*", os.path.basename(folder)] + ([variant] if variant else []) + [str(ranks)])
    return sorted(glob.glob(os.path.join(folder, name)))


def reference_log(folder, variant=None, ranks=1):
    """The example's one reference log of a run; an error when it has none or several."""
    found = reference_logs(folder, variant, ranks)
    if len(found) != 1:
        raise SystemExit("%s: %d reference logs of run %s on %d ranks, not one: %s"
                         % (folder, len(found), variant, ranks, found))
    return found[0]
