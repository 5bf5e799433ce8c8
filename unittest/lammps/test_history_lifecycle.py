"""The contact history lives as long as its griddem pair style, as stock's does, and follows a
fix griddem redefined after a run, on a dense random polydisperse gas with friction.
- A griddem run, a stock gran/hooke run, then griddem again equals the same three runs with stock
  gran/hooke/history in place of griddem (stock drops its history when another pair style is
  set) to 1e-10 relative, with the pair style's own fix GRIDDEM and with a fix griddem of the
  script's, which keeps its options (cell edge 0.37); during the stock run the griddem grid values are
  refused with a message.
- After a run, `fix grid all griddem cell exact` (a new ID, or the ID of the fix that ran; 1 or 2 ranks) keeps
  the history: the elastic energy of the same state (`run 0`) is the uninterrupted run's to
  1e-12, and 30 more steps equal it to 1e-10 (the cell mode changes only the speed). Atoms deleted
  in between lose their rows with a warning that counts them; two fixes of the script's before a
  run are refused, naming both.
- thermo_style names f_GRIDDEM after read_restart, and the history comes back from the file: the
  elastic energy of the restart's state (`run 0`) is the one before writing it.
- `replicate` after pair_style and before the first run runs as stock's does (the fix joins
  LAMMPS's per-atom data only at the first run): KE and pressure 30 steps on equal stock's to
  1e-10, with and without history.
- `reset_atoms id` before any run, or after a run of a style without history, runs and equals
  stock; after a run that stored contacts (their partners keyed by atom ID), or after read_restart
  of a style with history, the contacts keep their history under the new IDs: the run equals the
  one without the reset (stock runs on with stale history).
- delete_atoms with compress yes (its default) after a run, or after read_restart: the contacts
  keep their history under the new IDs, as with compress no (renumbered)."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

HOOKE = "2e3 NULL 20 NULL 0.5 1"
START = t.PERIODIC_SPHERES + """
timestep 2e-4
fix integrate all nve/sphere
thermo 10
"""


def thermo(columns):
    """thermo_style custom step ke and columns, all digits (thermo_style resets the format)"""
    return "thermo_style custom step ke %s\nthermo_modify format float %%.17g\n" % columns


def last(out, column):
    values = t.thermo_values(out, column)
    return values[-1] if values else float("nan")


def rel(a, b):
    return abs(a - b) / max(abs(b), 1e-300)


def switch_styles(wd, data, label, styles, fix=""):
    """30 steps with styles[0], 20 with stock gran/hooke, 30 with styles[0] again; the last KE
    and pressure, and the value of f_grid[4] (cell edge) at the ends of the griddem runs."""
    first, again = styles
    edge = "f_grid[4]" if fix else ""
    text = START.format(data=data, pair=first + " " + HOOKE, coeffs="pair_coeff * *\n" + fix) + \
        thermo("press " + edge) + "run 30\n" + \
        "pair_style gran/hooke %s\npair_coeff * *\n" % HOOKE + thermo("press") + "run 20\n" + \
        "pair_style %s %s\npair_coeff * *\n" % (again, HOOKE) + thermo("press " + edge) + "run 30\n"
    return t.run_ok(text, wd, name="in." + label)


def stale_history(wd, data):
    ref = switch_styles(wd, data, "stock", ("gran/hooke/history", "gran/hooke/history"))
    ke, press = last(ref, "KinEng"), last(ref, "Press")
    t.check(len(t.thermo_values(ref, "KinEng")) == 11, "stock: three runs printed")
    for label, fix in (("auto", ""), ("own", "fix grid all griddem cell 0.37")):
        out = switch_styles(wd, data, "griddem_" + label, ("griddem/hooke/history", "griddem/hooke/history"), fix)
        err = max(rel(last(out, "KinEng"), ke), rel(last(out, "Press"), press))
        t.check(err <= 1e-10, "griddem, stock, griddem (%s fix): KE and pressure as stock's three runs, "
                "relative error %.3g" % (label, err))
        if fix:
            edges = t.thermo_values(out, "f_grid[4]")
            t.check(len(edges) == 8 and all(e == 0.37 for e in edges),
                    "fix grid keeps its cell edge 0.37 after the stock run: edges %s" % edges)
    # asking for the grid values while stock runs: a message, not the last griddem step's values
    for label, fix, name in (("auto", "", "GRIDDEM"), ("own", "fix grid all griddem", "grid")):
        text = START.format(data=data, pair="griddem/hooke/history " + HOOKE, coeffs="pair_coeff * *\n" + fix) + \
            thermo("f_%s[5]" % name) + "run 10\npair_style gran/hooke %s\npair_coeff * *\nrun 10\n" % HOOKE
        rc, out = t.run_lmp(text, wd, name="in.stock_asks_" + label)
        said = "\n".join(t.errors(out))
        wanted = "Could not find thermo fix ID GRIDDEM" if not fix else "is not a griddem pair style"
        t.check(rc != 0 and wanted in said, "f_%s during a stock run: error '%s', got %r" % (name, wanted, said))


def redefinition(wd, data):
    base = START.format(data=data, pair="griddem/hooke/history " + HOOKE, coeffs="pair_coeff * *")
    through = t.run_ok(base + thermo("f_GRIDDEM[7]") + "run 30\nrun 0\nrun 30\n", wd, name="in.through")
    energy = t.thermo_values(through, "f_GRIDDEM[7]")
    t.check(len(energy) == 9 and energy[4] > 0.0, "uninterrupted run: elastic energy at run 0 %s" % energy[4:5])
    ke = last(through, "KinEng")
    # on 2 ranks too: the rows a fix replaced in place leaves are taken back by atom ID
    cases = [("new_id", "", "fix grid all griddem cell exact", "grid", 1),
             ("same_id", "", "fix GRIDDEM all griddem cell exact", "GRIDDEM", 1),
             ("same_id_2_ranks", "", "fix GRIDDEM all griddem cell exact", "GRIDDEM", 2),
             ("own_same_id", "fix grid all griddem cell multi\n", "fix grid all griddem cell exact", "grid", 1),
             ("own_new_id", "fix grid all griddem cell multi\n", "fix grid2 all griddem cell exact", "grid2", 1)]
    for label, before, redefine, name, nprocs in cases:
        first = "GRIDDEM" if not before else "grid"
        text = base + before + thermo("f_%s[7]" % first) + "run 30\n" + redefine + "\n" + \
            thermo("f_%s[7] f_%s[4]" % (name, name)) + "run 0\nrun 30\n"
        rc, out = t.run_lmp(text, wd, nprocs=nprocs, name="in.redefine_" + label)
        t.check(rc == 0, "%s: runs (%s)" % (label, t.errors(out)))
        e = t.thermo_values(out, "f_%s[7]" % name)[-5:]    # the runs after the redefinition
        t.check(len(e) == 5 and rel(e[0], energy[4]) <= (1e-12 if nprocs == 1 else 1e-10),
                "%s: elastic energy at run 0 after redefining the fix %.17g, uninterrupted %.17g"
                % (label, e[0] if e else 0, energy[4]))
        err = rel(last(out, "KinEng"), ke)
        t.check(err <= 1e-10, "%s: 30 steps after redefining the fix as the uninterrupted run, KE relative error %.3g"
                % (label, err))
        edges = t.thermo_values(out, "f_%s[4]" % name)
        t.check(len(edges) == 5 and edges[0] > 0.0, "%s: the new fix reports its grid" % label)


def deleted_in_between(wd, data):
    """atoms deleted between a fix's redefinition (same ID) and the run: their rows are dropped
    with a warning that counts them, as many as compute contact/atom finds touching others"""
    text = START.format(data=data, pair="griddem/hooke/history " + HOOKE, coeffs="pair_coeff * *") + \
        "run 30\ngroup few id <= 10\ncompute touches all contact/atom\n" + \
        "variable touching atom c_touches>0\ncompute touching few reduce sum v_touching\n" + \
        thermo("c_touching") + "thermo_modify norm no\nrun 0\n" + \
        "fix GRIDDEM all griddem cell exact\ndelete_atoms group few compress no\nrun 0\n"
    rc, out = t.run_lmp(text, wd, name="in.deleted")
    said = [line for line in out.splitlines() if "lose theirs" in line]
    count = int(said[0].split(" atoms with contacts")[0].split()[-1]) if said else -1
    touching = t.thermo_values(out, "c_touching")
    t.check(rc == 0 and touching and count == touching[0] > 0,
            "atoms deleted after the redefinition: warning counts %d, touching %s (%s)" % (count, touching, said[:1]))


def two_fixes(wd, data):
    """two fix griddem of the script's before any run: refused, naming both"""
    text = START.format(data=data, pair="griddem/hooke/history " + HOOKE, coeffs="pair_coeff * *") + \
        "fix grid all griddem\nfix grid2 all griddem cell exact\nrun 0\n"
    rc, out = t.run_lmp(text, wd, name="in.two_fixes")
    said = "\n".join(t.errors(out))
    t.check(rc != 0 and "Only one fix griddem" in said and "grid and grid2" in said,
            "two fixes griddem before a run: refused naming both, got %r" % said)


