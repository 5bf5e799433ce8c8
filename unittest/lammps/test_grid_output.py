"""compute griddem/grid: the channels as LAMMPS grid data. On 1 and 4 ranks the cell counts sum to
the number of atoms, the binned solid times the cell volume sums to the spheres' volume, the
mass-averaged velocity is the velocity all atoms share. Each output read back by VTK's own XML
readers (those ParaView uses, by the file's extension): dump grid/vtk's .vtr (a rectilinear grid,
one array Scalar or Vector), and tools/dump2vtk's conversions of dump grid (.vtr, one cell array
per value, named) and dump custom (.vtp, points with named arrays), each with its time (the step,
or the time with dump_modify time yes) as VTK reports it. Fix ave/grid averaging the compute gets
the counts of the steps it samples. dump2vtk keeps two values of one name apart and names a
missing, an empty or a repeated step's file."""
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
DUMP2VTK = os.path.join(HERE, "..", "..", "tools", "dump2vtk")
sys.path.insert(0, HERE)
import griddem_testlib as t
from griddemtools import grid  # noqa: E402 (griddem_testlib puts python/ on the path)

t.require_modules(("vtkmodules.vtkIOXML",),
                  "test_grid_output: needs VTK's Python module (Debian python3-vtk9 or python3-paraview: "
                  "tools/install-deps)", skip=False)
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLPolyDataReader, vtkXMLRectilinearGridReader

# the reader ParaView picks for each extension of VTK's XML formats
READER = {".vtr": vtkXMLRectilinearGridReader, ".vtp": vtkXMLPolyDataReader}

TEXT = """
units lj
atom_style sphere
boundary p p p
comm_modify vel yes
read_data {data}
velocity all set 0.3 -0.2 0.1
pair_style griddem/hooke/history 1e3 NULL 10 NULL 0.5 1
pair_coeff * *
fix integrate all nve/sphere
timestep 1e-4
compute channels all griddem/grid 5 4 3 count binned_solid vx vy vz
compute contacts all contact/atom
compute contact_sum all reduce sum c_contacts
thermo_style custom step c_contact_sum f_GRIDDEM[5]
thermo_modify norm no
dump cells all grid 5 grid.*.txt c_channels:grid:data[*]
dump_modify cells format float %.17g sort id
dump named all grid 5 named.*.txt c_channels:grid:count c_channels:grid:binned_solid c_channels:grid:vx c_channels:grid:vy c_channels:grid:vz
dump_modify named format float %.17g sort id time yes
dump atoms all custom 5 atoms.dump id type x y z radius vx vy vz
dump_modify atoms format float %.17g
dump solid all grid/vtk 5 solid.*.vtr c_channels:grid:binned_solid
dump vel all grid/vtk 5 vel.*.vtr c_channels:grid:vx c_channels:grid:vy c_channels:grid:vz
run 10
"""


def read_grid_dump(path):
    with open(path) as f:
        lines = f.read().splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("ITEM: GRID CELLS")) + 1
    return [[float(v) for v in line.split()] for line in lines[start:] if line.strip()]


def read_vtk(path):
    """The dataset and its time (TIME_STEPS, or None) read by the reader of the path's extension,
    which must recognise the file."""
    reader = READER[os.path.splitext(path)[1]]()
    t.check(reader.CanReadFile(path), "%s: %s recognises the file" % (os.path.basename(path), reader.GetClassName()))
    reader.SetFileName(path)
    reader.UpdateInformation()
    info = reader.GetOutputInformation(0)
    key = vtkStreamingDemandDrivenPipeline.TIME_STEPS()
    times = info.Get(key) if info.Has(key) else None
    reader.Update()
    return reader.GetOutput(), times


def values(array):
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def array_names(data):
    return [data.GetArrayName(i) for i in range(data.GetNumberOfArrays())]


def convert(sub, prefix, pattern):
    """tools/dump2vtk on the files matching pattern in sub; the files it wrote."""
    files = sorted(f for f in os.listdir(sub) if f.startswith(pattern))
    proc = subprocess.run([sys.executable, DUMP2VTK, "-o", prefix] + files, cwd=sub, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, universal_newlines=True)
    t.check(proc.returncode == 0, "dump2vtk %s: exit %d %s" % (pattern, proc.returncode, proc.stdout[-500:]))
    return proc.stdout.split()


