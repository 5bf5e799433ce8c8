"""fix griddem/rom (adaptive reduced-order DEM), on models written here by hand:
- model-file checks: a wrong format version, a weight matrix whose size does not fit the grid,
  a number of controls other than the fix's, a box other than the simulation's: each refused with
  an error naming it;
- eps = 0: no atom becomes kinematic and the run is the plain run, digit for digit;
- a uniform predicted field U (weights: bias only): a resting atom (|v - U| = |U| <= eps v0)
  becomes kinematic, its velocity is U exactly and it moves by U dt per step although gravity
  acts; an atom whose speed relative to U exceeds eps v0 stays dynamic and falls freely;
- contacts: two resting kinematic atoms that overlap exert no force (the pair virial is exactly
  zero, and nonzero in the same scene without the fix), while a dynamic atom overlapping a
  kinematic one is pushed away by it and the kinematic one does not move; an atom overlapping
  beyond `overlap` min(ri, rj) is never made kinematic."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

WD = t.workdir()


def write_model(path, n, box, controls=0, bias=(0.0, 0.0, 0.0), version=1, nrow=None, ncol=None,
                control_weight=None):
    """A model whose field is the uniform bias (plus control_weight * control 1 on vx)."""
    nvox = n[0] * n[1] * n[2]
    nrow = 3 * nvox if nrow is None else nrow
    ncol = 1 + nvox + controls if ncol is None else ncol
    with open(path, "w") as f:
        f.write("# test model\ngriddem/rom %s\ngrid %d %d %d\nbox %s\ncontrols %d\nlambda 0.001\n"
                % (version, n[0], n[1], n[2], " ".join("%.17g" % b for b in box), controls))
        f.write("weights %d %d\n" % (nrow, ncol))
        for r in range(nrow):
            row = [0.0] * ncol
            row[0] = bias[r % 3]
            if control_weight is not None and r % 3 == 0:
                row[ncol - 1] = control_weight
            f.write(" ".join("%.17g" % w for w in row) + "\n")


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


def model_checks():
    good = os.path.join(WD, "good.model")
    write_model(good, (3, 3, 3), BOX, controls=1)
    cases = [
        ("version", dict(version=2), "format version 2"),
        ("grid size", dict(nrow=3 * 26), "grid size 3 3 3"),
        ("columns", dict(ncol=1 + 27), "grid size 3 3 3 and 1 controls"),
        ("controls", dict(controls=2), "has 2 controls, the fix names 1"),
    ]
    for name, kw, expected in cases:
        path = os.path.join(WD, "bad_%s.model" % name.replace(" ", "_"))
        args = dict(controls=1)
        args.update(kw)
        write_model(path, (3, 3, 3), BOX, **args)
        text = HEAD.format(bnd="f f f") + PAIR + """
variable w equal 1.0
fix integrate all nve/sphere
fix rom all griddem/rom model {m} eps 0.1 v0 1 every 1 control v_w
run 0
""".format(m=path)
        rc, out = t.run_lmp(text, WD, name="in.bad_" + name.replace(" ", "_"))
        t.check(rc != 0 and expected in out, "model with a wrong %s refused naming it (%r)" % (name, expected))
    path = os.path.join(WD, "bad_box.model")
    write_model(path, (3, 3, 3), (0.0, 6.0, 0.0, 6.0, 0.0, 7.0), controls=1)
    text = HEAD.format(bnd="f f f") + PAIR + """
variable w equal 1.0
fix integrate all nve/sphere
fix rom all griddem/rom model {m} eps 0.1 v0 1 every 1 control v_w
run 0
""".format(m=path)
    rc, out = t.run_lmp(text, WD, name="in.bad_box")
    t.check(rc != 0 and "differs from the simulation box" in out, "model with a wrong box refused")
    # and the good one runs
    text = HEAD.format(bnd="f f f") + PAIR + """
variable w equal 1.0
fix integrate all nve/sphere
fix rom all griddem/rom model {m} eps 0.1 v0 1 every 1 control v_w
run 0
""".format(m=good)
    rc, out = t.run_lmp(text, WD, name="in.good")
    t.check(rc == 0, "a consistent model is accepted")


def eps_zero():
    model = os.path.join(WD, "zero.model")
    write_model(model, (3, 3, 3), BOX)
    base = HEAD.format(bnd="p p p") + """
