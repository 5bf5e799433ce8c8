"""MPI-decomposition invariance and restarts, for griddem/hooke/history and for griddem/granular
with tangential and rolling history on two atom types. 1, 2 and 4 ranks give the same 100-step
trajectory (atoms migrate between ranks and keep their contact history), and so do 2 OpenMP
threads on one rank; a run continued from a restart file reproduces the uninterrupted run bit
for bit."""
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


if __name__ == "__main__":
    main()
