"""Bad input and extreme states stop with an error (or warn) that names the cause. fix griddem's
contacts N is only the initial history size per atom: an atom touching more atoms than N runs and
equals stock, and a restart written with contacts 8 and read with contacts 1 continues bit for
bit like the uninterrupted run. The package's computes and fixes: compute griddem/grid before the
box or in a box made triclinic later, fix griddem cell with a word, fix griddem/kinematic moving
atoms out of a 2d plane or at an infinite speed, fix griddem kernel naming one the processor lacks (run
under valgrind, whose processor has no AVX-512, where this one has it): each an error naming it."""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

BASE = """
units lj
atom_style {atom_style}
dimension {dim}
boundary p p {zb}
{comm}
region box block 0 4 0 4 {zbox}
create_box 1 box
{atoms}
{pre}
pair_style {pair}
pair_coeff {coeff}
{post}
timestep {dt}
fix integrate all {integrate}
run 5
"""
TWO = "create_atoms 1 single 1 1 1\ncreate_atoms 1 single {x2} 1 1\nset type 1 diameter 1.0\n" \
      "set type 1 density 1.0\nvelocity all set {v} 0 0"


def case(name, expect, warning=False, atom_style="sphere", dim=3, comm="comm_modify vel yes",
         pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1", coeff="* *", pre="", post="", dt=1e-4,
         x2=1.9, v=0.0, nan_expected=False):
    zb, zbox = ("p", "0 4") if dim == 3 else ("p", "-0.5 0.5")
    atoms = TWO.format(x2=x2, v=v) if atom_style == "sphere" else "create_atoms 1 single 1 1 1\nmass 1 1.0"
    text = BASE.format(atom_style=atom_style, dim=dim, zb=zb, zbox=zbox, comm=comm, atoms=atoms, pre=pre,
                       pair=pair, coeff=coeff, post=post, dt=dt,
                       integrate="nve/sphere" if atom_style == "sphere" else "nve")
    if dim == 2:
        text = text.replace("create_atoms 1 single 1 1 1", "create_atoms 1 single 1 1 0").replace(
            "create_atoms 1 single %s 1 1" % x2, "create_atoms 1 single %s 1 0" % x2)
    rc, out = t.run_lmp(text, WD, name="in." + name)
    if warning:
        t.check(rc == 0, "%s: run completes (exit %d)" % (name, rc))
        t.check("WARNING" in out and expect in out, "%s: warning '%s' printed" % (name, expect))
    else:
        t.check(rc != 0, "%s: stops with an error (exit %d)" % (name, rc))
        t.check("ERROR" in out and expect in out, "%s: message '%s' in: %s" % (
            name, expect, t.errors(out)[:2]))
    if not nan_expected:
        t.check("nan" not in out.lower().replace("nano", ""), "%s: no NaN printed" % name)


WD = t.workdir()
case("coincident", "atoms 1 and 2 are at the same position", x2=1.0)
case("too_fast", "atom 1 moves", v=-6000.0, x2=3.0)
case("infinite_speed", "atom 2 has a non-finite velocity (inf", nan_expected=True,
     pre='variable bad atom "(id==2)*1e308*1e308"\nset atom 2 vx v_bad')
case("nan_speed", "atom 2 has a non-finite velocity", nan_expected=True,
     pre='variable bad atom "(id==2)*(1e308*1e308-1e308*1e308)"\nset atom 2 vx v_bad')
case("dt_above_limit", "exceeds the stability limit pi/5*sqrt(m/Kn)", warning=True, dt=0.02)
case("atom_style", "requires atom attributes radius, rmass, omega", atom_style="atomic")
case("zero_radius", "requires positive radii: atom 2 has a radius that is not positive (smallest radius 0)",
     pre="set atom 2 diameter 0")
