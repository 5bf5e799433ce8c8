"""fix griddem/rom (adaptive reduced-order DEM), on models written here by hand:
- model-file checks: a wrong format version, a weight matrix whose size does not fit the grid,
  a number of controls other than the fix's, a box other than the simulation's: each refused with
  an error naming it; words after the weights or the force block, binary bytes (at the start and
  in a row of weights) and a weights block cut short: refused naming the line and what was expected
  there, bytes other than printable ASCII as \\xNN;
- the counters f_rom[2], [3], [4], [7] (made kinematic, released by hits, by overlaps,
  classifications) on a scene counted by hand over two runs;
- eps = 0: no atom becomes kinematic and the run is the plain run, digit for digit (drive match and
  drive box);
- a uniform predicted field U (weights: bias only): a resting atom (|v - U| = |U| <= eps v0)
  becomes kinematic, its velocity is U exactly and it moves by U dt per step although gravity
  acts; an atom whose speed relative to U exceeds eps v0 stays dynamic and falls freely;
- freeze yes (the do-nothing baseline): the same field classifies the atoms, a kinematic one is at
  rest and in place; an atom at -U, slower than eps v0 but not within eps v0 of U, stays dynamic;
- contacts: two resting kinematic atoms that overlap exert no force (the pair virial is exactly
  zero, and nonzero in the same scene without the fix), while a dynamic atom overlapping a
  kinematic one is pushed away by it and the kinematic one does not move; an atom overlapping
  beyond `overlap` min(ri, rj) is never made kinematic; the same on 2 processes with the two
  kinematic atoms on different processes (their state reaches the ghosts);
- release: a kinematic atom driven by the field into a wall is released once the wall's force
  exceeds eps v0 m / (N dt), so its penetration stays below that force's spring length plus one
  step's travel and a small margin (it would reach 0.13 otherwise); a kinematic atom hit by a fast
  dynamic one is released and takes up momentum; a kinematic atom carrying a resting dynamic one
  under gravity is not released (contacts and gravity do not count in the force rule); a
  kinematic atom where the field jumps by more than eps v0 is released at rest, not kicked;
- separate: overlapping kinematic atoms released together (a field jump) each move by half their
  overlap, one released alone (a resolved region) by all of it from its kinematic partner; they
  touch without overlap and keep the field's velocity (positions to 1e-12); with separate no the
  overlap throws them apart;
- the field and density as grid data (dump grid) on 1 and 2 processes;
- a resolved region keeps its atoms dynamic, also as its bound moves; a missing one is refused;
- a moving frame (model line 'frame moving', keyword origin): a field linear in the frame's x is
  sampled at the atom's position less the origin, a variable that moves, at each classification;
  an atom outside the placed frame stays dynamic; the force block predicts bias + control weight
  + the sum of the voxel densities (the mass inside the frame over the voxel volume); a moving
  model without origin, origin without a moving model, a 'frame' line in version 1, a force block
  of the wrong size, an origin that moves along a periodic axis and an origin variable that is
  missing or not equal-style are refused naming them; the
  density the fix deposits on a moving frame (dump grid) equals python/griddemtools/blade.py's
  numpy binning of the dumped atoms in the frame (its training data);
- drive box (the paper's blade): from the set-up on, every atom of the group in the model's box is
  kinematic whatever its velocity and whatever hits it (against drive match, where the same atoms
  stay dynamic); outside the box an atom at rest is held at rest and one that moves is dynamic,
  also one the field carried out of the box (counted in f_rom[5]); 2 processes give 1 process's
  dumps; a drive other than match, box or dense, and drive dense without a positive density, are
  refused;
- drive dense: from the set-up on, the atoms where the deposited density reaches RHO are driven
  whatever their velocity and whatever hits them, the others classified as with drive match (the
  densities by hand, two thresholds); 2 processes give 1 process's dumps;
- the box: an atom the field would carry out through a face that is not periodic stays dynamic
  (held at rest, or with the velocity it had), one driven through a periodic face stays
  kinematic, and nothing is lost (f_rom[19] counts them);
- a model of form occupancy (version 3): each voxel's field is its own density (as dumped) times
  the bias plus the control's weight times the control, on 1 and 2 processes;
- train_rom.py recovers an exact linear map (synthetic fields, one run's control following a
  schedule file): every weight to 1e-3; with --form occupancy an exact occupancy map the same
  way."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from griddemtools.grid import read_grid_dump  # noqa: E402 (griddem_testlib puts python/ on the path)

WD = t.workdir()


BOX = (0.0, 6.0, 0.0, 6.0, 0.0, 6.0)
HEAD = """
units lj
atom_style sphere
atom_modify map array
boundary {bnd}
comm_modify vel yes
region box block 0 6 0 6 0 6
create_box 1 box
"""
PAIR = """
pair_style griddem/hooke/history 2000 NULL 50 NULL 0.5 1
pair_coeff * *
timestep 0.001
"""


def resting_spheres(*centres):
    """The walled box with unit spheres (density 1) at rest at the given centres."""
    return HEAD.format(bnd="f f f") + "".join("create_atoms 1 single %s %s %s\n" % c for c in centres) + \
        "set type 1 diameter 1.0\nset type 1 density 1.0\nvelocity all set 0 0 0\n"


# integration, the fix griddem/rom line ({rom}) and the pair virial printed every step
VIRIAL_EACH_STEP = """
{rom}
fix integrate {dyn} nve/sphere
compute vir all pressure NULL virial
thermo_style custom step c_vir
thermo_modify format float %.17g
thermo 1
"""


def model_input(path):
    """A one-control fix griddem/rom reading the model file at path, run 0."""
    return HEAD.format(bnd="f f f") + PAIR + """
