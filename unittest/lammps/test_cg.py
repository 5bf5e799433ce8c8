"""compute griddem/cg: coarse-grained fields by cloud-in-cell assignment and FFT Gaussian smoothing.
Each number checked has its own reason: total mass and solid volume (conservation: the kernel
sums to 1), the packing fraction and coordination of a simple cubic lattice, the slope of a
linear shear profile (cloud-in-cell and a symmetric kernel keep linear fields exactly), the
pressure tensor of compute pressure (the stress field is built from the same per-atom virial and
velocities), a direct real-space convolution written here from the documented scheme, and the
same fields on 1, 2 and 4 ranks (and under fix deform on 1 and 2)."""
import math
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

ALL = ["solid", "density", "vx", "vy", "vz", "pxx", "pyy", "pzz", "pxy", "pxz", "pyz",
       "temperature", "coordination"]
NEGLIGIBLE = 1e-17    # beyond this fraction of its peak the Gaussian is below rounding of its sum
NONNEGATIVE = ["solid", "density", "temperature", "coordination"]

RANDOM = """
units lj
atom_style sphere
boundary {boundary}
comm_modify vel yes
read_data {data}
pair_style {pair}
pair_coeff * * {coeffs}
fix integrate all nve/sphere
compute T all temp
compute P all pressure T
compute W all pressure NULL virial
thermo_style custom step c_P[1] c_P[2] c_P[3] c_P[4] c_P[5] c_P[6] c_W
thermo_modify format float %.17g
"""


def cg_lines(grid, width, values):
    """compute griddem/cg and one grid/vtk dump per value (vtk files hold the grid in global order)."""
    lines = ["compute cg all griddem/cg %d %d %d %.17g %s" % (grid + (width, " ".join(values)))]
    for v in values:
        lines.append("dump f_%s all grid/vtk 1 %s.*.vti c_cg:grid:%s" % (v, v, v))
        lines.append("dump_modify f_%s format float %%.17g" % v)
    return "\n".join(lines + ["run 0"]) + "\n"


def read_vti(path):
    """Cell values of a one-value .vti file, x fastest."""
    with open(path) as f:
        text = f.read()
    block = re.search(r"<CellData>.*?format=\"ascii\">(.*?)</DataArray>", text, re.S).group(1)
    return [float(v) for v in block.split()]


def read_fields(wd, values):
    return {v: read_vti(os.path.join(wd, "%s.0.vti" % v)) for v in values}


def read_atoms(path):
    """(mass, volume, x, y, z) of each atom of a write_random_spheres file (density 1)."""
    with open(path) as f:
        block = f.read().split("Atoms # sphere")[1].split("Velocities")[0]
    atoms = []
    for line in block.strip().splitlines():
        w = line.split()
        d, rho = float(w[2]), float(w[3])
        vol = math.pi / 6.0 * d ** 3
        atoms.append((rho * vol, vol, float(w[4]), float(w[5]), float(w[6])))
    return atoms


def cic(x, h, n, periodic):
    """Documented assignment: grid points at cell centres, weights 1-f and f on floor(u), floor(u)+1
    with u = x/h - 1/2; along a non-periodic axis indices are moved into 0..n-1, else wrapped."""
    u = x / h - 0.5
    i0 = math.floor(u)
    f = u - i0
    out = []
    for i, w in ((i0, 1.0 - f), (i0 + 1, f)):
        out.append((i % n if periodic else min(max(i, 0), n - 1), w))
    return out


def kernel_axis(n, h, width, periodic):
    """The documented kernel along one axis, by brute force: the Gaussian exp(-(d h)^2 / (2 W^2))
    over its sum over all integer offsets d, summed over the periodic images on a periodic axis
    (indexed by d mod n), at every offset inside the box (|d| < n) on a non-periodic one."""
    span = int(40 * width / h) + 2 * n + 10
    g = {d: math.exp(-(d * h) ** 2 / (2 * width ** 2)) for d in range(-span, span + 1)}
    norm = sum(g.values())
    if periodic:
        out = {r: 0.0 for r in range(n)}
        for d, v in g.items():
            out[d % n] += v / norm
        return out
    return {d: g[d] / norm for d in range(-(n - 1), n)}


