"""griddem/hooke/history next to the stock fixes a granular script uses: fix pour, fix gravity,
fix wall/gran, fix wall/gran/region, fix deform on a triclinic box, fix pour of rigid clumps (fix
rigid/small). Each scene is run with the
stock style and with griddem; trajectories agree (1e-8 relative) after hundreds of steps."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t
from test_stock_parity import CLUMP, clump_box

POUR = """
units lj
atom_style sphere
boundary p p fm
comm_modify vel yes
region box block 0 8 0 8 0 14 units box
create_box 1 box
pair_style {pair} 2000.0 NULL 50.0 NULL 0.5 1
pair_coeff * *
timestep 0.001
fix integrate all nve/sphere
fix gravity all gravity 1.0 vector 0 0 -1
fix floor all wall/gran hooke/history 2000.0 NULL 50.0 NULL 0.5 0 zplane 0.0 NULL
region drum cylinder z 4 4 3.9 0 14 side in units box
fix drumwall all wall/gran/region hooke/history 2000.0 NULL 50.0 NULL 0.5 1 region drum
region slab block 1.5 6.5 1.5 6.5 2 12 units box
fix feed all pour 400 1 4767548 vol 0.4 20 diam range 0.8 1.2 region slab
thermo_style custom step atoms ke
thermo 6000
dump snap all custom 6000 dump.{name} id x y z vx vy vz fx fy fz
dump_modify snap format float %.17g sort id
run 6000
"""

# fix pour of rigid clumps of three spheres (test_stock_parity.CLUMP): no body exists at the
# first step, the bodies' masses are taken as they come
POUR_CLUMPS = clump_box("p p fm", 6, 12) + """pair_style {pair} 2000.0 NULL 50.0 NULL 0.5 1
pair_coeff * *
neigh_modify exclude molecule/intra all
timestep 0.001
fix gravity all gravity 1.0 vector 0 0 -1
fix floor all wall/gran hooke/history 2000.0 NULL 50.0 NULL 0.5 0 zplane 0.0 NULL
fix bodies all rigid/small molecule mol clump
region slab block 0.5 5.5 0.5 5.5 3 11 units box
fix feed all pour 150 0 4767 vol 0.2 20 mol clump rigid bodies region slab
thermo_style custom step atoms
thermo 2500
dump snap all custom 2500 dump.{name} id x y z vx vy vz fx fy fz
dump_modify snap format float %.17g sort id
run 2500
"""
# (2500 steps: the first clumps have landed; their rebounds amplify round-off by ten every 250
# steps after that, as any chaotic pour's)

DEFORM = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
pair_style {pair} 1e4 NULL 50 NULL 0.5 1
pair_coeff * *
timestep 1e-4
fix integrate all nve/sphere
fix shear all deform 1 xy erate 0.5 remap v
thermo_style custom step ke press xy
thermo 100
dump snap all custom 400 dump.{name} id x y z vx vy vz fx fy fz
dump_modify snap format float %.17g sort id
run 400
"""
STATE = ["x", "y", "z", "vx", "vy", "vz"]


def compare(label, template, **kw):
    snaps = {}
    for style in ("gran/hooke/history", "griddem/hooke/history"):
        name = label + ("_grid" if style.startswith("griddem") else "_stock")
        t.run_ok(template.format(pair=style, name=name, **kw), WD, name="in." + name)
        snaps[style] = t.read_dump(os.path.join(WD, "dump." + name))
    ref, test = snaps["gran/hooke/history"], snaps["griddem/hooke/history"]
    t.check(len(ref[1]) > 60, "%s: %d atoms in the scene" % (label, len(ref[1])))
    err = t.max_rel_diff(test, ref, STATE)
    t.check(err <= 1e-8, "%s: griddem vs stock trajectory differs by %.3g relative" % (label, err))
    err = t.max_rel_diff(test, ref, ["fx", "fy", "fz"])
    t.check(err <= 1e-8, "%s: griddem vs stock forces differ by %.3g relative" % (label, err))


WD = t.workdir()
compare("pour", POUR)
clump = os.path.join(WD, "clump.mol")
with open(clump, "w") as f:
    f.write(CLUMP)
compare("pour_clumps", POUR_CLUMPS, clump=clump)
data = os.path.join(WD, "data.tri")
t.write_random_spheres(data, 800, (4.5, 4.5, 4.5), 0.1, 0.3, seed=13, triclinic=(0.0, 0.0, 0.0))
compare("deform", DEFORM, data=data)
t.finish()
