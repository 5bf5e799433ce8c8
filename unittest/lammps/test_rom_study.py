"""bench/rom.py, the reduced-order study, and bench/romerror.py, its errors:
- the baseline is the resolved pair style with the smaller median loop time (hand-fed times where
  the fastest single run and the fastest median disagree);
- each error is 0 for identical fields, and for a uniform offset the offset over the scale it is
  relative to: velocity |dv| / V_c, temperature dT / T_c, surface height sum |dh| / sum h; V_c of a
  uniform field is its speed; the worst tenth of a series is the mean of its largest tenth;
- the same through error_series on hand-made grid frames (two voxel columns above the floor);
  surface heights per (x, y) column of a frame two voxels deep;
- the blade's open-loop accuracy of a model field off by a known offset (form linear on the
  blade's velocity, form occupancy on its cut's controls, read by name), and the model file's
  round trip; in.blade refuses a blade shape or controls it does not have, by name; the blade's force read from
  fix ave/time's columns of its walls (minus their sum) and of the model's prediction;
- a smoke run of the pile study (a tiny horizon: 1000 steps, two training widths) writes a record
  with every field the issue names, a speed-up against the faster baseline of its own loop times,
  the scanned skin that ran fastest, and a griddem resolved run that equals stock's of the same
  seed (gran/hooke/history parity: accuracies 1 to 1e-8), and the figure of the errors over time
  with the reduced run, the do-nothing run and the three pairs of stock seeds."""
import json
import os
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

t.require_modules(["numpy"], "bench/romerror.py needs numpy", skip=False)
import numpy as np  # noqa: E402

TOP = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(TOP, "bench"))
sys.path.insert(0, os.path.join(TOP, "python"))
import romerror  # noqa: E402
import romfigure  # noqa: E402
from griddemtools.grid import GridFrame  # noqa: E402
from rom import pick_baseline  # noqa: E402

WD = t.workdir()


def baseline():
    # stock's fastest run (1.0) beats griddem's 1.5, its median (2.0) does not
    t.check(pick_baseline({"gran/hooke/history": [3.0, 1.0, 2.0], "griddem/hooke/history": [1.5]}) ==
            ("griddem/hooke/history", 1.5), "baseline: the smaller median, griddem's 1.5 against stock's 2.0")
    t.check(pick_baseline({"granular": [3.0, 1.0, 2.0], "griddem/granular": [2.5]}) == ("granular", 2.0),
            "baseline: stock's median 2.0 against griddem's 2.5")


def errors():
    rho = [0.2, 1.0, 0.6]
    v = [[0.1, 0.0, -0.3], [0.5, 0.2, 0.0], [-0.4, 0.0, 0.7]]
    dv = np.array([0.3, 0.0, -0.4])   # |dv| = 0.5
    t.check(romerror.velocity_error(rho, v, v, 2.0) == 0.0, "velocity error 0 for identical fields")
    e = romerror.velocity_error(rho, v, np.array(v) + dv, 2.0)
    t.check(abs(e - 0.25) < 1e-15, "velocity error of a uniform offset 0.5 at V_c 2: %.17g (0.25)" % e)
    temp = [0.01, 0.03, 0.02]
    t.check(romerror.temperature_error(rho, temp, temp, 0.5) == 0.0, "temperature error 0 for identical fields")
    e = romerror.temperature_error(rho, temp, np.array(temp) + 0.1, 0.5)
    t.check(abs(e - 0.2) < 1e-15, "temperature error of an offset 0.1 at T_c 0.5: %.17g (0.2)" % e)
    h = [1.0, 2.0, 3.0, 4.0]
    t.check(romerror.height_error(h, h) == 0.0, "height error 0 for identical surfaces")
    e = romerror.height_error(h, [1.5, 1.5, 3.5, 3.5])
    t.check(abs(e - 0.2) < 1e-15, "height error: 4 columns off by 0.5 over a volume 10: %.17g (0.2)" % e)
    s = romerror.characteristic_speed([rho, rho], [[[0.0, 3.0, 0.0]] * 3] * 2)
    t.check(abs(s - 3.0) < 1e-15, "V_c of a uniform field of speed 3: %.17g" % s)
    mean, worst = romerror.summary(list(range(1, 21)))
    t.check(mean == 10.5 and worst == 19.5, "summary of 1..20: mean %g (10.5), worst tenth %g (19.5)" % (mean, worst))


