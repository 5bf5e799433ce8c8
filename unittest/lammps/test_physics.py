"""griddem/hooke/history against analytic results:
- head-on collision: restitution e = exp(-pi z / sqrt(1 - z^2)), z = gamma_n meff / (2 sqrt(Kn meff)),
  and contact duration pi / sqrt(Kn/meff - (gamma_n/2)^2);
- free fall onto a frozen sphere without damping (NN4DEM set I, 0.95 m): rebounds to the drop height;
- sliding with Coulomb friction (NN4DEM set I, 1.414 m/s, mu 0.5, no rotation) over the top of a
  frozen sphere of diameter 100: stops where its equation of motion along the arc puts it (0.2051 m;
  v^2 / (2 mu g) = 0.2038 m on a flat floor), less the tangential spring's stretch mu m g / Kt
  that pulls it back once it sticks (4.9e-4 m), to 2.4e-4 m;
- no damping, no friction: kinetic plus contact spring energy conserved to 1e-6 over 1e5 steps;
- the spring energy (fix griddem's value 7) tallied only on the steps LAMMPS tallies energy: read
  by fix ave/time every 700 steps, with thermo printing none, it equals the every-step run's at those
  steps; read on a step that tallied none, the run stops naming the value and the step."""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

WD = t.workdir()


def head_on():
    kn, gamman, dt = 1e5, 100.0, 1e-5
    text = """
units lj
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -5 5 -5 5 -5 5
create_box 1 box
create_atoms 1 single -0.505 0 0
create_atoms 1 single 0.505 0 0
set type 1 diameter 1.0
set type 1 density {rho}
velocity all set 0 0 0
set atom 1 vx 0.5
set atom 2 vx -0.5
pair_style griddem/hooke/history {kn} NULL {gamman} NULL 0.5 1
pair_coeff * *
timestep {dt}
fix integrate all nve/sphere
variable vrel equal vx[2]-vx[1]
thermo_style custom step f_GRIDDEM[5] v_vrel
thermo_modify format float %.17g
thermo 1
run 3000
""".format(rho=6.0 / math.pi, kn=kn, gamman=gamman, dt=dt)
    out = t.run_ok(text, WD, name="in.head_on")
    contacts = t.thermo_values(out, "f_GRIDDEM[5]")
    vrel = t.thermo_values(out, "v_vrel")
    meff = 0.5
    z = gamman * meff / (2.0 * math.sqrt(kn * meff))
    e = math.exp(-math.pi * z / math.sqrt(1.0 - z * z))
    duration = math.pi / math.sqrt(kn / meff - (gamman / 2.0) ** 2)
    t.check(abs(vrel[-1] / 1.0 - e) <= 2e-3 * e, "restitution %.6f, analytic %.6f" % (vrel[-1], e))
    steps = sum(1 for c in contacts if c > 0)
    t.check(abs(steps * dt - duration) <= 2 * dt, "contact duration %.6g, analytic %.6g" % (steps * dt, duration))


def free_fall():
    text = """
units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -1 1 -1 1 -0.2 1.5
create_box 1 box
create_atoms 1 single 0 0 0
create_atoms 1 single 0 0 0.95
set type 1 diameter 0.1
set type 1 density 2700
group floor id 1
group ball id 2
fix frozen floor freeze
pair_style griddem/hooke/history 5e4 NULL 0.0 NULL 0.5 1
pair_coeff * *
timestep 1e-4
fix integrate all nve/sphere
fix gravity ball gravity 9.81 vector 0 0 -1
variable z equal z[2]
thermo_style custom step v_z
thermo_modify format float %.17g
thermo 50
run 9000
"""
    out = t.run_ok(text, WD, name="in.free_fall")
    z = t.thermo_values(out, "v_z")
    bottom = min(range(len(z)), key=lambda k: z[k])
    t.check(z[bottom] < 0.11, "the sphere reached the floor sphere (lowest %.4f m)" % z[bottom])
    peak = max(z[bottom:])
    t.check(abs(peak - 0.95) <= 2e-3 * 0.95, "rebound height %.5f m, dropped from 0.95 m" % peak)