def direct_density(atoms, grid, box, width, periodic):
    """Density by assignment and a real-space convolution with the kernel of kernel_axis: the 3d
    Gaussian factorises into one factor per axis; periodic axes wrap, non-periodic ones drop what
    leaves the box. A smoothed mass below 1e-9 of the mean per point is none (density 0)."""
    h = [box[d] / grid[d] for d in range(3)]
    npts = grid[0] * grid[1] * grid[2]
    field = [0.0] * npts
    for m, _, *x in atoms:
        parts = [cic(x[d], h[d], grid[d], periodic[d]) for d in range(3)]
        for ix, wx in parts[0]:
            for iy, wy in parts[1]:
                for iz, wz in parts[2]:
                    field[ix + grid[0] * (iy + grid[1] * iz)] += m * wx * wy * wz
    kernels = [kernel_axis(grid[d], h[d], width, periodic[d]) for d in range(3)]

    def factor(d, i, j):
        return kernels[d][(i - j) % grid[d] if periodic[d] else i - j]

    out = [0.0] * npts
    cellvol = box[0] * box[1] * box[2] / npts
    for j, mass in enumerate(field):
        if mass == 0.0:
            continue
        jx, jy, jz = j % grid[0], j // grid[0] % grid[1], j // (grid[0] * grid[1])
        for i in range(npts):
            ix, iy, iz = i % grid[0], i // grid[0] % grid[1], i // (grid[0] * grid[1])
            out[i] += mass * factor(0, ix, jx) * factor(1, iy, jy) * factor(2, iz, jz) / cellvol
    floor = 1e-9 * sum(a[0] for a in atoms) / npts
    return [rho if rho * cellvol > floor else 0.0 for rho in out]


def max_diff(a, b):
    return max(abs(p - q) for p, q in zip(a, b))


def check_random(wd, pair, coeffs, tag, ranks_list):
    """Random overlapping spheres with random velocities, periodic: conservation, stress integral
    against compute pressure, the direct convolution, and agreement across ranks."""
    data = os.path.join(wd, "data.%s" % tag)
    box, grid, width = (4.0, 4.0, 4.0), (8, 6, 5), 0.45
    t.write_random_spheres(data, 300, box, 0.1, 0.3, seed=11)
    atoms = read_atoms(data)
    mass, volume = sum(a[0] for a in atoms), sum(a[1] for a in atoms)
    cellvol = box[0] * box[1] * box[2] / (grid[0] * grid[1] * grid[2])
    text = RANDOM.format(boundary="p p p", data=data, pair=pair, coeffs=coeffs) + cg_lines(grid, width, ALL)
    reference = None
    for ranks in ranks_list:
        sub = os.path.join(wd, "%s.np%d" % (tag, ranks))
        os.mkdir(sub)
        out = t.run_ok(text, sub, nprocs=ranks, name="in.cg")
        f = read_fields(sub, ALL)
        what = "%s, %d ranks" % (tag, ranks)
        total = sum(f["density"]) * cellvol
        t.check(abs(total - mass) <= 1e-12 * mass, "%s: integral of density %.17g = total mass %.17g" % (what, total, mass))
        solid = sum(f["solid"]) * cellvol
        t.check(abs(solid - volume) <= 1e-12 * volume, "%s: integral of solid fraction %.17g = sphere volume %.17g" % (what, solid, volume))
        # compute pressure (with compute temp) is (sum m v v + virial) / V: fluctuations about zero
        # velocity. The field's kinetic part is about the local mean velocity V, so add back the
        # mean-flow flux rho V V, from the dumped density and velocity fields, before comparing.
        pressure = [t.thermo_values(out, "c_P[%d]" % k)[0] for k in range(1, 7)]
        pairs = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
        vel = [f["vx"], f["vy"], f["vz"]]
        scale = max(abs(p) for p in pressure) * box[0] * box[1] * box[2]
        worst = 0.0
        for k, name in enumerate(["pxx", "pyy", "pzz", "pxy", "pxz", "pyz"]):
            a, b = pairs[k]
            integral = sum(s + rho * va * vb for s, rho, va, vb in zip(f[name], f["density"], vel[a], vel[b])) * cellvol
            worst = max(worst, abs(integral - pressure[k] * box[0] * box[1] * box[2]) / scale)
        t.check(worst <= 1e-10, "%s: stress integral + mean-flow flux = compute pressure * V (rel. %.3g)" % (what, worst))
        contact = t.thermo_values(out, "c_W")[0]
        t.check(contact > 0.1 * sum(pressure[:3]) / 3 and min(f["temperature"]) > 0.0,
                "%s: contacts carry a real share of the pressure (%.3g of %.3g), temperature > 0" % (what, contact, sum(pressure[:3]) / 3))
        if reference is None:
            reference = f
            direct = direct_density(atoms, grid, box, width, (True, True, True))
            diff = max_diff(f["density"], direct) / max(direct)
            t.check(diff <= 1e-12, "%s: FFT density = direct real-space convolution (rel. %.3g)" % (what, diff))
        else:
            worst = max(max_diff(f[v], reference[v]) / (max(abs(x) for x in reference[v]) or 1.0) for v in ALL)
            t.check(worst <= 1e-12, "%s: all fields equal the 1-rank fields (rel. %.3g)" % (what, worst))