def restart(wd, data):
    text = START.format(data=data, pair="griddem/hooke/history " + HOOKE, coeffs="pair_coeff * *") + \
        thermo("f_GRIDDEM[7]") + "run 30\nwrite_restart restart.lifecycle\nrun 0\n"
    written = last(t.run_ok(text, wd, name="in.write"), "f_GRIDDEM[7]")
    text = """
read_restart restart.lifecycle
comm_modify vel yes
fix integrate all nve/sphere
thermo_style custom step ke f_GRIDDEM[7]
thermo_modify format float %.17g
run 0
"""
    rc, out = t.run_lmp(text, wd, name="in.read")
    got = last(out, "f_GRIDDEM[7]")
    t.check(rc == 0 and rel(got, written) <= 1e-12,
            "f_GRIDDEM[7] at run 0 after read_restart %.17g, at run 0 after writing %.17g (%s)"
            % (got, written, t.errors(out)))


def replicated(wd, data):
    for griddem, stock in (("griddem/hooke/history", "gran/hooke/history"), ("griddem/hooke", "gran/hooke")):
        values = {}
        for style in (griddem, stock):
            text = START.format(data=data, pair=style + " " + HOOKE, coeffs="pair_coeff * *") + \
                "replicate 2 1 1\n" + thermo("press atoms") + "run 30\n"
            out = t.run_ok(text, wd, name="in.replicate_" + style.replace("/", "_"))
            values[style] = (last(out, "KinEng"), last(out, "Press"), last(out, "Atoms"))
        (ke, press, atoms), (ke0, press0, atoms0) = values[griddem], values[stock]
        err = max(rel(ke, ke0), rel(press, press0))
        t.check(atoms == atoms0 == 1200 and err <= 1e-10,
                "replicate after pair_style %s: %g atoms (stock %g), KE and pressure relative error %.3g"
                % (griddem, atoms, atoms0, err))