def check_vtk(sub, ranks, cells, n, volume, cellvol):
    """Every output kind through VTK's readers; cells = the text dump's rows at step 0."""
    what = "%d ranks" % ranks
    solid, _ = read_vtk(os.path.join(sub, "solid.0.vtr"))
    t.check(not vtkXMLImageDataReader().CanReadFile(os.path.join(sub, "solid.0.vtr")),
            "%s: dump grid/vtk's file is no image data (the .vti reader refuses it)" % what)
    t.check(solid.GetNumberOfCells() == 60 and array_names(solid.GetCellData()) == ["Scalar"],
            "%s: dump grid/vtk: 60 cells, LAMMPS's one array Scalar (%s)" % (what, array_names(solid.GetCellData())))
    scalar = values(solid.GetCellData().GetArray("Scalar"))
    t.check(abs(sum(scalar) * cellvol - volume) <= 1e-6 * volume, "%s: .vtr binned solid sums to the sphere volume (float32)" % what)
    vel, _ = read_vtk(os.path.join(sub, "vel.0.vtr"))
    vector = vel.GetCellData().GetArray("Vector")
    t.check(vector is not None and vector.GetNumberOfComponents() == 3 and vector.GetNumberOfTuples() == 60,
            "%s: dump grid/vtk: a 3-component array Vector on 60 cells" % what)

    # dump grid (sorted by ID) converted: named cell arrays, real times (dump_modify time yes)
    written = convert(sub, "named", "named.")
    t.check(sorted(written) == ["named.0.vtr", "named.10.vtr", "named.5.vtr"], "%s: one .vtr per step (%s)" % (what, written))
    for name in written:
        step = int(name.split(".")[1])
        grid, times = read_vtk(os.path.join(sub, name))
        cell_data = grid.GetCellData()
        t.check(array_names(cell_data) == ["count", "binned_solid", "vx", "vy", "vz"],
                "%s: %s: arrays named by value (%s)" % (what, name, array_names(cell_data)))
        t.check(times is not None and len(times) == 1 and abs(times[0] - 1e-4 * step) <= 1e-15,
                "%s: %s: VTK's time %s = step %d x dt 1e-4" % (what, name, times, step))
        count = values(cell_data.GetArray("count"))
        t.check(grid.GetNumberOfCells() == 60 and sum(count) == n, "%s: %s: 60 cells, counts sum to %d atoms (%g)" % (what, name, n, sum(count)))
        bounds = grid.GetBounds()
        t.check(max(abs(b - e) for b, e in zip(bounds, (0, 4, 0, 4, 0, 4))) <= 1e-12, "%s: %s spans the box %s" % (what, name, bounds))
        if step == 0:
            binned = values(cell_data.GetArray("binned_solid"))
            t.check(count == [c[0] for c in cells] and max(abs(a - b) for a, b in zip(binned, scalar)) <= 1e-6 * max(scalar),
                    "%s: cell by cell, the counts of the text dump and the binned solid of dump grid/vtk" % what)

    # dump custom converted: points with named arrays, the step as time
    written = convert(sub, "atoms", "atoms.dump")
    t.check(written == ["atoms.0.vtp", "atoms.5.vtp", "atoms.10.vtp"], "%s: one .vtp per step (%s)" % (what, written))
    cloud, times = read_vtk(os.path.join(sub, "atoms.0.vtp"))
    point_data = cloud.GetPointData()
    t.check(array_names(point_data) == ["id", "type", "radius", "v"] and point_data.GetArray("v").GetNumberOfComponents() == 3,
            "%s: .vtp arrays id, type, radius, v (%s)" % (what, array_names(point_data)))
    t.check(cloud.GetNumberOfPoints() == n and cloud.GetNumberOfVerts() == n, "%s: %d points, each a vertex" % (what, n))
    radii = values(point_data.GetArray("radius"))
    t.check(abs(sum(4.0 / 3.0 * math.pi * r ** 3 for r in radii) - volume) <= 1e-12 * volume, "%s: .vtp radii give the sphere volume" % what)
    v = point_data.GetArray("v")
    t.check(all(v.GetTuple3(i) == (0.3, -0.2, 0.1) for i in range(n)), "%s: .vtp v is the common velocity" % what)
    _, times = read_vtk(os.path.join(sub, "atoms.10.vtp"))
    t.check(times == (10.0,), "%s: atoms.10.vtp: VTK's time %s = step 10" % (what, times))


