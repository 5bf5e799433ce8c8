"""python/griddemtools's readers on small hand-written LAMMPS outputs whose values are known by
construction (each text below is written here, in the layout LAMMPS writes), and the command
lines of its LAMMPS runner. Standard library only; exits 1 on any failed check."""
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from griddemtools import chunks, dump, grid, lammps, log  # noqa: E402
from griddemtools.spheres import write_random_spheres  # noqa: E402

failures, passed = [], 0

# two snapshots: an orthogonal box, then a triclinic one with dump_modify time's item before the
# atoms, and a different atom count
DUMP = """ITEM: TIMESTEP
0
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS pp pp ff
0.0000000000000000e+00 1.0000000000000000e+01
-1.0000000000000000e+00 1.0000000000000000e+00
0.0000000000000000e+00 5.0000000000000000e+00
ITEM: ATOMS id type x y z radius
2 1 1.5 0.25 2 0.5
1 2 0.5 0 1e-3 0.25
ITEM: TIMESTEP
100
ITEM: TIME
0.01
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS xy xz yz pp pp ff
0 10 0.5
-1 1 0
0 5 -0.25
ITEM: ATOMS id x z
1 0.75 -2.5
3 9 4
2 1.25 3.5
"""

GRID = """ITEM: TIMESTEP
40
ITEM: BOX BOUNDS ff pp ff
0.0 2.0
0.0 1.0
-1.0 2.0
ITEM: DIMENSION
3
ITEM: GRID SIZE nx ny nz
2 1 3
ITEM: GRID CELLS c_cg:grid:density f_rom:field:vx f_avg:grid:data[2]
1 0.5 10
2 -0.5 20
3 1.5 30
4 2.5 40
5 3.5 50
6 4.5 60
ITEM: TIMESTEP
80
ITEM: BOX BOUNDS ff pp ff
0.0 2.0
0.0 1.0
-1.0 2.0
ITEM: DIMENSION
3
ITEM: GRID SIZE nx ny nz
1 1 1
ITEM: GRID CELLS c_cg:grid:density f_rom:field:vx f_avg:grid:data[2]
7 8 9
"""

# fix ave/chunk: three comment lines, then blocks "step nchunks total count"
CHUNKS = """# Chunk-averaged data for fix profile and group flow
# Timestep Number-of-chunks Total-count
# Chunk Coord1 Ncount density/mass vx
1000 2 30
  1 0.25 10 0.6 0.125
  2 0.75 20 0.3 1.5
2000 3 31
  1 0.25 11 0.61 0.25
  2 0.75 19 0.29 1.75
  3 1.25 1 0.01 2.5
"""

# a log of two runs: the first's table broken by WARNING lines (one as many words as the table
# has columns), the second's columns in another order and one more; loop lines with and without a
# CPU use line; between the runs a line (a print's) of as many numbers as the table has columns,
# not a row of it
LOG = """LAMMPS (4 Feb 2025)
thermo_style custom step temp v_h
Per MPI rank memory allocation (min/avg/max) = 5 | 5 | 5 Mbytes
   Step          Temp            v_h
         0   0              0.95
WARNING: insertions (src/x.cpp:2)
        10   1.5            0.9
WARNING: something the run says (src/x.cpp:1)
        20   2.5            0.5
Loop time of 0.125 on 2 procs for 20 steps with 100 atoms

Performance: 1 tau/day, 2 timesteps/s, 3 katom-step/s
97.5% CPU use with 2 MPI tasks x 1 OpenMP threads

MPI task timing breakdown:
Section |  min time  |  avg time  |  max time  |%varavg| %total
---------------------------------------------------------------
Pair    | 0.05       | 0.06       | 0.07       |   1.0 | 48.00
Neigh   | 0.01       | 0.01       | 0.01       |   0.0 |  8.50
Other   |            | 0.054      |            |       | 43.50

Nlocal:             50 ave          51 max          49 min
5 6 7
   Step            v_h           Temp           c_x
        20   0.5            2.5            1
        30   0.25           3.75           -2
Loop time of 1.5e-05 on 1 procs for 10 steps with 99 atoms

Total wall time: 0:00:01
"""


def check(cond, message):
    global passed
    if cond:
        passed += 1
    else:
        failures.append(message)
        print("FAILED: " + message, file=sys.stderr)


