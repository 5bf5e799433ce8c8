"""MPI-decomposition invariance and restarts, for griddem/hooke/history and for griddem/granular
on two atom types with tangential and rolling history (hertz, linear_history, sds), with JKR
(contacts held beyond touching; mindlin_rescale with k from the material, rolling sds, twisting
marshall), with DMT (mindlin_rescale/force, twisting sds), cohesion weak enough for a gas, with
mindlin, mindlin/force, linear_history_classic and coeff_restitution damping, and with a history
layout per type pair.
1, 2 and 4 ranks give the same 100-step trajectory (atoms migrate between ranks and keep their
contact history), and so do 2 OpenMP threads on one rank; a run continued from a restart file
reproduces the uninterrupted run bit for bit. A sphere with ~1000 contacts crosses between ranks
(its history fills one exchange message of thousands of values) and the trajectory equals one
rank's. The same for a 1:7 polydisperse gas on two size classes (cell classes). Fix balance defined
before the pair style moves atoms in its own pre-exchange, before fix griddem's has mirrored the
contacts the sweep kept in one row: the rows it sends are completed as they are read, and 2
ranks still equal 1. A restart file written during a run on 1 rank (restart N), read on 2, continues
the uninterrupted run."""
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
# positions unwrapped, for runs in which fix balance or a restart wraps atoms at other steps
DUMP_UNWRAPPED = DUMP.replace(" x y z ", " xu yu zu ")
STATE_UNWRAPPED = ["xu", "yu", "zu"] + STATE[3:]


PAIRS = {
    "hooke": "pair_style griddem/hooke/history 2e3 NULL 20 NULL 0.5 1\npair_coeff * *",
    "granular": "pair_style griddem/granular\n"
                "pair_coeff 1 1 hertz 4e4 20 tangential linear_history 1e4 0.5 0.5 rolling sds 100 1 0.2\n"
                "pair_coeff 2 2 hertz 2e4 10 tangential linear_history 8e3 0.4 0.3 rolling sds 50 2 0.1",
    # pull-off force 3 pi c R ~ 1, a few percent of a collision's peak force at these speeds
    "jkr": "pair_style griddem/granular\n"
           "pair_coeff 1 1 jkr 5e4 20 0.3 2 tangential mindlin_rescale NULL 0.5 0.5 rolling sds 100 1 0.2 twisting marshall\n"
           "pair_coeff 2 2 jkr 3e4 10 0.25 1 tangential mindlin_rescale NULL 0.4 0.3 rolling sds 50 2 0.1 twisting marshall",
    # twisting acts on the spin directly: k and damping small against I/dt^2 and I/dt (I >= 1.7e-5)
    "dmt": "pair_style griddem/granular\n"
           "pair_coeff 1 1 dmt 5e4 20 0.3 2 tangential mindlin_rescale/force 1e4 0.5 0.5 twisting sds 2 0.005 0.2\n"
           "pair_coeff 2 2 dmt 3e4 10 0.25 1 tangential mindlin_rescale/force 8e3 0.4 0.3 twisting sds 1 0.002 0.1",
    # the remaining history-keeping sub-models: mindlin (k from the material), mindlin/force,
    # linear_history_classic; coeff_restitution damping
    "mindlin": "pair_style griddem/granular\n"
               "pair_coeff 1 1 hertz/material 2e4 0.8 0.3 damping coeff_restitution tangential mindlin NULL 0.5 0.5\n"
               "pair_coeff 2 2 hertz/material 1.5e4 0.7 0.25 damping coeff_restitution tangential mindlin/force 8e3 0.4 0.3\n"
               "pair_coeff 1 2 hertz/material 1.7e4 0.75 0.28 damping coeff_restitution tangential mindlin 9e3 0.45 0.4",
    "classic": "pair_style griddem/granular\n"
               "pair_coeff * * hooke 2e3 0.8 damping coeff_restitution tangential linear_history_classic 1e4 0.5 0.5",
    # a history layout per type pair: rolling on type 1, twisting on type 2, none between them
    "mixed": "pair_style griddem/granular\n"
             "pair_coeff 1 1 hertz 4e4 20 tangential linear_history 1e4 0.5 0.5 rolling sds 100 1 0.2\n"
             "pair_coeff 2 2 hertz 2e4 10 tangential mindlin_rescale 8e3 0.4 0.3 twisting sds 1 0.002 0.1\n"
             "pair_coeff 1 2 hooke 3e3 20 damping mass_velocity tangential linear_nohistory 0.5 0.5",
}


def main():
    size_classes(t.workdir())
    check_models(t.workdir())
    balance_first(t.workdir())
    restart_mid_run(t.workdir())
    big_sphere(t.workdir())
    t.finish()