def reset_ids(wd, data):
    def run(style, before, after, reset="reset_atoms id\n"):
        text = START.format(data=data, pair=style + " " + HOOKE, coeffs="pair_coeff * *") + \
            thermo("press") + before + reset + after + "run 30\n"
        return t.run_lmp(text, wd, name="in.reset_" + style.replace("/", "_") + ("_after" if before else "") +
                         ("" if reset else "_none"))
    for griddem, stock, before in (("griddem/hooke/history", "gran/hooke/history", ""),
                                   ("griddem/hooke", "gran/hooke", "run 30\n")):
        (rc, out), (rc0, out0) = run(griddem, before, ""), run(stock, before, "")
        err = max(rel(last(out, "KinEng"), last(out0, "KinEng")), rel(last(out, "Press"), last(out0, "Press")))
        t.check(rc == 0 and rc0 == 0 and err <= 1e-10, "reset_atoms id %s with %s: runs as stock, KE and pressure "
                "relative error %.3g (%s)" % ("after a run" if before else "before any run", griddem, err, t.errors(out)))
    # after a run that stored contacts (keyed by the partners' IDs) the rows follow the new IDs:
    # the run equals the one without the reset (sort yes renumbers the most)
    (rc, out), (rc0, out0) = run("griddem/hooke/history", "run 30\n", "", "reset_atoms id sort yes\n"), \
        run("griddem/hooke/history", "run 30\n", "", "")
    err = max(rel(last(out, "KinEng"), last(out0, "KinEng")), rel(last(out, "Press"), last(out0, "Press")))
    t.check(rc == 0 and rc0 == 0 and err <= 1e-10, "reset_atoms id sort yes after a run with contacts: as without "
            "it, KE and pressure relative error %.3g (%s)" % (err, t.errors(out)))
    # read from a restart file (restart() wrote it after a run with contacts), before any run
    def from_file(reset):
        text = "read_restart restart.lifecycle\ncomm_modify vel yes\nfix integrate all nve/sphere\n" + reset + \
            thermo("press") + "run 30\n"
        return t.run_lmp(text, wd, name="in.reset_restart" + ("" if reset else "_none"))
    (rc, out), (rc0, out0) = from_file("reset_atoms id sort yes\n"), from_file("")
    err = max(rel(last(out, "KinEng"), last(out0, "KinEng")), rel(last(out, "Press"), last(out0, "Press")))
    t.check(rc == 0 and rc0 == 0 and err <= 1e-10, "reset_atoms id sort yes after read_restart: as without it, KE "
            "and pressure relative error %.3g (%s)" % (err, t.errors(out)))