def low_bed(wd):
    """60 spheres in the lowest quarter (z < 2) of a 3 x 3 x 8 box: the data file and its atoms."""
    data = os.path.join(wd, "data.wall")
    if not os.path.exists(data):
        t.write_random_spheres(data, 60, (3.0, 3.0, 2.0), 0.1, 0.2, seed=3)
        with open(data) as f:
            text = f.read().replace("0 2 zlo zhi", "0 8 zlo zhi")
        with open(data, "w") as f:
            f.write(text)
    return data, read_atoms(data)


def check_wall(wd):
    """z non-periodic, atoms in the lowest quarter: the zero-padded FFT equals the open-boundary
    direct convolution (which drops what the kernel puts below the wall) and the top of the box
    stays empty, where the periodic box carries mass across."""
    box, grid, width = (3.0, 3.0, 8.0), (6, 6, 16), 0.3
    data, atoms = low_bed(wd)
    for boundary, periodic in (("p p f", False), ("p p p", True)):
        for ranks in (1, 2):
            sub = os.path.join(wd, "wall.%s.np%d" % (boundary.replace(" ", ""), ranks))
            os.mkdir(sub)
            t.run_ok(RANDOM.format(boundary=boundary, data=data, pair="granular",
                                   coeffs="hooke 1000 0 tangential linear_nohistory 0 0.5") +
                     cg_lines(grid, width, ["density"]), sub, nprocs=ranks, name="in.cg")
            rho = read_fields(sub, ["density"])["density"]
            direct = direct_density(atoms, grid, box, width, (True, True, periodic))
            what = "%s, %d ranks" % (boundary, ranks)
            t.check(max_diff(rho, direct) <= 1e-12 * max(direct),
                    "%s: FFT density = direct convolution (rel. %.3g)" % (what, max_diff(rho, direct) / max(direct)))
            top = max(rho[-grid[0] * grid[1]:])
            if periodic:
                t.check(top > 1e-3 * max(rho), "%s: the periodic box carries mass across z (top plane %.3g)" % (what, top))
            else:
                t.check(top <= 1e-13 * max(rho), "%s: nothing folded onto the top wall (%.3g)" % (what, top))


def check_nonnegative(wd):
    """Fields that cannot be negative (solid, density, temperature, coordination) are not, also
    where the kernel never reached and FFT rounding leaves +-1e-16 of the peak: above the bed of
    low_bed (top point of the assignment 4, the Gaussian below rounding beyond 8.85 W = 5.3
    spacings) solid fraction and density are exactly 0, and positive in the bed."""
    data, _ = low_bed(wd)
    grid, width = (6, 6, 16), 0.3
    sub = os.path.join(wd, "nonnegative")
    os.mkdir(sub)
    t.run_ok(RANDOM.format(boundary="p p f", data=data, pair="granular",
                           coeffs="hooke 1000 0 tangential linear_nohistory 0 0.5") +
             cg_lines(grid, width, NONNEGATIVE), sub, name="in.cg")
    f = read_fields(sub, NONNEGATIVE)
    plane = grid[0] * grid[1]
    for v in NONNEGATIVE:
        negative = [x for x in f[v] if x < 0.0]
        t.check(not negative, "%s: no negative value (%d of %d, lowest %.3g)" % (v, len(negative), len(f[v]), min(f[v])))
    for v in ("solid", "density"):
        t.check(all(x == 0.0 for x in f[v][10 * plane:]) and min(f[v][:4 * plane]) > 0.0,
                "%s: exactly 0 beyond the kernel's reach, > 0 in the bed" % v)


