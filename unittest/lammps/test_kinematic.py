"""fix griddem/kinematic: atoms of the group inside the region move at the prescribed velocity,
without rotating, whatever the forces on them; membership is tested every step.

Four spheres under gravity in a box with the region z < 2: atom 1 starts inside, pressed by atom
2 resting on it (contact forces that must not move it); atom 3 falls freely from z = 3 into the
region; atom 4 is outside the fix's group. Positions are checked against a step-by-step model of
the documented rule (velocity Verlet with gravity 1 until the end-of-step position is in the
region, then the prescribed velocity from the next step on), to 1e-12; with a constant velocity
and with an equal-style variable; on 1 and 2 processes (f_ID summed over them). Bad input is
refused naming the cause, also a missing velocity variable and run style respa."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

DT = 0.001
STEPS = 1500
SCENE = """
units lj
atom_style sphere
atom_modify map array
boundary p p f
comm_modify vel yes
region box block 0 8 0 4 -5 8 units box
create_box 1 box
create_atoms 1 single 2 2 1.5 units box
create_atoms 1 single 2 2 2.45 units box
create_atoms 1 single 6 2 3 units box
create_atoms 1 single 6 2 7 units box
set group all diameter 1.0
set group all density 1.0
velocity all set 0 0 0
set atom 1 vx 0.3 vz 0.2
set atom 1 omega 1 2 3
set atom 3 vx 0.05
group moving id 1 2 3
pair_style griddem/hooke/history 2000.0 NULL 50.0 NULL 0.5 1
pair_coeff * *
timestep {dt}
variable vz equal {vz}
fix integrate all nve/sphere
fix gravity all gravity 1.0 vector 0 0 -1
region outlet block INF INF INF INF INF 2 units box
{before}
fix kin moving griddem/kinematic region outlet velocity 0.1 0 v_vz
{after}
thermo_style custom step f_kin
thermo 100
dump d all custom {steps} dump.kin id x y z vx vy vz omegax omegay omegaz
dump_modify d format float %.17g sort id
run {steps}
"""
def script(vz, before="", after="", steps=STEPS):
    """The scene with velocity z component vz (a number or an expression) and extra lines before
    and after the fix."""
    return SCENE.format(dt=DT, vz=vz, steps=steps, before=before, after=after)


def model(x0, v0, vz_of_step, held_region=lambda z: z < 2):
    """The documented rule for a free atom under gravity 1 (no contacts): returns its final
    position and velocity and the step it was first held."""
    x, v = list(x0), list(v0)
    first = None
    if held_region(x[2]):
        v = [0.1, 0.0, vz_of_step(0)]
        first = 0
    for n in range(1, STEPS + 1):
        held = first is not None
        if not held:
            v[2] -= 0.5 * DT
        x = [x[d] + DT * v[d] for d in range(3)]
        if held or held_region(x[2]):
            v = [0.1, 0.0, vz_of_step(n)]
            if first is None:
                first = n
        else:
            v[2] -= 0.5 * DT
    return x, v, first


def check_run(label, vz_text, vz_of_step, nprocs=1):
    wd = t.workdir()
    out = t.run_ok(script(vz_text), wd, nprocs=nprocs)
    names, atoms = t.read_dump(os.path.join(wd, "dump.kin"))
    col = {c: names.index(c) for c in names}
    # atom 1: held from the start, its velocity set at step 0
    x1 = [2.0, 2.0, 1.5]
    for n in range(STEPS):
        x1 = [x1[0] + DT * 0.1, x1[1], x1[2] + DT * vz_of_step(n)]
    a1 = atoms[1]
    t.check(all(abs(a1[col[c]] - x1[d]) < 1e-12 for d, c in enumerate("xyz")),
            "%s: held atom 1 at %s, the rule gives %s" % (label, [a1[col[c]] for c in "xyz"], x1))
    t.check(a1[col["vx"]] == 0.1 and a1[col["vy"]] == 0.0 and abs(a1[col["vz"]] - vz_of_step(STEPS)) < 1e-15,
            "%s: held atom 1's velocity %s" % (label, [a1[col[c]] for c in ("vx", "vy", "vz")]))
    t.check(all(a1[col[c]] == 0.0 for c in ("omegax", "omegay", "omegaz")), "%s: held atom 1 does not rotate" % label)
    # atom 3: free fall into the region, then held
    x3, v3, first = model([6.0, 2.0, 3.0], [0.05, 0.0, 0.0], vz_of_step)
    a3 = atoms[3]
    t.check(first is not None and 0 < first < STEPS, "%s: atom 3 enters the region during the run (step %s)"
            % (label, first))
    t.check(all(abs(a3[col[c]] - x3[d]) < 1e-12 for d, c in enumerate("xyz")),
            "%s: falling atom 3 at %s, the rule gives %s" % (label, [a3[col[c]] for c in "xyz"], x3))
    # atom 4: not in the group, a free fall (t = 1.5: z = 7 - t^2 / 2)
    t.check(abs(atoms[4][col["z"]] - (7.0 - 0.5 * (STEPS * DT) ** 2)) < 1e-9,
            "%s: atom 4 (outside the group) falls freely: z %r" % (label, atoms[4][col["z"]]))
    # the scalar: atoms held at the last step (1 and 3; atom 2 rests on atom 1 above z = 2)
    held = t.thermo_values(out, "f_kin")
    t.check(held[0] == 1 and held[-1] == 2, "%s: f_kin %s at the first and last thermo rows, expected 1 and 2"
            % (label, held[::len(held) - 1]))
    return atoms


def main():
    constant = check_run("constant", "-0.2", lambda n: -0.2)
    # an equal-style variable of the step
    varying = check_run("variable", "-0.1-0.0002*step", lambda n: -0.1 - 0.0002 * n)
    parallel = check_run("variable, 2 processes", "-0.1-0.0002*step", lambda n: -0.1 - 0.0002 * n, nprocs=2)
    t.check(parallel == varying, "2 processes give the 1-process run's dump digit for digit")
    t.check(constant != varying, "the velocity variable changes the run")

    wd = t.workdir()
    refused = [
        ("a fix that sets forces after it", script("-0.2", after="fix a all gravity 1.0 vector 0 0 -1"),
         "must come after fix a (gravity)"),
        ("missing region", script("-0.2").replace("region outlet velocity", "region nowhere velocity"),
         "region nowhere does not exist"),
        ("missing keyword", script("-0.2").replace("region outlet velocity", "zone outlet velocity"),
         "expected keyword 'region', got 'zone'"),
        ("atom-style variable", script("-0.2").replace("variable vz equal -0.2", "variable vz atom -0.2"),
         "variable vz is not equal-style"),
        ("too few values", script("-0.2").replace("velocity 0.1 0 v_vz", "velocity 0.1 0"),
         "expected region R velocity VX VY VZ"),
        ("missing variable", script("-0.2").replace("velocity 0.1 0 v_vz", "velocity 0.1 0 v_nothere"),
         "variable nothere does not exist"),
        ("run style respa", script("-0.2").replace("\nrun ", "\nrun_style respa 2 2\nrun "),
         "does not support run style respa"),
    ]
    for label, text, message in refused:
        rc, out = t.run_lmp(text, wd)
        t.check(rc != 0 and any(message in line for line in t.errors(out)),
                "%s: refused with an error saying %r (exit %d, errors %s)" % (label, message, rc, t.errors(out)))
    t.finish()


if __name__ == "__main__":
    main()
