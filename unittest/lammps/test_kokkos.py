"""The Kokkos styles griddem/hooke/kk, griddem/hooke/history/kk and griddem/granular/kk (with and
without contact history: linear_history, mindlin variants, rolling and twisting, dmt, jkr)
against the CPU griddem styles and stock gran/hooke(/history) and pair granular: forces and
torques at step 0, positions and velocities after 20 steps, and the virial (thermo press and the
pair part of compute pressure) agree to 1e-10 relative on a dense random polydisperse (1:3)
configuration of two atom types with random linear and angular velocities, run with
`-k on t N -sf kk -pk kokkos newton off neigh half` on 1 and 2 Kokkos (OpenMP) threads and on
1 and 2 MPI ranks. Contact lists get room for two candidates more than an atom had, so in the
first steps of these dense runs atoms with more are listed again at the end of the list, and
lists and history rows that outgrow the room the last step needed make the step run again, without
changing a number, also with fix griddem contacts 1 (the CPU fix's rows then grow); a restart
written by a kk run continues bit for bit under kk and the CPU style, and a CPU restart under kk;
a step waits for the device once between reneighborings (section synchronisation).

On a host back end the kk styles run the CPU engine over fix griddem's store unless the script
defines a fix griddem (fix griddem/kk under -sf kk), with which they run the Kokkos kernels; the
section engine checks both. `--kernels` gives every kk run whose script has no fix griddem one
(`fix GRIDDEM all griddem`, the ID the styles give their own), so that every section runs the
kernels; run the suite with and without it.

Skipped (exit code 77, ctest SKIP_RETURN_CODE) when GRIDDEM_LMP has no KOKKOS package. With
GRIDDEM_KK_GPUS=N (a CUDA/HIP build on a GPU machine) the kk runs use `-k on g N` on one MPI rank
instead of OpenMP threads and 1 and 2 ranks; a build whose only host back end is Serial (lmp -h:
"KOKKOS package API: Serial") runs on 1 thread and 1 and 2 ranks. `--only laws,growth,...` runs the named sections
(SECTIONS, at the end) alone."""
import collections
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from test_granular_parity import FROZEN_LIST, HEAT, MODELS
from test_stock_parity import CLUMP, CLUMPS, FORCES, STATE, TEMPLATE, compare as parity_compare, growing_text, \
    run as parity_run

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench"))
from gpu import POLY  # noqa: E402  (bench/gpu.py's polydisperse scene)

SKIP = 77
GPUS = os.environ.get("GRIDDEM_KK_GPUS")
KERNELS = "--kernels" in sys.argv
FIX_GRIDDEM = re.compile(r"^fix\s+\S+\s+\S+\s+griddem(/kk\S*)?(\s|$)", re.M)


def run_lmp(text, cwd, nprocs=1, name="in.test", extra=(), threads=None, timeout=900):
    """griddem_testlib's run_lmp; with --kernels a Kokkos run (-k on) of a script without a fix
    griddem gets one after its first pair_coeff line (else before its first run)."""
    if KERNELS and "-k" in extra and not FIX_GRIDDEM.search(text):
        at = re.search(r"^pair_coeff.*\n", text, re.M)
        at = at.end() if at else (re.search(r"^run\s", text, re.M) or re.search(r"$", text)).start()
        text = text[:at] + "fix GRIDDEM all griddem\n" + text[at:]
    return plain_run_lmp(text, cwd, nprocs=nprocs, name=name, extra=extra, threads=threads, timeout=timeout)


plain_run_lmp, t.run_lmp = t.run_lmp, run_lmp
RANKS = (1,) if GPUS else (1, 2)
THREADS = (1,) if GPUS else (1, 2)