def check_wide_kernel(wd):
    """A Gaussian far wider than the box costs what a narrow one does (it once took time growing
    as (W/h)^3: W = 1e4 never returned) and is flat: along periodic x and y it averages over the
    box, along the open z it is h / (W sqrt(2 pi)) to 1e-7 over the 8 points, so solid fraction
    and density are the totals over Lx Ly W sqrt(2 pi) everywhere. The widest finite W underflows
    to fields of 0, without NaN."""
    data = os.path.join(wd, "data.wide")
    box, grid = (2.0, 2.0, 4.0), (4, 4, 8)
    t.write_random_spheres(data, 40, box, 0.1, 0.2, seed=2)
    atoms = read_atoms(data)
    mass, volume = sum(a[0] for a in atoms), sum(a[1] for a in atoms)
    for width in (0.5, 1e4, 1e300):
        sub = os.path.join(wd, "wide.%g" % width)
        os.mkdir(sub)
        text = RANDOM.format(boundary="p p f", data=data, pair="granular",
                             coeffs="hooke 1000 0 tangential linear_nohistory 0 0.5") + cg_lines(grid, width, ["solid", "density"])
        start = time.time()
        try:
            rc, out = t.run_lmp(text, sub, name="in.cg", timeout=120)
        except subprocess.TimeoutExpired:
            t.check(False, "W = %g: compute griddem/cg did not finish within 120 s" % width)
            continue
        seconds = time.time() - start
        t.check(rc == 0, "W = %g runs (exit %d): %s" % (width, rc, t.errors(out)[:1]))
        if rc:
            continue
        print("W = %g: %.2f s for the run" % (width, seconds))
        f = read_fields(sub, ["solid", "density"])
        if width == 0.5:
            continue
        for v, total in (("solid", volume), ("density", mass)):
            flat = total / (box[0] * box[1] * width * math.sqrt(2.0 * math.pi))
            worst = max(abs(x - flat) for x in f[v])
            if width > 1e100:
                t.check(all(x == 0.0 for x in f[v]), "W = %g: %s underflows to 0 everywhere" % (width, v))
            else:
                t.check(worst <= 1e-6 * flat, "W = %g: %s flat at %.6g (off by %.3g)" % (width, v, flat, worst))


LATTICE = """
units lj
atom_style sphere
boundary p p {zboundary}
comm_modify vel yes
lattice sc 1.0 origin 0.37 0.21 0.55
region b block 0 {n} 0 {n} 0 {nz}
create_box 1 b
create_atoms 1 box
set group all diameter {diameter}
variable shear atom {gamma}*z
velocity all set v_shear 0.25 -0.5
pair_style granular
pair_coeff * * hooke 1000 0 tangential linear_nohistory 0 0.5
"""


def check_lattice(wd):
    """Simple cubic lattice of spacing 1 = grid spacing, shifted off the grid points so each atom
    splits its weights: cloud-in-cell then gives every point the same mass, so solid fraction and
    coordination are exact; and vx = gamma z comes back with slope gamma away from walls."""
    d, n = 1.001, 6
    sub = os.path.join(wd, "lattice")
    os.mkdir(sub)
    t.run_ok(LATTICE.format(zboundary="p", n=n, nz=n, diameter=d, gamma=0.0) +
             cg_lines((n, n, n), 0.8, ["solid", "coordination", "vy", "temperature"]), sub, name="in.cg")
    f = read_fields(sub, ["solid", "coordination", "vy", "temperature"])
    packing = math.pi / 6.0 * d ** 3
    t.check(max(abs(s - packing) for s in f["solid"]) <= 1e-12 * packing,
            "lattice: solid fraction = packing fraction pi d^3/6 = %.12g (%.12g..%.12g)" % (packing, min(f["solid"]), max(f["solid"])))
    t.check(max(abs(c - 6.0) for c in f["coordination"]) <= 1e-12,
            "lattice of touching spheres: 6 contacts per particle (%.15g..%.15g)" % (min(f["coordination"]), max(f["coordination"])))
    t.check(max(abs(v - 0.25) for v in f["vy"]) <= 1e-12, "common velocity 0.25 recovered")
    t.check(max(abs(T) for T in f["temperature"]) <= 1e-12, "no fluctuation, no temperature")

    gamma, nz, width = 0.5, 16, 0.6
    for ranks in (1, 2):
        sub = os.path.join(wd, "shear.np%d" % ranks)
        os.mkdir(sub)
        t.run_ok(LATTICE.format(zboundary="f", n=n, nz=nz, diameter=d, gamma=gamma) +
                 cg_lines((n, n, nz), width, ["vx"]), sub, nprocs=ranks, name="in.cg")
        vx = read_fields(sub, ["vx"])["vx"]
        reach = int(math.floor(width * math.sqrt(-2.0 * math.log(NEGLIGIBLE))))
        # interior points: the kernel reaches neither wall nor the wall point the clamp loads
        worst = 0.0
        for k in range(reach + 1, nz - reach - 1):
            for j in range(n * n):
                worst = max(worst, abs(vx[j + n * n * k] - gamma * (k + 0.5)) / (gamma * nz))
        t.check(worst <= 1e-12, "%d ranks: linear shear vx = gamma z at interior points (rel. %.3g)" % (ranks, worst))
        slope = (vx[n * n * (nz - reach - 2)] - vx[n * n * (reach + 1)]) / (nz - 2 * reach - 3)
        t.check(abs(slope - gamma) <= 1e-12 * gamma, "%d ranks: slope %.15g = gamma %g" % (ranks, slope, gamma))