BINARY = """
compute cg all griddem/cg 5 4 3 0.5 density vx temperature
dump gtext all grid 5 cg.txt c_cg:grid:density c_cg:grid:vx c_cg:grid:temperature
dump_modify gtext format float %.17g
dump gbin all grid 5 cg.bin c_cg:grid:density c_cg:grid:vx c_cg:grid:temperature
dump atext all custom 5 atoms.txt id x y z vx mass
dump_modify atext format float %.17g
dump abin all custom 5 atoms.bin id x y z vx mass
run 10
"""


def check_binary(wd, data):
    """griddemtools reads LAMMPS's binary dumps (custom and grid, *.bin) as the same run's text dumps
    of every digit (%.17g); on 2 ranks the atoms of both processes' chunks, and a grid of two
    bricks is refused (its cells are not in order)."""
    for ranks in (1, 2):
        sub = os.path.join(wd, "binary.np%d" % ranks)
        os.mkdir(sub)
        t.run_ok(TEXT.format(data=data).split("compute channels")[0] + BINARY, sub, nprocs=ranks, name="in.binary")
        text, binary = (t.dump.read_dump(os.path.join(sub, "atoms." + e)) for e in ("txt", "bin"))
        same = [a.step == b.step and a.natoms == b.natoms and a.box == b.box and a.columns == b.columns and
                sorted(a.rows) == sorted(b.rows) for a, b in zip(text, binary)]
        t.check(len(text) == 3 and len(binary) == 3 and all(same) and text[0].natoms == 300,
                "%d ranks: dump custom binary read as its text twin (steps %s)" % (ranks, [s.step for s in binary]))
        if ranks == 1:
            text, binary = (grid.read_grid_dump(os.path.join(sub, "cg." + e)) for e in ("txt", "bin"))
            same = [a.step == b.step and a.box == b.box and a.n == b.n and a.names == b.names and
                    all(list(a.columns[k]) == list(b.columns[k]) for k in a.columns) for a, b in zip(text, binary)]
            t.check(len(binary) == 3 and all(same) and max(binary[-1].columns["density"]) > 0.0,
                    "dump grid binary read as its text twin (steps %s)" % [f.step for f in binary])
        else:
            try:
                grid.read_grid_dump(os.path.join(sub, "cg.bin"))
                refused = ""
            except ValueError as e:
                refused = str(e)
            t.check("written by 2 processes" in refused, "a grid binary of two bricks refused (%s)" % refused)