def written(text, name):
    path = os.path.join(tempfile.mkdtemp(prefix="griddemtools-test-"), name)
    with open(path, "w") as f:
        f.write(text)
    return path


def raises(function, *args):
    try:
        function(*args)
    except ValueError:
        return True
    return False


def dumps():
    path = written(DUMP, "dump.atoms")
    s = dump.read_dump(path)
    check([x.step for x in s] == [0, 100] and [x.natoms for x in s] == [2, 3], "dump: steps 0, 100 of 2 and 3 atoms")
    check(s[0].box == [[0.0, 10.0], [-1.0, 1.0], [0.0, 5.0]] and s[1].box == [[0, 10, 0.5], [-1, 1, 0], [0, 5, -0.25]],
          "dump: orthogonal and triclinic boxes (%s, %s)" % (s[0].box, s[1].box))
    check(s[0].columns == ["id", "type", "x", "y", "z", "radius"] and s[1].columns == ["id", "x", "z"],
          "dump: each snapshot's columns")
    check(s[0].rows == [[2, 1, 1.5, 0.25, 2, 0.5], [1, 2, 0.5, 0, 1e-3, 0.25]], "dump: rows in the file's order")
    check(s[0].column("z") == [2.0, 0.001] and s[1].column("x") == [0.75, 9.0, 1.25], "dump: a column by name")
    check(s[1].atoms()[2] == {"id": 2.0, "x": 1.25, "z": 3.5}, "dump: an atom as a dict")
    check(s[1].by_id() == {1: [0.75, -2.5], 3: [9.0, 4.0], 2: [1.25, 3.5]}, "dump: atoms by id")
    check(dump.last_snapshot(path).step == 100, "dump: the last snapshot")
    cut = written(DUMP[:DUMP.rindex("2 1.25")], "dump.cut")
    check(raises(dump.read_dump, cut), "dump: a snapshot with fewer rows than atoms is an error")
    # b's largest |fx| is 4 and |fz| 2: a's fx off by 1 at atom 2 (1/4), fz by 0.5 at atom 1 (0.5/2)
    a = (["fx", "fz"], {1: [3.0, 1.5], 2: [-3.0, 1.0]})
    b = (["fz", "fx"], {1: [2.0, 3.0], 2: [1.0, -4.0]})
    check(dump.max_rel_diff(a, b, ["fx"]) == 0.25 and dump.max_rel_diff(a, b, ["fx", "fz"]) == 0.25 and
          dump.max_rel_diff(a, b, ["fz"]) == 0.25 and dump.max_rel_diff(b, b, ["fx", "fz"]) == 0.0,
          "dump: the largest difference relative to each column's largest value")


def grids():
    path = written(GRID, "grid.txt")
    f = grid.read_grid_dump(path)
    check([x.step for x in f] == [40, 80] and f[0].n == (2, 1, 3) and f[1].n == (1, 1, 1),
          "grid: steps 40, 80, sizes 2 1 3 and 1 1 1")
    check(f[0].box == [0.0, 2.0, 0.0, 1.0, -1.0, 2.0], "grid: the box as xlo xhi ylo yhi zlo zhi")
    check(f[0].names == ["c_cg:grid:density", "f_rom:field:vx", "f_avg:grid:data[2]"], "grid: full column names")
    check(list(f[0].columns) == ["density", "vx", "data[2]"], "grid: short names in order")
    check(f[0].columns["density"] == [1, 2, 3, 4, 5, 6] and f[0].columns["vx"] == [0.5, -0.5, 1.5, 2.5, 3.5, 4.5]
          and f[0].columns["data[2]"] == [10, 20, 30, 40, 50, 60], "grid: each column cell by cell")
    check(f[1].columns == {"density": [7.0], "vx": [8.0], "data[2]": [9.0]}, "grid: the second frame")
    check(raises(grid.read_grid_dump, written(GRID[:GRID.index("6 4.5")], "grid.cut")),
          "grid: a frame with fewer rows than cells is an error")
    clash = GRID.replace("f_rom:field:vx", "c_cg:grid:density")
    check(raises(grid.read_grid_dump, written(clash, "grid.clash")), "grid: two columns of one short name are an error")