def sliding_stop(v0, mu, g, radius, m, kn):
    """Where a ball sliding over the top of a frozen sphere (centres radius apart), with Coulomb
    friction mu and no rotation, comes to rest. Along the arc s, w = v^2 obeys
    dw/ds = 2 g sin(s/R) - 2 mu (g cos(s/R) - w/R): gravity's downhill part speeds it, and the
    centripetal part lightens the contact (together 0.6 % farther than on a flat floor here);
    integrated by RK4 in s to w = 0. While sliding, the tangential spring (Kt = 2/7 Kn) is stretched
    by mu m g / Kt; once the ball sticks it springs back by that much. Returns the x of rest."""
    def slope(s, w):
        return 2.0 * g * math.sin(s / radius) - 2.0 * mu * (g * math.cos(s / radius) - w / radius)
    s, w, ds = 0.0, v0 * v0, 1e-5
    while True:
        k1 = slope(s, w)
        k2 = slope(s + 0.5 * ds, w + 0.5 * ds * k1)
        k3 = slope(s + 0.5 * ds, w + 0.5 * ds * k2)
        k4 = slope(s + ds, w + ds * k3)
        after = w + ds / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
        if after <= 0.0:
            s += ds * w / (w - after)    # w is linear in s to 1e-10 of ds here
            break
        s, w = s + ds, after
    return radius * math.sin(s / radius) - mu * m * g / (2.0 / 7.0 * kn)


def sliding():
    m = 2700 * 4.0 / 3.0 * math.pi * 0.05 ** 3
    sink = m * 9.81 / 5e4
    text = """
units si
atom_style sphere
atom_modify map array
boundary f f f
comm_modify vel yes
region box block -60 60 -60 60 -60 60
create_box 1 box
create_atoms 1 single 0 0 0
create_atoms 1 single 0 0 {z}
set atom 1 diameter 100.0
set atom 2 diameter 0.1
set type 1 density 2700
group floor id 1
group ball id 2
fix frozen floor freeze
fix grid all griddem cell multi
pair_style griddem/hooke/history 5e4 NULL 50.0 NULL 0.5 1
pair_coeff * *
timestep 1e-4
fix integrate ball nve
fix gravity ball gravity 9.81 vector 0 0 -1
velocity ball set 1.414 0 0
variable x equal x[2]
variable v equal vx[2]
thermo_style custom step v_x v_v
thermo_modify format float %.17g
thermo 100
run 5000
""".format(z=50.05 - sink)
    out = t.run_ok(text, WD, name="in.sliding")
    x, v = t.thermo_values(out, "v_x"), t.thermo_values(out, "v_v")
    expected = sliding_stop(1.414, 0.5, 9.81, 50.05 - sink, m, 5e4)
    t.check(abs(v[-1]) < 1e-2, "the ball stopped (v = %.3g m/s)" % v[-1])
    # measured: 7.9e-5 m from the expected rest, the stick oscillation of the tangential spring not
    # yet damped out at t = 0.5 s; allowed 3 times that (mu 0.51 would stop 4e-3 m short)
    t.check(abs(x[-1] - expected) <= 2.4e-4, "slid %.6f m, expected %.6f m" % (x[-1], expected))


# an elastic gas (no damping, no friction) and its kinetic plus spring energy
ELASTIC_GAS = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
pair_style griddem/hooke/history 1e4 NULL 0.0 NULL 0.0 0
pair_coeff * *
timestep 2e-5
fix integrate all nve/sphere
compute rot all erotate/sphere
compute trans all ke
variable etotal equal c_trans+c_rot+f_GRIDDEM[7]
"""


def energy():
    data = os.path.join(WD, "data.gas")
    t.write_random_spheres(data, 216, (6.6, 6.6, 6.6), 0.3, 0.45, seed=5, vscale=1.0, wscale=1.0,
                           lattice=1.1)
    text = ELASTIC_GAS.format(data=data) + """thermo_style custom step atoms f_GRIDDEM[5] v_etotal