# pair hybrid: a griddem style only as its one style on every type pair
TWO_ATOMS = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block 0 4 0 4 0 4
create_box 2 box
create_atoms 1 single 1 1 1
create_atoms 2 single 2 1 1
"""
rc, out = t.run_lmp(TWO_ATOMS + """pair_style hybrid griddem/hooke/history 1e3 NULL 10 NULL 0.5 1 lj/cut 1.0
pair_coeff 1 1 griddem/hooke/history
pair_coeff * 2 lj/cut 1.0 1.0
run 0
""", WD, name="in.hybrid")
t.check(rc != 0 and "as a sub-style of pair hybrid a griddem style must be set on every type pair, and once" in out,
        "hybrid: griddem beside another sub-style refused: %s" % t.errors(out)[:1])
# two instances of one griddem style, each on some type pairs: both would find every contact
rc, out = t.run_lmp(TWO_ATOMS + """pair_style hybrid griddem/hooke/history 1e3 NULL 10 NULL 0.5 1 griddem/hooke/history 2e3 NULL 10 NULL 0.5 1
pair_coeff * * griddem/hooke/history 1
pair_coeff 2 2 griddem/hooke/history 2
run 0
""", WD, name="in.hybrid_twice")
t.check(rc != 0 and "must be set on every type pair, and once" in out, "hybrid_twice: two griddem sub-styles refused: %s" % t.errors(out)[:1])

# radius ratio 1:100 in NN4DEM cells: the contact distance spans more cells than the stencil holds
rc, out = t.run_lmp("""
units lj
atom_style sphere
boundary f f f
comm_modify vel yes
region box block 0 2.2 0 1.2 0 1.2
create_box 1 box
create_atoms 1 single 0.55 0.6 0.6
create_atoms 1 single 1.7 0.6 0.6
set type 1 diameter 1.0
set atom 2 diameter 0.01
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
fix grid all griddem cell exact
fix integrate all nve/sphere
run 5
""", WD, name="in.stencil_reach")
t.check(rc != 0 and "spans more than 32 cells" in out and "radius ratio 100" in out and "use fix griddem cell auto" in out,
        "stencil_reach: error names the ratio and the remedy")
# radii that outgrow the ghost cutoff (fix adapt doubles them in 400 steps; ghosts are kept
# within 2 r + skin of the start): stopped with the cause and the remedy, where stock's lists
# would lose contacts with ghost atoms without a word
OUTGROWN = """
units lj
atom_style sphere 1
boundary {boundary}
comm_modify vel yes
lattice sc 0.5
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 box
set type 1 diameter 1.0
set type 1 density 1.0
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
neighbor 0.2 bin
variable grow equal 1+step/400
fix grow all adapt 1 atom diameter v_grow scale yes reset no
fix integrate all nve/sphere
run 400
"""
rc, out = t.run_lmp(OUTGROWN.format(boundary="p p p"), WD, name="in.outgrown")
t.check(rc != 0 and "exceeds the ghost cutoff 1.2: contacts with atoms of other processes" in out
        and "set comm_modify cutoff to at least" in out and "WARNING" in out and "less the neighbor skin 0.2" in out,
        "outgrown: radii growing past the ghost cutoff warned of, then stopped: %s" % t.errors(out)[:2])
# one process and no periodic boundary: no ghosts, nothing to lose, no word
rc, out = t.run_lmp(OUTGROWN.format(boundary="m m m"), WD, name="in.outgrown_alone")
t.check(rc == 0 and "ghost cutoff" not in out, "outgrown_alone: runs without ghosts: %s" % t.errors(out)[:2])

# a pull-off distance of one type pair (jkr, small spheres) is not added to another's contact
# distance (large spheres, hertz): no warning where every type pair's contact is within the cutoff
rc, out = t.run_lmp("""
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block -3 3 -3 3 -3 3
create_box 2 box
create_atoms 1 single 0 0 0
create_atoms 2 single 0.3 0.1 1.05
create_atoms 2 single -1.5 -1.5 -1.5
set type 1 diameter 1.0
set type 2 diameter 0.8
set group all density 1.0
pair_style griddem/granular
pair_coeff 1 * hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji
pair_coeff 2 2 jkr 1e5 0.1 0.3 50 tangential mindlin NULL 1.0 0.5
neighbor 0.2 bin
fix 1 all nve/sphere
timestep 0.0005
run 200
""", WD, name="in.pulloff_of_one_pair")
t.check(rc == 0 and "ghost cutoff" not in out,
        "pulloff_of_one_pair: no ghost-cutoff warning where each type pair's contact is within reach: %s"
        % [l for l in out.splitlines() if "WARNING" in l][:1])

# two rigid-body fixes: a contact takes one fix's body masses, as stock's styles (which refuse
# two as well)
from test_stock_parity import CLUMP, CLUMPS
clump_file = os.path.join(WD, "clump.mol")
with open(clump_file, "w") as f:
    f.write(CLUMP)
rc, out = t.run_lmp(CLUMPS.format(clump=clump_file, pair="griddem/hooke/history 1e4 NULL 50 NULL 0.5 1", name="two_rigid")
                    .replace("fix bodies all rigid/small molecule\n",
                             "group front id <= 120\ngroup back id > 120\nfix front front rigid/small molecule\n"
                             "fix back back rigid/small molecule\n"), WD, name="in.two_rigid")
t.check(rc != 0 and "only one fix rigid at a time (fix front and fix back)" in out,
        "two_rigid: two rigid-body fixes refused by name: %s" % t.errors(out)[:2])

# 2d runs with the pair styles (test_stock_parity.py); the reduced-order model's voxels are 3d
flat_model = os.path.join(WD, "flat.model")
t.write_rom_model(flat_model, (2, 2, 1), (0.0, 4.0, 0.0, 4.0, -0.5, 0.5))
case("rom_two_d", "Fix griddem/rom requires a 3d simulation", dim=2,
     post="fix rom all griddem/rom model %s eps 0.1 v0 1 every 1" % flat_model)
case("no_ghost_velocity", "comm_modify vel yes", comm="")
case("arg_count", "expects Kn Kt gamma_n gamma_t xmu dampflag", pair="griddem/hooke/history 1e3 NULL 10")
case("negative_kn", "Kn must be >= 0", pair="griddem/hooke -5 NULL 10 NULL 0.5 1")
case("dampflag", "dampflag must be 0 or 1", pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 2")
case("keyword", "unknown keyword nolimit", pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1 nolimit")
case("xmu", "xmu must be in [0,10000]", pair="griddem/hooke/history 1e3 NULL 10 NULL -1 1")
case("coeff_args", "takes only the two atom types", coeff="* * 1.0")
case("fix_keyword", "Unknown fix griddem keyword: slots", pre="fix grid all griddem slots 3")
case("fix_cell", "classes or a positive edge, not -1", pre="fix grid all griddem cell -1")
case("fix_precision", "precision must be single or double, not half", pre="fix grid all griddem precision half")
case("precision_cpu", "precision single is implemented by the Kokkos styles only",
     pre="fix grid all griddem precision single")
case("fix_search", "search must be auto, thread or team, not warp", pre="fix grid all griddem search warp")
case("search_cpu", "search team chooses among the Kokkos styles' searches",
     pre="fix grid all griddem search team")
case("fix_kernel", "kernel must be auto, scalar, avx2 or avx512, not sse9", pre="fix grid all griddem kernel sse9")


def kernel_lacking():
    """A kernel the processor lacks stops the run naming the widest it runs: kernel avx512, run
    as it is where the processor has no AVX-512, else under valgrind, whose processor has none"""
    text = BASE.format(atom_style="sphere", dim=3, zb="p", zbox="0 4", comm="comm_modify vel yes",
                       atoms=TWO.format(x2=1.9, v=0.0), pre="fix grid all griddem kernel avx512",
                       pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1", coeff="* *", post="", dt=1e-4,
                       integrate="nve/sphere")
    rc, out = t.run_lmp(text, WD, name="in.kernel_lacking")
    if rc == 0:
        valgrind = shutil.which("valgrind")
        if not valgrind:
            print("kernel_lacking: not checked (this processor runs AVX-512 and there is no valgrind)")
            return
        proc = subprocess.run([valgrind, "-q", "--tool=none", t.LMP, "-in", "in.kernel_lacking", "-log", "none"],
                              cwd=WD, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                              timeout=600)
        rc, out = proc.returncode, proc.stdout
    t.check(rc != 0 and any("fix grid kernel avx512: this processor or build does not run it (the widest it runs: "
                            in l for l in t.errors(out)), "kernel_lacking: refused naming the widest: %s" % t.errors(out)[:1])


kernel_lacking()
case("kt_zero", "Kt = 0 with tangential damping divides by Kt",
     pair="griddem/hooke/history 1e3 0 10 NULL 0.5 1")
case("fix_no_slots", "needs contact history: fix grid has contacts 0", pre="fix grid all griddem contacts 0")
# a script's fix of the ID the styles give their own is the script's: kept as written, not remade
case("script_fix_GRIDDEM", "needs contact history: fix GRIDDEM has contacts 0", pre="fix GRIDDEM all griddem contacts 0")


# contacts 1 is an initial size: atom 1 touches atoms 2 and 3 (the history grows) and the run
# equals stock gran/hooke/history's
THREE = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block 0 4 0 4 0 4
create_box 1 box
create_atoms 1 single 1 1 1
create_atoms 1 single 1.9 1 1
create_atoms 1 single 1 1.9 1
set type 1 diameter 1.0
set type 1 density 1.0
velocity all set 0.3 -0.2 0.1
set atom 1 omega 2 -1 3
pair_style {pair} 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
{fix}
timestep 1e-4
fix integrate all nve/sphere
thermo_style custom step {most}
thermo 10
dump snap all custom 50 dump.{name} id x y z vx vy vz omegax omegay omegaz fx fy fz
dump_modify snap format float %.17g sort id
run 50
"""
STATE = ["x", "y", "z", "vx", "vy", "vz", "omegax", "omegay", "omegaz", "fx", "fy", "fz"]
rc, out = t.run_lmp(THREE.format(pair="griddem/hooke/history", fix="fix grid all griddem contacts 1",
                                 most="f_grid[6]", name="one"), WD, name="in.contacts_one")