def frame(step, density, vx, temperature):
    """A 2 x 1 x 2 grid dump frame over x 0..2, z -1..1: voxel row z < 0 below the floor."""
    n = len(density)
    return GridFrame(step, [0.0, 2.0, 0.0, 1.0, -1.0, 1.0], (2, 1, 2), [],
                     dict(density=density, vx=vx, vy=[0.0] * n, vz=[0.0] * n, temperature=temperature))


def series():
    res = [frame(s, [0.3, 0.3, 0.6, 0.3], [0.0, 0.0, 2.0, 2.0], [0.1] * 4) for s in (0, 250)]
    same = romerror.error_series(res, res)
    t.check(same["steps"] == [0, 250] and all(max(same[k]) == 0.0 for k in ("velocity", "height", "temperature")),
            "error series 0 against itself: %s" % {k: same[k] for k in ("velocity", "height", "temperature")})
    # V_c: the density-weighted RMS speed, sqrt((0.6 * 4 + 0.3 * 4) / 1.5) = sqrt(2.4)
    rom = [frame(s, [0.3, 0.3, 0.3, 0.6], [0.5, 0.5, 2.5, 2.5], [0.15] * 4) for s in (0, 250)]
    e = romerror.error_series(res, rom)
    t.check(abs(e["characteristic_speed"] - 2.4 ** 0.5) < 1e-14, "V_c %.17g (sqrt 2.4)" % e["characteristic_speed"])
    t.check(all(abs(x - 0.5 / 2.4 ** 0.5) < 1e-14 for x in e["velocity"]),
            "uniform vx offset 0.5: velocity error %s (0.5 / sqrt 2.4)" % e["velocity"])
    # T_c = 0.1: offset 0.05 -> 0.5; heights above z = 0: columns 0.6, 0.3 against 0.3, 0.6 (over a
    # bulk density): |dh| sums to 0.6, the volume 0.9
    t.check(all(abs(x - 0.5) < 1e-14 for x in e["temperature"]), "temperature error %s (0.5)" % e["temperature"])
    t.check(all(abs(x - 0.6 / 0.9) < 1e-14 for x in e["height"]), "height error %s (2/3)" % e["height"])
    acc = romerror.accuracies(e)
    t.check(abs(acc["velocity_accuracy"] - (1 - 0.5 / 2.4 ** 0.5)) < 1e-14 and
            acc["height_accuracy_worst10"] == acc["height_accuracy"], "accuracies one minus the errors: %s" % acc)


def columns_3d():
    """A 2 x 2 x 2 frame (x 0..2, y 0..1, z -1..1): heights per (x, y) column, x fastest; a surface
    that moves material from one y column to the other at equal means along y is an error (the
    paper's blade leaves berms beside its path)."""
    from griddemtools.rom import heights

    def frame3(density_above):
        rho = [0.0] * 4 + list(density_above)    # the voxel layer below the floor, then above
        return GridFrame(0, [0.0, 2.0, 0.0, 1.0, -1.0, 1.0], (2, 2, 2), [], dict(density=rho))
    h = heights(frame3([0.6, 0.3, 0.0, 0.3]))
    t.check(np.allclose(h, [1.0, 0.5, 0.0, 0.5], rtol=0, atol=1e-15), "heights per (x, y) column: %s" % h)
    e = romerror.height_error(heights(frame3([0.6, 0.3, 0.0, 0.3])), heights(frame3([0.0, 0.3, 0.6, 0.3])))
    t.check(abs(e - 1.0) < 1e-15, "height error of material moved across y at equal y means: %.17g (1)" % e)