thermo_modify format float %.17g norm no
thermo 10000
run 100000
"""
    out = t.run_ok(text, WD, name="in.energy")
    e = t.thermo_values(out, "v_etotal")
    contacts = t.thermo_values(out, "f_GRIDDEM[5]")
    t.check(len(e) == 11, "energy printed 11 times")
    t.check(sum(1 for c in contacts if c > 0) >= 3, "contacts happened (%s)" % contacts)
    drift = max(abs(x - e[0]) for x in e) / e[0]
    t.check(drift <= 1e-6, "total energy drift %.3g relative over 1e5 steps" % drift)


def energy_on_demand():
    """fix ave/time reads v_etotal every 700 steps while thermo (every 1000) prints no energy: each
    value equals the one of a run that prints it every step (the state does not depend on when
    energy is tallied, so the two runs agree to the bit)."""
    data = os.path.join(WD, "data.demand")
    t.write_random_spheres(data, 216, (6.2, 6.2, 6.2), 0.3, 0.45, seed=5, vscale=1.0, wscale=1.0,
                           lattice=0.85)    # neighbours up to 0.05 deep: springs loaded throughout
    base = ELASTIC_GAS.format(data=data) + "variable spring equal f_GRIDDEM[7]\n"
    fmt = "\nthermo_modify format float %.17g norm no\n"
    every = t.run_ok(base + "thermo_style custom step f_GRIDDEM[5] v_spring v_etotal" + fmt + "thermo 1\nrun 2100\n", WD,
                     name="in.energy_every")
    steps, springs = t.thermo_values(every, "Step"), t.thermo_values(every, "v_spring")
    total = dict(zip(steps, t.thermo_values(every, "v_etotal")))
    spring = dict(zip(steps, springs))
    t.run_ok(base + "thermo_style custom step f_GRIDDEM[5]\nthermo 1000\n"
             "fix tell all ave/time 1 1 700 v_spring v_etotal file demand.txt format \" %.17g\"\n"
             "run 2100\n", WD, name="in.energy_demand")
    with open(os.path.join(WD, "demand.txt")) as f:
        printed = [line.split() for line in f if not line.startswith("#")]
    t.check([int(p[0]) for p in printed] == [0, 700, 1400, 2100], "fix ave/time read the energy at steps %s"
            % [p[0] for p in printed])
    for p in printed:
        n = int(p[0])
        t.check(float(p[1]) == spring[n] and float(p[2]) == total[n],
                "step %d: spring %s, total %s; every step's run %.17g, %.17g" % (n, p[1], p[2], spring[n], total[n]))
    t.check(min(spring[int(p[0])] for p in printed) > 0.0, "springs loaded at every printed step")
    # read after a run whose last step tallied no energy (thermo prints none, nothing read it)
    rc, out = t.run_lmp(base + "thermo_style custom step\nthermo 50\nrun 100\nprint \"LATE $(f_GRIDDEM[7])\"\n", WD,
                        name="in.energy_late")
    t.check(rc != 0 and "value 7 (the elastic energy) is tallied on the steps LAMMPS tallies energy, and step 100 "
            "was not one" in out and "\nLATE " not in out, "reading value 7 on a step without energy stops the run (rc %d)" % rc)
    # run 0 tallies it (its setup step asks every compute), and the value is the last step's
    late = t.run_ok(base + "thermo_style custom step\nthermo 50\nrun 2100\nrun 0\nprint \"LATE $(f_GRIDDEM[7]:%.17g)\"\n",
                    WD, name="in.energy_run0")
    value = [float(line.split()[1]) for line in late.splitlines() if line.startswith("LATE ")]
    t.check(value == [spring[2100]], "after run 0: %s, the every-step run's %.17g" % (value, spring[2100]))


head_on()
free_fall()
sliding()
energy()
energy_on_demand()
t.finish()