def main():
    wd = t.workdir()
    data = os.path.join(wd, "data.g")
    n, box = 300, (4.0, 4.0, 4.0)
    t.write_random_spheres(data, n, box, 0.1, 0.3, seed=5, lattice=None)
    volume = 0.0
    with open(data) as f:
        atoms = f.read().split("Atoms # sphere")[1].split("Velocities")[0]
    for line in atoms.strip().splitlines():
        volume += math.pi / 6.0 * float(line.split()[2]) ** 3
    cellvol = box[0] * box[1] * box[2] / 60.0
    for ranks in (1, 4):
        sub = os.path.join(wd, "np%d" % ranks)
        os.mkdir(sub)
        out = t.run_ok(TEXT.format(data=data), sub, nprocs=ranks, name="in.grid")
        seen, pairs = t.thermo_values(out, "c_contact_sum"), t.thermo_values(out, "f_GRIDDEM[5]")
        t.check(seen and pairs and pairs[0] > 50 and seen[0] == 2 * pairs[0],
                "%d ranks: compute contact/atom counts each of the %s contacts from both atoms (%s)" % (ranks, pairs, seen))
        cells = read_grid_dump(os.path.join(sub, "grid.0.txt"))
        t.check(len(cells) == 60, "%d ranks: 5x4x3 cells written (%d)" % (ranks, len(cells)))
        t.check(sum(c[0] for c in cells) == n, "%d ranks: counts sum to %d atoms" % (ranks, n))
        solid = sum(c[1] for c in cells) * cellvol
        t.check(abs(solid - volume) <= 1e-9 * volume, "%d ranks: solid volume %.12g, spheres %.12g" % (ranks, solid, volume))
        occupied = [c for c in cells if c[0] > 0]
        worst = max(abs(c[2] - 0.3) + abs(c[3] + 0.2) + abs(c[4] - 0.1) for c in occupied)
        t.check(worst <= 1e-12, "%d ranks: cell velocities equal the common velocity (%.3g)" % (ranks, worst))
        t.check(all(c[2] == 0.0 for c in cells if c[0] == 0), "%d ranks: empty cells have zero velocity" % ranks)
        check_vtk(sub, ranks, cells, n, volume, cellvol)
    check_binary(wd, data)

    # fix ave/grid reads the compute's data without asking for this step's: it gets this step's
    averaged = TEXT.format(data=data).split("compute contacts")[0].replace("velocity all set 0.3 -0.2 0.1",
                                                                            "velocity all set 3.0 -2.0 1.0") + """
fix ave all ave/grid 10 1 10 5 4 3 c_channels:grid:count
dump both all grid 10 both.*.txt c_channels:grid:count f_ave:grid:data
dump_modify both sort id
compute other all griddem/grid 5 4 3 count
dump twice all grid 100 twice.*.txt c_channels:grid:count c_other:grid:count
dump_modify twice sort id
run 100
"""
    sub = os.path.join(wd, "ave")
    os.mkdir(sub)
    t.run_ok(averaged, sub, name="in.ave")
    differ = [s for s in range(10, 101, 10) if any(c[0] != c[1] for c in read_grid_dump(os.path.join(sub, "both.%d.txt" % s)))]
    moved = sum(abs(a[0] - b[0]) for a, b in zip(read_grid_dump(os.path.join(sub, "both.0.txt")),
                                                 read_grid_dump(os.path.join(sub, "both.100.txt"))))
    t.check(moved > 0 and not differ, "fix ave/grid every 10 steps of one sample: the compute's counts of that step "
            "(atoms changed cells: %g; steps where they differ: %s)" % (moved, differ))
    # dump2vtk: two values of one name keep their whole names; bad files named
    twice, _ = read_vtk(os.path.join(sub, convert(sub, "twice", "twice.100.txt")[0]))
    t.check(array_names(twice.GetCellData()) == ["c_channels:grid:count", "c_other:grid:count"],
            "dump2vtk: two values named count are two arrays (%s)" % array_names(twice.GetCellData()))
    open(os.path.join(sub, "empty.txt"), "w").close()
    for files, expect in ((["missing.txt"], "missing.txt: No such file"), (["empty.txt"], "empty.txt: no snapshot"),
                          (["both.10.txt", "twice.100.txt", "both.100.txt"], "both hold step 100")):
        proc = subprocess.run([sys.executable, DUMP2VTK, "-o", "bad"] + files, cwd=sub, stdout=subprocess.PIPE,
                              stderr=subprocess.STDOUT, universal_newlines=True)
        t.check(proc.returncode != 0 and expect in proc.stdout and "Traceback" not in proc.stdout,
                "dump2vtk %s: '%s' (%s)" % (" ".join(files), expect, proc.stdout.strip()[-200:]))

    rc, out = t.run_lmp("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\n"
                        "compute c all griddem/grid 2 2 2 count pressure\n", wd, name="in.bad")
    t.check(rc != 0 and "unknown value pressure" in out, "unknown field refused by name")
    rc, out = t.run_lmp("units lj\natom_style sphere\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\n"
                        "compute c all griddem/grid 2 2 2 count solid\n", wd, name="in.bad")
    t.check(rc != 0 and "no value solid: binned_solid is the sphere volume binned by centre" in out,
            "the value solid is refused, naming binned_solid")
    for setup, args, expect in [("atom_style sphere\nregion b block 0 1 0 1 0 1", "0 2 2 count", "grid count x must be between 1 and 100000, not 0"),
                                ("atom_style sphere\nregion b prism 0 1 0 1 0 1 0.1 0 0", "2 2 2 count", "does not support triclinic"),
                                ("atom_style atomic\nregion b block 0 1 0 1 0 1", "2 2 2 count", "requires atom attributes radius and rmass")]:
        rc, out = t.run_lmp("units lj\n%s\ncreate_box 1 b\ncompute c all griddem/grid %s\n" % (setup, args), wd,
                            name="in.bad")
        t.check(rc != 0 and expect in out, "compute griddem/grid %s: '%s'" % (args, expect))
    t.finish()


if __name__ == "__main__":
    main()
