"""MPI-decomposition invariance and restarts, for griddem/hooke/history and for griddem/granular
with tangential and rolling history on two atom types. 1, 2 and 4 ranks give the same 100-step
trajectory (atoms migrate between ranks and keep their contact history), and so do 2 OpenMP
threads on one rank; a run continued from a restart file reproduces the uninterrupted run bit
for bit. A sphere with ~1000 contacts crosses between ranks (its history fills one exchange
message of thousands of values) and the trajectory equals one rank's."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

SETUP = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
{start}
{pair}
timestep 2e-4
fix integrate all nve/sphere
thermo_style custom step atoms ke f_GRIDDEM[5]
thermo_modify format float %.17g
thermo 50
"""
DUMP = """
dump snap all custom {every} dump.{name} id x y z vx vy vz omegax omegay omegaz fx fy fz
dump_modify snap format float %.17g sort id
"""
STATE = ["x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz"]


PAIRS = {
    "hooke": "pair_style griddem/hooke/history 2e3 NULL 20 NULL 0.5 1\npair_coeff * *",
    "granular": "pair_style griddem/granular\n"
                "pair_coeff 1 1 hertz 4e4 20 tangential linear_history 1e4 0.5 0.5 rolling sds 100 1 0.2\n"
                "pair_coeff 2 2 hertz 2e4 10 tangential linear_history 8e3 0.4 0.3 rolling sds 50 2 0.1",
}


def main():
    for label, pair in PAIRS.items():
        check_model(label, pair)
    big_sphere(t.workdir())
    t.finish()


def check_model(label, pair):
    wd = t.workdir()
    data = os.path.join(wd, "data.gas")
    t.write_random_spheres(data, 900, (4.5, 4.5, 4.5), 0.1, 0.3, seed=3, vscale=5.0, wscale=5.0,
                           ntypes=2)
    setup = SETUP.replace("{pair}", pair)

    snaps = {}
    for n in (1, 2, 4):
        text = setup.format(start="read_data " + data) + DUMP.format(every=100, name="np%d" % n) + "run 100\n"
        out = t.run_ok(text, wd, nprocs=n, name="in.np%d" % n)
        snaps[n] = t.read_dump(os.path.join(wd, "dump.np%d" % n))
        t.check(len(snaps[n][1]) == 900, "%s, %d ranks: no atom lost" % (label, n))
        contacts = t.thermo_values(out, "f_GRIDDEM[5]")
        t.check(contacts and min(contacts) > 100, "%s, %d ranks: contacts engaged (%s)" % (label, n, contacts))
        if n == 1:
            contacts_1 = contacts
        else:
            t.check(contacts == contacts_1, "%s, %d ranks: same contact counts as 1 rank" % (label, n))
    text = setup.format(start="read_data " + data) + DUMP.format(every=100, name="omp2") + "run 100\n"
    t.run_ok(text, wd, name="in.omp2", threads=2)
    err = t.max_rel_diff(t.read_dump(os.path.join(wd, "dump.omp2")), snaps[1], STATE)
    t.check(err <= 1e-10, "%s, 2 OpenMP threads vs 1: trajectory differs by %.3g relative" % (label, err))
    for n in (2, 4):
        err = t.max_rel_diff(snaps[n], snaps[1], STATE)
        t.check(err <= 1e-10, "%s, %d ranks vs 1 rank: trajectory differs by %.3g relative" % (label, n, err))

    # restart: uninterrupted (two runs of 50) against write_restart + read_restart
    for n in (1, 2):
        whole = setup.format(start="read_data " + data) + "run 50\nwrite_restart restart.np%d\n" % n + \
            DUMP.format(every=50, name="whole%d" % n) + "run 50\n"
        t.run_ok(whole, wd, nprocs=n, name="in.whole%d" % n)
        again = setup.format(start="read_restart restart.np%d" % n) + \
            DUMP.format(every=50, name="again%d" % n) + "run 50\n"
        t.run_ok(again, wd, nprocs=n, name="in.again%d" % n)
        a = t.read_dumps(os.path.join(wd, "dump.whole%d" % n))
        b = t.read_dumps(os.path.join(wd, "dump.again%d" % n))
        t.check(len(a) == len(b) == 2, "%s restart on %d ranks: two snapshots each" % (label, n))
        t.check(a[-1][1] == b[-1][1], "%s restart on %d ranks: step 100 identical bit for bit" % (label, n))
        t.check(a[0][1] == b[0][1], "%s restart on %d ranks: step 50 forces identical bit for bit" % (label, n))


def big_sphere(wd):
    """A sphere of radius 2 touching ~1000 spheres of radius 0.1 crosses from one rank to the
    other: its history row (thousands of values) travels in one exchange message."""
    import math
    data = os.path.join(wd, "data.big")
    # 1000 spheres evenly over a shell overlapping the big one by 0.03 (a Fibonacci lattice,
    # neighbours ~0.23 apart), heavy enough to stay in contact for the run
    small = []
    for k in range(1000):
        zc = 1.0 - (2.0 * k + 1.0) / 1000.0
        phi = k * math.pi * (3.0 - math.sqrt(5.0))
        rho = math.sqrt(1.0 - zc * zc)
        small.append((5.0 + 2.07 * rho * math.cos(phi), 5.0 + 2.07 * rho * math.sin(phi), 4.95 + 2.07 * zc))
    lines = ["big sphere", "", "%d atoms" % (len(small) + 1), "1 atom types", "",
             "0 10 xlo xhi", "0 10 ylo yhi", "0 10 zlo zhi", "", "Atoms # sphere", "",
             "1 1 4.0 1.0 5.0 5.0 4.95"]
    lines += ["%d 1 0.2 1000.0 %.17g %.17g %.17g" % (k + 2, x, y, z) for k, (x, y, z) in enumerate(small)]
    # all move across z = 5, where two ranks split this box
    lines += ["", "Velocities", "", "1 0 0 3.0 0 0 0"]
    lines += ["%d 0 0 3.0 0 0 0" % (k + 2) for k in range(len(small))]
    with open(data, "w") as f:
        f.write("\n".join(lines) + "\n")
    text = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
fix grid all griddem cell multi contacts 2000
neighbor 0.02 bin
timestep 1e-3
fix integrate all nve/sphere
thermo_style custom step atoms f_grid[6]
thermo 10
dump snap all custom 40 dump.big{n} id proc x y z vx vy vz
dump_modify snap format float %.17g sort id
run 40
"""
    snaps = {}
    for n in (1, 2):
        out = t.run_ok(text.replace("{data}", data).replace("{n}", str(n)), wd, nprocs=n, name="in.big%d" % n)
        most = t.thermo_values(out, "f_grid[6]")
        t.check(most and min(most) == 1000, "big sphere, %d ranks: it keeps its 1000 contacts (%s)" % (n, most))
        snaps[n] = t.read_dump(os.path.join(wd, "dump.big%d" % n))
    first = t.read_dumps(os.path.join(wd, "dump.big2"))[0]
    proc = lambda snap: snap[1][1][snap[0].index("proc")]
    t.check(proc(first) != proc(snaps[2]), "big sphere: it moved to the other rank (%g -> %g)" % (proc(first), proc(snaps[2])))
    err = t.max_rel_diff(snaps[2], snaps[1], STATE[:6])
    t.check(err <= 1e-10, "big sphere crossing ranks: 2 ranks vs 1 differ by %.3g" % err)


if __name__ == "__main__":
    main()