def open_loop():
    """The blade's open-loop accuracy (bench/rom.py open_loop_accuracy) of a model whose field is
    the snapshot's own plus 0.5 in x in every voxel: every atom moves at vx 1, so every filled voxel's
    speed is 1, V_c is 1 and the error 0.5: accuracy 0.5. The model file survives a round trip. The
    same field from a model of form occupancy on the cut controls (each filled voxel's weight its
    field over its density), with a force block of the weights' 4 columns; a controls file without
    the cut's columns is refused naming them."""
    from rom import open_loop_accuracy
    from griddemtools.rom import read_model, write_model
    from griddemtools.blade import ATOMS, CONTROLS, FRAMES, load_run
    FRAME_N, FRAME_BOX = FRAMES["block"]
    wd = os.path.join(WD, "openloop")
    os.makedirs(wd, exist_ok=True)
    here = os.getcwd()
    os.chdir(wd)
    try:
        atoms = [(1, 0.5, 0.5), (2, 3.2, 1.7), (3, 3.4, 1.9), (4, -2.0, 3.1)]   # id, x, z; blade at bx 0
        with open(ATOMS % "t", "w") as f:    # a text dump: the reader takes either
            f.write("ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n%d\n" % len(atoms))
            f.write("ITEM: BOX BOUNDS pp pp ff\n-10 30\n0 1\n0 6\nITEM: ATOMS id x y z vx vy vz mass v_kin\n")
            f.writelines("%d %g 0.5 %g 1 0 0 %g 0\n" % (i, x, z, 0.5 + 0.1 * i) for i, x, z in atoms)
        with open("controls.t.txt", "w") as f:
            f.write("# step bx bz vbx vbz cutx cutz depth\n100 0 0 0.5 0 0.1 0 0.2\n")
        with open("force.t.txt", "w") as f:
            f.write("# Time-averaged data for fix force\n# TimeStep c_onspheres[1] c_onspheres[2]\n100 -1 -2\n")
        X, Y, _ = load_run("t", FRAMES["block"], CONTROLS["velocity"])
        nvox = FRAME_N[0] * FRAME_N[1] * FRAME_N[2]
        W = np.zeros((3 * nvox, 1 + nvox + 2))
        W[:, 0] = Y[0] + np.tile([0.5, 0.0, 0.0], nvox)
        write_model("m.model", FRAME_N, FRAME_BOX, 1.0, W, frame="moving", force=np.zeros((3, W.shape[1])))
        m = read_model("m.model")
        t.check(m["n"] == FRAME_N and m["box"] == FRAME_BOX and m["frame"] == "moving" and m["controls"] == 2 and
                np.array_equal(m["weights"], W) and m["force"].shape == (3, W.shape[1]), "model file round trip")
        acc = open_loop_accuracy("m.model", "t", "velocity")
        t.check(acc["open_loop_frames"] == 1 and abs(acc["open_loop_velocity_accuracy"] - 0.5) < 1e-12,
                "open-loop accuracy of a field off by 0.5 at speed 1: %s (0.5)" % acc)
        Xc, _, _ = load_run("t", FRAMES["block"], CONTROLS["cut"])
        rho = np.repeat(Xc[0, :nvox], 3)
        t.check(np.array_equal(Xc[0, nvox:], [0.1, 0.0, 0.2]), "the cut's controls by name: %s" % Xc[0, nvox:])
        Wo = np.zeros((3 * nvox, 4))
        Wo[:, 0] = np.divide(W[:, 0], rho, out=np.zeros_like(rho), where=rho > 0)
        write_model("o.model", FRAME_N, FRAME_BOX, 1.0, Wo, frame="moving", force=np.ones((3, 4)), form="occupancy")
        acc = open_loop_accuracy("o.model", "t", "cut")
        t.check(read_model("o.model")["force"].shape == (3, 4) and abs(acc["open_loop_velocity_accuracy"] - 0.5) < 1e-9,
                "form occupancy, cut controls: open-loop accuracy %s (0.5; the file's weights to 10 digits)" % acc)
        with open("controls.t.txt", "w") as f:
            f.write("# step bx bz vbx vbz\n100 0 0 0.5 0\n")
        try:
            load_run("t", FRAMES["block"], CONTROLS["cut"])
            refused = ""
        except ValueError as e:
            refused = str(e)
        t.check("has no column cutx cutz depth" in refused, "a controls file without the cut's columns: %r" % refused)
    finally:
        os.chdir(here)