def ave_chunks():
    path = written(CHUNKS, "profile.txt")
    b = chunks.read_ave_chunk(path)
    check([s for s, _ in b] == [1000, 2000] and [len(r) for _, r in b] == [2, 3], "chunks: blocks of 2 and 3 rows")
    check(b[0][1] == [[1, 0.25, 10, 0.6, 0.125], [2, 0.75, 20, 0.3, 1.5]], "chunks: the first block's rows")
    check(chunks.last_block(path)[2] == [3, 1.25, 1, 0.01, 2.5], "chunks: the last block")
    check(raises(chunks.read_ave_chunk, written(CHUNKS[:CHUNKS.rindex("  3 1.25")], "profile.cut")),
          "chunks: a block with fewer rows than its count is an error")


def logs():
    path = written(LOG, "log.lammps")
    check(log.thermo(path, "v_h") == [0.95, 0.9, 0.5, 0.5, 0.25], "log: v_h over both runs, from a file")
    check(log.thermo(LOG, "Temp") == [0, 1.5, 2.5, 2.5, 3.75], "log: Temp over both runs, from the text")
    check(log.thermo(LOG, "Step") == [0, 10, 20, 20, 30], "log: the Step column")
    check(log.thermo(LOG, "c_x") == [1, -2], "log: a column of the second run only")
    check(log.thermo_table(LOG, "Step", "v_h") == [(0, 0.95), (10, 0.9), (20, 0.5), (20, 0.5), (30, 0.25)],
          "log: two columns row by row, each table's own order")
    check(log.thermo_table(LOG, "c_x", "Step") == [(1, 20), (-2, 30)], "log: rows of the tables that have all columns")
    runs = log.loop_times(LOG)
    check(runs == [(0.125, 2, 20, 100, 97.5), (1.5e-05, 1, 10, 99, None)],
          "log: loop seconds, procs, steps, atoms, CPU use per run (%s)" % (runs,))
    check(log.timing_sections(LOG) == {"Pair": 48.0, "Neigh": 8.5, "Other": 43.5}, "log: the timing breakdown")
    check(log.timing_sections("no table\n") == {}, "log: no timing breakdown")


def spheres_file():
    path = os.path.join(tempfile.mkdtemp(prefix="griddemtools-"), "data.spheres")
    write_random_spheres(path, 27, (3.0, 3.0, 3.0), 0.1, 0.4, seed=5, lattice=1.0, ntypes=2)
    text = open(path).read().split("\n")
    atoms = text[text.index("Atoms # sphere") + 2:text.index("Velocities") - 1]
    rows = [[float(v) for v in line.split()] for line in atoms]
    check(len(rows) == 27 and "27 atoms" in text and "2 atom types" in text, "spheres: 27 atoms of 2 types")
    check(sorted((r[4], r[5], r[6]) for r in rows) == sorted((x, y, z) for x in range(3) for y in range(3)
                                                          for z in range(3)), "spheres: the centres on the lattice")
    check(all(0.2 <= r[2] <= 0.8 and r[1] == 1 + int(r[0]) % 2 for r in rows), "spheres: diameters and types")


def runner():
    check(lammps.command("lmp", ["-in", "in.x"]) == ["lmp", "-in", "in.x"], "lammps: one rank, no mpirun")
    check(lammps.command("lmp", ["-in", "in.x"], 4, ["--bind-to", "core"]) ==
          ["mpirun", "-np", "4", "--bind-to", "core", "lmp", "-in", "in.x"], "lammps: mpirun -np 4 and its switches")
    env = lammps.environment(3, {"X_TEST": "1"})
    check(env["OMP_NUM_THREADS"] == "3" and env["OMPI_ALLOW_RUN_AS_ROOT"] == "1" and
          env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] == "1" and env["X_TEST"] == "1",
          "lammps: threads, Open MPI's root consent and extra variables")
    check(os.path.isfile(os.path.join(lammps.TOP, "python", "griddemtools", "lammps.py")), "lammps: TOP is the repository")
    done = lammps.run(sys.executable, ["-c", "import os; print(os.environ['OMP_NUM_THREADS'])"], tempfile.gettempdir(),
                      threads=2)
    check(done.returncode == 0 and done.stdout.strip() == "2", "lammps: run captures the output (%r)" % done.stdout)


dumps()
grids()
ave_chunks()
logs()
spheres_file()
runner()
print("%d passed, %d failed" % (passed, len(failures)))
sys.exit(1 if failures or not passed else 0)