def size_classes(wd):
    """Radii 0.05-0.35 (1:7): two size classes, pairs across them searched from the small sphere
    into the coarse grid. 1, 2 and 4 ranks and 2 OpenMP threads agree to 1e-10 after 100 steps; a
    restart at step 50 continues bit for bit on 1 and 2 ranks."""
    data = os.path.join(wd, "data.classes")
    t.write_random_spheres(data, 700, (4.5, 4.5, 4.5), 0.05, 0.35, seed=21, vscale=2.0, wscale=5.0)
    setup = SETUP.replace("{pair}", "pair_style griddem/hooke/history 500 NULL 5 NULL 0.5 1\npair_coeff * *\n"
                          "fix GRIDDEM all griddem cell classes")
    snaps = {}
    for n in (1, 2, 4):
        text = setup.format(start="read_data " + data) + "run 50\nwrite_restart restart.classes%d\n" % n + \
            DUMP.format(every=50, name="classes%d" % n) + "run 50\n"
        t.run_ok(text, wd, nprocs=n, name="in.classes%d" % n)
        snaps[n] = t.read_dumps(os.path.join(wd, "dump.classes%d" % n))
    for n in (2, 4):
        err = t.max_rel_diff(snaps[n][-1], snaps[1][-1], STATE)
        t.check(err <= 1e-10, "size classes, %d ranks vs 1: trajectory differs by %.3g relative" % (n, err))
    # the same runs (50 steps, a restart file, 50 more) as the 1-rank reference
    text = setup.format(start="read_data " + data) + "run 50\nwrite_restart restart.classes_omp2\n" + \
        DUMP.format(every=50, name="classes_omp2") + "run 50\n"
    t.run_ok(text, wd, name="in.classes_omp2", threads=2)
    err = t.max_rel_diff(t.read_dumps(os.path.join(wd, "dump.classes_omp2"))[-1], snaps[1][-1], STATE)
    t.check(err <= 1e-10, "size classes, 2 OpenMP threads vs 1: trajectory differs by %.3g relative" % err)
    for n in (1, 2):
        again = setup.format(start="read_restart restart.classes%d" % n)
        t.run_ok(again + DUMP.format(every=50, name="classes_again%d" % n) + "run 50\n", wd, nprocs=n,
                 name="in.classes_again%d" % n)
        b = t.read_dumps(os.path.join(wd, "dump.classes_again%d" % n))
        t.check(b[0][1] == snaps[n][0][1] and b[-1][1] == snaps[n][-1][1],
                "size classes, restart on %d ranks: steps 50 and 100 identical bit for bit" % n)


def per_model(out):
    """The screen output of a multi-model input, split at the MODEL lines it prints."""
    parts, label = {}, None
    for line in out.splitlines():
        if line.startswith("MODEL "):
            label = line.split()[1]
            parts[label] = []
        elif label:
            parts[label].append(line)
    return {k: "\n".join(v) for k, v in parts.items()}


def write_gas(wd):
    """The gas of check_models, balance_first and restart_mid_run: 900 spheres of radii 0.1-0.3 and
    two types in a 4.5 box, written to wd; its path."""
    data = os.path.join(wd, "data.gas")
    t.write_random_spheres(data, 900, (4.5, 4.5, 4.5), 0.1, 0.3, seed=3, vscale=5.0, wscale=5.0,
                           ntypes=2)
    return data


