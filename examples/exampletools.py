"""Shared by the examples' checks and plots: read thermo columns from a LAMMPS log, whether a log
echoes its input script, and the analytic references of the NN4DEM single-particle scenes."""
import glob
import math
import os
import re


def thermo(path_or_text, column):
    """Values of a thermo column in a log file (or log text), all runs concatenated."""
    text = path_or_text
    if "\n" not in path_or_text:
        with open(path_or_text) as f:
            text = f.read()
    values, header = [], None
    for line in text.splitlines():
        words = line.split()
        if words[:1] == ["Step"]:
            header = words
        elif header and words[:1] == ["Loop"]:
            header = None
        elif header and len(words) == len(header):
            try:
                values.append(float(words[header.index(column)]))
            except ValueError:
                header = None
    return values


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


def apexes(heights, floor=0.01):
    """Local maxima of a height series above floor: the apex after each bounce."""
    return [heights[k] for k in range(1, len(heights) - 1)
            if heights[k] >= heights[k - 1] and heights[k] > heights[k + 1] and heights[k] > floor]


def bounce_apexes(drop, k, eta, m, count):
    """Apex heights of a sphere dropped from drop onto an infinitely heavy partner: linear spring k,
    absolute damping eta: each bounce keeps e^2 of the height, e = exp(-pi z / sqrt(1 - z^2)),
    z = eta / (2 sqrt(k m))."""
    z = eta / (2.0 * math.sqrt(k * m))
    e = math.exp(-math.pi * z / math.sqrt(1.0 - z * z))
    return [drop * e ** (2 * n) for n in range(1, count + 1)]


def slide_on_sphere(v0, mu, g, rc, dt=1e-6):
    """Distance along x a non-rotating sphere slides before it stops, starting at the top of a
    sphere of radius rc (centre distance) at speed v0 with Coulomb friction mu."""
    th, w = 0.0, v0 / rc
    while w > 0:
        normal = g * math.cos(th) - rc * w * w
        w += (g * math.sin(th) - mu * normal) / rc * dt
        th += w * dt
    return rc * math.sin(th)


def last_snapshot(path):
    """Atoms of the last snapshot of a dump custom file, as dicts by column name."""
    with open(path) as f:
        lines = f.read().splitlines()
    start = max(k for k, line in enumerate(lines) if line.startswith("ITEM: ATOMS"))
    names = lines[start].split()[2:]
    return [dict(zip(names, map(float, line.split()))) for line in lines[start + 1:] if line.strip()]


def draw_slice(ax, atoms, y0, half_width, colour, cmap, clim=None):
    """Spheres whose centres lie within half_width of the plane y = y0, drawn as their x-z
    circles, coloured by colour(atom)."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle
    inside = [a for a in atoms if abs(a["y"] - y0) < half_width]
    coll = PatchCollection([Circle((a["x"], a["z"]), a["radius"]) for a in inside], cmap=cmap)
    coll.set_array([colour(a) for a in inside])
    if clim:
        coll.set_clim(*clim)
    ax.add_collection(coll)
    ax.set_aspect("equal")
    return coll


def _without_comment(line):
    """The line up to a '#' outside quotes, whitespace collapsed (LAMMPS's comment rule)."""
    quote = None
    for k, c in enumerate(line):
        if quote:
            quote = None if c == quote else quote
        elif c in "'\"":
            quote = c
        elif c == "#":
            line = line[:k]
            break
    return " ".join(line.split())


def input_commands(path):
    """The commands of an input script as LAMMPS reads and echoes them: a line ending in '&'
    joined with the next, comments and blank lines dropped, whitespace collapsed."""
    commands, pending = [], ""
    with open(path) as f:
        for raw in f:
            line = pending + raw.rstrip()
            if line.endswith("&"):
                pending = line[:-1] + " "
                continue
            pending = ""
            line = _without_comment(line)
            if line:
                commands.append(line)
    return commands


def _substituted(command):
    """A pattern matching the command after any of its $x, ${name} and $(expression) were
    substituted: LAMMPS echoes each substitution as it makes it."""
    parts, k, literal = [], 0, ""
    while k < len(command):
        if command[k] == "$" and k + 1 < len(command):
            parts.append(re.escape(literal))
            literal = ""
            if command[k + 1] in "({":
                opening = command[k + 1]
                close, depth, k = ")" if opening == "(" else "}", 0, k + 1
                while k < len(command):
                    depth += command[k] == opening
                    depth -= command[k] == close
                    k += 1
                    if depth == 0:
                        break
            else:
                k += 2
            parts.append(".*")
        else:
            literal += command[k]
            k += 1
    parts.append(re.escape(literal))
    return re.compile("".join(parts) + "$")


def echo_fault(input_path, log_text):
    """None when a LAMMPS log echoes the input script: every command of the input in order, and no
    command line the input does not have (a command the input dropped or changed since the log
    was written). Otherwise a sentence naming the first difference."""
    commands = input_commands(input_path)
    # commands an if runs are echoed on their own: their quoted strings are commands too
    inner = [q for c in commands if c.startswith("if ") for q in re.findall(r'"([^"]*)"', c)]
    patterns = [_substituted(c) for c in commands + inner]
    words = {c.split()[0] for c in commands + inner if c.split()}
    echoed = [(_without_comment(line), line) for line in log_text.splitlines()]
    k = 0
    for number, command in enumerate(commands, 1):
        while k < len(echoed) and echoed[k][0] != command:
            k += 1
        if k == len(echoed):
            return "the input's command %d is not echoed in order: %s" % (number, command)
        k += 1
    for line, raw in echoed:
        # LAMMPS's own messages are indented or start with no command word
        if line and not raw[0].isspace() and line.split()[0] in words \
                and not any(p.match(line) for p in patterns):
            return "the log echoes a command the input does not have: %s" % line
    return None