def renumbered(wd, data):
    """delete_atoms with compress yes (its default) gives the remaining atoms new IDs between runs:
    the contacts keep their history, so the state equals that of compress no (IDs kept): the
    elastic energy at run 0 to 1e-12, KE and pressure 30 steps on to 1e-10, on 1, 2 and 3 ranks
    (3: the new IDs meet most keys on a process that owns neither atom, old ID % 3).
    Stock gran/hooke/history loses or mixes its history there (printed, not checked)."""
    def run(style, compress, nprocs):
        text = START.format(data=data, pair=style + " " + HOOKE, coeffs="pair_coeff * *") + \
            "run 30\ngroup few id <= 40\ndelete_atoms group few compress %s\n" % compress + \
            thermo("press" + (" f_GRIDDEM[7]" if "griddem" in style else "")) + "run 0\nrun 30\n"
        return t.run_ok(text, wd, nprocs=nprocs, name="in.renumber_%s_%s_%d" % (style.split("/")[0], compress, nprocs))
    for nprocs in (1, 2, 3):
        kept, renumbered_run = run("griddem/hooke/history", "no", nprocs), run("griddem/hooke/history", "yes", nprocs)
        e_kept, e_new = t.thermo_values(kept, "f_GRIDDEM[7]"), t.thermo_values(renumbered_run, "f_GRIDDEM[7]")
        t.check(e_kept and e_new and e_kept[0] > 0.0 and rel(e_new[0], e_kept[0]) <= 1e-12,
                "%d rank(s): elastic energy at run 0 after delete_atoms compress yes %.17g, compress no %.17g"
                % (nprocs, e_new[0] if e_new else 0, e_kept[0] if e_kept else 0))
        err = max(rel(last(renumbered_run, "KinEng"), last(kept, "KinEng")),
                  rel(last(renumbered_run, "Press"), last(kept, "Press")))
        t.check(err <= 1e-10, "%d rank(s): 30 steps after delete_atoms compress yes as with compress no, KE and "
                "pressure relative error %.3g" % (nprocs, err))
    # rows read from a restart file (restart() wrote it after a run with contacts) and renumbered
    # before any run: the file's IDs go with each row
    def from_file(compress):
        text = "read_restart restart.lifecycle\ncomm_modify vel yes\nfix integrate all nve/sphere\n" + \
            "group few id <= 40\ndelete_atoms group few compress %s\n" % compress + thermo("press f_GRIDDEM[7]") + \
            "run 0\nrun 30\n"
        return t.run_ok(text, wd, name="in.renumber_restart_" + compress)
    kept, renumbered_run = from_file("no"), from_file("yes")
    e_kept, e_new = t.thermo_values(kept, "f_GRIDDEM[7]"), t.thermo_values(renumbered_run, "f_GRIDDEM[7]")
    err = max(rel(last(renumbered_run, "KinEng"), last(kept, "KinEng")),
              rel(last(renumbered_run, "Press"), last(kept, "Press")))
    t.check(e_kept and e_new and e_kept[0] > 0.0 and rel(e_new[0], e_kept[0]) <= 1e-12 and err <= 1e-10,
            "read_restart, then delete_atoms compress yes: elastic energy at run 0 %.17g (compress no %.17g), "
            "30 steps on KE and pressure relative error %.3g" % (e_new[0] if e_new else 0, e_kept[0] if e_kept else 0, err))
    stock_kept, stock_new = run("gran/hooke/history", "no", 1), run("gran/hooke/history", "yes", 1)
    print("stock gran/hooke/history, 30 steps after delete_atoms compress yes against compress no: pressure "
          "relative error %.3g" % rel(last(stock_new, "Press"), last(stock_kept, "Press")))


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.gas")
    t.write_random_spheres(data, 600, (3.6, 3.6, 3.6), 0.1, 0.3, seed=5, vscale=1.0, wscale=5.0)
    stale_history(wd, data)
    redefinition(wd, data)
    deleted_in_between(wd, data)
    two_fixes(wd, data)
    restart(wd, data)
    replicated(wd, data)
    reset_ids(wd, data)
    renumbered(wd, data)
    t.finish()


if __name__ == "__main__":
    main()