BED = """
units lj
atom_style sphere
boundary p p f
comm_modify vel yes
lattice sc 0.7 origin 0.5 0.5 0.5
region box block 0 12 0 12 0 24
create_box 1 box
region fill block 0 12 0 12 0 12
create_atoms 1 region fill
set group all diameter 1.0
velocity all create 0.1 7 loop geom
pair_style griddem/hooke/history 2000 NULL 20 NULL 0.5 1
pair_coeff * *
fix walls all wall/gran hooke/history 2000 NULL 20 NULL 0.5 1 zplane 0 NULL
fix gravity all gravity 1.0 vector 0 0 -1
fix damp all viscous 0.5
fix integrate all nve/sphere
timestep 0.002
run 8000
"""


def check_static_bed(wd):
    """Momentum balance: in a bed settled on a floor under gravity g = 1, the coarse-grained pzz at
    each height equals the weight of the material above it per unit area, g times the integral
    of the coarse-grained density above (measured to 0.7%; 3% allowed for what the damped bed
    still moves), at heights beyond 3 W from the floor (W = 1.5), where less than 0.2% of the
    kernel reaches past the wall."""
    rc, out = t.run_lmp(BED + cg_lines((12, 12, 24), 1.5, ["density", "pzz"]), wd, name="in.bed")
    t.check(rc == 0, "settled bed runs (exit %d)" % rc)
    if rc:
        return
    rho, pzz = (read_vti(os.path.join(wd, "%s.8000.vti" % v)) for v in ("density", "pzz"))
    nxy, dz = 144, (1.0 / 0.7) ** (1.0 / 3.0)    # lattice sc 0.7: the box is 24 lattice spacings high
    plane = lambda f, k: sum(f[k * nxy:(k + 1) * nxy]) / nxy
    worst = 0.0
    for k in range(24):
        above = sum(plane(rho, m) for m in range(k + 1, 24)) * dz + 0.5 * plane(rho, k) * dz
        if (k + 0.5) * dz > 4.5 and above > 0.5:
            worst = max(worst, abs(plane(pzz, k) - above) / above)
    print("settled bed: |pzz - weight above| / weight <= %.3g beyond 3 W from the floor" % worst)
    t.check(worst <= 0.03, "settled bed: pzz = weight of the material above (relative %.3g)" % worst)