REQUIRED = ["build", "baseline", "speedup", "velocity_accuracy", "height_accuracy", "temperature_accuracy",
            "do_nothing_velocity_accuracy", "do_nothing_height_accuracy", "left_out", "stock_skin", "skin_scan",
            "noise_velocity_accuracy", "noise_height_accuracy", "velocity_accuracy_worst10", "height_accuracy_worst10"]


def blade_force_file():
    """griddemtools.blade.read_force: the blade's force is minus the sum of its walls' forces on the
    spheres (x at the odd columns of c_onspheres, z at the even), the prediction f_rom[14] and [16]
    as they are, 0 where a resolved run has none."""
    from griddemtools.blade import read_force
    here = os.getcwd()
    os.chdir(WD)
    try:
        with open("force.plates.txt", "w") as f:
            f.write("# Time-averaged data for fix force\n# TimeStep c_onspheres[1] c_onspheres[2] c_onspheres[3] "
                    "c_onspheres[4] f_rom[14] f_rom[16]\n100 1 2 3 4 5 6\n200 -1 0.5 0.25 0 7 8\n")
        with open("force.block.txt", "w") as f:
            f.write("# Time-averaged data for fix force\n# TimeStep c_onspheres[1] c_onspheres[2]\n100 -1 -2\n")
        plates, block = read_force("plates"), read_force("block")
    finally:
        os.chdir(here)
    t.check(np.array_equal(plates, [[100, -4, -6, 5, 6], [200, 0.75, -0.5, 7, 8]]),
            "two walls and the prediction: %s" % plates.tolist())
    t.check(np.array_equal(block, [[100, 1, 2, 0, 0]]), "one wall, no prediction: %s" % block.tolist())


def kinematic_share():
    """griddemtools.rom.kinematic_series: the kinematic share of the scene's atoms (v_natoms, fix
    griddem/rom's f_rom[18], where the log has it: 4291 of 4300 while LAMMPS holds 44 and the store
    the rest), else of LAMMPS's (Atoms)."""
    from griddemtools.rom import kinematic_series
    header = "   Step          Time         Atoms        %sKinEng         v_nkin        v_nnear    \n"
    rows = ["      6000   3              4300   %s  0.001   4300   40\n", "      6500   3.25             44   %s  0.001   4291   35\n"]
    logs = {}
    for name, total in (("with", ("4300", "4300")), ("without", ("", ""))):
        text = header % ("v_natoms      " if total[0] else "") + "".join(r % n for r, n in zip(rows, total))
        logs[name] = os.path.join(WD, "log.share.%s" % name)
        with open(logs[name], "w") as f:
            f.write(text + "Loop time of 1 on 1 procs for 500 steps with 44 atoms\n")
    steps, share = kinematic_series(logs["with"])
    t.check(list(steps) == [6000, 6500] and np.allclose(share, [1.0, 4291 / 4300], rtol=0, atol=1e-15),
            "kinematic share of the scene's atoms (v_natoms): %s" % list(share))
    steps, share = kinematic_series(logs["without"])
    t.check(np.allclose(share, [1.0, 4291 / 44], rtol=0, atol=1e-12), "without v_natoms, of LAMMPS's atoms: %s" % list(share))