variable w equal 1.0
fix rom all griddem/rom model {m} eps 0.1 v0 1 every 1 control v_w
fix integrate rom_dynamic nve/sphere
run 0
""".format(m=path)


def model_checks():
    good = os.path.join(WD, "good.model")
    t.write_rom_model(good, (3, 3, 3), BOX, controls=1)
    cases = [
        ("version", dict(version=4), "format version 4"),
        ("grid size", dict(nrow=3 * 26), "grid size 3 3 3"),
        ("columns", dict(ncol=1 + 27), "grid size 3 3 3 and 1 controls"),
        ("controls", dict(controls=2), "has 2 controls, the fix names 1"),
    ]
    for name, kw, expected in cases:
        path = os.path.join(WD, "bad_%s.model" % name.replace(" ", "_"))
        args = dict(controls=1)
        args.update(kw)
        t.write_rom_model(path, (3, 3, 3), BOX, **args)
        text = model_input(path)
        rc, out = t.run_lmp(text, WD, name="in.bad_" + name.replace(" ", "_"))
        t.check(rc != 0 and expected in out, "model with a wrong %s refused naming it (%r)" % (name, expected))
    path = os.path.join(WD, "bad_box.model")
    t.write_rom_model(path, (3, 3, 3), (0.0, 6.0, 0.0, 6.0, 0.0, 7.0), controls=1)
    text = model_input(path)
    rc, out = t.run_lmp(text, WD, name="in.bad_box")
    t.check(rc != 0 and "differs from the simulation box" in out, "model with a wrong box refused")
    # and the good one runs
    text = model_input(good)
    rc, out = t.run_lmp(text, WD, name="in.good")
    t.check(rc == 0, "a consistent model is accepted")


def model_file_messages():
    """Words after the weights, and binary bytes, are refused naming the line and what was expected
    there, with bytes other than printable ASCII as \\xNN. A test model's lines: 1 comment,
    2 version, 3 grid, 4 box, 5 controls, 6 lambda, 7 'weights 81 29', 8-88 the 81 rows."""
    def refused(path, expected, what):
        rc, out = t.run_lmp(model_input(path), WD, name="in.msg_" + os.path.basename(path).split(".")[0])
        t.check(rc != 0 and expected in out, "%s refused naming line and expectation (%r): %s"
                % (what, expected, t.errors(out)[:1]))

    for version, expected in ((1, "line 89: expected the end of the file after the 81 x 29 weights, found 'end'"),
                              (2, "line 89: expected the end of the file or a block 'force 3 29' after the 81 x 29 "
                                  "weights, found 'end'")):
        path = os.path.join(WD, "trailing%d.model" % version)
        t.write_rom_model(path, (3, 3, 3), BOX, controls=1, version=version)
        with open(path, "a") as f:
            f.write("end\n")
        refused(path, expected, "version %d: a word after the weights" % version)
    path = os.path.join(WD, "trailing_force.model")
    t.write_rom_model(path, (3, 3, 3), BOX, controls=1, version=2, force=[[0.0] * 29] * 3)
    with open(path, "a") as f:
        f.write("0.5\n")
    refused(path, "line 93: expected the end of the file after the 3 x 29 force values, found '0.5'",
            "a word after the force block")

    def escaped(data):
        return "".join(chr(b) if 0x20 <= b < 0x7f else "\\x%02x" % b for b in data)
    # a binary file: its first word is 64 bytes without white space (shown: 40 of them, then ...)
    binary = b"\x7fELF\x02\x01\x01" + bytes(57)
    path = os.path.join(WD, "binary.model")
    with open(path, "wb") as f:
        f.write(binary + b"\n\x03\x00\x00\n")
    refused(path, "line 1: expected 'griddem/rom VERSION', found '%s...'" % escaped(binary[:40]), "a binary file")
    # binary bytes in the weights' second row (line 9)
    path = os.path.join(WD, "binary_row.model")
    t.write_rom_model(path, (3, 3, 3), BOX, controls=1)
    with open(path, "rb") as f:
        lines = f.read().split(b"\n")
    lines[8] = b"\x00\x01 " + lines[8]
    with open(path, "wb") as f:
        f.write(b"\n".join(lines))
    refused(path, "line 9: expected value 1 of row 2 of 'weights' (a finite number), found '\\x00\\x01'",
            "binary bytes in a row of weights")
    # too few weights: where the file ends, and what the header asked for
    path = os.path.join(WD, "short.model")
    t.write_rom_model(path, (3, 3, 3), BOX, controls=1, nrow=80)
    with open(path) as f:
        text = f.read().replace("weights 80 29", "weights 81 29")
    with open(path, "w") as f:
        f.write(text)
    refused(path, "at its end (line 87): 'weights 81 29' (line 7) needs 81 x 29 = 2349 values, found 2320",
            "a weights block cut short")


def counters():
    """f_rom[2], [3], [4], [7] (made kinematic, released by a hit, released by an overlap,
    classifications) on a scene counted by hand: zero field, eps v0 = 0.5, every 5, two runs of 5
    steps (a classification at the end of each; the counters add up over the fix's runs).
    Run 1: atoms 1, 2, 3, 4 rest alone and are made kinematic; atom 6 rests against atom 7 (outside
    the fix's group), which slides past it at 1 (overlap 0.01): 6 is not made kinematic, and not
    counted as released, since it was not kinematic. Made 4, hits 0, overlaps 0, 1 classification.
    Between the runs: atom 5 (outside the group) is set against kinematic atom 1 (overlap 0.01),
    sliding past it at 1 (5 steps of friction leave it above 0.5); kinematic atoms 2 and 3 are set
    to overlap by 0.1 (> 0.1 min(ri, rj) = 0.05; no force acts between kinematic atoms to part them);
    atoms 6 and 7 are parted and stopped.
    Run 2: 1 is released by a hit, 2 and 3 by their overlap, 4 stays kinematic (not made again),
    6 is made kinematic. Made 5, hits 1, overlaps 2, 2 classifications; kinematic now 4 and 6."""
    model = os.path.join(WD, "rest_counts.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    text = resting_spheres((1.5, 1.5, 1.5), (4.5, 1.5, 1.5), (4.5, 4.5, 1.5), (1.5, 4.5, 4.5), (1.5, 4.5, 1.5),
                           (4.5, 4.5, 4.5), (4.5, 4.5, 3.51)) + PAIR + """
group romable id 1 2 3 4 6
set atom 7 vx 1.0
fix rom romable griddem/rom model {m} eps 0.5 v0 1 every 5
fix integrate rom_dynamic nve/sphere
thermo_style custom step f_rom[1] f_rom[2] f_rom[3] f_rom[4] f_rom[6] f_rom[7]
thermo 5
run 5
set atom 5 x 2.49 y 1.5 z 1.5 vx 0.0 vy 1.0 vz 0.0
set atom 3 x 4.5 y 2.4 z 1.5
set atom 7 x 4.5 y 1.5 z 4.5 vx 0.0
set atom 6 vx 0.0 vy 0.0 vz 0.0
run 5
""".format(m=model)
    out = t.run_ok(text, WD, name="in.counters")
    columns = ("f_rom[1]", "f_rom[2]", "f_rom[3]", "f_rom[4]", "f_rom[6]", "f_rom[7]")
    names = ("kinematic", "made", "hits", "overlaps", "released by a force", "classifications")
    got = [t.thermo_values(out, c) for c in columns]
    # thermo rows: steps 0 and 5 (run 1), 5 and 10 (run 2)
    for label, row, expected in (("run 1", 1, (4, 4, 0, 0, 0, 1)), ("run 2", 3, (2, 5, 1, 2, 0, 2))):
        for name, values, want in zip(names, got, expected):
            t.check(len(values) == 4 and values[row] == want,
                    "counters, %s: %s %s, counted by hand %d" % (label, name, values[row:row + 1], want))


def eps_zero():
    model = os.path.join(WD, "zero.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    base = HEAD.format(bnd="p p p") + """
lattice sc 1.1 origin 0.5 0.5 0.5
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.0
velocity all create 0.5 4928 dist gaussian
""" + PAIR + """
{rom}
fix integrate {dyn} nve/sphere
dump d all custom 200 {dump} id x y z vx vy vz omegax fx {extra}
dump_modify d format float %.17g sort id
thermo 100
run 400
"""
    t.run_ok(base.format(rom="", dyn="all", dump="plain.dump", extra=""), WD, name="in.plain")
    t.run_ok(base.format(dyn="rom_dynamic", rom="fix rom all griddem/rom model %s eps 0 v0 1 every 1" % model,
                         dump="rom0.dump", extra="f_rom"), WD, name="in.rom0")
    plain, rom = t.read_dumps(os.path.join(WD, "plain.dump")), t.read_dumps(os.path.join(WD, "rom0.dump"))
    t.check(len(plain) == len(rom) == 3, "three snapshots each")
    same = all(all(r[1][tag][:8] == p[1][tag] for tag in p[1]) for p, r in zip(plain, rom))
    moved = any(abs(rom[-1][1][tag][4] - rom[0][1][tag][4]) > 0 for tag in rom[0][1])
    t.check(moved, "the eps 0 scene has collisions (velocities change)")
    t.check(same, "eps 0: positions, velocities, spins, forces equal the plain run exactly")
    t.check(all(v[8] == 0.0 for snap in rom for v in snap[1].values()), "eps 0: no atom kinematic")
    # drive box too: eps 0 switches the reduction off
    t.run_ok(base.format(dyn="rom_dynamic", rom="fix rom all griddem/rom model %s eps 0 v0 1 every 1 drive box" % model,
                         dump="rom0box.dump", extra="f_rom"), WD, name="in.rom0box")
    box = t.read_dumps(os.path.join(WD, "rom0box.dump"))
    t.check(len(box) == 3 and all(all(r[1][tag][:8] == p[1][tag] for tag in p[1]) for p, r in zip(plain, box)) and
            all(v[8] == 0.0 for snap in box for v in snap[1].values()),
            "eps 0 with drive box: no atom kinematic, the plain run exactly")


def uniform_field():
    U = (0.3, -0.2, 0.1)
    model = os.path.join(WD, "uniform.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    g = 2.0
    text = resting_spheres((1.5, 1.5, 3.0), (4.5, 4.5, 3.0)) + """
set atom 2 vx 0.9
""" + PAIR + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5
fix integrate rom_dynamic nve/sphere
fix down all gravity {g} vector 0 0 -1
dump d all custom 5 uniform.dump id x y z vx vy vz f_rom
dump_modify d format float %.17g sort id
run 25
""".format(g=g, m=model)
    t.run_ok(text, WD, name="in.uniform")
    snaps = t.read_dumps(os.path.join(WD, "uniform.dump"))
    dt = 0.001
    # |v1 - U| = |U| = 0.374 <= eps v0 = 0.5: kinematic from step 5 on
    s5, s25 = snaps[1][1], snaps[-1][1]
    t.check(s5[1][6] == 1.0 and s25[1][6] == 1.0, "resting atom made kinematic by a field within eps v0")
    # the trilinear weights sum to 1 up to rounding: the field to a few ulps
    t.check(all(abs(s25[1][3 + d] - U[d]) <= 4e-16 * abs(U[d]) for d in range(3)),
            "kinematic velocity equals the field: %s" % s25[1][3:6])
    ok = all(abs(s25[1][d] - (s5[1][d] + 20 * dt * U[d])) <= 1e-12 for d in range(3))
    t.check(ok, "kinematic atom moves by U dt per step despite gravity")
    # atom 2: |v - U| = sqrt(0.6^2 + 0.2^2 + 0.1^2) = 0.64 > 0.5: dynamic, free fall vz = -g t
    t.check(all(s[1][2][6] == 0.0 for s in snaps), "atom moving at more than eps v0 relative to the field stays dynamic")
    t.check(abs(s25[2][5] - (-g * 25 * dt)) <= 1e-12, "dynamic atom falls freely: vz %.15g, -g t %.15g" % (s25[2][5], -g * 25 * dt))


def contacts():
    model = os.path.join(WD, "rest.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    # atoms 1, 2 overlap by 0.005 (bound 0.1 * 0.5 = 0.05); atom 3 (not in the fix group) overlaps
    # atom 1 by 0.005 from the other side; atoms 4, 5 overlap by 0.1 > 0.05 (never kinematic)
    base = resting_spheres((3.0, 3.0, 3.0), (3.995, 3.0, 3.0), (3.0, 3.995, 3.0), (1.0, 1.0, 1.0),
                           (1.9, 1.0, 1.0)) + """
group romable id 1 2 4 5
""" + PAIR + VIRIAL_EACH_STEP + """dump d all custom 10 {dump} id x y z vx vy vz {extra}
dump_modify d format float %.17g sort id
run 10
"""
    out = t.run_ok(base.format(dyn="rom_dynamic", rom="fix rom romable griddem/rom model %s eps 0.5 v0 1 every 1" % model,
                               dump="contacts.dump", extra="f_rom"), WD, name="in.contacts")
    snaps = t.read_dumps(os.path.join(WD, "contacts.dump"))
    s = snaps[-1][1]
    t.check(s[1][6] == 1.0 and s[2][6] == 1.0, "resting overlapping atoms 1, 2 kinematic")
    t.check(s[4][6] == 0.0 and s[5][6] == 0.0, "atoms 4, 5 overlapping beyond the bound stay dynamic")
    t.check(s[3][6] == 0.0, "atom 3 (outside the fix group) dynamic")
    # kinematic with a zero field: atoms 1, 2 stand still after their classification at step 1
    t.check(s[1][3:6] == [0.0, 0.0, 0.0] and s[2][3:6] == [0.0, 0.0, 0.0], "kinematic atoms at rest")
    # atom 3 is pushed away from atom 1 along +y
    t.check(s[3][4] > 0.0, "dynamic atom pushed by the kinematic one: vy %g" % s[3][4])
    # the virial: 1-3 and 4-5 contacts only; without the 1-2 contact
    out_rom = out
    # the same scene with atom 3 and atoms 4, 5 removed: only the kinematic pair 1-2 remains
    only12 = base.replace("create_atoms 1 single 3.0 3.995 3.0\n", "").replace(
        "create_atoms 1 single 1.0 1.0 1.0\ncreate_atoms 1 single 1.9 1.0 1.0\n", "").replace(
        "group romable id 1 2 4 5", "group romable id 1 2")
    out = t.run_ok(only12.format(dyn="rom_dynamic", rom="fix rom romable griddem/rom model %s eps 0.5 v0 1 every 1" % model,
                                 dump="only12.dump", extra="f_rom"), WD, name="in.only12")
    vir = t.thermo_values(out, "c_vir")
    t.check(vir[0] != 0.0, "before the first classification the pair 1-2 pushes (virial %g)" % vir[0])
    t.check(all(v == 0.0 for v in vir[2:]), "after it the kinematic pair exerts no force (virial %s)" % vir[2:5])
    out = t.run_ok(only12.format(rom="", dyn="all", dump="only12plain.dump", extra=""), WD, name="in.only12plain")
    vir = t.thermo_values(out, "c_vir")
    t.check(all(v != 0.0 for v in vir[2:]), "the same pair without the fix keeps pushing")


def processes():
    model = os.path.join(WD, "rest2.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    text = HEAD.format(bnd="f f f").replace("region box", "processors 2 1 1\nregion box") + """
create_atoms 1 single 2.6 3.0 3.0
create_atoms 1 single 3.595 3.0 3.0
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set 0 0 0
""" + PAIR + VIRIAL_EACH_STEP + """run 10
"""
    out = t.run_ok(text.format(dyn="rom_dynamic", rom="fix rom all griddem/rom model %s eps 0.5 v0 1 every 1" % model),
                   WD, nprocs=2, name="in.procs")
    vir = t.thermo_values(out, "c_vir")
    t.check(vir[0] != 0.0 and all(v == 0.0 for v in vir[2:]),
            "2 processes: kinematic pair across the boundary exerts no force (virial %s)" % vir[:4])


def release():
    model = os.path.join(WD, "left.model")
    U = -0.3
    t.write_rom_model(model, (3, 3, 3), BOX, bias=(U, 0.0, 0.0))
    text = resting_spheres((0.52, 3.0, 3.0)) + """
""" + PAIR + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5
fix integrate rom_dynamic nve/sphere
fix wall all wall/gran hooke/history 2000 NULL 50 NULL 0.5 1 xplane 0 NULL
variable x equal x[1]
thermo_style custom step v_x f_rom[6]
thermo_modify format float %.17g
thermo 1
run 500
""".format(m=model)
    out = t.run_ok(text, WD, name="in.release")
    xs, released = t.thermo_values(out, "v_x"), t.thermo_values(out, "f_rom[6]")
    m, kn, n, dt = math.pi / 6.0, 2000.0, 5, 0.001
    bound = 0.5 * 1.0 * m / (kn * n * dt)       # eps v0 m / (kn N dt)
    depth = 0.5 - min(xs)
    t.check(released[-1] >= 1, "kinematic atom released by the wall's force")
    t.check(depth <= bound + abs(U) * dt + 0.01, "penetration %.4f within the release bound %.4f" % (depth, bound))

    model0 = os.path.join(WD, "rest3.model")
    t.write_rom_model(model0, (3, 3, 3), BOX)
    text = resting_spheres((3.0, 3.0, 3.0), (1.5, 3.0, 3.0)) + """
set atom 2 vx 1.0
group target id 1
""" + PAIR + """
fix rom target griddem/rom model {m} eps 0.2 v0 1 every 1
fix integrate rom_dynamic nve/sphere
dump d all custom 100 hit.dump id vx f_rom
dump_modify d format float %.17g sort id
run 1000
""".format(m=model0)
    t.run_ok(text, WD, name="in.hit")
    snaps = t.read_dumps(os.path.join(WD, "hit.dump"))
    t.check(snaps[1][1][1][1] == 1.0, "resting atom kinematic before the hit")
    t.check(snaps[-1][1][1][1] == 0.0 and snaps[-1][1][1][0] > 0.1,
            "hit atom released and moving (vx %g)" % snaps[-1][1][1][0])


def loaded():
    """A dynamic atom resting on a kinematic one under gravity: the contact's push (about m g) and
    gravity do not release it (the old rule, |f| N dt / m > eps v0 with f = 2 m g here, did: eps
    v0 = 0.08 lies between g N dt = 0.05 and 2 g N dt = 0.1); it stays put and carries the other."""
    model = os.path.join(WD, "rest.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    text = resting_spheres((3.0, 3.0, 2.0), (3.0, 3.0, 3.0)) + """
group bottom id 1
""" + PAIR + """
fix rom bottom griddem/rom model {m} eps 0.08 v0 1 every 50
fix integrate rom_dynamic nve/sphere
fix gravity all gravity 1.0 vector 0 0 -1
variable z1 equal z[1]
variable z2 equal z[2]
thermo_style custom step v_z1 v_z2 f_rom[1] f_rom[6]
thermo_modify format float %.17g
thermo 100
run 3000
""".format(m=model)
    out = t.run_ok(text, WD, name="in.loaded")
    z1, z2 = t.thermo_values(out, "v_z1"), t.thermo_values(out, "v_z2")
    kin, released = t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[6]")
    t.check(kin[-1] == 1 and released[-1] == 0, "loaded kinematic atom never released (kinematic %s, released %s)"
            % (kin[-1], released[-1]))
    t.check(max(z1[1:]) == min(z1[1:]) and z1[-1] < 2.0, "it stays where it was made kinematic (z %.15g .. %.15g)"
            % (min(z1[1:]), max(z1[1:])))
    overlap = 1.0 - (z2[-1] - z1[-1])
    t.check(0.0 < overlap < 3 * (math.pi / 6.0) / 2000.0,
            "the dynamic atom rests on it: overlap %.3g, about m g / kn = %.3g" % (overlap, math.pi / 6.0 / 2000.0))


def field_jump():
    """A resting kinematic atom where a control switches the field from 0 to 1 (> eps v0 = 0.5)
    is released with its velocity, not kicked: it stays at rest and is counted (f_rom[8])."""
    model = os.path.join(WD, "switch.model")
    t.write_rom_model(model, (3, 3, 3), BOX, controls=1, control_weight=1.0)
    text = resting_spheres((3.0, 3.0, 3.0)) + """
""" + PAIR + """
variable on equal step>100
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5 control v_on
fix integrate rom_dynamic nve/sphere
variable x equal x[1]
thermo_style custom step v_x f_rom[1] f_rom[8]
thermo_modify format float %.17g
thermo 50
run 300
""".format(m=model)
    out = t.run_ok(text, WD, name="in.jump")
    xs, kin, jumps = t.thermo_values(out, "v_x"), t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[8]")
    t.check(kin[1] == 1 and kin[-1] == 0 and jumps[-1] == 1, "kinematic before the switch, released by the jump "
            "after it (kinematic %s, jumps %s)" % (kin, jumps))
    t.check(all(x == 3.0 for x in xs), "the released atom stays at rest (x %s)" % xs[-1])


def resolved_region():
    """Keyword resolved: atoms in the region are never kinematic; a region whose bound moves (an
    equal-style variable) releases the kinematic atom it comes to hold (counted in f_rom[5])."""
    model = os.path.join(WD, "rest4.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    text = resting_spheres((3.0, 3.0, 1.5), (3.0, 3.0, 4.5)) + PAIR + """
variable zlo equal 4.0-3.0*(step>100)
region top block INF INF INF INF v_zlo INF
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5 resolved top
fix integrate rom_dynamic nve/sphere
thermo_style custom step f_rom[1] f_rom[5]
thermo 50
dump d all custom 50 region.dump id f_rom
dump_modify d sort id
run 200
""".format(m=model)
    out = t.run_ok(text, WD, name="in.region")
    kin, left = t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[5]")
    snaps = t.read_dumps(os.path.join(WD, "region.dump"))
    t.check(snaps[1][1][1][0] == 1.0 and snaps[1][1][2][0] == 0.0 and kin[1] == 1,
            "atom 1 kinematic, atom 2 in the resolved region dynamic (step 50: %s)" % snaps[1][1])
    t.check(kin[-1] == 0 and left[-1] == 1 and snaps[-1][1][1][0] == 0.0,
            "the region grown over atom 1 releases it (kinematic %s, released %s)" % (kin, left))
    rc, out = t.run_lmp(text.replace("resolved top", "resolved nowhere"), WD, name="in.noregion")
    t.check(rc != 0 and "region nowhere (keyword resolved) does not exist" in out, "a missing region is refused by name")


def lattice_fields(model, name, before="", forces=None):
    """The field and density (rows vx, vy, vz, density of the 27 voxels) that fix griddem/rom with
    model dumps at step 10 on 64 unit spheres at rest on a lattice of spacing 1.5 (lines before:
    the fix's controls), on 1 and 2 processes; the predicted force at step 10 (f_rom[14..16]) of
    each appended to the list forces if one is given."""
    frames = []
    for nprocs in (1, 2):
        text = HEAD.format(bnd="f f f").replace("region box", "processors %d 1 1\nregion box" % nprocs) + """
lattice sc 0.2962962962962963 origin 0.5 0.5 0.5
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set 0 0 0
""" + PAIR + before + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5{controls}
fix integrate rom_dynamic nve/sphere
dump g all grid 5 {name}{n}.txt f_rom:field:vx f_rom:field:vy f_rom:field:vz f_rom:field:density
dump_modify g sort id format float %.17g
thermo_style custom step f_rom[14] f_rom[15] f_rom[16]
thermo_modify format float %.17g
thermo 5
run 10
""".format(m=model, n=nprocs, name=name, controls=" control v_c" if before else "")
        out = t.run_ok(text, WD, nprocs=nprocs, name="in.%s%d" % (name, nprocs))
        if forces is not None:
            forces.append([t.thermo_values(out, "f_rom[%d]" % k)[-1] for k in (14, 15, 16)])
        with open(os.path.join(WD, "%s%d.txt" % (name, nprocs))) as f:
            lines = f.read().splitlines()
        k = max(i for i, line in enumerate(lines) if line.startswith("ITEM: GRID CELLS"))
        frames.append([[float(v) for v in line.split()] for line in lines[k + 1:k + 28]])
    return frames


def field_output():
    """The predicted field and the density as grid data (dump grid): a uniform field U in every
    voxel, the density summing to the mass of the 64 atoms (lattice spacing 1.5; CIC keeps mass),
    1 and 2 processes equal (to the order of the sum over processes)."""
    U = (0.3, -0.2, 0.1)
    model = os.path.join(WD, "grid.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    frames = lattice_fields(model, "field")
    rows = frames[0]
    t.check(len(rows) == 27 and all(r[:3] == list(U) for r in rows), "dump grid: the field is U in all 27 voxels")
    mass = sum(r[3] for r in rows) * 2.0 ** 3
    t.check(abs(mass - 64 * math.pi / 6.0) <= 1e-12 * mass, "dump grid: density sums to the mass (%.15g)" % mass)
    diff = max(abs(a - b) for r1, r2 in zip(frames[0], frames[1]) for a, b in zip(r1, r2))
    t.check(len(frames[1]) == 27 and diff <= 1e-14, "dump grid: 2 processes write the field of 1 "
            "(densities summed in another order: %.2g)" % diff)


def occupancy_form():
    """A model of form occupancy: voxel m's velocity is density(m) (w0 + w1 c) with c = 2 (an
    equal-style variable) and per-component weights: (0.2 + 0.1 c, -0.1, 0.05 m c) = (0.4, -0.1,
    0.1 m) times the density the fix dumps, on the lattice of field_output (1 and 2 processes).
    Its force block has the weights' two columns: the force is (1 + 0.5 c, 2, -1 + 0.25 c) =
    (2, 2, -0.5), with no density."""
    model = os.path.join(WD, "occupancy.model")
    with open(model, "w") as f:
        f.write("griddem/rom 3\ngrid 3 3 3\nbox %s\ncontrols 1\nlambda 0\nform occupancy\nweights 81 2\n"
                % " ".join("%.17g" % b for b in BOX))
        for m in range(27):
            f.write("0.2 0.1\n-0.1 0\n0 %.17g\n" % (0.05 * m))
        f.write("force 3 2\n1 0.5\n2 0\n-1 0.25\n")
    forces = []
    frames = lattice_fields(model, "occ", before="variable c equal 2\n", forces=forces)
    t.check(forces == [[2.0, 2.0, -0.5]] * 2,
            "form occupancy: the predicted force is (1 + 0.5 c, 2, -1 + 0.25 c) = (2, 2, -0.5) on 1 and 2 "
            "processes (%s)" % forces)
    rows = frames[0]
    worst = max(abs(r[d] - r[3] * (0.4, -0.1, 0.1 * m)[d]) for m, r in enumerate(rows) for d in range(3))
    t.check(len(rows) == 27 and min(r[3] for r in rows) > 0 and worst <= 1e-15,
            "form occupancy: each voxel's field is its density times (0.4, -0.1, 0.1 m) (worst %.2g)" % worst)
    diff = max(abs(a - b) for r1, r2 in zip(frames[0], frames[1]) for a, b in zip(r1, r2))
    t.check(len(frames[1]) == 27 and diff <= 1e-14, "form occupancy: 2 processes write the field of 1 (%.2g)" % diff)


def model_words(script, options, name, specs):
    """The words (comments left out) of the model file name that train_rom.py (script) with
    options makes from specs in WD, or None (reported) when it fails."""
    import subprocess
    out_model = os.path.join(WD, name)
    proc = subprocess.run(["/usr/bin/python3", script] + options + [out_model] + specs, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True)
    t.check(proc.returncode == 0, "train_rom.py %s runs: %s" % (" ".join(options), proc.stdout[-300:]))
    if proc.returncode != 0:
        return None
    words = []
    with open(out_model) as f:
        for line in f:
            words += line.split("#")[0].split()
    return words


def write_synthetic_frame(f, step, rho, vel):
    """One frame of a dump grid of compute griddem/cg (density vx vy vz) on a 2 x 1 x 2 grid."""
    f.write("ITEM: TIMESTEP\n%d\nITEM: BOX BOUNDS ff ff ff\n0 4\n0 1\n0 4\n" % step)
    f.write("ITEM: DIMENSION\n3\nITEM: GRID SIZE nx ny nz\n2 1 2\n")
    f.write("ITEM: GRID CELLS c_cg:grid:density c_cg:grid:vx c_cg:grid:vy c_cg:grid:vz\n")
    for v in range(len(rho)):
        f.write("%.17g %.17g %.17g %.17g\n" % (rho[v], vel[3 * v], vel[3 * v + 1], vel[3 * v + 2]))


def training():
    """Synthetic dumps whose velocities are an exact linear function of density and control; then
    an exact occupancy map (density times a linear function of the control)."""
    import random
    rng = random.Random(5)
    n, m = (2, 1, 2), 4
    A = [[rng.uniform(-1, 1) for _ in range(m + 1)] for _ in range(3 * m)]   # density + control
    b = [rng.uniform(-1, 1) for _ in range(3 * m)]
    specs = []
    # the third run's control changes during the run (a schedule file: until step 100 it is 0.5,
    # until 200 2.5, then 1.5); a frame at step 100 still has 0.5
    schedule = os.path.join(WD, "syn_schedule.txt")
    with open(schedule, "w") as f:
        f.write("# until_step control\n100 0.5\n200 2.5\n290 1.5\n")
    for run, control in enumerate((1.0, 2.0, None)):
        path = os.path.join(WD, "syn%d.txt" % run)
        with open(path, "w") as f:
            for frame in range(30):
                step = frame * 10
                w = control if control is not None else (0.5 if step <= 100 else 2.5 if step <= 200 else 1.5)
                rho = [rng.uniform(0.0, 1.0) for _ in range(m)]
                vel = [b[r] + sum(A[r][k] * rho[k] for k in range(m)) + A[r][m] * w for r in range(3 * m)]
                write_synthetic_frame(f, step, rho, vel)
        specs.append("%s:%s" % (path, "%g" % control if control is not None else "@" + schedule))
    here = os.path.dirname(os.path.abspath(__file__))
    script = os.path.join(os.path.dirname(os.path.dirname(here)), "examples", "rom-pile", "train_rom.py")
    words = model_words(script, [], "syn.model", specs)
    if words is None:
        return
    k = words.index("weights")
    nrow, ncol = int(words[k + 1]), int(words[k + 2])
    t.check(words[:2] == ["griddem/rom", "1"] and words[2:6] == ["grid", "2", "1", "2"] and
            (nrow, ncol) == (12, 6), "model header: version 1, grid 2 1 2, 12 x 6 weights")
    W = [[float(x) for x in words[k + 3 + r * ncol:k + 3 + (r + 1) * ncol]] for r in range(nrow)]
    worst = max(max(abs(W[r][0] - b[r]), max(abs(W[r][1 + c] - A[r][c]) for c in range(m + 1)))
                for r in range(nrow))
    t.check(worst <= 1e-3, "train_rom.py recovers the exact linear map, controls constant and scheduled (worst "
            "weight error %.2g)" % worst)

    # form occupancy: vel[3 v + d] = rho[v] (B[r][0] + B[r][1] control), the same runs' densities
    B = [[rng.uniform(-1, 1) for _ in range(2)] for _ in range(3 * m)]
    specs = []
    for run, control in enumerate((1.0, 2.0, 0.5)):
        path = os.path.join(WD, "occ_syn%d.txt" % run)
        with open(path, "w") as f:
            for frame in range(30):
                rho = [rng.uniform(0.0, 1.0) for _ in range(m)]
                vel = [rho[r // 3] * (B[r][0] + B[r][1] * control) for r in range(3 * m)]
                write_synthetic_frame(f, frame * 10, rho, vel)
        specs.append("%s:%g" % (path, control))
    words = model_words(script, ["--form", "occupancy"], "occ_syn.model", specs)
    if words is None:
        return
    k = words.index("weights")
    t.check(words[:2] == ["griddem/rom", "3"] and words[k - 2:k] == ["form", "occupancy"] and
            words[k + 1:k + 3] == ["12", "2"], "occupancy model header: version 3, form occupancy, 12 x 2 weights")
    W = [[float(x) for x in words[k + 3 + 2 * r:k + 5 + 2 * r]] for r in range(3 * m)]
    worst = max(abs(W[r][c] - B[r][c]) for r in range(3 * m) for c in range(2))
    t.check(worst <= 1e-3, "train_rom.py --form occupancy recovers the exact occupancy map (worst weight error "
            "%.2g)" % worst)


def model_step():
    """A kinematic atom that no dynamic atom can reach moves only at the model step, by exactly
    U M dt, where M follows the CFL rule M = floor(cfl h / (|U| dt)) = floor(0.01 x 2 / (0.374 x
    0.001)) = 53 (every 100 caps it); between model steps it stays put; at the run's end it is
    brought up to date (x0 + U t)."""
    U = (0.3, -0.2, 0.1)
    model = os.path.join(WD, "uniform_step.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    text = resting_spheres((3.0, 3.0, 3.0)) + PAIR + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 100 cfl 0.01
fix integrate rom_dynamic nve/sphere
dump d all custom 1 step.dump id x y z f_rom
dump_modify d format float %.17g sort id
thermo_style custom step f_rom[1] f_rom[9] f_rom[10]
thermo 10
run 180
print "FINAL $(x[1]:%.17g) $(y[1]:%.17g) $(z[1]:%.17g)"
""".format(m=model)
    out = t.run_ok(text, WD, name="in.step")
    dt, x0 = 0.001, (3.0, 3.0, 3.0)
    steps = int(0.01 * 2.0 / (math.sqrt(sum(u * u for u in U)) * dt))
    t.check(steps == 53 and t.thermo_values(out, "f_rom[10]")[-1] == 53, "model step by the CFL rule: %s, expected %d"
            % (t.thermo_values(out, "f_rom[10]")[-1], steps))
    t.check(t.thermo_values(out, "f_rom[9]")[-1] == 0, "the atom is not within reach of a dynamic one")
    snaps = t.read_dumps(os.path.join(WD, "step.dump"))
    pos = {k: snaps[k][1][1][:3] for k in range(len(snaps))}
    t.check(snaps[100][1][1][3] == 1.0 and pos[100] == list(x0) and pos[152] == list(x0),
            "kinematic from step 100; it stays put until the next model step (step 152 %s)" % pos[152])
    ok = all(abs(pos[153][d] - (x0[d] + 53 * dt * U[d])) <= 1e-14 for d in range(3))
    t.check(ok and pos[179] == pos[153], "at step 153 it has moved by U 53 dt (%s) and then waits" % pos[153])
    final = [float(w) for w in out.split("FINAL")[-1].split()[:3]]
    t.check(all(abs(final[d] - (x0[d] + 80 * dt * U[d])) <= 1e-14 for d in range(3)),
            "at the run's end it is at x0 + U (180 - 100) dt: %s" % final)


def boundary(nprocs, reach=""):
    """A kinematic atom carried at U = 1 along x towards a resting dynamic atom 0.3 away, on
    nprocs processes (2: the atoms on different ones, the kinematic one crossing over). Lagging
    (model step 50) it would jump into the other by up to U 50 dt = 0.05; held at DEM's step within
    reach, it pushes it like a rigid obstacle at speed U, whose overlap is at most U sqrt(m / kn)
    = 0.0162 (the undamped value; damping lowers it). The kinematic atom ends at x0 + U t."""
    model = os.path.join(WD, "push.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=(1.0, 0.0, 0.0))
    text = resting_spheres((1.9, 3.0, 3.0), (3.2, 3.0, 3.0)).replace(
        "region box", "processors %d 1 1\nregion box" % nprocs) + PAIR + """
set atom 1 vx 1.0
group carried id 1
fix rom carried griddem/rom model {m} eps 2 v0 1 every 50 {reach}
fix integrate rom_dynamic nve/sphere
variable gap equal sqrt((x[2]-x[1])^2+(y[2]-y[1])^2+(z[2]-z[1])^2)-1.0
variable kin equal f_rom[1]
thermo_style custom step v_gap v_kin f_rom[9] f_rom[11] atoms
thermo_modify format float %.17g
thermo 1
run 1500
print "FINAL $(x[1]:%.17g) $(vx[2]:%.17g) $(atoms)"
""".format(m=model, reach=reach)
    out = t.run_ok(text, WD, nprocs=nprocs, name="in.boundary%d%s" % (nprocs, reach.replace(" ", "")))
    gap, kin = t.thermo_values(out, "v_gap"), t.thermo_values(out, "v_kin")
    final = [float(w) for w in out.split("FINAL")[-1].split()[:3]]
    bound = 1.0 * math.sqrt((math.pi / 6.0) / 2000.0)
    label = "%d process(es)%s" % (nprocs, ", " + reach if reach else "")
    t.check(kin[50:] == [1.0] * len(kin[50:]) and min(gap) < -0.005,
            "%s: the atom stays kinematic and pushes the other (deepest overlap %.4f)" % (label, -min(gap)))
    t.check(-min(gap) <= bound, "%s: overlap %.5f within a rigid obstacle's %.5f" % (label, -min(gap), bound))
    t.check(abs(final[0] - (1.9 + 1.5)) <= 1e-12 and final[1] > 0.9 and final[2] == 2,
            "%s: kinematic atom at x0 + U t = 3.4 (%.15g), the other pushed (vx %.3f), 2 atoms" % (label, final[0],
                                                                                              final[1]))


FLOW = (0.7, 0.4, 0.0)


def flow_lattice(model, processors="1 1 1"):
    """125 spheres (lattice spacing 1.2, gaps 0.2) in a periodic box, all moving at FLOW; fix rom
    (model: a uniform field FLOW, every 200) on all but the 25 of the plane z = 0.3 (group low),
    its keyword store left as {store}."""
    return HEAD.format(bnd="p p p").replace("region box", "processors %s\nregion box" % processors) + """
lattice sc 0.5787037037037037 origin 0.25 0.25 0.25
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set %r %r %r units box
region low block INF INF INF INF INF 1.0
group low region low
group carried subtract all low
""" % FLOW + PAIR + """
fix rom carried griddem/rom model %s eps 0.5 v0 1 every 200 store {store}
fix integrate rom_dynamic nve/sphere
""" % model


def migration():
    """125 spheres (lattice spacing 1.2, gaps 0.2) in a periodic box all moving at U: 100 carried
    by the uniform field U (kinematic), the 25 of the plane z = 0.3 outside the fix's group
    (dynamic, free flight), so that the 50 of the planes z = 1.5 and 5.1 (across the periodic
    boundary) are within reach (gap 0.2 < reach 0.3) and move at every step; the other 50 lag and
    are held out of LAMMPS between model steps (keyword store). They cross the sub-domains of 2 and
    4 processes many times; at every step LAMMPS's atoms and the held ones make the 125 (f_rom[18],
    and thermo's atoms plus f_rom[17]), with atoms held at most steps; no atom is lost or has its ID
    twice at the end, every atom ends at x0 + U t (wrapped), and the classification, the atoms within
    reach and the reach tests between model steps are the same on 1, 2 and 4 processes and with
    store no, where thermo's atoms stay 125 (a reach test the skin rule calls for reads the held
    atoms where they are, on several processes every process's, so they are back only for the model
    steps)."""
    U = FLOW
    model = os.path.join(WD, "flow.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    results = []
    for nprocs, grid, store in ((1, "1 1 1", "yes"), (2, "2 1 1", "yes"), (4, "2 2 1", "yes"), (1, "1 1 1", "no")):
        text = flow_lattice(model, grid).format(store=store) + """
write_dump all custom start{n}.dump id x y z modify sort id format float %.17g
thermo_style custom step atoms f_rom[1] f_rom[9] f_rom[11] f_rom[17] f_rom[18]
thermo 1
run 3000
write_dump all custom end{n}.dump id x y z modify sort id format float %.17g
""".format(n=nprocs)
        label = "%d processes, store %s" % (nprocs, store)
        out = t.run_ok(text, WD, nprocs=nprocs, name="in.migrate%d%s" % (nprocs, store))
        start = t.read_dump(os.path.join(WD, "start%d.dump" % nprocs))[1]
        end_text = open(os.path.join(WD, "end%d.dump" % nprocs)).read().split("ITEM: ATOMS")[1].split("\n")[1:]
        ids = [int(line.split()[0]) for line in end_text if line.strip()]
        end = t.read_dump(os.path.join(WD, "end%d.dump" % nprocs))[1]
        worst = 0.0
        for tag, x0 in start.items():
            for d in range(3):
                dx = (end[tag][d] - x0[d] - U[d] * 3000 * 0.001) % 6.0
                worst = max(worst, min(dx, 6.0 - dx))
        counts = [t.thermo_values(out, c) for c in ("Atoms", "f_rom[1]", "f_rom[9]", "f_rom[11]", "f_rom[17]",
                                                     "f_rom[18]")]
        atoms, held, total = counts[0], counts[4], counts[5]
        t.check(len(atoms) == 3001 and all(a + h == 125 and s == 125 for a, h, s in zip(atoms, held, total)),
                "%s: LAMMPS's atoms and the held ones make 125 at every step (held: %d to %d)" %
                (label, min(held), max(held)))
        if store == "yes":
            t.check(sum(h == 50 for h in held) > 2500, "%s: the 50 lagging atoms held at %d of 3001 steps" %
                    (label, sum(h == 50 for h in held)))
            # the reach tests between model steps read the held atoms in place, so they are back only
            # around the 14 model steps after the first (the step itself and the next)
            back = sum(h != 50 for h in held[202:])
            reach_tests = t.thermo_values(out, "f_rom[11]")[-1]
            t.check(back <= 2 * 14 + 2, "%s: held atoms back at %d steps after step 201 (model steps only; %d "
                    "reach tests between them)" % (label, back, reach_tests))
        else:
            t.check(max(held) == 0, "%s: none held" % label)
        t.check(len(ids) == 125 and sorted(ids) == list(range(1, 126)), "%s: IDs 1-125 once each at the end" % label)
        t.check(worst <= 1e-10, "%s: every atom at x0 + U t (worst %.2g)" % (label, worst))
        results.append(counts[1:4])
    t.check(results[0][0][-1] == 100 and results[0][1][-1] == 50 and results[0][2][-1] > 0,
            "100 kinematic, 50 within reach; reach tests between model steps: %s" % results[0][2][-1])
    t.check(all(r[:2] == results[0][:2] and r[2][-1] == results[0][2][-1] for r in results[1:]),
            "kinematic and within reach at every step, and the reach tests, equal on 1, 2 and 4 processes and "
            "with store no")
    t.check(results[0][2] == results[1][2] == results[2][2], "reach tests at the same steps on 1, 2 and 4 processes")


def unreadable_records():
    """migration()'s lattice with atom style hybrid charge sphere, whose exchange records put the
    charge before the radius (record offsets not where the in-place reach test reads them): the
    held atoms come back for each reach test instead, and every atom still ends at x0 + U t."""
    U = FLOW
    model = os.path.join(WD, "flow.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    text = flow_lattice(model).format(store="yes").replace("atom_style sphere", "atom_style hybrid charge sphere") + """
write_dump all custom start.dump id x y z modify sort id format float %.17g
thermo_style custom step atoms f_rom[11] f_rom[17]
thermo 1
run 1000
write_dump all custom end.dump id x y z modify sort id format float %.17g
"""
    out = t.run_ok(text, WD, name="in.unreadable")
    held, reach_tests = t.thermo_values(out, "f_rom[17]"), t.thermo_values(out, "f_rom[11]")[-1]
    back = sum(h != 50 for h in held[202:])
    t.check(max(held) == 50 and reach_tests > 0 and back >= 2 * reach_tests,
            "held atoms back at %d steps after step 201, twice the %d reach tests at least" % (back, reach_tests))
    start, end = t.read_dump(os.path.join(WD, "start.dump"))[1], t.read_dump(os.path.join(WD, "end.dump"))[1]
    worst = 0.0
    for tag, x0 in start.items():
        for d in range(3):
            dx = (end[tag][d] - x0[d] - U[d] * 1000 * 0.001) % 6.0
            worst = max(worst, min(dx, 6.0 - dx))
    t.check(len(end) == 125 and worst <= 1e-10, "every atom at x0 + U t (worst %.2g)" % worst)


def store_in_place():
    """migration()'s lattice, every 500, with the atom at (0.3, 0.3, 1.5) removed and the dynamic
    atom below it, at (0.3, 0.3, 0.3), shot up through the hole at 1.5 on top of the flow: it nears
    the held atom above the hole, at z = 2.7, between model steps (steps 500 and 1000), so that the
    reach test, reading the held atoms where they are (on 2 processes every process's), brings that
    atom back alone (the others stay held: the held count drops by one) to move at every step as a
    kinematic obstacle, which the shot atom hits and bounces off. On 2 processes split along z at
    z = 2 (balance), the shot atom is below the cut and the held atom above it when that happens: a
    process finds near a held atom of the other. Every atom ends where it ends with store no on as
    many processes (1 and 2), also where a dump brings every held atom back at the step that one
    comes back."""
    model = os.path.join(WD, "flow.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=FLOW)
    for nprocs, grid in ((1, "1 1 1"), (2, "2 1 1"), (2, "1 1 2")):
        ends, held, partial = {}, {}, []
        cut = "balance 1.0 z 0.3333333333\n" if grid == "1 1 2" else ""
        where = "%d process(es) %s" % (nprocs, grid.replace(" ", "x"))
        # store yes and, on one process, again with a dump at the step that atom comes back, where every
        # held atom comes back too (that atom still as a near one)
        for run in ("no", "yes", "yes, dumped") if nprocs == 1 else ("no", "yes"):
            dumped = "dump at all custom %d at.dump id x\n" % partial[0] if "dumped" in run else ""
            text = flow_lattice(model, grid).format(store=run[:3].strip(",")).replace("every 200", "every 500") + """
region hole block 0 0.6 0 0.6 1.2 1.8 units box
region gun block 0 0.6 0 0.6 0 0.6 units box
group hole region hole
group shot region gun
delete_atoms group hole
velocity shot set 0.7 0.4 1.5 units box
variable vz equal vcm(shot,z)
variable zs equal xcm(shot,z)
thermo_style custom step atoms f_rom[9] f_rom[11] f_rom[17] v_vz v_zs
thermo 1
""" + cut + dumped + """run 1200
write_dump all custom end.dump id x y z vx vy vz modify sort id format float %.17g
"""
            label = "%s, store %s" % (where, run)
            out = t.run_ok(text, WD, nprocs=nprocs, name="in.inplace%d%s%s" % (nprocs, run.replace(", ", ""),
                                                                              grid.replace(" ", "")))
            ends[run] = t.read_dump(os.path.join(WD, "end.dump"))[1]
            held[run] = t.thermo_values(out, "f_rom[17]")
            vz = t.thermo_values(out, "v_vz")
            t.check(min(vz) < -0.5, "%s: the shot atom bounces off the atom above the hole (vz down to %.3f)" %
                    (label, min(vz)))
            if run == "yes":    # a drop by one between model steps: that atom alone came back
                partial = [k for k in range(1, len(held[run])) if 0 < held[run][k] == held[run][k - 1] - 1 and k % 500]
                shot_z = t.thermo_values(out, "v_zs")
        t.check(len(partial) == 1, "%s: the held atom the shot one nears comes back alone, between model steps "
                "(step %s)" % (where, partial))
        if cut and partial:
            t.check(shot_z[partial[0] - 1] < 2.0, "%s: the shot atom below the cut at z = 2 (z %.3f), the held atom "
                    "at 2.7 above it, at the reach test" % (where, shot_z[partial[0] - 1]))
        if nprocs == 1:
            later = [held[run][partial[0] + 5] for run in ("yes", "yes, dumped")]
            t.check(held["yes, dumped"][partial[0]] == 0 and later[0] == later[1],
                    "1 process: all held atoms back at the dump's step %d, and then all but that one out again "
                    "(held 5 steps later: %s, as without the dump: %s)" % (partial[0], later[1], later[0]))
        # positions modulo the box: a held atom comes back at a run's end unwrapped
        for run, end in ends.items():
            worst = max(min(abs(a - b) % 6.0, 6.0 - abs(a - b) % 6.0) if d < 3 else abs(a - b)
                        for tag in ends["no"] for d, (a, b) in enumerate(zip(end[tag], ends["no"][tag])))
            t.check(len(end) == 124 and worst <= 1e-12, "%s, store %s: the 124 atoms end as with store no "
                    "(largest difference %.2g)" % (where, run, worst))


def corridor(model, centres, every, store):
    """A periodic box 12 x 3 x 3 on 4 processes along x (sub-domains 3 wide), unit spheres at the
    centres (x, at y = z = 1.5), atom 1 driven by the uniform field (2, 0, 0) of model (drive box,
    every steps apart: cfl 5 lets the model step be that long), keyword store as given."""
    return HEAD.format(bnd="p p p").replace("region box block 0 6 0 6 0 6", "processors 4 1 1\nregion box block 0 12 0 3 0 3") + \
        "".join("create_atoms 1 single %r 1.5 1.5 units box\n" % c for c in centres) + """set type 1 diameter 1.0
set type 1 density 1.0
group carried id 1
velocity carried set 2 0 0 units box
""" + PAIR + """fix rom carried griddem/rom model %s eps 0.5 v0 1 every %d cfl 5 drive box store %s
fix integrate rom_dynamic nve/sphere
""" % (model, every, store)


def push_model():
    model = os.path.join(WD, "push.model")
    t.write_rom_model(model, (3, 1, 1), (0.0, 12.0, 0.0, 3.0, 0.0, 3.0), bias=(2.0, 0.0, 0.0))
    return model


def near_elsewhere():
    """A held atom found near by another process than its own: in a periodic box 12 x 3 x 3 on 4
    processes along x (sub-domains 3 wide), atom 1 is driven by the uniform field (2, 0, 0) (drive
    box) from x = 1 (process 0, which holds it from step 1 on; one model step, at 0) toward atom 2, outside
    the fix's group, at rest at x = 8 (process 2). By the reach test that finds it near (gap below
    0.3, x about 6.7) it lies 3.7 from process 0's sub-domain, and atom 2 is no ghost of process 0
    (ghost cutoff 1.3): only process 2 can find it near, and tells process 0. It comes back alone
    then (held 1 at every step before, so no earlier reach test brought it back), hits atom 2 as a
    kinematic obstacle, and both end as with store no."""
    model = push_model()
    runs = {}
    for store in ("no", "yes"):
        text = corridor(model, (1.0, 8.0), 5000, store) + """variable x1 equal x[1]
variable v2 equal vx[2]
thermo_style custom step atoms f_rom[9] f_rom[11] f_rom[17] v_x1 v_v2
thermo_modify format float %.17g
thermo 1
run 3500
write_dump all custom end.dump id x y z vx vy vz modify sort id format float %.17g
"""
        out = t.run_ok(text, WD, nprocs=4, name="in.near_elsewhere_%s" % store)
        runs[store] = (t.read_dump(os.path.join(WD, "end.dump"))[1], t.thermo_values(out, "f_rom[17]"),
                       t.thermo_values(out, "v_x1"), t.thermo_values(out, "v_v2"), t.thermo_values(out, "f_rom[11]"))
    end, held, x1, v2, reach_tests = runs["yes"]
    back = [k for k in range(2, len(held)) if held[k] == 0]
    t.check(back and all(h == 1 for h in held[2:back[0]]) and reach_tests[back[0]] > 1,
            "atom 1 held from step 2 until it comes back at step %s, after %s reach tests" %
            (back[0] if back else None, reach_tests[back[0]] if back else None))
    if back:    # (x[1] reads 0 while it is held)
        t.check(6.0 < x1[back[0]] < 7.0, "atom 1 back at x %.3f: 3 or more past process 0's sub-domain" % x1[back[0]])
    t.check(v2[-1] > 0.5 and v2[-1] == runs["no"][3][-1], "atom 2 pushed to vx %.6f, as with store no (%.6f)"
            % (v2[-1], runs["no"][3][-1]))
    worst = max(abs(a - b) for tag in end for a, b in zip(end[tag], runs["no"][0][tag]))
    t.check(worst <= 1e-12, "both atoms end as with store no (largest difference %.2g)" % worst)


def far_catch_up():
    """One atom driven by the uniform field (2, 0, 0) in a periodic box 12 x 3 x 3 on 4 processes
    along x (sub-domains 3 wide), model steps 2000 steps apart (cfl 5), no dynamic atom (so no
    reach test): at each model step the lagging atom catches up by 4, past the neighbouring
    sub-domain, which LAMMPS's exchange does not reach. With the store and without, no atom is lost
    and it ends at x0 + 2 t (wrapped)."""
    model = push_model()
    for store in ("no", "yes"):
        text = corridor(model, (1.0,), 2000, store) + """thermo_style custom step atoms f_rom[1] f_rom[11] f_rom[18]
thermo 500
run 4001
write_dump all custom end.dump id x y z modify sort id format float %.17g
"""
        rc, out = t.run_lmp(text, WD, nprocs=4, name="in.far_catch_up_%s" % store)
        end = t.read_dump(os.path.join(WD, "end.dump"))[1] if rc == 0 else {}
        x = end[1][0] if 1 in end else float("nan")
        t.check(rc == 0 and abs(x - (1.0 + 2.0 * 4.001) % 12.0) <= 1e-9,
                "store %s: no atom lost (rc %d%s), the atom at x %.12g (x0 + 2 t: %.12g)" %
                (store, rc, ", lost atoms" if "Lost atoms" in out else "", x, (1.0 + 2.0 * 4.001) % 12.0))


def store_limits():
    """What the store (keyword store) refuses, on migration()'s lattice (the 50 atoms of the planes
    z = 2.7 and 3.9, IDs 51-100, lag from the first model step, 200, and are held out of LAMMPS
    from step 201):
    - compute griddem/cg invoked by fix ave/grid every 40 steps (running averages of density and
      velocity): the held atoms are back at its steps (none held there, 50 between), and the
      averages equal store no's to round-off;
    - no ID given twice: fix evaporate deletes the top plane (IDs 101-125, the largest) at step 250
      with fix deposit's first atom (step 1, ID 126), and fix deposit adds its second at step 301;
      the held atoms (IDs 51-100) are back at both steps, so the new atom gets ID 101 (held out of
      their sight, it would get 51);
    - fix deposit into the planes of the held atoms: they are back at its steps, so it places no
      atom on them (every pair of centres at least its `near` 1.0 apart at the end);
    - model steps every 10 steps: the lagging atoms would be out too briefly to pay for their store
      and return (4 atom-steps per atom of the scene, below 8): they stay;
    - restart files written during the run hold all 125 atoms, and a run stopped early by fix halt
      ends with them in LAMMPS;
    - fix balance, fix deform: the atoms stay in LAMMPS (warning; f_rom[17] stays 0)."""
    U = FLOW
    model = os.path.join(WD, "flow_limits.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    lattice = flow_lattice(model)
    cg = lattice + """
compute cg all griddem/cg 3 3 3 0.1 density vx vz
fix avg all ave/grid 40 1 40 3 3 3 c_cg:grid:density c_cg:grid:vx c_cg:grid:vz ave running
thermo_style custom step atoms f_rom[17]
thermo 1
run 600
write_dump all grid cg.{store} f_avg:grid:data[1] f_avg:grid:data[2] f_avg:grid:data[3] modify format float %.17g
"""
    fields, held = {}, {}
    for store in ("yes", "no"):
        out = t.run_ok(cg.format(store=store), WD, name="in.store_cg_" + store)
        held[store] = t.thermo_values(out, "f_rom[17]")
        with open(os.path.join(WD, "cg." + store)) as f:
            fields[store] = [float(w) for line in f.read().split("ITEM: GRID CELLS")[1].splitlines()[1:]
                             for w in line.split()]
    worst = max(abs(a - b) / max(abs(b), 1e-300) for a, b in zip(fields["yes"], fields["no"]) if b != 0.0)
    step_held = [h for step, h in enumerate(held["yes"]) if step > 200 and step % 40 == 0]
    t.check(max(held["yes"]) == 50 and step_held == [0.0] * len(step_held) and
            len(fields["yes"]) == len(fields["no"]) == 81 and worst <= 1e-12,
            "compute griddem/cg through fix ave/grid every 40 steps sees the held atoms (back at its steps, "
            "held between): running averages equal to store no's (largest relative difference %.2g)" % worst)

    twice = lattice + """
thermo_style custom step atoms f_rom[17] f_rom[18]
thermo 10
region top block 0 6 0 6 4.5 6 units box
fix drop all evaporate 250 100 top 4711
fix add all deposit 2 1 300 4712 region top near 1.0 attempt 100 id max
run 350
write_dump all custom twice.dump id x y z modify sort id
"""
    out = t.run_ok(twice.format(store="yes"), WD, name="in.store_twice")
    ids = sorted(t.read_dump(os.path.join(WD, "twice.dump"))[1])
    t.check(ids == list(range(1, 101)) + [101], "fix deposit's atom after fix evaporate took IDs 101-125 has ID 101, "
            "above the held atoms' (IDs at the end: %d, largest %d)" % (len(ids), ids[-1]))

    # fix deposit every 50 steps into the planes of the held atoms (z 2.2-4.4), new atoms moving
    # with U: the held atoms are back at its steps, so it finds no room at least 1.0 from every
    # atom but near the cubes' centres (1.039 from their corners); held out of its sight, it
    # would place atoms on them
    deposit = lattice + """
region mid block 0 6 0 6 2.2 4.4 units box
fix add all deposit 20 1 50 4712 region mid near 1.0 attempt 50 id max vx {u0} {u0} vy {u1} {u1}
run 1000
write_dump all custom deposit.dump id x y z modify sort id format float %.17g
""".format(u0=U[0], u1=U[1])
    out = t.run_ok(deposit.format(store="yes"), WD, name="in.store_deposit")
    atoms = t.read_dump(os.path.join(WD, "deposit.dump"))[1]
    closest = min(math.sqrt(sum(min(abs(a[d] - b[d]) % 6.0, 6.0 - abs(a[d] - b[d]) % 6.0) ** 2 for d in range(3)))
                  for i, a in atoms.items() for j, b in atoms.items() if i < j)
    t.check(closest >= 1.0 - 1e-9, "fix deposit sees the held atoms: %d atoms, closest centres %.4f apart (>= 1)" %
            (len(atoms), closest))

    # model steps every 10 steps: the 50 lagging atoms of 125 would stay out at most 10 steps,
    # 4 atom-steps per atom of the scene, below the 8 a store and its return cost
    short = lattice.replace("every 200", "every 10") + """
thermo_style custom step atoms f_rom[1] f_rom[9] f_rom[17]
thermo 1
run 300
"""
    out = t.run_ok(short.format(store="yes"), WD, name="in.store_short")
    lagging = [k - n for k, n in zip(t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[9]"))]
    t.check(max(lagging) == 50 and max(t.thermo_values(out, "f_rom[17]")) == 0,
            "with model steps every 10 steps the 50 lagging atoms are not stored (it would not pay)")

    # restart files written while atoms are held hold every atom; a run stopped early by fix halt
    # (no last step to plan for) brings them back at its end (the plane z = 0.3 of spheres 1.3
    # wide, dynamic, touching along it)
    outputs = lattice + """
set group low diameter 1.3
restart 150 held.*.restart
variable early equal step>=360
fix stop all halt 1 v_early > 0.5 error continue
thermo_style custom step atoms f_rom[17]
thermo 10
run 400
write_dump all custom halted.dump id x y z modify sort id
unfix stop
thermo_style custom step atoms f_rom[17] f_GRIDDEM[5]
run 20
"""
    out = t.run_ok(outputs.format(store="yes"), WD, name="in.store_outputs")
    held = t.thermo_values(out, "f_rom[17]")
    halted = sorted(t.read_dump(os.path.join(WD, "halted.dump"))[1])
    t.check(max(held) == 50 and halted == list(range(1, 126)),
            "a run stopped by fix halt while 50 atoms are held ends with the 125 atoms in LAMMPS")
    # the IDs fix griddem keeps between runs (for delete_atoms compress yes) are taken once those
    # atoms are back: they came back as they left, and the next run's atoms and contacts are sound
    after = t.thermo_values(out, "Atoms")[-3:]
    contacts = t.thermo_values(out, "f_GRIDDEM[5]")
    t.check(after == [125, 125, 125] and contacts and contacts[0] > 0,
            "the run after the halted one: atoms %s, contacts %s" % (after, contacts[:1]))
    reread = t.run_ok("""
read_restart held.300.restart
print "RESTORED $(atoms)"
""", WD, name="in.store_reread")
    t.check("RESTORED 125" in reread, "a restart file written at step 300, with 50 atoms held before and after, "
            "holds the 125")

    balance = flow_lattice(model, "2 1 1") + """
fix lb all balance 100 1.0 shift x 5 1.1
thermo_style custom step atoms f_rom[17]
thermo 10
run 200
"""
    out = t.run_ok(balance.format(store="yes"), WD, nprocs=2, name="in.store_balance")
    held = t.thermo_values(out, "f_rom[17]")
    t.check("fix balance moves sub-domains while lagging atoms" in out and max(held) == 0 and
            all(a == 125 for a in t.thermo_values(out, "Atoms")),
            "with fix balance the atoms stay in LAMMPS, with a warning")
    # (a fix deform that keeps the box: one that changes it stops the run at the next model step)
    deform = lattice + """
fix df all deform 1 x final 0.0 6.0 remap x units box
thermo_style custom step atoms f_rom[17]
thermo 10
run 250
"""
    out = t.run_ok(deform.format(store="yes"), WD, name="in.store_deform")
    t.check("fix deform changes the box" in out and max(t.thermo_values(out, "f_rom[17]")) == 0,
            "with fix deform the atoms stay in LAMMPS, with a warning")


def blocks():
    """Keyword block: voxel (0,1,1) holds two resting atoms, voxel (1,1,1) one resting and one
    moving at 0.9 > eps v0 relative to the zero field, on different processes. Block 1: the resting
    atom of the second voxel stays dynamic with its neighbour (counted in f_rom[12]); block 0.5:
    half its atoms qualify, so it is kinematic; block 0: atom by atom."""
    model = os.path.join(WD, "rest_blocks.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    expected = {"1": (2, 1), "0.5": (3, 0), "0": (3, 0)}
    for fraction, (nkin, held) in expected.items():
        text = resting_spheres((0.55, 3.0, 3.0), (1.6, 3.0, 3.0), (2.65, 3.0, 3.0), (3.7, 3.0, 3.0)).replace(
            "region box", "processors 2 1 1\nregion box") + PAIR + """
set atom 4 vx 0.9
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5 block {b}
fix integrate rom_dynamic nve/sphere
thermo_style custom step f_rom[1] f_rom[12]
thermo 5
run 5
""".format(m=model, b=fraction)
        out = t.run_ok(text, WD, nprocs=2, name="in.block%s" % fraction)
        got = (t.thermo_values(out, "f_rom[1]")[-1], t.thermo_values(out, "f_rom[12]")[-1])
        t.check(got == (nkin, held), "block %s: %d kinematic, %d held dynamic by the voxel (got %s)"
                % (fraction, nkin, held, got))


def frozen_field():
    """freeze yes: the uniform field U of uniform_field classifies the atoms, but a kinematic atom
    is held at rest; an atom moving at -U (|v| <= eps v0 < |v - U|) stays dynamic, as the field,
    not a zero field, classifies it."""
    U = (0.3, -0.2, 0.1)
    model = os.path.join(WD, "uniform_frozen.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    g = 2.0
    text = resting_spheres((1.5, 1.5, 3.0), (4.5, 4.5, 3.0), (1.5, 4.5, 3.0)) + """
set atom 2 vx 0.9
set atom 3 vx {ux} vy {uy} vz {uz}
""".format(ux=-U[0], uy=-U[1], uz=-U[2]) + PAIR + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5 freeze yes
fix integrate rom_dynamic nve/sphere
fix down all gravity {g} vector 0 0 -1
dump d all custom 5 frozen.dump id x y z vx vy vz f_rom
dump_modify d format float %.17g sort id
run 25
""".format(g=g, m=model)
    t.run_ok(text, WD, name="in.frozen")
    snaps = t.read_dumps(os.path.join(WD, "frozen.dump"))
    s5, s25 = snaps[1][1], snaps[-1][1]
    t.check(s5[1][6] == 1.0 and s25[1][6] == 1.0, "frozen: resting atom made kinematic by the field within eps v0")
    t.check(s25[1][3:6] == [0.0, 0.0, 0.0] and s25[1][0:3] == s5[1][0:3],
            "frozen: kinematic atom at rest and in place despite gravity: x %s v %s" % (s25[1][0:3], s25[1][3:6]))
    t.check(all(s[1][2][6] == 0.0 and s[1][3][6] == 0.0 for s in snaps),
            "frozen: atoms moving at more than eps v0 relative to the field stay dynamic, also one slower than eps v0")
    dt = 0.001
    t.check(abs(s25[2][5] - (-g * 25 * dt)) <= 1e-12, "frozen: dynamic atom falls freely: vz %.15g" % s25[2][5])


def restart_schedule():
    """A restart file written between model steps (step 22 of every 5) continues the schedule: the
    run read back from it has its model steps at 25, 30, ..., as the run that did not stop, and ends
    where it ends (kinetic energy to 1e-12 after 38 more steps, on 1 and 2 processes); a triclinic
    box is refused, and so is a box fix deform takes away from the model's during a run."""
    model = os.path.join(WD, "schedule.model")
    t.write_rom_model(model, (1, 1, 1), BOX, bias=(0.3, 0.0, 0.0))
    scene = t.LATTICE_SPHERES.format(diameter=0.95) + "velocity all create 0.15 12345 loop geom\n"
    rest = PAIR + """fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5
fix integrate rom_dynamic nve/sphere
thermo_style custom step ke
thermo_modify format float %.17g
""".format(m=model)
    for nprocs in (1, 2):
        through = t.run_ok(scene + rest + "run 22\nrun 38\n", WD, nprocs=nprocs, name="in.schedule_through")
        t.run_ok(scene + rest + "run 22\nwrite_restart schedule.restart\n", WD, nprocs=nprocs, name="in.schedule_write")
        read = t.run_ok("units lj\nread_restart schedule.restart\ncomm_modify vel yes\n" + rest + "run 38\n", WD,
                        nprocs=nprocs, name="in.schedule_read")
        ke, ke0 = t.thermo_values(read, "KinEng")[-1], t.thermo_values(through, "KinEng")[-1]
        t.check(abs(ke - ke0) <= 1e-12 * abs(ke0), "%d process(es): run read back at step 22 ends at KE %.17g, the "
                "uninterrupted run at %.17g" % (nprocs, ke, ke0))
    rc, out = t.run_lmp(scene.replace("region box block 0 6 0 6 0 6", "region box prism 0 6 0 6 0 6 0.5 0 0") + rest +
                        "run 5\n", WD, name="in.schedule_triclinic")
    t.check(rc != 0 and "Fix griddem/rom does not support triclinic boxes" in out, "a triclinic box refused: %s"
            % t.errors(out)[:1])
    rc, out = t.run_lmp(scene + rest + "fix d all deform 1 x final 0 7 remap x\nrun 10\n", WD, name="in.schedule_deform")
    t.check(rc != 0 and "model box 0 6 along axis x differs from the simulation box 0 6.4 at step 5" in out,
            "fix deform taking the box from the model's: refused at the first model step: %s" % t.errors(out)[:1])


def averaged_store():
    """With the store on, fix ave/grid over compute griddem/grid and LAMMPS's own binning of atoms
    (density/number) average every atom, as with it off: 50 atoms are stored between model steps
    every 200, and the averages every 70 steps over 630 are the same to the bit; an origin variable
    that is not finite stops the run naming it."""
    model = os.path.join(WD, "flow_averaged.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=FLOW)
    text = flow_lattice(model) + """
compute g all griddem/grid 3 3 3 count vx
fix ag all ave/grid 70 1 70 3 3 3 c_g:grid:count c_g:grid:vx ave running
fix aa all ave/grid 70 1 70 3 3 3 density/number ave running
thermo_style custom step atoms f_rom[17]
thermo 10
run 630
write_dump all grid averaged_{store}.txt f_ag:grid:data[1] f_ag:grid:data[2] f_aa:grid:data modify sort id
"""
    outs, cells = {}, {}
    for store in ("yes", "no"):
        outs[store] = t.run_ok(text.format(store=store), WD, name="in.averaged_" + store)
        with open(os.path.join(WD, "averaged_%s.txt" % store)) as f:
            cells[store] = f.read().split("ITEM: GRID CELLS")[1]
    held = t.thermo_values(outs["yes"], "f_rom[17]")
    t.check(max(held) == 50 and cells["yes"] == cells["no"],
            "fix ave/grid with %d atoms stored at times: the averages of store no (%s)"
            % (max(held), "the same" if cells["yes"] == cells["no"] else "they differ"))
    frame = (0.0, 3.0, 0.0, 6.0, 0.0, 6.0)
    moving = os.path.join(WD, "nan_origin.model")
    t.write_rom_model(moving, (3, 1, 1), frame, version=2, frame="moving")
    rc, out = t.run_lmp(resting_spheres((2.0, 3.0, 3.0)) + PAIR + """
variable ox equal ternary(step>=10,exp(1000)-exp(1000),1)
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5 origin v_ox 0 0
fix integrate rom_dynamic nve/sphere
run 20
""".format(m=moving), WD, name="in.nan_origin")
    t.check(rc != 0 and "Fix griddem/rom: origin variable ox is" in out and "at step 10" in out,
            "an origin variable turning NaN stops the run naming it: %s" % t.errors(out)[:1])


def fields_from_store():
    """A dump grid of compute griddem/cg every 40 steps on migration()'s lattice (50 atoms held
    between the model steps every 200): on one process, with values made of the atoms' own
    quantities (density vx vz temperature solid), the compute reads the held atoms where they are held,
    so they stay out at its steps (50 held there), and every frame equals store no's to round-off;
    also with model steps every 1500 on a 12 x 12 x 12 grid, where the in-place reach tests carry
    held atoms up to 0.6 across the periodic boundary (they are deposited wrapped into the box; the
    lagging atoms of store no are deposited where they are, beyond it). Velocities are compared as
    momentum densities. With coordination (contacts counted among LAMMPS's atoms) and on two
    processes the held atoms are back at its steps (none held there), the frames equal store no's
    as well."""
    model = os.path.join(WD, "flow_fields.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=FLOW)
    for nprocs, grid, values, every, n in ((1, "1 1 1", "density vx vz temperature solid", 200, 3),
                                           (1, "1 1 1", "density vx vz", 1500, 12),
                                           (1, "1 1 1", "density vx coordination", 200, 3),
                                           (2, "2 1 1", "density vx vz temperature", 200, 3)):
        frames, held = {}, {}
        for store in ("no", "yes"):
            text = flow_lattice(model, grid).format(store=store).replace("every 200", "every %d" % every) + """
compute cg all griddem/cg {n} {n} {n} 0.1 {values}
dump fields all grid 40 fields.{store}.txt {columns}
dump_modify fields format float %.17g
thermo_style custom step atoms f_rom[7] f_rom[17]
thermo 1
run {steps}
""".format(n=n, values=values, store=store, columns=" ".join("c_cg:grid:" + v for v in values.split()),
           steps=3 * every)
            out = t.run_ok(text, WD, nprocs=nprocs, name="in.fields_%d_%s" % (nprocs, store))
            held[store] = t.thermo_values(out, "f_rom[17]")
            models = t.thermo_values(out, "f_rom[7]")
            frames[store] = read_grid_dump(os.path.join(WD, "fields.%s.txt" % store))
        label = "%d process(es), %s, every %d" % (nprocs, values, every)
        # each value's differences relative to its largest magnitude in the frame, or to U^2 (the
        # temperature of atoms moving as one is rounding alone); velocities as momentum densities (a
        # ratio over a nearly empty grid point's mass carries the smoothing's rounding)
        def weighted(frame, name):
            return [rho * v for rho, v in zip(frame.columns["density"], frame.columns[name])] if name[0] == "v" \
                else frame.columns[name]
        worst = 0.0
        for fy, fn in zip(frames["yes"], frames["no"]):
            for name in values.split():
                a, b = weighted(fy, name), weighted(fn, name)
                scale = max(max(abs(c) for c in b), sum(u * u for u in FLOW))
                worst = max(worst, max(abs(p - q) for p, q in zip(a, b)) / scale)
        values_of, values_no = frames["yes"], frames["no"]
        # the dump steps after the first store that are no model step (where every atom is back)
        at_dumps = [held["yes"][step] for step in range(every + 40, 3 * every + 1, 40)
                    if models[step] == models[step - 1] and step < 3 * every]
        in_place = nprocs == 1 and "coordination" not in values
        t.check(max(held["yes"]) == 50 and len(values_of) == len(values_no) == 3 * every // 40 + 1 and worst <= 1e-12 and
                all(h == (50 if in_place else 0) for h in at_dumps),
                "%s: atoms held at the dump steps %s (%s), every frame as with store no (largest relative "
                "difference %.2g)" % (label, at_dumps, "read where they are" if in_place else "brought back", worst))


def keyword_checks():
    model = os.path.join(WD, "rest_kw.model")
    t.write_rom_model(model, (3, 3, 3), BOX)
    base = resting_spheres((3.0, 3.0, 3.0)) + PAIR + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5 {kw}
fix integrate {grp} nve/sphere
run 10
"""
    cases = [("cfl 0", "rom_dynamic", "keyword cfl must be > 0"),
             ("block 1.5", "rom_dynamic", "keyword block must be between 0 and 1"),
             ("reach -1", "rom_dynamic", "keyword reach must be >= 0"),
             ("reach 5", "rom_dynamic", "keyword reach 5 exceeds the ghost cutoff's bound"),
             ("drive sideways", "rom_dynamic", "keyword drive must be match, box or dense, not sideways"),
             ("drive dense 0", "rom_dynamic", "keyword drive dense needs a density > 0, not 0"),
             ("separate maybe", "rom_dynamic", "Expected boolean parameter instead of 'maybe'"),
             ("", "all", "fix integrate (nve/sphere) integrates group all, which holds atoms of the fix's group")]
    for kw, grp, expected in cases:
        name = "in.kw_" + (kw or grp).replace(" ", "_")
        rc, out = t.run_lmp(base.format(m=model, kw=kw, grp=grp), WD, name=name)
        t.check(rc != 0 and expected in out, "%s / integrator on %s refused naming it (%r)" % (kw, grp, expected))


def drive_box():
    """Keyword drive box against drive match on one scene. Frame x 0..3 (3 voxels of 1) placed at
    origin 1 (x 1..4); field vx = 1 in the last voxel (centre 3.5) and 0 elsewhere, so u = 0 for
    x <= 2.5 and u = (1, 0, 0) beyond x = 3.5; eps v0 = 0.5; every 5. drive box classifies at the
    set-up too (steps 0, 5, 10), drive match at steps 5 and 10. Atom 1 in the box at x 2 and vx
    0.9 (0.9 from u); atom 2 at rest outside (x 5); atom 3 outside at vz 0.6; atom 4 at rest at x
    3.9995, where u = 1; atom 5 at rest at x 2.5, touched by atom 6 (not in the fix's group)
    coming down at vz -1."""
    frame = (0.0, 3.0, 0.0, 6.0, 0.0, 6.0)
    model = os.path.join(WD, "drive.model")
    t.write_rom_model(model, (3, 1, 1), frame, version=2, frame="moving",
                      vx_of_voxel=lambda m: 1.0 if m == 2 else 0.0)
    base = resting_spheres((2.0, 3.0, 3.0), (5.0, 3.0, 3.0), (5.0, 1.5, 1.5), (3.9995, 1.5, 4.5),
                           (2.5, 4.5, 3.0), (2.5, 4.5, 3.995)) + """
set atom 1 vx 0.9
set atom 3 vz 0.6
set atom 6 vz -1.0
group romable id 1:5
""" + PAIR + """
fix rom romable griddem/rom model {m} eps 0.5 v0 1 every 5 origin 1 0 0 drive {how}
fix integrate rom_dynamic nve/sphere
dump d all custom 5 drive_{how}.dump id x y z vx vy vz f_rom
dump_modify d format float %.17g sort id
thermo_style custom step f_rom[1] f_rom[3] f_rom[5] f_rom[7]
thermo 5
run 10
"""
    snaps, outs = {}, {}
    for how in ("match", "box"):
        outs[how] = t.run_ok(base.format(m=model, how=how), WD, name="in.drive_" + how)
        snaps[how] = t.read_dumps(os.path.join(WD, "drive_%s.dump" % how))
    m0, m5 = snaps["match"][0][1], snaps["match"][1][1]
    t.check(all(m0[k][6] == 0.0 for k in m0) and [m5[k][6] for k in (1, 2, 4, 5)] == [0.0] * 4,
            "drive match: no atom kinematic before the first model step; then the atom 0.9 off the field, "
            "the resting ones outside the box or where u = 1, and the hit one stay dynamic")
    b0, b5, b10 = (snaps["box"][k][1] for k in range(3))
    dt = 0.001
    t.check(b0[1][6] == b5[1][6] == b10[1][6] == 1.0 and b10[1][3:6] == [0.0] * 3 and b10[1][0] == 2.0,
            "drive box: the atom 0.9 off the field is kinematic from the set-up on and held where u = 0 "
            "(x %.17g)" % b10[1][0])
    t.check(b0[2][6] == b10[2][6] == 1.0 and b10[2][0] == 5.0 and b10[2][3:6] == [0.0] * 3,
            "drive box: the atom at rest outside the box is kinematic at rest")
    t.check(b0[3][6] == b10[3][6] == 0.0 and abs(b10[3][2] - (1.5 + 0.6 * 10 * dt)) <= 1e-13,
            "drive box: the atom moving outside the box is dynamic and flies on (z %.17g)" % b10[3][2])
    x5 = 3.9995 + 5 * dt * b0[4][3]
    t.check(b0[4][6] == 1.0 and abs(b0[4][3] - 1.0) <= 1e-15 and b5[4][6] == 0.0 and
            abs(b5[4][0] - x5) <= 1e-13 and b5[4][3] == b0[4][3] and abs(b10[4][0] - (x5 + 5 * dt * b0[4][3])) <= 1e-13,
            "drive box: the atom the field (vx %.17g) carries out of the box leaves it moving, dynamic "
            "(x %.17g at step 5)" % (b0[4][3], b5[4][0]))
    t.check(b0[5][6] == b5[5][6] == b10[5][6] == 1.0, "drive box: the atom hit at the classifications stays kinematic")
    out = outs["box"]
    hits, left = t.thermo_values(out, "f_rom[3]"), t.thermo_values(out, "f_rom[5]")
    classified = t.thermo_values(out, "f_rom[7]")
    t.check(hits[-1] == 0 and left[-1] == 1 and classified[-1] == 3,
            "drive box: no release by a hit, one by leaving the box, three classifications (%s, %s, %s)"
            % (hits, left, classified))
    # two processes (x split at 3: atoms 1, 5, 6 on one, 2, 3, 4 on the other): the same dumps
    t.run_ok(base.format(m=model, how="box").replace("region box", "processors 2 1 1\nregion box").replace(
        "drive_box.dump", "drive_box2.dump"), WD, nprocs=2, name="in.drive_box2")
    two = t.read_dumps(os.path.join(WD, "drive_box2.dump"))
    t.check(two == snaps["box"], "drive box: two processes give the one process's dumps, digit for digit")


def box_guard():
    """The field never carries an atom out through a face that is not periodic: a uniform field
    U = (-1, 0, -1), eps v0 2 (every resting atom qualifies), every 100 (0.1 of travel a model step),
    boundary p p f, spheres of radius 0.05, no gravity, a floor wall at z = 0 for dynamic atoms.
    Atom 1 (x 0.05, z 3) is driven through the periodic x face; atom 2 (z 0.06) would be carried to
    z -0.04 and is held dynamic at rest at both classifications; atom 3 (z 0.16) is driven to z 0.06,
    then held dynamic with its velocity and bounces off the floor. Without the guard LAMMPS loses
    atom 2 before step 200."""
    U = (-1.0, 0.0, -1.0)
    model = os.path.join(WD, "guard.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=U)
    text = HEAD.format(bnd="p p f") + """
create_atoms 1 single 0.05 3 3
create_atoms 1 single 3 3 0.06
create_atoms 1 single 4.5 4.5 0.16
set type 1 diameter 0.1
set type 1 density 1000
velocity all set 0 0 0
""" + PAIR + """
fix rom all griddem/rom model {m} eps 2 v0 1 every 100
fix integrate rom_dynamic nve/sphere
fix floor rom_dynamic wall/gran hooke/history 2000 NULL 50 NULL 0.5 1 zplane 0.0 NULL
dump d all custom 50 guard.dump id x y z vx vy vz f_rom
dump_modify d format float %.17g sort id
thermo_style custom step atoms f_rom[1] f_rom[19]
thermo 50
run 250
""".format(m=model)
    out = t.run_ok(text, WD, name="in.guard")
    snaps = t.read_dumps(os.path.join(WD, "guard.dump"))    # steps 0, 50, .., 250
    s100, s200, s250 = snaps[2][1], snaps[4][1], snaps[5][1]
    # (a lagging atom is dumped where the last model step, 200, left it)
    t.check(s100[1][6] == s250[1][6] == 1.0 and abs(s250[1][0] - (6.0 + 0.05 - 0.1)) <= 1e-12 and
            abs(s250[1][2] - (3.0 - 0.1)) <= 1e-12,
            "the atom driven through the periodic face stays kinematic (x %.17g, z %.17g)" % (s250[1][0], s250[1][2]))
    t.check(all(s[2][6] == 0.0 and s[2][2] == 0.06 and s[2][3:6] == [0.0] * 3 for s in (s100, s200, s250)),
            "the atom the field would carry out through the floor stays dynamic, at rest")
    t.check(s100[3][6] == 1.0 and s200[3][6] == 0.0 and abs(s200[3][2] - 0.06) <= 1e-12 and
            all(abs(s200[3][3 + d] - U[d]) <= 4e-16 for d in range(3)) and s250[3][2] > 0.0 and s250[3][5] > 0.0,
            "the atom driven to z 0.06 is then held dynamic with its velocity and bounces off the floor "
            "(z %.17g, vz %.17g at step 250)" % (s250[3][2], s250[3][5]))
    t.check(t.thermo_values(out, "Atoms")[-1] == 3 and t.thermo_values(out, "f_rom[19]")[-1] == 3,
            "no atom lost; three held by the box (%s)" % t.thermo_values(out, "f_rom[19]"))


def drive_dense():
    """Keyword drive dense: the model drives the atoms where the density it deposits (interpolated
    at the atom by the field's weights) is at least RHO; elsewhere drive match's rule. The frame of
    drive_box (voxels 1 x 6 x 6 centred at x 1.5, 2.5, 3.5 once placed, vx = 1 in the last);
    unit spheres of mass pi/6 placed at voxel centres along x, so each deposits its whole mass into
    one voxel: three at x 1.5 (density 3 (pi/6) / 36 = 0.0436; atom 1 moving at vx 0.9, 0.9 off
    u = 0), atom 4 at rest at x 3.5 (density 0.0145, 1 off u = 1), atom 5 at rest at x 2.5 (density
    0.0145, on u = 0), atom 6 at rest outside the box; atom 7, not in the fix's group, touches
    atom 2 coming down at vz -1 (a hit, which releases no atom with drive dense). RHO 0.03: atoms
    1-3 driven (atom 1 held at rest), 5 kinematic by the match rule, 4 and 6 dynamic; RHO 0.05:
    atom 1 dynamic as with drive match. Both classify at the set-up (steps 0, 5, 10)."""
    frame = (0.0, 3.0, 0.0, 6.0, 0.0, 6.0)
    model = os.path.join(WD, "dense.model")
    t.write_rom_model(model, (3, 1, 1), frame, version=2, frame="moving",
                      vx_of_voxel=lambda m: 1.0 if m == 2 else 0.0)
    base = resting_spheres((1.5, 1.5, 3.0), (1.5, 3.0, 3.0), (1.5, 4.5, 3.0), (3.5, 3.0, 3.0), (2.5, 1.5, 1.5),
                           (5.0, 3.0, 3.0), (1.5, 3.0, 3.995)) + """
set atom 1 vx 0.9
set atom 7 vz -1.0
group romable id 1:6
""" + PAIR + """
fix rom romable griddem/rom model {m} eps 0.5 v0 1 every 5 origin 1 0 0 drive dense {rho}
fix integrate rom_dynamic nve/sphere
dump d all custom 5 {name}.dump id x y z vx vy vz f_rom
dump_modify d format float %.17g sort id
thermo_style custom step f_rom[1] f_rom[3] f_rom[7]
thermo 5
run 10
"""
    dt = 0.001
    expected = {"0.03": ({1, 2, 3, 5}, 1.5), "0.05": ({2, 3, 5}, 1.5 + 0.9 * 10 * dt)}
    snaps = {}
    for rho, (kinematic, x1) in expected.items():
        name = "dense_%s" % rho
        out = t.run_ok(base.format(m=model, rho=rho, name=name), WD, name="in." + name)
        snaps[rho] = t.read_dumps(os.path.join(WD, name + ".dump"))
        states = [{k for k, a in snap[1].items() if a[6] == 1.0} for snap in snaps[rho]]
        t.check(states == [kinematic] * 3, "drive dense %s: kinematic atoms %s at steps 0, 5, 10 (got %s)"
                % (rho, sorted(kinematic), [sorted(s) for s in states]))
        last = snaps[rho][-1][1]
        t.check(abs(last[1][0] - x1) <= 1e-13 and last[1][3] == (0.0 if 1 in kinematic else 0.9),
                "drive dense %s: atom 1 at x %.17g (expected %.17g), vx %.17g" % (rho, last[1][0], x1, last[1][3]))
        t.check(t.thermo_values(out, "f_rom[1]") == [len(kinematic)] * 3 and t.thermo_values(out, "f_rom[7]")[-1] == 3
                and t.thermo_values(out, "f_rom[3]")[-1] == 0,
                "drive dense %s: %d kinematic at each output, three classifications, no release by the hit"
                % (rho, len(kinematic)))
    t.run_ok(base.format(m=model, rho="0.03", name="dense2").replace("region box", "processors 2 1 1\nregion box"),
             WD, nprocs=2, name="in.dense2")
    t.check(t.read_dumps(os.path.join(WD, "dense2.dump")) == snaps["0.03"],
            "drive dense: two processes give the one process's dumps, digit for digit")


def newcomer():
    """An atom inserted (fix deposit) overlapping a lagging kinematic atom by 0.1 feels it in its
    first step: the reach test runs when atoms appear, so the lagging atom is in the grid again.
    Both at rest, no gravity: the contact force is kn delta = 2000 x 0.1 = 200 along x."""
    model = os.path.join(WD, "still.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=(0.0, 0.0, 0.0))
    text = resting_spheres((3.0, 3.0, 3.0)) + PAIR + """
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 10
fix integrate rom_dynamic nve/sphere
thermo_style custom step f_rom[1] f_rom[9]
thermo 10
run 20
region spot block 3.9 3.9000001 2.9999999 3.0000001 2.9999999 3.0000001 units box
fix newcomer all deposit 1 1 100 4417 region spot units box
dump d all custom 1 newcomer.dump id x fx
dump_modify d format float %.17g sort id
run 3
""".format(m=model)
    out = t.run_ok(text, WD, name="in.newcomer")
    kin, near = t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[9]")
    t.check(kin[1] == 1 and near[1] == 0, "atom 1 kinematic and lagging before the insertion (near %s)" % near[1])
    snaps = [atoms for _, atoms in t.read_dumps(os.path.join(WD, "newcomer.dump"))]
    first = min(k for k, atoms in enumerate(snaps) if 2 in atoms)
    x2, fx2 = snaps[first][2][0], snaps[first][2][1]
    expected = 2000.0 * (1.0 - (x2 - 3.0))
    t.check(abs(fx2 - expected) <= 1e-9 * expected and abs(expected - 200.0) < 1e-3,
            "the new atom is pushed by the lagging one in its first step (snapshot %d): fx %.12g, kn delta %.12g" % (first, fx2, expected))


def moving_frame(nprocs=1):
    """Frame box x 0..3 (3 voxels of 1), y, z 0..6 (one voxel), moving with the origin
    o = 1 + 0.01 step along x; field vx = 0.1 (frame x of the voxel centre): linear between the
    first and last centres, so u = 0.1 (x - o) there. Atom 1 rests at x = 2.5: at the first
    classification (step 5) u = 0.1 (2.5 - 1.05) = 0.145; at step 10 it is at 2.5 + 0.145 5 dt
    and u = 0.1 (x - 1.10). Atom 2 at x = 5.5 is outside the placed frame (1.05..4.05): dynamic. Force
    block: x = 1 + 0.5 c (c = 2), y = 2, z = 3 + sum of densities = 3 + (pi / 6) / 36 (atom 1's mass
    over the voxel volume 1 x 6 x 6: cloud-in-cell keeps the mass). On 2 processes the two atoms
    are on different ones (x split at 3) and every value is the same; the refusals run once."""
    frame = (0.0, 3.0, 0.0, 6.0, 0.0, 6.0)
    ncol = 1 + 3 + 1
    force = [[1.0, 0, 0, 0, 0.5], [2.0, 0, 0, 0, 0], [3.0, 1, 1, 1, 0]]
    model = os.path.join(WD, "frame.model")
    t.write_rom_model(model, (3, 1, 1), frame, version=2, frame="moving", controls=1,
                      vx_of_voxel=lambda m: 0.1 * (m + 0.5), force=force)
    text = resting_spheres((2.5, 3.0, 3.0), (5.5, 3.0, 3.0)).replace(
        "region box", "processors %d 1 1\nregion box" % nprocs) + PAIR + """
variable o equal 1+0.01*step
variable c equal 2.0
fix rom all griddem/rom model {m} eps 1 v0 1 every 5 control v_c origin v_o 0 0
fix integrate rom_dynamic nve/sphere
dump d all custom 5 frame{n}.dump id x vx f_rom
dump_modify d format float %.17g sort id
thermo_style custom step f_rom[14] f_rom[15] f_rom[16]
thermo_modify format float %.17g
thermo 5
run 10
""".format(m=model, n=nprocs)
    out = t.run_ok(text, WD, nprocs=nprocs, name="in.frame%d" % nprocs)
    snaps = t.read_dumps(os.path.join(WD, "frame%d.dump" % nprocs))
    label = "%d process(es): " % nprocs
    s5, s10 = snaps[1][1], snaps[2][1]
    t.check(s5[1][2] == 1.0 and abs(s5[1][1] - 0.145) <= 1e-14,
            label + "step 5: kinematic, vx = 0.1 (2.5 - 1.05) = 0.145 (%.17g)" % s5[1][1])
    x10 = 2.5 + 0.145 * 5 * 0.001
    t.check(abs(s10[1][0] - x10) <= 1e-14 and abs(s10[1][1] - 0.1 * (x10 - 1.10)) <= 1e-14,
            label + "step 10: at %.15g, vx = 0.1 (x - 1.10) (%.17g)" % (s10[1][0], s10[1][1]))
    t.check(s5[2][2] == 0.0 and s10[2][2] == 0.0 and s10[2][0] == 5.5,
            label + "the atom outside the frame stays dynamic")
    fx, fy, fz = (t.thermo_values(out, "f_rom[%d]" % k)[-1] for k in (14, 15, 16))
    t.check(fx == 2.0 and fy == 2.0 and abs(fz - (3.0 + (math.pi / 6.0) / 36.0)) <= 1e-14,
            label + "predicted force (%.17g %.17g %.17g) = (2, 2, 3 + (pi/6)/36)" % (fx, fy, fz))
    if nprocs > 1:
        return
    # refusals
    fixed = os.path.join(WD, "fixed_c1.model")
    t.write_rom_model(fixed, (3, 3, 3), BOX, controls=1)
    v1frame = os.path.join(WD, "v1frame.model")
    t.write_rom_model(v1frame, (3, 1, 1), frame, version=1, frame="moving", controls=1)
    badforce = os.path.join(WD, "badforce.model")
    t.write_rom_model(badforce, (3, 1, 1), frame, version=2, frame="moving", controls=1, force=[r[:4] for r in force])
    periodic = os.path.join(WD, "periodic.model")
    t.write_rom_model(periodic, (3, 1, 1), frame, version=2, frame="moving", controls=1)
    cases = [(model, "", "f f f", "has a moving frame (line 'frame moving'): keyword origin is required"),
             (fixed, "origin v_o 0 0", "f f f", "keyword origin needs a model with a moving frame"),
             (v1frame, "origin v_o 0 0", "f f f", "line 5: 'frame' needs format version 2"),
             (badforce, "origin v_o 0 0", "f f f", "force has 3 rows and 4 columns; expected 3 and 5"),
             (periodic, "origin v_o 0 v_o", "f f p", "keyword origin moves the frame along the periodic axis z"),
             (model, "origin v_nothing 0 0", "f f f", "origin variable nothing does not exist"),
             (model, "origin v_a 0 0", "f f f", "origin variable a is not equal-style")]
    for path, kw, bnd, expected in cases:
        text = HEAD.format(bnd=bnd) + PAIR + """
variable o equal 1
variable a atom x
variable c equal 2.0
fix rom all griddem/rom model {m} eps 1 v0 1 every 5 control v_c {kw}
fix integrate rom_dynamic nve/sphere
run 0
""".format(m=path, kw=kw)
        name = "in.frame_bad_%s" % os.path.basename(path).split(".")[0] + kw.replace(" ", "_")
        rc, out = t.run_lmp(text, WD, name=name)
        t.check(rc != 0 and expected in out, "refused naming it (%r)%s" % (expected, "" if rc else ": " + out[-300:]))


def frame_binning():
    """30 spheres at random in a box periodic along y; a moving frame of 4 x 1 x 3 voxels (the
    slice's layout) and of 4 x 3 x 3 (periodic along y, the 3D blade's) over x -1..3 (relative),
    y 0..6, z 0..3, origin x = 1.7: the fix's density field at its first classification (dump grid)
    against griddemtools.blade's bin_frame of the dumped positions."""
    for n in ((4, 1, 3), (4, 3, 3)):
        binned_alike(n, (-1.0, 3.0, 0.0, 6.0, 0.0, 3.0))


def binned_alike(n, frame):
    name = "binning.%d" % n[1]
    model = os.path.join(WD, name + ".model")
    t.write_rom_model(model, n, frame, version=2, frame="moving")
    text = HEAD.format(bnd="f p f") + """
create_atoms 1 random 30 7741 NULL overlap 0.3
set type 1 diameter 0.3
set type 1 density 1.0
velocity all set 0 0 0
""" + PAIR + """
fix rom all griddem/rom model {m} eps 1 v0 1 every 5 origin 1.7 0 0
fix integrate rom_dynamic nve/sphere
dump a all custom 5 {name}.atoms id x y z vx vy vz mass
dump_modify a format float %.17g
dump g all grid 5 {name}.grid f_rom:field:density
dump_modify g format float %.17g
run 5
""".format(m=model, name=name)
    t.run_ok(text, WD, name="in." + name)
    # griddemtools.blade needs numpy: the system interpreter's, as train_rom.py in training()
    import subprocess
    top = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    # the plain readers of griddemtools read both files; griddemtools.blade.bin_frame is what is checked
    script = """
import sys
sys.path.insert(0, %r)
from griddemtools.blade import bin_frame, read_snapshots
from griddemtools.grid import read_grid_dump
a = dict(read_snapshots(%r))[5]
fix = read_grid_dump(%r)[-1].columns["density"]
rho = bin_frame(a["x"] - 1.7, a["y"], a["z"], a["vx"], a["vy"], a["vz"], a["mass"], %r, %r)[0]
inside = ((a["x"] - 1.7 >= -1) & (a["x"] - 1.7 < 3) & (a["z"] < 3)).sum()
print(len(fix), max(abs(fix - rho)), inside)
""" % (os.path.join(top, "python"), os.path.join(WD, name + ".atoms"),
       os.path.join(WD, name + ".grid"), n, frame)
    proc = subprocess.run(["/usr/bin/python3", "-c", script], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True)
    t.check(proc.returncode == 0, "griddemtools.blade's binning runs: " + proc.stdout[-300:])
    if proc.returncode != 0:
        return
    nfix, worst, inside = proc.stdout.split()[-3:]
    nfix, worst, inside = int(nfix), float(worst), int(inside)
    t.check(nfix == n[0] * n[1] * n[2] and worst <= 1e-12 and 5 <= inside < 30,
            "moving frame of %d x %d x %d voxels: the fix's density equals griddemtools.blade's binning (%d of 30 "
            "atoms inside; worst difference %.3g)" % (n + (inside, worst)))


def rejoin():
    """A lagging kinematic atom released by a field jump rejoins DEM where the field has carried
    it and with the velocity the model predicted: field vx = 0.3 + c, c switching from 0 to 1 at
    step 100 (> eps v0 = 0.5); kinematic from step 60 (model step 60), released at 120; then free
    flight: x = x0 + 0.3 (200 - 60) dt (80 steps of rounding: 1e-13) and vx = 0.3 at step 200."""
    model = os.path.join(WD, "rejoin.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=(0.3, 0.0, 0.0), controls=1, control_weight=1.0)
    text = resting_spheres((2.0, 3.0, 3.0)) + PAIR + """
variable on equal step>100
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 60 control v_on
fix integrate rom_dynamic nve/sphere
thermo_style custom step f_rom[1] f_rom[8]
thermo 20
run 200
print "FINAL $(x[1]:%.17g) $(vx[1]:%.17g)"
""".format(m=model)
    out = t.run_ok(text, WD, name="in.rejoin")
    kin, jumps = t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[8]")
    final = [float(w) for w in out.split("FINAL")[-1].split()[:2]]
    t.check(kin[3] == 1 and kin[-1] == 0 and jumps[-1] == 1, "kinematic at step 60, released by the jump at 120")
    t.check(abs(final[0] - (2.0 + 0.3 * 140 * 0.001)) <= 1e-13 and abs(final[1] - 0.3) <= 1e-15,
            "released where the field carried it, with the predicted velocity (x %.17g, vx %.17g)" % tuple(final))


def separation():
    """A released atom starts DEM without the overlap the model left it (keyword separate, default
    yes). Unit spheres overlapping by 0.2 (overlap bound 1.0 x 0.5), kinematic from step 60 in the
    field vx = 0.3 (nothing integrated before: they would repel), released at the classification of
    step 120 and then in free flight to step 200:
    two released together (a field jump) are each moved by half the overlap, one released alone
    (a resolved region grown over it) by all of it from its kinematic partner; either way they
    touch without overlap and keep vx 0.3: positions x0 + 0.3 x 140 dt, centres 1 apart along the
    line they overlapped on, f_rom[20] counting the moved atoms. With separate no the overlap
    throws them apart."""
    model = os.path.join(WD, "separate.model")
    t.write_rom_model(model, (3, 3, 3), BOX, bias=(0.3, 0.0, 0.0), controls=1, control_weight=1.0)
    scenes = {
        "released together": ((2.0, 3.0, 3.0), (2.8, 3.0, 3.0), "variable on equal step>100",
                              "control v_on", "x"),
        "released alone": ((2.0, 3.0, 2.0), (2.0, 3.0, 2.8), """variable on equal 0
variable zlo equal 10.0-7.6*(step>100)
region top block INF INF INF INF v_zlo INF""", "control v_on resolved top", "z"),
    }
    for name, (a, b, variables, keywords, axis) in scenes.items():
        for separate in ("yes", "no"):
            text = resting_spheres(a, b) + PAIR + """{v}
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 60 overlap 1.0 {k} separate {s}
thermo_style custom step f_rom[1] f_rom[20]
thermo 20
run 60
fix integrate rom_dynamic nve/sphere
run 140
print "FINAL $(x[1]:%.17g) $(y[1]:%.17g) $(z[1]:%.17g) $(x[2]:%.17g) $(y[2]:%.17g) $(z[2]:%.17g) $(vx[1]:%.17g) $(vx[2]:%.17g) $(vz[2]:%.17g)"
""".format(v=variables, m=model, k=keywords, s=separate)
            label = "%s, separate %s" % (name, separate)
            out = t.run_ok(text, WD, name="in.separate_%s_%s" % (axis, separate))
            kin, moved = t.thermo_values(out, "f_rom[1]"), t.thermo_values(out, "f_rom[20]")
            f = [float(w) for w in out.split("FINAL")[-1].split()[:9]]
            x1, x2 = f[0:3], f[3:6]
            gap = math.dist(x1, x2) - 1.0
            t.check(kin[3] == 2 and kin[-1] == (0 if axis == "x" else 1),
                    "%s: both kinematic at step 60, released at 120 (kinematic %s)" % (label, kin))
            if separate == "yes":
                d = "xyz".index(axis)
                expect2 = list(b)
                expect2[0] += 0.3 * 140 * 0.001
                expect2[d] += 0.1 if axis == "x" else 0.2
                worst = max(abs(u - w) for u, w in zip(x2, expect2))
                t.check(abs(gap) <= 1e-12 and worst <= 1e-12 and max(abs(f[6] - 0.3), abs(f[7] - 0.3), abs(f[8])) <= 1e-12,
                        "%s: touching without overlap (gap %.3g), atom 2 at %s (worst %.3g), vx 0.3 (%.17g, %.17g)"
                        % (label, gap, x2, worst, f[6], f[7]))
                t.check(moved[-1] == (2 if axis == "x" else 1), "%s: %g atoms moved (f_rom[20])" % (label, moved[-1]))
            else:
                t.check(gap > 0.01 and moved[-1] == 0, "%s: the overlap throws them apart (gap %.3g)" % (label, gap))


model_checks()
model_file_messages()
counters()
newcomer()
moving_frame()
moving_frame(2)
frame_binning()
rejoin()
separation()
keyword_checks()
restart_schedule()
averaged_store()
drive_box()
drive_dense()
box_guard()
model_step()
boundary(1)
boundary(2)
boundary(1, "reach 0")
migration()
unreadable_records()
store_in_place()
near_elsewhere()
far_catch_up()
store_limits()
fields_from_store()
blocks()
processes()
release()
loaded()
field_jump()
field_output()
occupancy_form()
resolved_region()
training()
eps_zero()
uniform_field()
frozen_field()
contacts()
t.finish()
