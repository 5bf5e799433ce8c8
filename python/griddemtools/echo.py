"""Whether a LAMMPS log echoes an input script: the commands of the input, in order, as LAMMPS reads
and echoes them."""
import re


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