def blade_shape_refused():
    """examples/rom-blade's in.blade with a blade or controls it does not have stops before reading
    its bed, naming the value."""
    for var, value, expected in (("blade", "wedge", "in.blade: -var blade wedge: neither block nor plates"),
                                 ("controls", "force", "in.blade: -var controls force: neither velocity nor cut")):
        rc, out = t.run_lmp("include %s\n" % os.path.join(TOP, "examples", "rom-blade", "in.blade"), WD,
                            name="in.blade_%s" % value, extra=("-var", var, value))
        t.check(rc != 0 and expected in out, "in.blade -var %s %s refused by name (exit %d): %s" % (var, value, rc,
                                                                                                   out[-200:]))


def smoke():
    out = os.path.join(WD, "rom.jsonl")
    proc = subprocess.run([sys.executable, os.path.join(TOP, "bench", "rom.py"), "--lmp", t.LMP, "--steps", "1000",
                           "--train", "3,6", "--scan-steps", "200", "--work", os.path.join(WD, "work"), "--out", out,
                           "--figure", os.path.join(WD, "errors.png")],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    if proc.returncode != 0:
        print(proc.stdout[-3000:], file=sys.stderr)
    t.check(proc.returncode == 0, "bench/rom.py pile smoke run (exit %d)" % proc.returncode)
    if proc.returncode != 0:
        return
    with open(out) as f:
        rec = [json.loads(line) for line in f]
    t.check(len(rec) == 1, "one record")
    r = rec[0]
    missing = [k for k in REQUIRED if k not in r]
    t.check(not missing and r["left_out"] == {}, "record has every field: missing %s, left out %s"
            % (missing, r.get("left_out")))
    if missing:
        return
    times = r["loop_s"]
    medians = {s: statistics.median(times[s]) for s in ("gran/hooke/history", "griddem/hooke/history")}
    fastest = min(medians, key=medians.get)
    t.check(len(times["gran/hooke/history"]) == 3 and len(times["reduced"]) == 3 and "do_nothing" in times,
            "three stock runs, three reduced, one do-nothing: %s" % times)
    t.check(r["baseline"] == {"pair_style": fastest, "loop_s": medians[fastest]},
            "baseline the faster resolved style %s: %s" % (medians, r["baseline"]))
    t.check(abs(r["speedup"] - medians[fastest] / statistics.median(times["reduced"])) < 1e-12,
            "speed-up against the baseline: %s" % r["speedup"])
    scan = r["skin_scan"]["loop_s"]
    t.check(float(min(scan, key=scan.get)) == r["stock_skin"], "the fastest scanned skin %s: %s" % (scan, r["stock_skin"]))
    t.check(len(r["noise_velocity_accuracy"]) == 3, "noise floor: three pairs of seeds")
    parity = [r["griddem_vs_stock_%s_accuracy" % k] for k in ("velocity", "height", "temperature")]
    t.check(all(abs(1.0 - p) < 1e-8 for p in parity), "griddem resolved equals stock of its seed: %s" % parity)
    t.check(all(np.isfinite(r[k]) for k in REQUIRED[3:8]), "accuracies finite")
    # the errors over time: the reduced and do-nothing runs and the three pairs of stock seeds
    t.check(os.path.getsize(os.path.join(WD, "errors.png")) > 10000, "errors-over-time figure written")
    drawn = romfigure.draw(os.path.join(WD, "work", os.listdir(os.path.join(WD, "work"))[0]), os.path.join(WD, "again.png"))
    t.check(drawn == ["reduced", "do-nothing", "noise floor (stock seeds)", None, None],
            "figure curves: %s" % drawn)


baseline()
errors()
series()
columns_3d()
open_loop()
blade_force_file()
kinematic_share()
blade_shape_refused()
smoke()
t.finish()