t.check(rc == 0, "contacts 1 with an atom touching 2: the run completes (exit %d): %s" % (
    rc, t.errors(out)[:1]))
most = t.thermo_values(out, "f_grid[6]")
t.check(most and max(most) == 2, "contacts 1: atom 1 has 2 contacts (%s)" % most)
t.run_ok(THREE.format(pair="gran/hooke/history", fix="", most="ke", name="stock"), WD, name="in.contacts_stock")
if rc == 0:
    err = t.max_rel_diff(t.read_dump(os.path.join(WD, "dump.one")), t.read_dump(os.path.join(WD, "dump.stock")), STATE)
    t.check(err <= 1e-10, "contacts 1 with 2 contacts: differs from stock by %.3g relative" % err)

# a restart whose atoms have more contacts than the contacts value of the fix griddem that reads
# it continues exactly like the uninterrupted run: 27 spheres in a slightly compressed cubic
# cluster, up to 6 contacts each
restart_setup = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
region box block 0 6 0 6 0 6
create_box 1 box
lattice sc $(1.0/0.95^3) origin 0.5 0.5 0.5
region cluster block 1 4 1 4 1 4
create_atoms 1 region cluster
set type 1 diameter 1.0
set type 1 density 1.0
velocity all create 0.5 4928 loop geom
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
fix grid all griddem contacts 8
timestep 1e-4
fix integrate all nve/sphere
thermo_style custom step f_grid[6]
thermo 20
run 20
write_restart restart.contacts
dump snap all custom 20 dump.whole id x y z vx vy vz omegax omegay omegaz fx fy fz
dump_modify snap format float %.17g sort id
run 20
"""
out = t.run_ok(restart_setup, WD, name="in.write_contacts")
most = t.thermo_values(out, "f_grid[6]")
t.check(most and min(most) >= 4, "restart cluster: atoms with several contacts (%s)" % most)
rc, out = t.run_lmp("""
read_restart restart.contacts
comm_modify vel yes
fix grid all griddem contacts 1
timestep 1e-4
fix integrate all nve/sphere
dump snap all custom 20 dump.again id x y z vx vy vz omegax omegay omegaz fx fy fz
dump_modify snap format float %.17g sort id
run 20
""", WD, name="in.read_contacts")
t.check(rc == 0, "restart with more contacts than contacts 1: read and continued (exit %d): %s" % (
    rc, t.errors(out)[:1]))
if rc == 0:
    a, b = t.read_dumps(os.path.join(WD, "dump.whole")), t.read_dumps(os.path.join(WD, "dump.again"))
    t.check(len(a) == len(b) == 2, "restart read with contacts 1: two snapshots each")
    t.check(a[0][1] == b[0][1], "restart read with contacts 1: forces on reading identical bit for bit")
    t.check(a[-1][1] == b[-1][1], "restart read with contacts 1: 20 steps later identical bit for bit")

# the package's other commands: an error naming the cause, not a crash or a silent run
LATTICE = t.LATTICE_SPHERES.format(diameter=1.0) + """pair_style griddem/hooke/history 2000 NULL 50 NULL 0.5 1
pair_coeff * *
timestep 0.001
fix integrate all nve/sphere
"""
for name, text, expect in [
        ("grid_before_box", "units lj\natom_style sphere\ncompute g all griddem/grid 6 6 6 count\n",
         "Compute griddem/grid command before simulation box is defined"),
        ("grid_triclinic_later", LATTICE + "compute g all griddem/grid 6 6 6 count\nrun 1\nchange_box all triclinic\n"
         "dump g all grid 1 g.*.txt c_g:grid:count\nrun 1\n", "Compute griddem/grid does not support triclinic boxes"),
        ("fix_cell_word", LATTICE + "fix grid all griddem cell bogus\nrun 1\n",
         "Fix griddem cell must be auto, exact, multi, classes or a positive edge, not bogus"),
        ("kinematic_2d_vz", LATTICE.replace("units lj", "units lj\ndimension 2").replace("0 6 0 6 0 6", "0 6 0 6 -0.5 0.5")
         .replace("lattice sc", "lattice sq").replace("0.5 5.5 0.5 5.5 0.5 5.5", "0.5 5.5 0.5 5.5 -0.5 0.5") +
         "fix e all enforce2d\nregion r block 0 3 INF INF INF INF\nfix k all griddem/kinematic region r velocity 0 0 1\nrun 5\n",
         "Fix griddem/kinematic k: velocity along z is 1, and a 2d run needs 0"),
        ("kinematic_inf", LATTICE + "variable big equal 1e308*10\nregion r block 0 3 INF INF INF INF\n"
         "fix k all griddem/kinematic region r velocity v_big 0 0\nrun 5\n",
         "Fix griddem/kinematic k: velocity along x is inf (variable big)")]:
    rc, out = t.run_lmp(text, WD, name="in." + name)
    t.check(rc != 0 and expect in out, "%s: error '%s', got %s" % (name, expect, t.errors(out)[:1]))
t.finish()