lattice sc 1.1 origin 0.5 0.5 0.5
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.0
velocity all create 0.5 4928 dist gaussian
""" + PAIR + """
fix integrate all nve/sphere
{rom}
dump d all custom 200 {dump} id x y z vx vy vz omegax fx {extra}
dump_modify d format float %.17g sort id
thermo 100
run 400
"""
    t.run_ok(base.format(rom="", dump="plain.dump", extra=""), WD, name="in.plain")
    t.run_ok(base.format(rom="fix rom all griddem/rom model %s eps 0 v0 1 every 1" % model,
                         dump="rom0.dump", extra="f_rom"), WD, name="in.rom0")
    plain, rom = t.read_dumps(os.path.join(WD, "plain.dump")), t.read_dumps(os.path.join(WD, "rom0.dump"))
    t.check(len(plain) == len(rom) == 3, "three snapshots each")
    same = all(all(r[1][tag][:8] == p[1][tag] for tag in p[1]) for p, r in zip(plain, rom))
    moved = any(abs(rom[-1][1][tag][4] - rom[0][1][tag][4]) > 0 for tag in rom[0][1])
    t.check(moved, "the eps 0 scene has collisions (velocities change)")
    t.check(same, "eps 0: positions, velocities, spins, forces equal the plain run exactly")
    t.check(all(v[8] == 0.0 for snap in rom for v in snap[1].values()), "eps 0: no atom kinematic")


def uniform_field():
    U = (0.3, -0.2, 0.1)
    model = os.path.join(WD, "uniform.model")
    write_model(model, (3, 3, 3), BOX, bias=U)
    g = 2.0
    text = HEAD.format(bnd="f f f") + """
create_atoms 1 single 1.5 1.5 3.0
create_atoms 1 single 4.5 4.5 3.0
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set 0 0 0
set atom 2 vx 0.9
""" + PAIR + """
fix integrate all nve/sphere
fix down all gravity {g} vector 0 0 -1
fix rom all griddem/rom model {m} eps 0.5 v0 1 every 5
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
    write_model(model, (3, 3, 3), BOX)
    # atoms 1, 2 overlap by 0.005 (bound 0.1 * 0.5 = 0.05); atom 3 (not in the fix group) overlaps
    # atom 1 by 0.005 from the other side; atoms 4, 5 overlap by 0.1 > 0.05 (never kinematic)
    base = HEAD.format(bnd="f f f") + """
create_atoms 1 single 3.0 3.0 3.0
create_atoms 1 single 3.995 3.0 3.0
create_atoms 1 single 3.0 3.995 3.0
create_atoms 1 single 1.0 1.0 1.0
create_atoms 1 single 1.9 1.0 1.0
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set 0 0 0
group romable id 1 2 4 5
""" + PAIR + """
fix integrate all nve/sphere
{rom}
compute vir all pressure NULL virial
thermo_style custom step c_vir
thermo_modify format float %.17g
thermo 1
dump d all custom 10 {dump} id x y z vx vy vz {extra}
dump_modify d format float %.17g sort id
run 10
"""
    out = t.run_ok(base.format(rom="fix rom romable griddem/rom model %s eps 0.5 v0 1 every 1" % model,
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
    out = t.run_ok(only12.format(rom="fix rom romable griddem/rom model %s eps 0.5 v0 1 every 1" % model,
                                 dump="only12.dump", extra="f_rom"), WD, name="in.only12")
    vir = t.thermo_values(out, "c_vir")
    t.check(vir[0] != 0.0, "before the first classification the pair 1-2 pushes (virial %g)" % vir[0])
    t.check(all(v == 0.0 for v in vir[2:]), "after it the kinematic pair exerts no force (virial %s)" % vir[2:5])
    out = t.run_ok(only12.format(rom="", dump="only12plain.dump", extra=""), WD, name="in.only12plain")
    vir = t.thermo_values(out, "c_vir")
    t.check(all(v != 0.0 for v in vir[2:]), "the same pair without the fix keeps pushing")


model_checks()
eps_zero()
uniform_field()
contacts()
t.finish()