def check_models(wd):
    """Every model of PAIRS on 1, 2 and 4 ranks, 2 threads, and read from restarts; one lmp run
    per case holds all the models, one after another (clear), to spare the start-up of ~30 runs."""
    data = write_gas(wd)

    # each run stops at step 50 to write a restart file and goes on to step 100: the ranks and
    # threads are compared at step 100, and the runs on 1 and 2 ranks are the uninterrupted
    # references of the restarts
    def whole(tag):
        return "".join("clear\nprint 'MODEL %s'\n" % label +
                       SETUP.replace("{pair}", pair).format(start="read_data " + data) +
                       "run 50\nwrite_restart restart.%s.%s\n" % (label, tag) +
                       DUMP.format(every=50, name="%s.%s" % (label, tag)) + "run 50\n"
                       for label, pair in PAIRS.items())

    def again(tag):
        return "".join("clear\nprint 'MODEL %s'\n" % label +
                       SETUP.replace("{pair}", pair).format(start="read_restart restart.%s.%s" % (label, tag)) +
                       DUMP.format(every=50, name="%s.again%s" % (label, tag)) + "run 50\n"
                       for label, pair in PAIRS.items())

    snaps, contacts = {}, {}
    for n in (1, 2, 4):
        out = per_model(t.run_ok(whole("np%d" % n), wd, nprocs=n, name="in.np%d" % n))
        for label in PAIRS:
            snaps[label, n] = t.read_dump(os.path.join(wd, "dump.%s.np%d" % (label, n)))
            t.check(len(snaps[label, n][1]) == 900, "%s, %d ranks: no atom lost" % (label, n))
            contacts[label, n] = t.thermo_values(out.get(label, ""), "f_GRIDDEM[5]")
            t.check(contacts[label, n] and min(contacts[label, n]) > 100,
                    "%s, %d ranks: contacts engaged (%s)" % (label, n, contacts[label, n]))
            if n > 1:
                t.check(contacts[label, n] == contacts[label, 1],
                        "%s, %d ranks: same contact counts as 1 rank" % (label, n))
                err = t.max_rel_diff(snaps[label, n], snaps[label, 1], STATE)
                t.check(err <= 1e-10, "%s, %d ranks vs 1 rank: trajectory differs by %.3g relative" % (label, n, err))
    t.run_ok(whole("omp2"), wd, name="in.omp2", threads=2)
    for label in PAIRS:
        err = t.max_rel_diff(t.read_dump(os.path.join(wd, "dump.%s.omp2" % label)), snaps[label, 1], STATE)
        t.check(err <= 1e-10, "%s, 2 OpenMP threads vs 1: trajectory differs by %.3g relative" % (label, err))

    # restart: the runs above (uninterrupted but for writing the file) against read_restart
    for n in (1, 2):
        t.run_ok(again("np%d" % n), wd, nprocs=n, name="in.again%d" % n)
        for label in PAIRS:
            a = t.read_dumps(os.path.join(wd, "dump.%s.np%d" % (label, n)))
            b = t.read_dumps(os.path.join(wd, "dump.%s.againnp%d" % (label, n)))
            t.check(len(a) == len(b) == 2, "%s restart on %d ranks: two snapshots each" % (label, n))
            t.check(a[-1][1] == b[-1][1], "%s restart on %d ranks: step 100 identical bit for bit" % (label, n))
            t.check(a[0][1] == b[0][1], "%s restart on %d ranks: step 50 forces identical bit for bit" % (label, n))


def balance_first(wd):
    """griddem/hooke/history on check_models's gas, fix balance (every 10 steps, recursive
    bisection, which migrates atoms itself) defined before the pair style, so that its
    pre-exchange runs before fix griddem's: 2 ranks against 1 rank without it, after 100 steps."""
    data = write_gas(wd)
    snaps = {}
    for n, balance in ((1, ""), (2, "comm_style tiled\nfix lb all balance 10 1.0 rcb\n")):
        text = SETUP.replace("{pair}", balance + PAIRS["hooke"]).format(start="read_data " + data) + \
            DUMP_UNWRAPPED.format(every=100, name="balance%d" % n) + "run 100\n"
        t.run_ok(text, wd, nprocs=n, name="in.balance%d" % n)
        snaps[n] = t.read_dump(os.path.join(wd, "dump.balance%d" % n))
        t.check(len(snaps[n][1]) == 900, "balance first, %d ranks: no atom lost" % n)
    err = t.max_rel_diff(snaps[2], snaps[1], STATE_UNWRAPPED)
    t.check(err <= 1e-10, "fix balance before fix griddem, 2 ranks vs 1: trajectory differs by %.3g relative" % err)


def restart_mid_run(wd):
    """griddem/hooke/history on check_models's gas, 1 rank: a restart file written by `restart` at
    the last step of a 50-step run (before the run ends, the rows as that step's sweep left them),
    read on 2 ranks and run 50 steps, against 1 rank running on (a new run, whose set-up a restart
    run has too)."""
    data = write_gas(wd)
    whole = SETUP.replace("{pair}", PAIRS["hooke"]).format(start="read_data " + data) + \
        "restart 50 restart.mid\n" + DUMP_UNWRAPPED.format(every=100, name="mid_whole") + "run 50\nrun 50\n"
    t.run_ok(whole, wd, name="in.mid_whole")
    again = SETUP.replace("{pair}", PAIRS["hooke"]).format(start="read_restart restart.mid.50") + \
        DUMP_UNWRAPPED.format(every=100, name="mid_again") + "run 50\n"
    t.run_ok(again, wd, nprocs=2, name="in.mid_again")
    a = t.read_dump(os.path.join(wd, "dump.mid_whole"))
    b = t.read_dump(os.path.join(wd, "dump.mid_again"))
    err = t.max_rel_diff(b, a, STATE_UNWRAPPED)
    t.check(err <= 1e-10, "restart written mid-run on 1 rank, read on 2: step 100 differs by %.3g relative" % err)


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