def check_time_average(wd):
    """fix ave/grid of the fields, a stress value among them (fix ave/grid schedules grid computes
    only at the start of its windows and reads their data without clearing their invoked flags;
    the compute then recomputes stale fields and asks for the per-atom virial every step): its
    average over steps 6-10 equals the mean of the fields dumped on each of those steps."""
    data = os.path.join(wd, "data.avg")
    t.write_random_spheres(data, 300, (4.0, 4.0, 4.0), 0.1, 0.3, seed=11)
    head = RANDOM.format(boundary="p p p", data=data, pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1", coeffs="")
    head += "timestep 1e-4\ncompute cg all griddem/cg 8 6 5 0.45 vx pzz\n"
    sub = os.path.join(wd, "avg")
    os.mkdir(sub)
    for value in ("vx", "pzz"):
        averaged = head + ("fix avg all ave/grid 1 5 10 8 6 5 c_cg:grid:%s\n"
                           "dump a all grid/vtk 10 %savg.*.vti f_avg:grid:data\n"
                           "dump_modify a format float %%.17g\nrun 10\n") % (value, value)
        rc, out = t.run_lmp(averaged, sub, name="in.avg")
        t.check(rc == 0, "fix ave/grid averages %s (exit %d): %s" % (value, rc, t.errors(out)[:1]))
        t.run_ok(head + "dump p all grid/vtk 1 %s.*.vti c_cg:grid:%s\ndump_modify p format float %%.17g\nrun 10\n"
                 % (value, value), sub, name="in.each")
        if rc:
            continue
        steps = [read_vti(os.path.join(sub, "%s.%d.vti" % (value, k))) for k in range(6, 11)]
        mean = [sum(v) / len(v) for v in zip(*steps)]
        diff = max_diff(read_vti(os.path.join(sub, "%savg.10.vti" % value)), mean) / max(abs(v) for v in mean)
        t.check(diff <= 1e-12, "fix ave/grid of %s over steps 6-10 = mean of the per-step fields (rel. %.3g)" % (value, diff))


def check_long_average(wd):
    """fix ave/grid over 2000 steps, past the samples that fix ave/grid (LAMMPS 4Feb2025) never
    announces to the computes: the second of a window with nevery 2 (step 804), the first of the
    second window with nevery 1 (step 1901). The kernel is far wider than the periodic box and the
    total momentum zero, so every grid point of pzz and pxy is the box's pressure tensor of compute
    pressure: fix ave/time of it over the same samples is the reference at steps 1000 and 2000."""
    data = os.path.join(wd, "data.long")
    t.write_random_spheres(data, 300, (4.0, 4.0, 4.0), 0.1, 0.3, seed=11)
    head = RANDOM.format(boundary="p p p", data=data, pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1", coeffs="")
    head += "velocity all zero linear\ntimestep 1e-4\ncompute cg all griddem/cg 8 6 5 1e3 pzz pxy\n"
    for every in (2, 1):
        sub = os.path.join(wd, "long.%d" % every)
        os.mkdir(sub)
        text = head + ("fix avg all ave/grid {0} 100 1000 8 6 5 c_cg:grid:pzz c_cg:grid:pxy\n"
                       "fix avt all ave/time {0} 100 1000 c_P[3] c_P[4]\n"
                       "dump zz all grid/vtk 1000 pzz.*.vti f_avg:grid:data[1]\n"
                       "dump xy all grid/vtk 1000 pxy.*.vti f_avg:grid:data[2]\n"
                       "dump_modify zz format float %.17g\ndump_modify xy format float %.17g\n"
                       "thermo_style custom step f_avt[1] f_avt[2]\nthermo_modify format float %.17g\nthermo 1000\nrun 2000\n").format(every)
        rc, out = t.run_lmp(text, sub, name="in.long")
        t.check(rc == 0, "fix ave/grid %d 100 1000 of pzz and pxy runs 2000 steps (exit %d): %s"
                % (every, rc, t.errors(out)[:1]))
        if rc:
            continue
        reference = list(zip(t.thermo_values(out, "f_avt[1]"), t.thermo_values(out, "f_avt[2]")))[1:]
        for step, (zz, xy) in zip((1000, 2000), reference):
            worst = max(max_diff(read_vti(os.path.join(sub, "%s.%d.vti" % (v, step))), [ref] * 240)
                        for v, ref in (("pzz", zz), ("pxy", xy))) / abs(zz)
            t.check(worst <= 1e-12, "fix ave/grid %d 100 1000 at step %d: pzz and pxy = compute pressure's "
                    "averaged by fix ave/time (rel. %.3g)" % (every, step, worst))


def check_doc_example(wd):
    """The Examples block of doc/compute_griddem_cg.md as written, for 1000 steps on spheres in a
    periodic 4 x 1 x 4 box: it runs (its fix ave/grid samples a stress-carrying compute every 10
    steps), and the dumped density and velocity carry the total mass and momentum."""
    doc = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "doc", "compute_griddem_cg.md")
    with open(doc) as f:
        block = f.read().split("## Examples")[1].split("```")[1]
    data = os.path.join(wd, "data.doc")
    t.write_random_spheres(data, 1600, (4.0, 1.0, 4.0), 0.05, 0.1, seed=5)
    atoms = read_atoms(data)
    mass = sum(a[0] for a in atoms)
    text = RANDOM.format(boundary="p p p", data=data, pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1", coeffs="")
    text += "timestep 1e-4\n" + block + ("dump_modify cells format float %.17g\nrun 1000\n"
                                         "print \"momentum $(vcm(all,x)*mass(all):%.17g)\"\n")
    sub = os.path.join(wd, "doc")
    os.mkdir(sub)
    rc, out = t.run_lmp(text, sub, name="in.doc")
    t.check(rc == 0, "doc/compute_griddem_cg.md's Examples block runs 1000 steps (exit %d): %s" % (rc, t.errors(out)[:1]))
    if rc:
        return
    with open(os.path.join(sub, "cg.1000.txt")) as f:
        rows = [[float(w) for w in line.split()] for line in f.read().split("ITEM: GRID CELLS")[1].splitlines()[1:] if line.strip()]
    cellvol = 4.0 * 1.0 * 4.0 / len(rows)
    momentum = float(out.split("momentum ")[-1].split()[0])
    dumped = (sum(r[0] for r in rows) * cellvol, sum(r[0] * r[1] for r in rows) * cellvol)
    t.check(len(rows) == 16000 and abs(dumped[0] - mass) <= 1e-12 * mass,
            "doc example: density integrates to the total mass (%.17g against %.17g)" % (dumped[0], mass))
    t.check(abs(dumped[1] - momentum) <= 1e-12 * mass,
            "doc example: density x vx integrates to the total x momentum (%.17g against %.17g)" % (dumped[1], momentum))


def check_deform_ranks(wd):
    """Under fix deform's remap the coordination at a dump step (after the remap, before the next
    step's communication) is the same on 1 and 2 ranks: the compute brings the ghosts to their
    atoms' remapped places before it counts contacts."""
    data = os.path.join(wd, "data.deform")
    t.write_random_spheres(data, 300, (4.0, 4.0, 4.0), 0.1, 0.3, seed=12)
    text = RANDOM.format(boundary="p p p", data=data, pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1",
                         coeffs="") + """compute cg all griddem/cg 5 4 6 0.8 coordination
dump g all grid/vtk 10 coordination.*.vti c_cg:grid:coordination
dump_modify g format float %.17g
timestep 1e-3
fix d all deform 1 x final 0 4.6 z final -0.3 4.3 remap x
run 10
"""
    fields = []
    for ranks in (1, 2):
        sub = os.path.join(wd, "deform.np%d" % ranks)
        os.mkdir(sub)
        t.run_ok(text, sub, nprocs=ranks, name="in.deform")
        fields.append(read_vti(os.path.join(sub, "coordination.10.vti")))
    worst = max_diff(fields[0], fields[1]) / max(max(fields[0]), 1e-300)
    t.check(max(fields[0]) > 0.0 and worst <= 1e-12, "fix deform: coordination on 2 ranks as on 1 (rel. %.3g, largest %.3g)"
            % (worst, max(fields[0])))


def check_deform_density(wd):
    """The density after fix deform stretched the box (a new grid spacing, so a new kernel on the
    grid) equals the direct convolution of the atoms where they are then, in the new box."""
    data = os.path.join(wd, "data.stretch")
    grid, width = (8, 6, 5), 0.45
    t.write_random_spheres(data, 300, (4.0, 4.0, 4.0), 0.1, 0.3, seed=13)
    text = RANDOM.format(boundary="p p p", data=data, pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1",
                         coeffs="") + """compute cg all griddem/cg %d %d %d %.17g density
dump g all grid/vtk 10 density.*.vti c_cg:grid:density
dump_modify g format float %%.17g
dump a all custom 10 atoms.*.txt id mass x y z
dump_modify a format float %%.17g
timestep 1e-3
fix d all deform 1 x final 0 5.0 remap x
run 10
""" % (grid + (width,))
    sub = os.path.join(wd, "stretch")
    os.mkdir(sub)
    t.run_ok(text, sub, name="in.stretch")
    snapshot = t.dump.last_snapshot(os.path.join(sub, "atoms.10.txt"))
    lengths = [hi - lo for lo, hi in (row[:2] for row in snapshot.box)]
    atoms = [(a["mass"], 0.0, a["x"], a["y"], a["z"]) for a in snapshot.atoms()]
    direct = direct_density(atoms, grid, lengths, width, (True, True, True))
    field = read_vti(os.path.join(sub, "density.10.vti"))
    diff = max_diff(field, direct) / max(direct)
    t.check(abs(lengths[0] - 5.0) <= 1e-12 and diff <= 1e-12,
            "box stretched to %.6g along x: density = direct convolution in the new box (rel. %.3g)" % (lengths[0], diff))


def check_narrow_kernel(wd):
    """A kernel whose truncation radius (8.85 W) is below every grid spacing reaches no other grid
    point: the density is cloud-in-cell alone, the direct convolution's to rounding, and sums to
    the mass."""
    data = os.path.join(wd, "data.narrow")
    box, grid, width = (4.0, 4.0, 4.0), (8, 6, 5), 0.05
    t.write_random_spheres(data, 300, box, 0.1, 0.3, seed=14)
    atoms = read_atoms(data)
    text = RANDOM.format(boundary="p p p", data=data, pair="griddem/hooke/history 1e3 NULL 10 NULL 0.5 1",
                         coeffs="") + cg_lines(grid, width, ["density"])
    sub = os.path.join(wd, "narrow")
    os.mkdir(sub)
    t.run_ok(text, sub, name="in.narrow")
    field = read_fields(sub, ["density"])["density"]
    direct = direct_density(atoms, grid, box, width, (True, True, True))
    diff = max_diff(field, direct) / max(direct)
    mass = sum(a[0] for a in atoms)
    total = sum(field) * box[0] * box[1] * box[2] / (grid[0] * grid[1] * grid[2])
    t.check(diff <= 1e-12 and abs(total - mass) <= 1e-12 * mass,
            "W = %g (reach %.3g below the spacing 0.5): density = direct convolution (rel. %.3g), mass %.17g of %.17g"
            % (width, 8.85 * width, diff, total, mass))


def check_errors(wd):
    rc, out = t.run_lmp("units lj\natom_style sphere\ncompute c all griddem/cg 2 2 2 0.5 density\n", wd, name="in.nobox")
    t.check(rc != 0 and "Compute griddem/cg command before simulation box is defined" in out,
            "compute griddem/cg before the box: an error, not a crash (%s)" % t.errors(out)[:1])
    base = "units lj\natom_style sphere\n%s\nregion b block 0 1 0 1 0 1\ncreate_box 1 b\ncompute c all griddem/cg %s\n"
    for dim, args, expect in [("", "2 2 2 0.5 density stress", "unknown value stress"),
                              ("", "2 2 2 0 density", "kernel width W must be > 0, not 0"),
                              ("", "2 0 2 0.5 density", "grid count Ny must be at least 1, not 0"),
                              ("", "2 2 2 0.5", "Illegal compute griddem/cg command: missing argument"),
                              ("dimension 2\nboundary p p p", "2 2 1 0.5 density", "requires a 3d simulation")]:
        text = base % (dim, args)
        if dim:
            text = text.replace("0 1 0 1 0 1", "0 1 0 1 -0.5 0.5")
        rc, out = t.run_lmp(text, wd, name="in.bad")
        t.check(rc != 0 and expect in out, "compute griddem/cg %s: '%s'" % (args, expect))


def main():
    wd = t.workdir()
    check_random(wd, "griddem/hooke/history 1e3 NULL 10 NULL 0.5 1", "", "griddem", (1, 2, 4))
    check_random(wd, "granular", "hooke 1000 0.5 tangential linear_history 500 0.5 0.5", "stock", (1, 2))
    check_wall(wd)
    check_nonnegative(wd)
    check_wide_kernel(wd)
    check_lattice(wd)
    check_static_bed(wd)
    check_time_average(wd)
    check_long_average(wd)
    check_doc_example(wd)
    check_deform_ranks(wd)
    check_deform_density(wd)
    check_narrow_kernel(wd)
    check_errors(wd)
    t.finish()


if __name__ == "__main__":
    main()