def lmp_help():
    """lmp -h's text."""
    try:
        return subprocess.run([t.LMP, "-h"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              universal_newlines=True, timeout=120).stdout
    except OSError as e:
        print("cannot run %s: %s" % (t.LMP, e))
        sys.exit(1)


def installed_packages(text):
    """Package names in the 'Installed packages:' section of lmp -h."""
    packages, inside = set(), False
    for line in text.splitlines():
        if line.startswith("Installed packages:"):
            inside = True
            continue
        if inside:
            if not line.strip():
                if packages:
                    break
                continue
            packages.update(line.split())
    return packages


def kokkos_backends(text):
    """The Kokkos back ends lmp -h names ("KOKKOS package API: OpenMP Serial")."""
    found = re.search(r"^KOKKOS package API:(.*)$", text, re.M)
    return set(found.group(1).split()) if found else set()


def kk_args(threads):
    device = ["g", GPUS] if GPUS else ["t", str(threads)]
    return ["-k", "on"] + device + ["-sf", "kk", "-pk", "kokkos", "newton", "off", "neigh", "half"]


def run(wd, name, data, pair, coeffs, nprocs=1, threads=None, extra="", dimension=3):
    """parity_run (test_stock_parity) with Kokkos options when threads is given."""
    if threads is None and nprocs == 1:
        return parity_run(wd, name, data, pair, extra, coeffs, dimension)
    head = "dimension 2\n" if dimension == 2 else ""
    text = head + TEMPLATE.format(data=data, pair=pair, coeffs=coeffs, extra=extra, name=name)
    rc, out = t.run_lmp(text, wd, nprocs=nprocs, name="in." + name,
                        extra=kk_args(threads) if threads else (), threads=threads)
    if rc != 0:
        print(out[-4000:], file=sys.stderr)
        raise SystemExit("lmp failed (exit %d) on %s" % (rc, name))
    return t.read_dumps(os.path.join(wd, "dump." + name)), out


def compare(label, ref, test):
    """test_stock_parity's checks, and the largest relative differences printed."""
    (ref_snaps, ref_out), (snaps, out) = ref, test
    if len(snaps) == 2 and len(ref_snaps) == 2:
        forces = max(t.max_rel_diff(snaps[k], ref_snaps[k], FORCES) for k in (0, 1))
        state = t.max_rel_diff(snaps[1], ref_snaps[1], STATE)
        a, b = t.thermo_values(out, "Press"), t.thermo_values(ref_out, "Press")
        press = max(abs(x - y) for x, y in zip(a, b)) / (max(abs(v) for v in b) or 1.0) if a and b else -1
        print("%s: force/torque %.2g, x/v at step 20 %.2g, press %.2g" % (label, forces, state, press))
    parity_compare(label, ref, test)


def run_cpu_and_kk(wd, label, text_for, kk_ranks=1, package=(), cpu_ranks=1):
    """The script text_for(name) run with the CPU styles on cpu_ranks ranks as label_cpu, then with
    -sf kk on THREADS[-1] threads and kk_ranks ranks (and the package kokkos keywords package) as
    label_kk, each checked to finish: [(name, output)] in that order."""
    runs = []
    for name, nprocs, extra in ((label + "_cpu", cpu_ranks, ()),
                                (label + "_kk", kk_ranks, kk_args(THREADS[-1]) + list(package))):
        rc, out = t.run_lmp(text_for(name), wd, nprocs=nprocs, name="in." + name, extra=extra,
                            threads=THREADS[-1] if extra else None)
        t.check(rc == 0, "%s runs (exit %d): %s" % (name, rc, t.errors(out)[:1]))
        runs.append((name, out))
    return runs



def as_cpu_says(line):
    """A message without its ERROR/WARNING prefix, its source location and the "/kk" of the
    style's name: the words the CPU and kk styles share."""
    return re.sub(r"^.*?: | \(src/.*$|/kk", "", line)


def errors_of_cpu_and_kk(wd, label, text):
    """The script run with the CPU styles and with -sf kk on one thread, either allowed to stop:
    {"cpu" | "kk": (stopped, [LAMMPS's ERROR lines, as_cpu_says])}. Other lines that contain
    "ERROR" are Open MPI's as the process aborts (seen once: "... Data unpack would read past end
    of buffer in file ../../../orte/util/show_help.c ..."), not the style's."""
    said = {}
    for name, extra in (("cpu", ()), ("kk", kk_args(1))):
        rc, out = t.run_lmp(text, wd, name="in.%s_%s" % (label, name), extra=extra)
        said[name] = (rc != 0, [as_cpu_says(l) for l in t.errors(out) if l.startswith("ERROR")])
    return said

# (label, CPU griddem style and stock style with their coefficients); the 1-2 pair is mixed
LAWS = [
    ("hooke", "griddem/hooke 1e4 NULL 50 NULL 0.5 1", "gran/hooke 1e4 NULL 50 NULL 0.5 1", "pair_coeff * *"),
    ("hooke dampflag 0 limit_damping", "griddem/hooke 2e4 3e3 80 20 0.3 0 limit_damping",
     "gran/hooke 2e4 3e3 80 20 0.3 0 limit_damping", "pair_coeff * *"),
    ("granular hooke mass_velocity linear_nohistory", "griddem/granular", "granular",
     "pair_coeff 1 1 hooke 1e4 50 damping mass_velocity tangential linear_nohistory 0.5 0.5\n"
     "pair_coeff 2 2 hooke 2e4 30 damping mass_velocity tangential linear_nohistory 0.4 0.3"),
    ("granular hertz viscoelastic linear_nohistory", "griddem/granular", "granular",
     "pair_coeff 1 1 hertz 1e5 20 tangential linear_nohistory 0.5 0.5\n"
     "pair_coeff 2 2 hertz 2e5 10 tangential linear_nohistory 0.6 0.4"),
    ("granular hertz/material tsuji linear_nohistory limit_damping", "griddem/granular", "granular",
     "pair_coeff 1 1 hertz/material 1e6 0.8 0.3 damping tsuji tangential linear_nohistory 1.0 0.5 limit_damping\n"
     "pair_coeff 2 2 hertz/material 5e5 0.6 0.25 damping tsuji tangential linear_nohistory 0.8 0.3 limit_damping"),
    ("hooke/history", "griddem/hooke/history 1e4 NULL 50 NULL 0.5 1", "gran/hooke/history 1e4 NULL 50 NULL 0.5 1",
     "pair_coeff * *"),
    ("hooke/history dampflag 0 limit_damping", "griddem/hooke/history 2e4 3e3 80 20 0.3 0 limit_damping",
     "gran/hooke/history 2e4 3e3 80 20 0.3 0 limit_damping", "pair_coeff * *"),
    ("hertz/history", "griddem/hertz/history 2e5 NULL 50 NULL 0.5 1", "gran/hertz/history 2e5 NULL 50 NULL 0.5 1",
     "pair_coeff * *"),
    ("granular, a history layout per type pair", "griddem/granular", "granular",
     "pair_coeff 1 1 hertz 1e5 20 tangential linear_history 3e4 0.5 0.5 rolling sds 500 5 0.1\n"
     "pair_coeff 2 2 hertz 2e5 10 tangential mindlin_rescale 2e4 0.6 0.4 twisting sds 100 0.005 0.2\n"
     "pair_coeff 1 2 hooke 1.5e4 30 damping mass_velocity tangential linear_nohistory 0.5 0.5"),
] + [("granular " + label, "griddem/granular", "granular", "pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2))
     for label, c1, c2 in MODELS if "nohistory" not in c1 and " heat " not in c1]  # the laws with history (the sub-model table's examples; heat is the CPU style's)
HISTORY = LAWS[5]


def main():
    global THREADS
    text = lmp_help()
    packages = installed_packages(text)
    if "KOKKOS" not in packages:
        print("SKIPPED: %s has no KOKKOS package (installed: %s); configure with -DPKG_KOKKOS=on "
              "(README, 'Building with KOKKOS') and set GRIDDEM_LMP to that lmp" % (t.LMP, " ".join(sorted(packages))))
        sys.exit(SKIP)
    backends = kokkos_backends(text)
    if not GPUS and not backends & {"OpenMP", "Threads"}:
        THREADS = (1,)    # Kokkos refuses more threads without a threading back end
    print("Kokkos back ends: %s; threads %s, ranks %s" % (" ".join(sorted(backends)) or "?",
                                                        ",".join(map(str, THREADS)), ",".join(map(str, RANKS))))

    only = sys.argv[sys.argv.index("--only") + 1].split(",") if "--only" in sys.argv else list(SECTIONS)
    unknown = [name for name in only if name not in SECTIONS]
    if unknown:
        raise SystemExit("test_kokkos.py --only: no section %s (sections: %s)" % (",".join(unknown), ",".join(SECTIONS)))
    wd = t.workdir()
    data = os.path.join(wd, "data.dense")
    t.write_random_spheres(data, 1500, (4.5, 4.5, 4.5), 0.1, 0.3, seed=23, vscale=1.0, wscale=5.0,
                           ntypes=2)
    for name in only:
        SECTIONS[name](wd, data)
    t.finish()


def check_pair_local(wd, data):
    """single() reads a pair's history from fix griddem/kk's rows (on the host, whatever layout the
    device gives them): compute pair/local after 20 steps of griddem/hooke/history/kk equals the
    CPU style's, pair by pair, every column. Both with newton off: a pair across a periodic
    boundary is then evaluated from the same side (ghost velocities lag the owned ones' final
    integration, so the two sides differ, in stock as here)."""
    from test_pair_local import TEMPLATE as LOCAL, read_local
    law = HISTORY
    runs = run_cpu_and_kk(wd, "local", lambda name: "newton off\n" + LOCAL.format(
        data=data, pair=law[1], coeffs=law[3] + "\nfix grid all griddem contacts 64",
        extras=" ".join("p%d" % k for k in range(1, 11)), name=name))
    cpu, kk = [read_local(os.path.join(wd, "dump." + name)) for name, _ in runs]
    touching = sorted(k for k, v in cpu.items() if v[1] != 0.0)
    t.check(len(touching) > 500 and touching == sorted(k for k, v in kk.items() if v[1] != 0.0),
            "pair/local under kk: the same %d pairs in contact as the CPU style" % len(touching))
    worst = 0.0
    for col in range(12):
        scale = max(abs(cpu[key][col]) for key in touching) or 1.0
        worst = max(worst, max(abs(kk[key][col] - cpu[key][col]) for key in touching if key in kk) / scale)
    # p1-p4 (tangential force and its magnitude) come from the shear history in the rows
    shear = max(abs(cpu[key][5]) for key in touching)
    print("pair/local (single) of %s/kk vs CPU: %.2g over %d pairs, largest shear force %.3g"
          % (law[1].split()[0], worst, len(touching), shear))
    t.check(worst <= 1e-10 and shear > 0.0, "single() under kk equals the CPU style (%.3g)" % worst)


ADD_DELETE = t.PERIODIC_SPHERES + """
timestep 1e-5
fix integrate all nve/sphere
run 10
region hole sphere 2.25 2.25 2.25 0.8
delete_atoms region hole compress {compress}
region box2 block 0 4.5 0 4.5 0 4.5
group old id > 0
create_atoms 1 random 40 4321 box2
group new subtract all old
set group new diameter 0.05 density 1.0
velocity new create 0.5 99 loop geom
dump snap all custom 10 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz
dump_modify snap format float %.17g sort id
run 10
"""


def check_add_delete(wd, data):
    """Atoms deleted between runs (their rows move with the atoms that take their places), with
    their IDs kept or the rest renumbered (compress yes: the rows follow the new IDs), and new atoms
    (empty rows, fix griddem's set_arrays) under griddem/hooke/history/kk: the state after the
    second run equals the CPU style's."""
    for compress in ("no", "yes"):
        runs = run_cpu_and_kk(wd, "adddel" + compress, lambda name: ADD_DELETE.format(
            data=data, pair=HISTORY[1], coeffs=HISTORY[3], name=name, compress=compress))
        got = [t.read_dumps(os.path.join(wd, "dump." + name))[-1] for name, _ in runs]
        ids = sorted(got[0][1])
        err = t.max_rel_diff(got[1], got[0], STATE + FORCES)
        print("%s/kk after deleting (compress %s) and adding atoms vs CPU: %.2g (%d atoms)"
              % (HISTORY[1].split()[0], compress, err, len(ids)))
        renumbered = ids == list(range(1, len(ids) + 1))
        t.check(len(ids) < 1540 and renumbered == (compress == "yes") and err <= 1e-10,
                "atoms deleted (compress %s) and added under kk as on the CPU (%.3g, %d atoms)" % (compress, err, len(ids)))


FIXES = """
units lj
atom_style sphere
boundary p p m
comm_modify vel yes
read_data {data}
pair_style griddem/hooke/history 1e4 NULL 50 NULL 0.5 1
pair_coeff * *
group base id <= 40
timestep 1e-4
fix frozen base freeze
fix integrate all nve/sphere
fix down all gravity 10.0 vector 0 0 -1
fix floor all wall/gran hooke/history 1e4 NULL 50 NULL 0.0 1 zplane 0.1 NULL
fix shear all deform 1 xy erate 0.5 remap v
info fixes
thermo_style custom step ke press
thermo 100
dump snap all custom 300 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz
dump_modify snap format float %.17g sort id
run 300
"""


def check_stock_fixes(wd, _data):
    """The kk fixes LAMMPS ships (gravity/kk, wall/gran/kk, deform/kk, freeze/kk, nve/sphere/kk)
    with griddem/hooke/history/kk, against the CPU style with the CPU fixes. The wall is
    frictionless: with friction, LAMMPS 4Feb2025's wall/gran/kk departs from its CPU wall/gran
    (stock gran/hooke/history with only that wall, CPU vs kk: relative 1 after 50 steps), so it
    cannot be the reference; stock gran/hooke/history/kk itself departs from its CPU style in this
    scene (0.07 after 50 steps), so the CPU griddem style is."""
    data = os.path.join(wd, "data.tri")
    t.write_random_spheres(data, 800, (4.5, 4.5, 4.5), 0.1, 0.3, seed=13, triclinic=(0.0, 0.0, 0.0))
    runs = run_cpu_and_kk(wd, "fx", lambda name: FIXES.format(data=data, name=name), kk_ranks=RANKS[-1])
    snaps = [t.read_dumps(os.path.join(wd, "dump." + name))[-1] for name, _ in runs]
    for fix in ("gravity/kk", "wall/gran/kk", "deform/kk", "freeze/kk", "nve/sphere/kk"):
        t.check(fix in runs[1][1], "the kk run uses fix %s" % fix)
    err = t.max_rel_diff(snaps[1], snaps[0], STATE + FORCES)
    print("griddem/hooke/history/kk beside the stock kk fixes, 300 steps, vs CPU: %.2g" % err)
    t.check(err <= 1e-8, "griddem/hooke/history/kk beside the stock kk fixes vs CPU (%.3g)" % err)


ROM = t.PERIODIC_SPHERES + """
fix rom all griddem/rom model {model} eps 1.5 v0 1 every 5 overlap 0.5
fix integrate rom_dynamic nve/sphere
timestep 2e-4
thermo_style custom step ke press f_rom[1]
thermo_modify format float %.17g
thermo 100
dump snap all custom 400 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz f_rom
dump_modify snap format float %.17g sort id
run 400
"""


def check_rom(wd, _data):
    """fix griddem/rom (a host fix) with griddem/hooke/history/kk equals it with the CPU style:
    on a lattice of spacing 0.45 (radii 0.15-0.25: many touch), atoms slower than 1.5 (field 0)
    become kinematic and the kk sweep skips their pairs with each other (the pressure, whose pair
    virial holds those pairs unless skipped, equals the CPU style's, which test_rom checks skips
    them); kinematic states, positions, velocities, forces after 400 steps. Then the store (keyword
    store), where the lagging atoms leave LAMMPS's arrays and the kk styles' views: a lattice of
    125 spheres carried across the periodic box by a uniform field (test_rom's migration), 50 of
    them lagging and held out of LAMMPS; as many held at every step as with the CPU styles on as
    many ranks (one process reads held atoms in place where several bring them back), 125 in all,
    and every atom at x0 + U t at the end on 2 ranks."""
    data = os.path.join(wd, "data.rom")
    t.write_random_spheres(data, 729, (4.05, 4.05, 4.05), 0.15, 0.25, seed=31, lattice=0.45)
    model = os.path.join(wd, "zero.model")
    t.write_rom_model(model, (3, 3, 3), (0.0, 4.05, 0.0, 4.05, 0.0, 4.05))
    runs = run_cpu_and_kk(wd, "rom", lambda name: ROM.format(data=data, pair=HISTORY[1], coeffs=HISTORY[3],
                                                           model=model, name=name))
    (cpu_name, cpu_out), (kk_name, kk_out) = runs
    cpu, kk = [t.read_dumps(os.path.join(wd, "dump." + name))[-1] for name in (cpu_name, kk_name)]
    kinematic = [t.thermo_values(o, "f_rom[1]") for o in (cpu_out, kk_out)]
    t.check(kinematic[0] == kinematic[1] and min(kinematic[1][1:]) > 50,
            "rom kk vs CPU: kinematic counts %s vs %s" % (kinematic[1], kinematic[0]))
    press = [t.thermo_values(o, "Press") for o in (cpu_out, kk_out)]
    perr = max(abs(a - b) for a, b in zip(*press)) / max(abs(b) for b in press[0])
    t.check(len(press[1]) == 5 and perr <= 1e-10, "rom kk vs CPU: pressure %s vs %s" % (press[1], press[0]))
    cols = cpu[0]
    k = cols.index("f_rom")
    t.check(all(cpu[1][i][k] == kk[1][i][k] for i in cpu[1]), "rom kk vs CPU: every atom's kinematic state equal")
    err = t.max_rel_diff(kk, cpu, STATE + FORCES)
    print("fix griddem/rom with griddem/hooke/history/kk vs CPU, 400 steps: %.2g" % err)
    t.check(err <= 1e-8, "fix griddem/rom with griddem/hooke/history/kk vs CPU (%.3g)" % err)

    U = (0.7, 0.4, 0.0)
    flow = os.path.join(wd, "flow.model")
    t.write_rom_model(flow, (3, 3, 3), (0.0, 6.0, 0.0, 6.0, 0.0, 6.0), bias=U)
    runs = run_cpu_and_kk(wd, "store", lambda name: ROM_STORE.format(model=flow, u0=U[0], u1=U[1], name=name),
                          kk_ranks=RANKS[-1], cpu_ranks=RANKS[-1])
    held, total = [[t.thermo_values(o, c) for _, o in runs] for c in ("f_rom[17]", "f_rom[18]")]
    t.check(held[0] == held[1] and sum(h == 50 for h in held[1]) > 1000 and total[1] == [125] * 1501,
            "rom store kk vs CPU: atoms held equal at every step (50 at %d of 1501), 125 in all" %
            sum(h == 50 for h in held[1]))
    end = t.read_dump(os.path.join(wd, "end.%s" % runs[1][0]))[1]
    start = t.read_dump(os.path.join(wd, "start.%s" % runs[1][0]))[1]
    worst = max(min((end[i][d] - start[i][d] - U[d] * 1.5) % 6.0, 6.0 - (end[i][d] - start[i][d] - U[d] * 1.5) % 6.0)
                for i in start for d in range(3))
    t.check(len(end) == 125 and worst <= 1e-10, "rom store kk: 125 atoms, each at x0 + U t (worst %.2g)" % worst)


ROM_STORE = t.PERIODIC_BOX6 + """lattice sc 0.5787037037037037 origin 0.25 0.25 0.25
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set {u0} {u1} 0.0 units box
region low block INF INF INF INF INF 1.0
group low region low
group carried subtract all low
pair_style griddem/hooke/history 2000 NULL 50 NULL 0.5 1
pair_coeff * *
timestep 0.001
fix rom carried griddem/rom model {model} eps 0.5 v0 1 every 200
fix integrate rom_dynamic nve/sphere
write_dump all custom start.{name} id x y z modify sort id format float %.17g
thermo_style custom step atoms f_rom[17] f_rom[18]
thermo 1
run 1500
write_dump all custom end.{name} id x y z modify sort id format float %.17g
"""


RESTART = t.PERIODIC_SPHERES.replace("read_data {data}", "{start}") + """
{write}
timestep 1e-5
fix integrate all nve/sphere
thermo_style custom step ke press
thermo_modify format float %.17g
thermo 10
dump snap all custom 10 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz
dump_modify snap format float %.17g sort id
run 10
{finish}
"""


def restart_run(wd, name, data, law, kk_first, kk_second, fix=""):
    """10 steps, written to a restart file, then 10 steps from it: the state at step 20."""
    first = RESTART.format(start="read_data %s" % data, pair=law[1], coeffs=law[3], name=name + "_a",
                           write=fix, finish="write_restart restart.%s" % name)
    rc, out = t.run_lmp(first, wd, name="in.%s_a" % name, extra=kk_args(1) if kk_first else ())
    t.check(rc == 0, "%s: first half runs (exit %d)" % (name, rc))
    second = RESTART.format(start="read_restart restart.%s" % name, pair=law[1], coeffs=law[3],
                            name=name + "_b", write=fix, finish="")
    rc, out = t.run_lmp(second, wd, name="in.%s_b" % name, extra=kk_args(1) if kk_second else ())
    t.check(rc == 0, "%s: second half runs (exit %d): %s" % (name, rc, t.errors(out)[:1]))
    return t.read_dumps(os.path.join(wd, "dump.%s_b" % name))[-1]


def check_restart(wd, data):
    # the second hooke/history case defines fix griddem in the script (named through -sf kk)
    for law, fix in ((HISTORY, ""), (LAWS[-1], ""), (HISTORY, "fix grid all griddem contacts 3")):
        straight = RESTART.format(start="read_data %s" % data, pair=law[1], coeffs=law[3], name="straight",
                                  write=fix, finish="run 10")
        rc, out = t.run_lmp(straight, wd, name="in.straight", extra=kk_args(1))
        t.check(rc == 0, "straight kk run (exit %d)" % rc)
        ref = t.read_dumps(os.path.join(wd, "dump.straight"))[-1]
        for kk_first, kk_second in ((True, True), (True, False), (False, True)):
            name = "rs_%d%d" % (kk_first, kk_second)
            got = restart_run(wd, name, data, law, kk_first, kk_second, fix)
            err = t.max_rel_diff(got, ref, STATE + FORCES)
            what = "%s [%s%s] restart %s -> %s" % (law[1].split()[0], law[0], ", " + fix if fix else "",
                                                   "kk" if kk_first else "CPU", "kk" if kk_second else "CPU")
            print("%s: %.2g" % (what, err))
            # kk after kk: bit for bit; across CPU and kk: the engines' round-off
            t.check(err == 0.0 if kk_first and kk_second else err <= 1e-10, "%s: state at step 20 (%.3g)" % (what, err))


def check_laws(wd, data):
    for k, (label, griddem, stock, coeffs) in enumerate(LAWS):
        ref = run(wd, "stock_%d" % k, data, stock, coeffs, extra=FROZEN_LIST)
        cpu = run(wd, "cpu_%d" % k, data, griddem, coeffs)
        for nprocs in RANKS:
            for threads in THREADS:
                kk = run(wd, "kk_%d_%d_%d" % (k, nprocs, threads), data, griddem, coeffs, nprocs, threads)
                what = "%s/kk [%s], %d rank(s), %d thread(s)" % (griddem.split()[0], label, nprocs, threads)
                compare(what + " vs stock " + stock.split()[0], ref, kk)
                compare(what + " vs CPU " + griddem.split()[0], cpu, kk)


def check_heat(wd, data):
    """The heat models of the sub-model table (heat radius, heat area) through griddem/granular/kk:
    each atom's temperature and heatflow at steps 0 and 20 equal the CPU style's (which
    test_granular_parity checks against the formula and stock) on 1 and 2 ranks and threads, and
    heat flows."""
    for label, c1, c2 in (m for m in MODELS if m[0].startswith("heat ")):
        coeffs = "pair_coeff 1 1 %s\npair_coeff 2 2 %s" % (c1, c2)
        name = "heat_cpu_" + label.split()[1]
        run(wd, name, data, "griddem/granular", coeffs, extra=HEAT.format(name=name))
        cpu = t.read_dumps(os.path.join(wd, "dump.heat." + name))
        t.check(len(cpu) == 2 and any(v[1] != 0.0 for v in cpu[1][1].values()), "%s: CPU heat dumped, heat flows" % label)
        for nprocs in RANKS:
            for threads in THREADS:
                name = "heat_kk_%s_%d_%d" % (label.split()[1], nprocs, threads)
                run(wd, name, data, "griddem/granular", coeffs, nprocs, threads, extra=HEAT.format(name=name))
                kk = t.read_dumps(os.path.join(wd, "dump.heat." + name))
                t.check(len(kk) == 2, "%s kk: heat dumped at steps 0 and 20" % label)
                err = max(t.max_rel_diff(a, b, ["c_heat[1]", "c_heat[2]"]) for a, b in zip(kk, cpu))
                print("griddem/granular/kk [%s], %d rank(s), %d thread(s) vs CPU: temperature/heatflow %.2g"
                      % (label, nprocs, threads, err))
                t.check(err <= 1e-10, "%s kk, %d rank(s), %d thread(s): temperature/heatflow relative error %.3g"
                        % (label, nprocs, threads, err))


def check_active(wd, data):
    # the kk styles really ran: with -sf kk the pair style is the kk one
    for law in (LAWS[0], LAWS[2], HISTORY):
        style = law[1].split()[0]
        rc, out = t.run_lmp(t.PERIODIC_SPHERES.format(data=data, pair=law[1], coeffs=law[3]) +
                            "print \"STYLE $(is_active(pair_style,%s/kk))\"\nrun 0\n" % style, wd,
                            name="in.active", extra=kk_args(1))
        t.check(rc == 0 and "STYLE 1" in out, "with -sf kk pair_style %s is %s/kk: %s"
                % (style, style, [l for l in out.splitlines() if "STYLE" in l or "ERROR" in l][-1:]))


def check_variants(wd, data):
    # the explicit /kk/host and /kk/device names (without -sf kk) give the same virial
    for law, variant in ((LAWS[0], "host"), (LAWS[3], "device")):
        words = law[1].split()
        pair = " ".join([words[0] + "/kk/" + variant] + words[1:])
        text = t.PERIODIC_SPHERES.format(data=data, pair=pair, coeffs=law[3]).replace(
            "atom_style sphere", "atom_style sphere/kk") + (
            "run_style verlet/kk\nfix integrate all nve/sphere/kk\ntimestep 1e-5\n"
            "thermo_style custom step press\nthermo_modify format float %.17g\nthermo 10\nrun 20\n")
        rc, out = t.run_lmp(text, wd, name="in.variant", extra=["-k", "on"] + (["g", GPUS] if GPUS else ["t", "1"]))
        a, b = t.thermo_values(out, "Press"), t.thermo_values(run(wd, "cpu_v", data, law[1], law[3])[1], "Press")
        worst = max(abs(x - y) for x, y in zip(a, b)) / max(abs(v) for v in b) if rc == 0 and len(a) == 3 else 1.0
        t.check(rc == 0 and worst <= 1e-10, "pair_style %s runs and matches the CPU style's press (%.3g, exit %d)"
                % (pair.split()[0], worst, rc))


def check_exclusions(wd, data):
    # neigh_modify exclude (type and group) and fix freeze (infinite mass) as the CPU style
    extra = ("group low id <= 700\nneigh_modify exclude group low low exclude type 1 2\n"
             "group base id > 1300\nset group base diameter 0.4\nset group base density 1.0\n"
             "fix frozen base freeze")
    for law in (LAWS[0], LAWS[3]):
        style = law[1].split()[0]
        cpu = run(wd, "cpu_ex", data, law[1], law[3], extra=extra)
        compare("%s/kk with exclusions and fix freeze vs CPU" % style, cpu,
                run(wd, "kk_ex", data, law[1], law[3], nprocs=RANKS[-1], threads=THREADS[-1], extra=extra))
        compare("%s/kk with exclusions and fix freeze vs stock" % style,
                run(wd, "stock_ex", data, law[2], law[3], extra=extra),
                run(wd, "kk_ex1", data, law[1], law[3], threads=1, extra=extra))


def check_virial(wd, data):
    # per-atom virial (compute stress/atom) as the CPU style's, on steps 0 to 3
    stress = ("compute s all stress/atom NULL pair\n"
              "dump st all custom 1 dump.st id c_s[1] c_s[2] c_s[3] c_s[4] c_s[5] c_s[6]\n"
              "dump_modify st format float %.17g sort id\n"
              "timestep 1e-5\nfix integrate all nve/sphere\nrun 3\n")
    cols = ["c_s[%d]" % k for k in range(1, 7)]
    per_atom = []
    for extra in ([], kk_args(THREADS[-1])):
        rc, out = t.run_lmp(t.PERIODIC_SPHERES.format(data=data, pair=LAWS[3][1], coeffs=LAWS[3][3]) + stress,
                            wd, name="in.stress", extra=extra, threads=THREADS[-1])
        t.check(rc == 0, "stress/atom run (exit %d)" % rc)
        per_atom.append(t.read_dumps(os.path.join(wd, "dump.st")))
    t.check(len(per_atom[0]) == len(per_atom[1]) == 4, "stress/atom dumped at steps 0 to 3")
    err = max(t.max_rel_diff(a, b, cols) for a, b in zip(per_atom[1], per_atom[0]))
    print("griddem/granular/kk per-atom virial vs CPU: %.2g" % err)
    t.check(err <= 1e-10, "griddem/granular/kk per-atom virial relative error %.3g" % err)


def check_mismatch(wd, data):
    # the history fix must be one the pair style sweeps: a CPU style's not fix griddem/kk, a kk
    # style's on a GPU not fix griddem (on a host back end it runs the CPU engine: section engine)
    cases = [("griddem/hooke/history", "griddem/kk", "griddem, but fix grid is fix griddem/kk:")]
    if GPUS:
        cases.append(("griddem/hooke/history/kk", "griddem", "griddem/kk, but fix grid is fix griddem:"))
    for pair, fix, wanted in cases:
        text = t.PERIODIC_SPHERES.format(data=data, pair=pair + " 1e4 NULL 50 NULL 0.5 1", coeffs="pair_coeff * *")
        text = text.replace("atom_style sphere", "atom_style sphere/kk") + "fix grid all %s\nrun 0\n" % fix
        rc, out = t.run_lmp(text, wd, name="in.mismatch", extra=["-k", "on"] + (["g", GPUS] if GPUS else ["t", "1"]))
        t.check(rc != 0 and any("keeps its contact history in fix " + wanted in l for l in t.errors(out)),
                "pair style %s with fix %s refused naming both: %s" % (pair, fix, t.errors(out)[:1]))
    # fix griddem kernel chooses among the CPU engine's candidate kernels: the kk kernels refuse it
    text = t.PERIODIC_SPHERES.format(data=data, pair="griddem/hooke/history/kk 1e4 NULL 50 NULL 0.5 1",
                                     coeffs="pair_coeff * *")
    text = text.replace("atom_style sphere", "atom_style sphere/kk") + "fix grid all griddem/kk kernel avx2\nrun 0\n"
    rc, out = t.run_lmp(text, wd, name="in.kernel", extra=["-k", "on"] + (["g", GPUS] if GPUS else ["t", "1"]))
    t.check(rc != 0 and any("kernel avx2 chooses among the CPU engine's candidate kernels" in l for l in t.errors(out)),
            "the kk kernels refuse fix griddem kernel avx2: %s" % t.errors(out)[:1])


def check_engine(wd, data):
    """On a host back end a kk style runs the CPU engine over fix griddem's store where the script
    defines no fix griddem (the style's own is fix griddem), or a fix griddem without the Kokkos
    suffix: its dumps (forces and torques at step 0, state at 20) and per-atom virial equal the
    CPU style's to the bit, on 1 and 2 ranks and THREADS[-1] threads, and no Kokkos kernel
    synchronises in its compute. With the script's fix griddem under -sf kk (fix griddem/kk) it
    runs the Kokkos kernels, which synchronise at least once a step; one defined after a run of the
    engine takes its history, and the kernels go on as the CPU style."""
    if GPUS:
        print("engine: skipped, a GPU runs the kk styles' kernels")
        return
    stress = ("compute s all stress/atom NULL pair\n"
              "dump st all custom 20 dump.{name}.st id c_s[1] c_s[2] c_s[3] c_s[4] c_s[5] c_s[6]\n"
              "dump_modify st format float %.17g sort id")
    cols = ["c_s[%d]" % k for k in range(1, 7)]
    for law in (LAWS[0], HISTORY, LAWS[8]):
        style = law[1].split()[0]
        for nprocs in RANKS:
            got = {}
            for kind, extra, fix in (("cpu", (), ""), ("kk", kk_args(THREADS[-1]), ""),
                                     ("kk_fix", ["-k", "on", "t", str(THREADS[-1])], "fix grid all griddem")):
                name = "engine_%s_%d" % (kind, nprocs)
                text = TEMPLATE.format(data=data, pair=law[1] if kind != "kk_fix" else law[1].replace(style, style + "/kk"),
                                       coeffs=law[3], extra=stress.format(name=name) + "\n" + fix, name=name)
                if kind == "kk_fix":
                    text = text.replace("atom_style sphere", "atom_style sphere/kk").replace(
                        "timestep 1e-5", "run_style verlet/kk\ntimestep 1e-5")
                rc, out = plain_run_lmp(text, wd, nprocs=nprocs, name="in." + name, extra=extra, threads=THREADS[-1])
                t.check(rc == 0, "%s %s on %d rank(s) runs (exit %d): %s" % (style, kind, nprocs, rc, t.errors(out)[:1]))
                got[kind] = (t.read_dumps(os.path.join(wd, "dump." + name)), t.read_dumps(os.path.join(wd, "dump." + name + ".st"))) if rc == 0 else None
            if not all(got.values()):
                continue
            for kind in ("kk", "kk_fix"):
                (snaps, st), (ref, ref_st) = got[kind], got["cpu"]
                if not (len(snaps) == len(st) == 2):
                    t.check(False, "%s %s on %d rank(s): dumps at steps 0 and 20" % (style, kind, nprocs))
                    continue
                first = max(t.max_rel_diff(snaps[0], ref[0], FORCES), t.max_rel_diff(st[0], ref_st[0], cols))
                last = max(t.max_rel_diff(snaps[1], ref[1], STATE + FORCES), t.max_rel_diff(st[1], ref_st[1], cols))
                print("%s/kk (%s) on %d rank(s), %d threads vs the CPU style: step 0 %.2g, step 20 %.2g"
                      % (style, kind, nprocs, THREADS[-1], first, last))
                # -sf kk also integrates with fix nve/sphere/kk, whose rounding differs from nve/sphere's
                t.check(first == 0.0 and (last == 0.0 if kind == "kk_fix" else last <= 1e-12),
                        "%s/kk%s on %d rank(s): the CPU engine's forces and per-atom virial to the bit, and its "
                        "state at step 20 %s (%.3g, %.3g)" % (style, " with the script's fix griddem" if kind == "kk_fix"
                                                              else "", nprocs, "to the bit" if kind == "kk_fix"
                                                              else "to 1e-12 (fix nve/sphere/kk)", first, last))
    # a fix griddem defined after a run (fix griddem/kk) takes the rows of the CPU store that ran
    text = t.PERIODIC_SPHERES.format(data=data, pair=HISTORY[1], coeffs=HISTORY[3]) + (
        "timestep 1e-5\nfix integrate all nve/sphere\nthermo 10\n"
        "dump d all custom 20 dump.{name} id xu yu zu vx vy vz fx fy fz tqx tqy tqz\n"
        "dump_modify d format float %.17g sort id\nrun 10\n{fix}run 10\n")
    handed = {}
    for kind, extra, fix in (("cpu", (), ""), ("kk", kk_args(THREADS[-1]), "fix grid all griddem\n")):
        name = "engine_handover_" + kind
        rc, out = plain_run_lmp(text.format(name=name, fix=fix), wd, name="in." + name, extra=extra, threads=THREADS[-1])
        said = [line for line in out.splitlines() if "takes its contact history" in line]
        t.check(rc == 0 and (kind == "cpu" or said), "%s: runs, the new fix taking the history (exit %d): %s %s"
                % (name, rc, said, t.errors(out)[:1]))
        handed[kind] = t.read_dumps(os.path.join(wd, "dump." + name)) if rc == 0 else []
    if len(handed["cpu"]) == len(handed["kk"]) == 2:
        err = t.max_rel_diff(handed["kk"][1], handed["cpu"][1], ["xu", "yu", "zu"] + STATE[3:] + FORCES)
        print("%s/kk, the CPU engine for 10 steps, then the kernels with a fix griddem defined after the run, vs "
              "the CPU style: %.2g" % (HISTORY[1].split()[0], err))
        t.check(err <= 1e-10, "the kernels go on from the CPU engine's history as the CPU style (%.3g)" % err)
    if not sync_counter_found():
        return
    for label, fix, expected in (("own fix", "", 0), ("fix griddem/kk", "fix grid all griddem\n", 1)):
        log = os.path.join(wd, "syncs.engine")
        text = t.PERIODIC_SPHERES.format(data=data, pair=HISTORY[1], coeffs=HISTORY[3]) + fix + (
            "timestep 1e-5\nfix integrate all nve/sphere\nneigh_modify every 1000 delay 0 check no\nrun 20\n")
        rc, out = run_counted(wd, "syncs_engine", text, log, run=plain_run_lmp)
        steps = [int(line.split()[0]) for line in open(log)][1:] if rc == 0 and os.path.exists(log) else []
        print("%s/kk with %s: blocking synchronisations per compute %s" % (HISTORY[1].split()[0], label, sorted(set(steps))))
        t.check(len(steps) == 20 and (set(steps) == {0} if expected == 0 else min(steps) >= 1),
                "%s/kk with %s: %s" % (HISTORY[1].split()[0], label, "the CPU engine, no Kokkos kernel"
                                       if expected == 0 else "the kernels, a synchronisation every step"))


def check_extremes(wd, data):
    # coincident centres: stopped with the atom IDs
    rc, out = t.run_lmp("units lj\natom_style sphere\nboundary p p p\ncomm_modify vel yes\n"
                        "region b block 0 4 0 4 0 4\ncreate_box 1 b\ncreate_atoms 1 single 1 1 1\n"
                        "create_atoms 1 single 2 2 2\ncreate_atoms 1 single 1 1 1\n"
                        "pair_style %s\npair_coeff * *\nrun 0\n" % LAWS[0][1], wd, name="in.same", extra=kk_args(1))
    errors = t.errors(out)
    t.check(rc != 0 and any("atoms 1 and 3 are at the same position" in l for l in errors),
            "griddem/hooke/kk names coincident atoms: %s" % errors[:1])

    # an atom faster than one exact-mode cell per step: stopped naming it, as the CPU style
    rc, out = t.run_lmp(t.PERIODIC_SPHERES.format(data=data, pair=LAWS[0][1], coeffs="pair_coeff * *") +
                        "set atom 42 vx 1e5\ntimestep 1e-5\nfix integrate all nve/sphere\nrun 2\n", wd,
                        name="in.fast", extra=kk_args(1))
    errors = t.errors(out)
    t.check(rc != 0 and any("atom 42 moves" in l for l in errors), "griddem/hooke/kk names a too fast atom: %s" % errors[:1])

    # a non-finite velocity (inf, and nan = inf - inf), found by the kk scan: stopped naming the
    # atom, in the CPU style's words
    for kind, value in (("inf", "1e308*1e308"), ("nan", "(1e308*1e308-1e308*1e308)")):
        bad_in = t.PERIODIC_SPHERES.format(data=data, pair=LAWS[0][1], coeffs="pair_coeff * *") + (
            'variable bad atom "(id==42)*%s"\nset atom 42 vx v_bad\nfix integrate all nve/sphere\nrun 2\n' % value)
        said = errors_of_cpu_and_kk(wd, "bad", bad_in)
        t.check(said["kk"] == said["cpu"] and said["kk"][0] and "atom 42 has a non-finite velocity" in said["kk"][1][0],
                "%s velocity: kk stops naming the atom as the CPU style: %s vs %s" % (kind, said["kk"], said["cpu"]))


SLIDING = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block -5 5 -5 5 -5 5
create_box 1 box
create_atoms 1 single 0 0 0
create_atoms 1 single 0.93 0 0
set atom 1 diameter 1.0 density 1.0 omega 3.0 -1.0 2.0
set atom 2 diameter 0.94 density 1.3 omega -0.5 0.25 1.5
pair_style {pair}
pair_coeff * * {coeffs}
group one id 1
group two id 2
fix still one move linear 0 0 0
fix orbit two move rotate 0 0 0 0.3 0.4 1 1.0
timestep 1e-3
dump forces all custom 1 dump.{name} id fx fy fz
dump_modify forces format float %.17g sort id
run 3000
"""


def check_oddness(wd, _data):
    """Each atom of a kk contact evaluates it from its own side with its own copy of the contact's
    history, so f_12 = -f_21 must hold to the bit, also where the compiler fuses multiply-adds (a
    build with -mfma -ffp-contract=fast, or a GPU). Sphere 2 orbits sphere 1 (fix move) at a fixed
    overlap for 3000 steps while both spin about tilted axes: a long sliding contact whose shear
    history enters the force every step, so a history copy that drifted from the other would show
    in the forces. Laws: gran/hooke/history's, and a granular one with rolling resistance."""
    granular = next(c1 for _label, c1, _c2 in MODELS if "rolling" in c1)
    for label, pair, coeffs in (("hooke/history", HISTORY[1], ""), ("granular", "griddem/granular", granular)):
        name = "odd_" + label.replace("/", "_")
        rc, out = t.run_lmp(SLIDING.format(pair=pair, coeffs=coeffs, name=name), wd, name="in." + name,
                            extra=kk_args(THREADS[-1]), threads=THREADS[-1])
        t.check(rc == 0, "%s: the sliding contact runs under kk: %s" % (label, t.errors(out)[:1]))
        if rc != 0:
            continue
        snaps = [atoms for _columns, atoms in t.read_dumps(os.path.join(wd, "dump." + name))]
        odd = sum(1 for atoms in snaps for c in range(3) if atoms[1][c] == -atoms[2][c])
        touching = sum(1 for atoms in snaps if atoms[1][0] != 0.0)
        t.check(len(snaps) == 3001 and touching == 3001 and odd == 3 * 3001,
                "%s (%s): f_12 = -f_21 to the bit at %d of %d force components, %d steps in contact"
                % (label, coeffs or pair, odd, 3 * len(snaps), touching))


def check_periodic_images(wd, _data):
    """Thin periodic slabs (test_periodic_images.py: z, yz and triclinic, narrower than twice the
    contact distance, contacts keyed by partner and periodic image): the kk history styles give
    the CPU style's positions, velocities, forces and torques after 300 steps to 1e-10, on
    THREADS[-1] threads and 1 and 2 ranks (split along z) and from a restart file the kk run wrote;
    and a box under 1/8 of the contact distance is refused in the CPU style's words."""
    import test_periodic_images as slabs
    files = slabs.slab_files(wd)
    for slab, (thin, _twin, _n) in files.items():
        for law in slabs.LAWS:
            label = "%s slab, %s" % (slab, law)
            tag = re.sub(r"\W", "_", label)
            cpu, _ = slabs.run_slab(wd, "cpu_" + tag, thin, law)
            if cpu is None:
                continue
            for ranks in RANKS:
                for restarted in (False, True):
                    what = "kk on %d rank%s%s" % (ranks, "s" if ranks > 1 else "", ", restarted" if restarted else "")
                    kk, _ = slabs.run_slab(wd, "kk_%s_%d_%d" % (tag, ranks, restarted), thin, law, nprocs=ranks,
                                           extra=kk_args(THREADS[-1]), threads=THREADS[-1], restarted=restarted)
                    if kk is None:
                        continue
                    diffs = slabs.vector_diff(kk, cpu)
                    print("%s, %s: relative difference from the CPU style %s" % (
                        label, what, ", ".join("%s %.3g" % d for d in diffs.items())))
                    t.check(max(diffs.values()) < 1e-10, "%s, %s: the CPU style's numbers: %s" % (label, what, diffs))
    refused = os.path.join(wd, "data.too_thin")
    atoms = [(1.0, [0.3, 0.5, 0.5], [0.0] * 3, [0.0] * 3), (1.15, [0.62, 0.5, 0.5], [0.0] * 3, [0.0] * 3)]
    slabs.write_slab(refused, atoms, (slabs.WIDE, slabs.WIDE, 0.12), (0.0, 0.0, 0.0), (1, 1, 1))
    said = errors_of_cpu_and_kk(wd, "too_thin", slabs.SCRIPT.format(
        start="read_data " + refused, pair=slabs.HISTORY, coeffs="pair_coeff * *", run="run 10"))
    t.check(said["kk"] == said["cpu"] and said["kk"][0] and
            "0.12 wide along z, less than 0.14375 (1/8 of the largest contact distance 1.15" in said["kk"][1][0],
            "a box 0.12 thick: kk refuses it as the CPU style: %s vs %s" % (said["kk"], said["cpu"]))


def check_two_d(wd, _data):
    """2d (discs in a periodic plane with fix enforce2d, test_stock_parity.py): the kk styles give
    stock's and the CPU style's forces, torques, 20-step trajectories and virial, on 1 and 2 ranks."""
    flat = os.path.join(wd, "data.flat")
    t.write_random_spheres(flat, 700, (8.0, 8.0, 1.0), 0.1, 0.3, seed=17, vscale=1.0, wscale=5.0, ntypes=2, flat=True)
    # every run reneighbors as stock's must (FROZEN_LIST, check_laws), so atoms wrap at the same steps
    plane = "fix plane all enforce2d\n" + FROZEN_LIST
    for k, (label, griddem, stock, coeffs) in enumerate((LAWS[0], HISTORY, LAWS[-1])):
        ref = run(wd, "stock_2d_%d" % k, flat, stock, coeffs, extra=plane, dimension=2)
        cpu = run(wd, "cpu_2d_%d" % k, flat, griddem, coeffs, extra=plane, dimension=2)
        for nprocs in RANKS:
            kk = run(wd, "kk_2d_%d_%d" % (k, nprocs), flat, griddem, coeffs, nprocs, THREADS[-1], extra=plane,
                     dimension=2)
            what = "2d %s/kk [%s], %d rank(s)" % (griddem.split()[0], label, nprocs)
            compare(what + " vs stock " + stock.split()[0], ref, kk)
            compare(what + " vs CPU " + griddem.split()[0], cpu, kk)


def stock_and_kk(wd, scene, text_of):
    """text_of(pair style with its arguments, run name) run with stock gran/hooke/history on one
    rank (stock_SCENE) and griddem/hooke/history/kk on each of RANKS (kk_SCENE_N): {name: (dumps,
    screen output)}."""
    runs = {}
    for name, pair, nprocs, extra in [("stock_" + scene, "gran/hooke/history", 1, ())] + [
            ("kk_%s_%d" % (scene, n), "griddem/hooke/history", n, kk_args(THREADS[-1])) for n in RANKS]:
        rc, out = t.run_lmp(text_of(pair + " 1e4 NULL 50 NULL 0.5 1", name), wd, nprocs=nprocs, name="in." + name,
                            extra=extra, threads=THREADS[-1] if extra else None)
        t.check(rc == 0, "%s runs (exit %d): %s" % (name, rc, t.errors(out)[:1]))
        runs[name] = (t.read_dumps(os.path.join(wd, "dump." + name)), out)
    return runs


def check_growing(wd, data):
    """Radii that grow during the run (test_stock_parity.growing_text): the kk styles follow the
    largest radius every step, and give stock's numbers, on 1 and 2 ranks."""
    runs = stock_and_kk(wd, "grow", lambda pair, name: growing_text(data, pair, name))
    for n in RANKS:
        compare("griddem/hooke/history/kk, radii growing, %d rank(s) vs stock" % n, runs["stock_grow"],
                runs["kk_grow_%d" % n])


def check_clumps(wd, _data):
    """Rigid clumps (test_stock_parity.CLUMPS: fix rigid/small, neigh_modify exclude
    molecule/intra): the kk history style gives stock's forces, torques, 20-step trajectory and
    virial on 1 and 2 ranks (a contact takes the bodies' masses, and no sphere touches another of
    its clump)."""
    path = os.path.join(wd, "clump.mol")
    with open(path, "w") as f:
        f.write(CLUMP)
    runs = stock_and_kk(wd, "clumps", lambda pair, name: CLUMPS.format(clump=path, pair=pair, name=name))
    # the same clumps on 2 ranks get other IDs (create_atoms random): stock on 2 ranks for those
    for n in RANKS:
        ref = runs["stock_clumps"]
        if n > 1:
            rc, out = t.run_lmp(CLUMPS.format(clump=path, pair="gran/hooke/history 1e4 NULL 50 NULL 0.5 1",
                                              name="stock_clumps_%d" % n), wd, nprocs=n, name="in.stock_clumps_%d" % n)
            t.check(rc == 0, "stock_clumps_%d runs" % n)
            ref = (t.read_dumps(os.path.join(wd, "dump.stock_clumps_%d" % n)), out)
        parity_compare("griddem/hooke/history/kk, rigid clumps, %d rank(s) vs stock" % n, ref,
                       runs["kk_clumps_%d" % n], thermo=("c_virial[1]", "c_virial[4]", "c_virial[6]"))


def check_grid_cost(wd, _data):
    """fix griddem cell multi at 1:100 (test_grid_cost.py's scene): the kk style warns with the CPU
    style's numbers, which it measures on the same layouts."""
    from test_grid_cost import SCENE, BIG, WARNING
    text = SCENE.format(big=BIG, fix="fix grid all griddem cell multi")
    found = {}
    for name, extra in (("cpu", ()), ("kk", kk_args(1))):
        rc, out = t.run_lmp(text, wd, name="in.cost_" + name, extra=extra)
        found[name] = (rc, re.findall(WARNING.replace("griddem/hooke/history", "griddem/hooke/history(?:/kk)?"), out))
    t.check(found["kk"] == found["cpu"] and found["kk"][0] == 0 and len(found["kk"][1]) == 1,
            "cell multi at 1:100: kk warns once with the CPU style's numbers: %s vs %s" % (found["kk"], found["cpu"]))


def check_reach(wd, data):
    # one grid of a given edge: a contact distance (1 here) over more than 32 edges is refused in
    # the CPU style's words (edge 1/32 = 0.03125: 33 cells, with the search's margin), and a
    # hair above that edge runs, on both
    reach_in = ("units lj\natom_style sphere\nboundary f f f\ncomm_modify vel yes\n"
                "region box block 0 2.2 0 1.2 0 1.2\ncreate_box 1 box\ncreate_atoms 1 single 0.55 0.6 0.6\n"
                "create_atoms 1 single 1.7 0.6 0.6\nset type 1 diameter 1.0\nset atom 2 diameter 0.01\n"
                "pair_style %s\n%s\nfix grid all griddem cell {edge}\nfix integrate all nve/sphere\nrun 5\n"
                % (HISTORY[1], HISTORY[3]))
    for edge, refused in (("0.03125", True), ("0.0313", False)):
        said = errors_of_cpu_and_kk(wd, "reach", reach_in.format(edge=edge))
        t.check(said["kk"] == said["cpu"] and said["kk"][0] == refused and
                (not refused or "spans more than 32 cells of edge 0.03125" in said["kk"][1][0]),
                "cell %s: kk %s as the CPU style: %s vs %s" % (edge, "refuses" if refused else "runs",
                                                               said["kk"], said["cpu"]))


def check_classes(wd, data):
    # size classes: radii 1:16 (three classes of a factor 4), each on its own grid, pairs across
    # classes searched from both sides; and the same on one grid (fix griddem cell multi), and on
    # one grid of a given edge smaller than the largest spheres' contact distance (0.8)
    poly = os.path.join(wd, "data.poly")
    t.write_random_spheres(poly, 1500, (4.5, 4.5, 4.5), 0.025, 0.4, seed=5, density=100.0, vscale=1.0, wscale=5.0, ntypes=2)
    for law in (HISTORY, LAWS[-1]):
        ref = run(wd, "poly_stock", poly, law[2], law[3], extra=FROZEN_LIST)
        cpu = run(wd, "poly_cpu", poly, law[1], law[3])
        for cell in ("classes", "multi", "0.3"):
            kk = run(wd, "poly_kk", poly, law[1], law[3], RANKS[-1], THREADS[-1], extra="fix grid all griddem cell " + cell)
            what = "%s/kk [%s] radii 1:16, cell %s" % (law[1].split()[0], law[0], cell)
            compare(what + " vs stock", ref, kk)
            compare(what + " vs CPU", cpu, kk)
    # the classes are real: the smaller spheres' own finer grid spreads them over more cells
    occupancy = {}
    for cell in ("classes", "multi"):
        rc, out = t.run_lmp(t.PERIODIC_SPHERES.format(data=poly, pair=HISTORY[1], coeffs=HISTORY[3]) +
                            "fix grid all griddem cell %s\nthermo_style custom step f_grid[1]\nrun 0\n" % cell,
                            wd, name="in.occ", extra=kk_args(1))
        occupancy[cell] = t.thermo_values(out, "f_grid[1]")
    print("occupied cells, radii 1:16: classes %s, multi %s" % (occupancy["classes"], occupancy["multi"]))
    t.check(occupancy["classes"] and occupancy["multi"] and occupancy["classes"][0] > 1.5 * occupancy["multi"][0],
            "size classes on kk: %s occupied cells, against %s on one grid" % (occupancy["classes"], occupancy["multi"]))


def check_diagnostics(wd, data):
    # fix griddem's diagnostics from the kk sweep, as the CPU engine reports them: cell edge,
    # contacts, most contacts of one atom, elastic energy (the same grid: cell multi, exact, or a
    # given edge, which the kk styles take as asked)
    for cell, edge in (("multi", None), ("exact", None), ("0.17", 0.17)):
        stats = {}
        stats_in = (t.PERIODIC_SPHERES.format(data=data, pair=LAWS[-1][1], coeffs=LAWS[-1][3]) +
                    "fix grid all griddem cell %s\nthermo_style custom step f_grid[4] f_grid[5] f_grid[6] f_grid[7]\n"
                    "thermo_modify format float %%.17g\nrun 0\n" % cell)
        for name, out in run_cpu_and_kk(wd, "stats", lambda name: stats_in):
            stats[name.split("_")[1]] = [t.thermo_values(out, "f_grid[%d]" % k) for k in (4, 5, 6, 7)]
        print("fix griddem diagnostics (edge, contacts, most, energy), cell %s: CPU %s, kk %s" % (cell, stats["cpu"], stats["kk"]))
        t.check(all(a and b and abs(a[0] - b[0]) <= 1e-12 * abs(a[0]) for a, b in zip(stats["cpu"], stats["kk"])) and
                stats["cpu"][1][0] > 0 and (edge is None or abs(stats["kk"][0][0] - edge) <= 1e-12 * edge),
                "kk diagnostics, cell %s, equal the CPU engine's: %s vs %s" % (cell, stats["kk"], stats["cpu"]))


def check_dilute(wd, data):
    # a dilute scene coarsens the grid asked for, with the CPU style's warning and edge
    dilute_in = ("units lj\natom_style sphere\nboundary f f f\ncomm_modify vel yes\natom_modify sort 0 0\n"
                 "region box block 0 1000 0 1000 0 1000\ncreate_box 1 box\ncreate_atoms 1 single 1 1 1\n"
                 "create_atoms 1 single 1.9 1 1\ncreate_atoms 1 single 900 900 900\n"
                 "set type 1 diameter 1.0\nset type 1 density 1.0\npair_style %s\n%s\n"
                 "fix grid all griddem cell 0.01\nthermo_style custom step f_grid[4]\n"
                 "thermo_modify format float %%.17g\nrun 0\n" % (HISTORY[1], HISTORY[3]))
    coarse = {}
    for name, out in run_cpu_and_kk(wd, "dilute", lambda name: dilute_in):
        warned = [as_cpu_says(l) for l in out.splitlines() if "enlarged" in l]
        coarse[name.split("_")[1]] = (warned, t.thermo_values(out, "f_grid[4]"))
    print("dilute, cell 0.01: CPU %s, kk %s" % (coarse["cpu"], coarse["kk"]))
    t.check(coarse["kk"] == coarse["cpu"] and len(coarse["kk"][0]) == 1 and "from 0.01 to" in coarse["kk"][0][0]
            and coarse["kk"][1] and coarse["kk"][1][0] > 1.0,
            "kk coarsens a dilute grid as the CPU style, with its warning: %s vs %s" % (coarse["kk"], coarse["cpu"]))


def check_occupancy(wd, data):
    # the occupancy (fix griddem values 1 and 2), which the kk styles count only when asked: 64
    # spheres of diameter 1 in a closed box, each centred in its own cell of the `multi` grid
    # (edge 1 + 1e-9 from boxlo) and two cells apart, and a 65th in the first one's cell
    lattice = [((2 * a + 0.5), (2 * b + 0.5), (2 * c + 0.5)) for a in range(4) for b in range(4) for c in range(4)]
    lattice.append((0.8, 0.5, 0.5))
    occupancy_in = ("units lj\natom_style sphere\nboundary f f f\ncomm_modify vel yes\n"
                    "region box block 0 8 0 8 0 8\ncreate_box 1 box\n" +
                    "".join("create_atoms 1 single %g %g %g\n" % p for p in lattice) +
                    "set type 1 diameter 1.0\nset type 1 density 1.0\npair_style %s\n%s\n"
                    "fix grid all griddem cell multi\nthermo_style custom step f_grid[1] f_grid[2]\nrun 0\n"
                    % (HISTORY[1], HISTORY[3]))
    for name, out in run_cpu_and_kk(wd, "occupancy", lambda name: occupancy_in):
        found = (t.thermo_values(out, "f_grid[1]"), t.thermo_values(out, "f_grid[2]"))
        t.check(found == ([64.0], [2.0]), "%s: 64 occupied cells, at most 2 centres in one: %s" % (name, found))

    # once a stock pair style replaced the kk one, the last griddem step's values are refused
    # naming the pair style (the CPU fix's rule: they would read as current), whether or not
    # the run counted them
    switch = ("pair_style gran/hooke/history 1e4 NULL 50 NULL 0.5 1\npair_coeff * *\n"
              "print \"OCC $(f_grid[1])\"\n")
    unread = occupancy_in.replace("thermo_style custom step f_grid[1] f_grid[2]\n", "")
    for name, text in (("unread", unread + switch), ("read", occupancy_in + switch)):
        rc, out = t.run_lmp(text, wd, name="in.occ_" + name, extra=kk_args(1))
        t.check(rc != 0 and "pair style gran/hooke/history/kk is not a griddem pair style" in out
                and not re.search(r"^OCC ", out, re.M),
                "occupancy (%s during the run) refused after the pair style changed: %s" % (name, t.errors(out)[:1]))


def check_empty_rank(wd, data):
    # a process without atoms: two overlapping spheres in one half of a closed box on 2 ranks
    # (all kernels run over no atoms there) give the one-rank CPU style's kinetic energy
    if RANKS[-1] == 1:
        return
    lone_in = ("units lj\natom_style sphere\nboundary f f f\ncomm_modify vel yes\n"
               "region box block 0 16 0 8 0 8\ncreate_box 1 box\n"
               "create_atoms 1 single 0.5 0.5 0.5\ncreate_atoms 1 single 1.4 0.5 0.5\n"
               "set type 1 diameter 1.0\nset type 1 density 1.0\npair_style %s\n%s\n"
               "fix 1 all nve/sphere\ntimestep 0.001\nthermo_style custom step ke\n"
               "thermo_modify format float %%.17g\nthermo 10\nrun 20\n" % (HISTORY[1], HISTORY[3]))
    ke = {name.split("_")[1]: t.thermo_values(out, "KinEng")
          for name, out in run_cpu_and_kk(wd, "lone", lambda name: lone_in, kk_ranks=2)}
    t.check(len(ke["kk"]) == 3 and ke["kk"][-1] > 0 and
            max(abs(a - b) for a, b in zip(ke["kk"], ke["cpu"])) <= 1e-10 * ke["cpu"][-1],
            "kk on 2 ranks, one without atoms, as the CPU style: KE %s vs %s" % (ke["kk"], ke["cpu"]))


def check_growth(wd, data):
    # fix griddem contacts 1: the CPU fix's rows grow from one contact; the kk rows are laid
    # out from each atom's contacts whatever N is. The numbers are unchanged either way
    few = "fix rows all griddem contacts 1"
    for law in (HISTORY, LAWS[-1]):
        compare("%s/kk [%s] with contacts 1 vs CPU" % (law[1].split()[0], law[0]),
                run(wd, "few_cpu", data, law[1], law[3], extra=few),
                run(wd, "few_kk", data, law[1], law[3], nprocs=RANKS[-1], threads=THREADS[-1], extra=few))




def peak_rss_mib(wd, text, name, extra):
    """Peak resident memory (MiB) of one lmp run of text, its exit code and its output."""
    with open(os.path.join(wd, "in." + name), "w") as f:
        f.write(text)
    with open(os.path.join(wd, "out." + name), "w+") as out:
        proc = subprocess.Popen([t.LMP, "-in", "in." + name, "-log", "none"] + extra, cwd=wd,
                                stdout=out, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
        out.seek(0)
        return usage.ru_maxrss / 1024.0, os.waitstatus_to_exitcode(status), out.read()


# LAMMPS 4Feb2025's fix neigh/history/kk reads d_partner(i, m) for m up to an atom's partner
# count, which can pass the view's 8 columns before they grow: with Kokkos's bounds check on,
# stock gran/hooke/history/kk stops with this label on the squeeze below
STOCK_PARTNER_BOUNDS = 'out of bounds access label=("neighbor_history:partner")'


def check_exchange_buffer(wd, _data):
    """bench/gpu.py's poly scene at 4,096 atoms (diameters 1:10 on a lattice, squeezed fast to
    half the edge): the longest history row grows one contact at a time to about 18, and
    LAMMPS's CommKokkos grows its send buffer by 1.5 each time a fix's maxexchange grows; fix
    griddem/kk sizes it by powers of two, so the run stays within twice stock kk's memory
    (griddem needs half of stock's per atom). With a maxexchange that followed each contact:
    472 MiB against stock's 78. On a build with Kokkos's bounds check stock stops in its own
    fix (STOCK_PARTNER_BOUNDS): griddem's run is then checked alone."""
    rss, stock_ran = {}, True
    for pair in ("gran/hooke/history", "griddem/hooke/history"):
        text = POLY.format(n=16, nz=16, style=pair, fix="", prep=300, steps=0)
        rss[pair], rc, out = peak_rss_mib(wd, text, "squeeze", kk_args(1))
        if rc != 0 and pair == "gran/hooke/history" and STOCK_PARTNER_BOUNDS in out:
            # stock's own fault, seen only where Kokkos checks bounds: no stock reference then
            print("SKIPPED: the memory comparison: stock gran/hooke/history/kk stops in its fix "
                  "neigh/history/kk (%s)" % t.errors(out)[:1])
            rc = 0
            stock_ran = False
        t.check(rc == 0, "%s/kk squeeze runs (exit %d): %s" % (pair, rc, t.errors(out)[:1]))
    if not stock_ran:
        return
    print("squeeze, peak RSS: stock kk %.0f MiB, griddem kk %.0f MiB" % (rss["gran/hooke/history"],
                                                                        rss["griddem/hooke/history"]))
    t.check(rss["griddem/hooke/history"] < 2.0 * rss["gran/hooke/history"],
            "griddem/hooke/history/kk's peak memory %.0f MiB within twice stock kk's %.0f MiB"
            % (rss["griddem/hooke/history"], rss["gran/hooke/history"]))


def check_precision(wd, data):
    # fix griddem precision single: channels in float, positions relative to their cell. Their
    # rounding (2^-24 of a cell edge, ~4e-8 here) moves forces by a few 1e-6 of the largest (the
    # smallest overlaps are ~1e-3 of the radii); more than round-off, well below 1e-4
    for law in (LAWS[0], HISTORY, LAWS[-1]):
        double = run(wd, "prec_d", data, law[1], law[3], 1, 1, extra="fix grid all griddem precision double")
        single = run(wd, "prec_s", data, law[1], law[3], RANKS[-1], THREADS[-1], extra="fix grid all griddem precision single")
        forces = max(t.max_rel_diff(single[0][k], double[0][k], FORCES) for k in (0, 1))
        state = t.max_rel_diff(single[0][1], double[0][1], STATE)
        print("%s/kk [%s] precision single vs double: force/torque %.2g, x/v at step 20 %.2g"
              % (law[1].split()[0], law[0], forces, state))
        t.check(1e-9 < forces < 1e-4 and state < 1e-5, "%s/kk [%s] single precision error %.3g (forces), %.3g (x/v)"
                % (law[1].split()[0], law[0], forces, state))


def check_migration(wd, data):
    # rows that migrate: atoms crossing between ranks and re-sorted in memory every 3 steps, with
    # LAMMPS reneighbouring (exchange) every step, as the CPU style on one rank; the exchange on the
    # device and on the host (package kokkos comm/exchange host, where MPI reads host memory: on a
    # GPU the rows' messages must be in the host buffer CommKokkos sends; on the host they are)
    moving = ("neigh_modify every 1 delay 0 check no\natom_modify sort 3 0.5\n"
              "velocity all scale 30.0\ntimestep 1e-4\nfix integrate all nve/sphere\nrun 60\n"
              "dump snap all custom 1 dump.{name} id x y z vx vy vz fx fy fz tqx tqy tqz\n"
              "dump_modify snap format float %.17g sort id\nrun 0\n")
    for law in (HISTORY, LAWS[-1]):
        for where in ("device", "host"):
            label = "mv" if where == "device" else "mvh"
            runs = run_cpu_and_kk(wd, label, lambda name: t.PERIODIC_SPHERES.format(data=data, pair=law[1], coeffs=law[3]) +
                                  moving.format(name=name), kk_ranks=RANKS[-1],
                                  package=("comm/exchange", where))
            got = [t.read_dumps(os.path.join(wd, "dump." + name))[-1] for name, _ in runs]
            err = t.max_rel_diff(got[1], got[0], STATE + FORCES)
            print("%s/kk [%s] after 60 steps of exchange (on the %s) and sorting vs CPU: %.2g"
                  % (law[1].split()[0], law[0], where, err))
            t.check(err <= 1e-10, "%s/kk [%s] rows migrate with their atoms, exchange on the %s (%.3g)"
                    % (law[1].split()[0], law[0], where, err))


def check_search(wd, data):
    """fix griddem search team (a team per block of 8 cells along x, the candidates of the
    block's neighbourhood in its size class copied into scratch memory) lists what search thread
    lists, in the same order, so forces, torques, positions and velocities after 20 steps are the
    same to the last bit; both equal the CPU style to 1e-10. On the dense scene with cell multi
    (3 cells wide stencil) and exact (5 wide), the 1:16 polydisperse scene with classes (the
    other classes' rows read from device memory), and a cell edge of 1.5 (about 55 centres a
    cell: windows beyond the team's 1024 candidates read device memory)."""
    poly = os.path.join(wd, "data.search_poly")
    t.write_random_spheres(poly, 1500, (4.5, 4.5, 4.5), 0.025, 0.4, seed=5, density=100.0,
                           vscale=1.0, wscale=5.0, ntypes=2)
    law = HISTORY
    for scene, cell in ((data, "multi"), (data, "exact"), (poly, "classes"), (data, "1.5")):
        fix = "fix grid all griddem contacts 16 cell " + cell
        cpu = run(wd, "search_cpu", scene, law[1], law[3], extra=fix)
        found = {}
        for mode in ("thread", "team"):
            found[mode] = run(wd, "search_" + mode, scene, law[1], law[3], 1, THREADS[-1],
                              extra=fix + " search " + mode)
            compare("%s/kk search %s, cell %s vs CPU" % (law[1].split()[0], mode, cell), cpu, found[mode])
        (a, _), (b, _) = found["thread"], found["team"]
        same = len(a) == len(b) == 2 and all(
            t.max_rel_diff(b[k], a[k], FORCES + STATE) == 0.0 for k in (0, 1))
        t.check(same, "cell %s: search team gives search thread's numbers to the last bit" % cell)


SYNC_COUNTER = os.environ.get("GRIDDEM_SYNC_COUNTER") or os.path.join(
    os.path.dirname(os.path.abspath(t.LMP)), "unittest", "kokkos_tools", "griddem_sync_counter.so")


def sync_counter_found():
    """Whether the sync counter library is there; a failed check where it is not."""
    found = os.path.exists(SYNC_COUNTER)
    t.check(found, "the Kokkos Tools sync counter is at %s (GRIDDEM_SYNC_COUNTER)" % SYNC_COUNTER)
    return found


def run_counted(wd, name, text, log, run=None):
    """The script with -sf kk on THREADS[-1] threads under the sync counter, which writes each
    compute's synchronisations and allocations to log: (exit code, output). run: t.run_lmp, or
    another with its arguments."""
    os.environ.update(KOKKOS_TOOLS_LIBS=SYNC_COUNTER, GRIDDEM_SYNC_LOG=log)
    try:
        return (run or t.run_lmp)(text, wd, name="in." + name, extra=kk_args(THREADS[-1]), threads=THREADS[-1])
    finally:
        for key in ("KOKKOS_TOOLS_LIBS", "GRIDDEM_SYNC_LOG"):
            del os.environ[key]


def check_synchronisation(wd, data):
    """One blocking synchronisation a step between reneighborings, two at a reneighboring, more
    only where a View grew: the Kokkos Tools library unittest/kokkos_tools/sync_counter.c
    counts, in each compute(), the runs of fences with no kernel launched between them, and the
    allocations. The dense scene, 200 steps of griddem/hooke/history/kk: without reneighboring
    after the setup, every compute that allocates nothing makes one; reneighboring whenever an
    atom moved half the skin, such computes make at most two, and at most as many make two as
    LAMMPS built neighbor lists. The history pools (fix griddem/kk's partner and value arrays, and
    their host mirrors) are never filled when they are allocated, in the setup or in a step: a
    row names the entries it holds, each written before it is read."""
    if not sync_counter_found():
        return
    for label, neigh in (("never", "neigh_modify every 1000 delay 0 check no"),
                         ("often", "neighbor 0.02 bin\nneigh_modify every 1 delay 0 check yes")):
        log = os.path.join(wd, "syncs." + label)
        text = t.PERIODIC_SPHERES.format(data=data, pair=HISTORY[1], coeffs=HISTORY[3]) + (
            "fix grid all griddem\n%s\ntimestep 1e-5\nfix integrate all nve/sphere\n"
            "thermo 50\nrun 200\n" % neigh)
        rc, out = run_counted(wd, "syncs_" + label, text, log)
        t.check(rc == 0 and os.path.exists(log), "%s: runs with the sync counter (exit %d): %s"
                % (label, rc, t.errors(out)[:1]))
        if rc != 0 or not os.path.exists(log):
            continue
        # per compute: synchronisations, allocations, and the first allocation's bytes and label
        steps = [line.rstrip("\n").split(" ", 3) for line in open(log)][1:]    # after the setup
        builds = int(re.search(r"Neighbor list builds = (\d+)", out).group(1))
        steady = [int(f[0]) for f in steps if f[1] == "0"]
        allocating = collections.Counter(" ".join(f[2:]) for f in steps if f[1] != "0")
        print("%s: %d computes after the setup, %d allocating%s; of the others %d with one blocking "
              "synchronisation, %d with two, %d with more; %d neighbor list builds"
              % (label, len(steps), len(steps) - len(steady),
                 " (first allocation, bytes and label: %s)" % dict(allocating.most_common(3)) if allocating else "",
                 steady.count(1), steady.count(2), sum(1 for n in steady if n > 2), builds))
        t.check(len(steps) == 200 and min(int(f[0]) for f in steps) >= 1,
                "%s: every step's compute counted, each reads its results" % label)
        t.check(len(steady) >= 190, "%s: %d of 200 computes allocate nothing (first allocations: %s)"
                % (label, len(steady), dict(allocating.most_common(3))))
        most = 1 if builds == 0 else 2
        t.check(steady and max(steady) <= most and steady.count(2) <= builds,
                "%s: one blocking synchronisation a step, two at the %d reneighborings (%d with "
                "two, most %s)" % (label, builds, steady.count(2), max(steady) if steady else "none counted"))
        fills = [line.split() for line in open(log + ".fills")] if os.path.exists(log + ".fills") else None
        pool_fills = [f for f in fills or [] if re.match(r"griddem/kk:(partner|value)", f[1])]
        t.check(fills is not None and not pool_fills,
                "%s: no history pool filled when allocated (%s)" % (
                    label, "no fill log" if fills is None else "%d fills: %s" % (len(pool_fills), pool_fills[:3])))

def check_replanned(wd, data):
    """A step whose atoms left the grid planned from the last step is planned again from a scan:
    two atoms of the dense scene (the box opened to z = 20, non-periodic) are moved by `set` to
    z = 15 and 15.3, ten units above the others, and the run goes on with `pre no` (no
    reneighboring, so the plan comes from the last step's boxes). The kk styles give the CPU
    style's forces at the step after the move to 1e-10, the moved pair touching (equal and
    opposite forces), and that compute synchronised more than once (it was computed again)."""
    if not sync_counter_found():
        return
    text = (t.PERIODIC_SPHERES.format(data=data, pair=HISTORY[1], coeffs=HISTORY[3]) +
            "change_box all z final 0 20 boundary p p f\nfix grid all griddem\ntimestep 1e-5\n"
            "fix integrate all nve/sphere\ndump d all custom 13 dump.{name} id fx fy fz\n"
            "dump_modify d sort id format float %.17g\nthermo 10\nrun 10\n"
            "set atom 5 x 2.0 y 2.0 z 15.0\nset atom 6 x 2.0 y 2.0 z 15.3\nrun 3 pre no\n")
    forces = {}
    log = os.path.join(wd, "syncs.replanned")
    for name in ("replanned_cpu", "replanned_kk"):
        if name.endswith("kk"):
            rc, out = run_counted(wd, name, text.format(name=name), log)
        else:
            rc, out = t.run_lmp(text.format(name=name), wd, name="in." + name)
        t.check(rc == 0, "%s runs (exit %d): %s" % (name, rc, t.errors(out)[:1]))
        snaps = t.read_dumps(os.path.join(wd, "dump." + name)) if rc == 0 else []
        forces[name.split("_")[1]] = snaps[-1] if len(snaps) == 2 else None
    if not (forces["cpu"] and forces["kk"]):
        return
    worst = t.max_rel_diff(forces["kk"], forces["cpu"], ["fx", "fy", "fz"])
    names, rows = forces["cpu"]
    fz = names.index("fz")
    print("moved pair: fz %.6g and %.6g; kk vs CPU %.2g" % (rows[5][fz], rows[6][fz], worst))
    t.check(worst <= 1e-10, "kk forces after atoms left the planned grid equal the CPU style's (%.2g)" % worst)
    t.check(rows[5][fz] < 0.0 and abs(rows[5][fz] + rows[6][fz]) <= 1e-12 * abs(rows[5][fz]),
            "the moved pair touches: fz %g and %g" % (rows[5][fz], rows[6][fz]))
    syncs = [int(line.split()[0]) for line in open(log)]
    # computes: the setup's and 10 steps, then the step of `run 3 pre no` after the move
    t.check(len(syncs) == 14 and syncs[11] > 1,
            "the compute after the move was computed again: %s synchronisations" % syncs[11:12])


# The suite's sections in the order they run; `test_kokkos.py --only a,b` runs those alone (the
# GPU session runs the ones that exercise device-only paths: list and row layouts, history rows
# that grow, migrate and go through restart)
SECTIONS = {f.__name__[len("check_"):]: f for f in (
    check_laws, check_heat, check_oddness, check_active, check_variants, check_exclusions, check_virial, check_mismatch, check_engine, check_extremes,
    check_reach, check_periodic_images, check_two_d, check_growing, check_clumps, check_grid_cost, check_classes, check_diagnostics, check_dilute, check_occupancy, check_empty_rank,
    check_growth, check_exchange_buffer, check_precision, check_migration, check_stock_fixes, check_rom, check_pair_local,
    check_add_delete, check_restart, check_synchronisation, check_search, check_replanned)}


if __name__ == "__main__":
    main()
