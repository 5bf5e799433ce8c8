#!/usr/bin/python3
"""Adaptive reduced-order DEM against the faster of two resolved runs, one study per command:

    /usr/bin/python3 bench/rom.py [--scene pile] [--W 20 --H 26 --fill 9 --inlet 18] [--steps 30000]
                                  [--train 3,4,5,6] [--test 4.5] [--eps 0.1] [--every 10] [--block 0] [--walls rom_dynamic]
    /usr/bin/python3 bench/rom.py --scene hopper [--seg 10000] [--train-feed R,R,../R,R,../...]
                                  [--train-outlet J,J,../J,J,../...] [--test-feed R,R,..]
                                  [--test-outlet J,J,..] [--form occupancy|linear] [--components xz]
                                  [--eps 0.3] [--v0 0.36] [--every 50] [--drive match|dense|box]
                                  [--dense 0.5] [--overlap 0.1]
    /usr/bin/python3 bench/rom.py --scene blade|plates [--train-traj Z:P,Z:P,...] [--test-traj Z:P] [--steps 10000]
                                  [--eps 0.1] [--v0 0.45] [--every 500] [--drive box|match|dense] [--guard no|yes]
                                  [--overlap 1.0] [--controls cut|velocity] [--form occupancy|linear]
    common: [--seeds 8172,3391,5807] [--skins S,S,S] [--scan-steps N] [--repeats 3] [--build NAME]
            [--figure PNG]

Each scene's training runs and model are made once and kept in bench/work-rom/<scene folder>
(ignored; --work another folder); then, all at the test's control and horizon, on one core, one after the other:
1. the skin scan: the stock resolved run (the scene's griddem pair style's stock twin,
   gran/hooke/history or granular, with neighbor lists) for --scan-steps steps at each skin of
   --skins; the fastest skin is used and recorded;
2. three stock resolved runs with the seeds --seeds (timing repeats and the noise floor: the
   accuracies of each pair of them);
3. one griddem resolved run with the first seed: the reference fields of the reduced runs;
4. --repeats reduced runs (fix griddem/rom, first seed);
5. one do-nothing run: fix griddem/rom freeze yes, the atoms the model classifies kinematic held at
   rest.
The baseline is the faster resolved pair style (median loop time of its runs); speedup is its loop
time over the reduced runs' median. Errors (bench/romerror.py: velocity, granular temperature,
surface height above the container's floor and walls) are series over the run's field frames,
written to errors.TAG.txt; the record holds one minus their time mean (*_accuracy) and one minus
the mean of their worst tenth (*_accuracy_worst10). One JSON line is appended to
bench/results/rom.jsonl (model: the model file, named by its training runs, controls and form);
what the study could not measure is named with its reason in left_out.
The errors over time (bench/romfigure.py) go to the example's reference/errors.png.

Scene pile (examples/rom-pile): the outlet width is the control; --steps is the horizon of every
run. Scene hopper (examples/rom-hopper, the method's paper's pile, up to some 21,000 polydisperse
spheres): every run fills the empty container; the controls are the feed rate and the speed of the
kinematic outlet, histories of --seg-step segments (the test's last outlet speed beyond the
trained range); the model's form is occupancy (each voxel's velocity its density times a linear
function of the controls, vx and vz only); the reduced run drives the atoms that move with the
field (--drive match, overlap 0.1: with drive dense, atoms were lost, see the example's README).
Scene blade
(examples/rom-blade, 5,200 spheres): the bed is built once; a blade is lowered to z = Z, pushed at
speed P and raised (trajectory Z:P); the model's controls are the blade's cut (--controls cut: its
velocity times its depth below the bed's surface, and that depth), its form occupancy (each
voxel's velocity its density times a linear function of the controls); as the method's paper drives its
blade's grid, the reduced run drives every atom in the model's grid (--drive box, no guard region
kept resolved near the blade); adds the blade-force accuracies (griddemtools.blade.force_accuracy),
the open-loop accuracy, and without_fields: the stock runs (three seeds) and the reduced runs
again without the field and atom dumps the errors are measured on (in.blade -var fields no), and
the speed-up of their medians.
Scene plates (examples/rom-blade's 3D blade of the method's paper, 4,300 spheres): the same study
with in.blade's blade plates (two plates 1.6 wide, the lower leaning back 35 degrees) in a bed 10
long, 3.2 wide (y periodic) and about 1.0 high, cuts of one to two diameters (trajectories
0.6-0.8:P), the model's grid 10 x 8 x 5 voxels around the blade (griddemtools.blade.FRAMES)."""
import argparse
import contextlib
import datetime
import json
import os
import statistics
import subprocess
import sys

import benchlib
import romerror
import romfigure

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
EXAMPLE = os.path.join(ROOT, "examples", "rom-pile")
HOPPER = os.path.join(ROOT, "examples", "rom-hopper")
BLADE = os.path.join(ROOT, "examples", "rom-blade")
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
from griddemtools import lammps, log  # noqa: E402
from griddemtools.blade import ATOMS, CONTROLS, FIELDS, force_accuracy, load_run  # noqa: E402
from griddemtools.grid import read_grid_dump  # noqa: E402
from griddemtools.rom import kinematic_fraction, near_fraction, occupancy_fit, predict, read_model  # noqa: E402

# a scene's griddem pair style -> the stock LAMMPS style with neighbor lists that it twins
STOCK_TWIN = {"griddem/hooke/history": "gran/hooke/history", "griddem/granular": "granular"}


def pick_baseline(loop_times):
    """{pair style: [loop seconds of its runs]} -> (style, median seconds) of the faster style."""
    style = min(loop_times, key=lambda s: statistics.median(loop_times[s]))
    return style, statistics.median(loop_times[style])


def log_path(wd, tag):
    """A run's log (lmp_run writes log.TAG in the study's folder)."""
    return os.path.join(wd, "log." + tag)


def loop_seconds(wd, tag):
    """Loop time of a run (summed over the runs of its log: a run in segments has several)."""
    return sum(run.seconds for run in log.loop_times(log_path(wd, tag)))


@contextlib.contextmanager
def in_folder(wd):
    """Work in folder wd (the examples' readers of a run's files open them where the runs are)."""
    here = os.getcwd()
    os.chdir(wd)
    try:
        yield
    finally:
        os.chdir(here)


def open_loop_accuracy(model, tag, controls):
    """The blade model's velocity field predicted from the densities and controls (in.blade's
    -var controls) of resolved run tag's snapshots (open loop, the paper's measure of its blade
    model), against that run's own field on the model's grid: open_loop_velocity_accuracy and
    _worst10, as the forward runs' (density-weighted, relative to the run's characteristic speed).
    Run where the files are."""
    m = read_model(model)
    X, Y, _ = load_run(tag, (m["n"], m["box"]), CONTROLS[controls])
    nvox = m["n"][0] * m["n"][1] * m["n"][2]
    rho = X[:, :nvox]
    v_res = Y.reshape(len(Y), nvox, 3)
    field = occupancy_fit(nvox)[1] if m["form"] == "occupancy" else predict
    v_rom = field(m["weights"], X).reshape(len(Y), nvox, 3)
    speed = romerror.characteristic_speed(rho, v_res)
    errors = [romerror.velocity_error(rho[t], v_res[t], v_rom[t], speed) for t in range(len(Y))]
    mean, worst = romerror.summary(errors)
    return dict(open_loop_velocity_accuracy=1.0 - mean, open_loop_velocity_accuracy_worst10=1.0 - worst,
                open_loop_frames=len(errors))


def lmp_run(lmp, wd, inp, tag, variables, scene=None):
    """Runs an example input in wd on one thread with the given variables (a list value: several
    words); scene: the file its ${scene} includes."""
    args = ["-in", inp, "-log", "log." + tag, "-echo", "none", "-screen", "none", "-var", "tag", tag]
    if scene:
        args += ["-var", "scene", scene]
    for k, v in variables.items():
        args += ["-var", k] + (v if isinstance(v, list) else [str(v)])
    lammps.run(lmp, args, wd, output=None, check=True)


def trained(wd, script, model, inputs, options=()):
    """The model file (in wd), made by the example's training script (with options) from inputs
    unless it is there already."""
    if not os.path.exists(os.path.join(wd, model)):
        subprocess.run([sys.executable, script] + list(options) + [model] + inputs, cwd=wd, check=True,
                       stdout=subprocess.DEVNULL)
    return model


class Pile:
    """examples/rom-pile: the outlet width is the control."""
    pair = "griddem/hooke/history"
    form = "linear"    # the model's form unless --form says otherwise
    example = EXAMPLE
    skins = "0.1,0.2,0.4"
    fields = "cg.%s.txt"

    def __init__(self, a, lmp):
        self.a, self.lmp = a, lmp
        self.vars = dict(W=a.W, H=a.H, fill=a.fill, steps=a.steps)
        if a.inlet is not None:
            self.vars["inlet"] = a.inlet
        self.wd = os.path.join(a.work, "W%dH%d" % (a.W, a.H) + ("I%g" % a.inlet if a.inlet is not None
                                                                          else ""))
        self.name = "rom-pile W%d H%d fill %g inlet %g test w %g steps %d" % (
            a.W, a.H, a.fill, a.W - 2 if a.inlet is None else a.inlet, a.test, a.steps)
        self.name += settings_named(dict(form=a.form), dict(form=self.form))

    def run(self, tag, variables):
        lmp_run(self.lmp, self.wd, os.path.join(EXAMPLE, "in.rom-pile"), tag, dict(self.vars, **variables))

    def train(self):
        specs = []
        for w in self.a.train.split(","):
            tag = "train.w%s.s%d" % (w, self.a.steps)
            if not os.path.exists(os.path.join(self.wd, self.fields % tag)):
                self.run(tag, dict(w=w))
            specs.append("%s:%s" % (self.fields % tag, w))
        model = "rom.%s.s%d.%s.model" % (self.a.train.replace(",", "_"), self.a.steps, self.a.form)
        return trained(self.wd, os.path.join(EXAMPLE, "train_rom.py"), model, specs, ("--form", self.a.form))

    def test(self, scan=False):
        """The test's variables (scan: cut to --scan-steps)."""
        return dict(w=self.a.test, **(dict(steps=self.a.scan_steps) if scan else {}))

    def rom(self):
        return dict(eps=self.a.eps, every=self.a.every, block=self.a.block, walls=self.a.walls)


class Hopper:
    """examples/rom-hopper, the paper's pile: filled from empty, the feed rate and the outlet's
    speed are the controls, histories of --seg-step segments."""
    pair = "griddem/granular"
    form = "occupancy"
    example = HOPPER
    skins = "0.03,0.06,0.12"
    fields = "cg.%s.txt"

    def __init__(self, a, lmp):
        self.a, self.lmp = a, lmp
        self.wd = os.path.join(a.work, "hopper-paper")
        self.name = "rom-hopper seg %d train %s outlet %s test %s outlet %s model %s %s" % (
            a.seg, a.train_feed, a.train_outlet, a.test_feed, a.test_outlet, a.form, a.components)
        self.name += settings_named(self.rom(), HOPPER_DEFAULTS)

    def run(self, tag, variables):
        lmp_run(self.lmp, self.wd, os.path.join(HOPPER, "in.feed"), tag, variables,
                os.path.join(HOPPER, "in.hopper-scene"))

    def train(self):
        feeds, outlets = self.a.train_feed.split("/"), self.a.train_outlet.split("/")
        if len(feeds) != len(outlets):
            raise SystemExit("--train-feed and --train-outlet: as many histories each")
        specs = []
        for feed, outlet in zip(feeds, outlets):
            rates, speeds = segments(feed, outlet, "--train-feed %s and --train-outlet %s" % (feed, outlet))
            tag = "train.f%s.j%s.s%d" % (feed.replace(",", "_"), outlet.replace(",", "_"), self.a.seg)
            with open(os.path.join(self.wd, "ctl.%s.txt" % tag), "w") as f:
                f.write("# until_step feed_rate outlet_speed\n")
                f.writelines("%d %s %s\n" % ((k + 1) * self.a.seg, r, j) for k, (r, j) in enumerate(zip(rates, speeds)))
            if not os.path.exists(os.path.join(self.wd, self.fields % tag)):
                self.run(tag, dict(rate=rates, outlet_speed=speeds, seg=self.a.seg))
            specs.append("%s:@ctl.%s.txt" % (self.fields % tag, tag))
        model = "rom.%s.%s.%s.j%s.s%d.model" % (
            self.a.form, self.a.components, self.a.train_feed.replace(",", "_").replace("/", "-"),
            self.a.train_outlet.replace(",", "_").replace("/", "-"), self.a.seg)
        return trained(self.wd, os.path.join(EXAMPLE, "train_rom.py"), model, specs,
                       ["--form", self.a.form, "--components", self.a.components])

    def test(self, scan=False):
        rates, speeds = segments(self.a.test_feed, self.a.test_outlet, "--test-feed and --test-outlet")
        if scan:
            return dict(rate=rates[:1], outlet_speed=speeds[:1], seg=self.a.scan_steps)
        return dict(rate=rates, outlet_speed=speeds, seg=self.a.seg)

    def rom(self):
        return dict(eps=self.a.eps, v0=self.a.v0, every=self.a.every, drive=drive_setting(self.a),
                    overlap=self.a.overlap)


# in.blade's and in.feed's own defaults of the reduced run's settings (a record's scene names
# those chosen otherwise)
BLADE_DEFAULTS = dict(drive="match", guard="yes", overlap=0.1, controls="cut")
HOPPER_DEFAULTS = dict(drive="match", overlap=0.1)


def segments(feed, outlet, what):
    """A history's feed rates and outlet speeds, segment by segment (what: the options, named
    where their numbers of segments differ)"""
    rates, speeds = feed.split(","), outlet.split(",")
    if len(rates) != len(speeds):
        raise SystemExit("%s: as many segments each" % what)
    return rates, speeds


def settings_named(settings, defaults):
    """The settings that differ from an input's own defaults, as " key value" each"""
    return "".join(" %s %s" % (k, v) for k, v in settings.items() if defaults.get(k, v) != v)


def drive_setting(a):
    """fix griddem/rom's drive keyword's values from --drive and --dense"""
    return "dense %g" % a.dense if a.drive == "dense" else a.drive


class Blade:
    """examples/rom-blade: the blade's cut (or its velocity: --controls) is the control, the model's
    grid moves with it."""
    pair = "griddem/granular"
    form = "occupancy"
    example = BLADE
    skins = "0.03,0.06,0.12"
    fields = FIELDS
    folder, label, figure = "blade", "rom-blade", "errors.png"
    bed = {}          # in.build's variables
    geometry = {}     # in.blade's scene variables, every run's
    blade = "block"

    def __init__(self, a, lmp):
        self.a, self.lmp = a, lmp
        self.wd = os.path.join(a.work, self.folder)
        self.name = "%s train %s test %s steps %d" % (self.label, a.train_traj, a.test_traj, a.steps)
        self.name += settings_named(self.rom(), BLADE_DEFAULTS) + settings_named(dict(form=a.form), dict(form=self.form))

    def run(self, tag, variables, inp="in.blade"):
        lmp_run(self.lmp, self.wd, os.path.join(BLADE, inp), tag, dict(self.geometry, **variables),
                os.path.join(BLADE, "in.blade-scene"))

    def train(self):
        if not os.path.exists(os.path.join(self.wd, "bed.restart")):
            self.run("build", dict(self.bed), "in.build")
        tags = []
        for traj in self.a.train_traj.split(","):
            zlow, push = traj.split(":")
            tag = "train.z%s.p%s" % (zlow, push)
            if not os.path.exists(os.path.join(self.wd, ATOMS % tag)):
                self.run(tag, dict(zlow=zlow, push=push, adump=100))
            tags.append(tag)
        model = "rom.%s.%s.%s.model" % (self.a.train_traj.replace(":", "_").replace(",", "-"), self.a.controls,
                                        self.a.form)
        return trained(self.wd, os.path.join(BLADE, "train_blade.py"), model, tags,
                       ("--blade", self.blade, "--controls", self.a.controls, "--form", self.a.form))

    def test(self, scan=False):
        zlow, push = self.a.test_traj.split(":")
        return dict(zlow=zlow, push=push, steps=self.a.scan_steps if scan else self.a.steps)

    def rom(self):
        return dict(eps=self.a.eps, v0=self.a.v0, every=self.a.every, drive=drive_setting(self.a),
                    guard=self.a.guard, overlap=self.a.overlap, controls=self.a.controls)


class PaperBlade(Blade):
    """examples/rom-blade's 3D blade of the method's paper: two plates 1.6 wide (in.blade's blade
    plates) in a bed 10 long and 3.2 wide (y periodic), cutting up to two diameters deep."""
    folder, label, figure = "blade-plates", "rom-blade plates", "errors-plates.png"
    bed = dict(n=4300, L=10, W=3.2, fill=1.15)
    geometry = dict(blade="plates", L=10, W=3.2, top=1.8, cgx=20, cgy=8, cgz=10)
    blade = "plates"


SCENES = dict(pile=Pile, hopper=Hopper, blade=Blade, plates=PaperBlade)


def series_of(wd, fields, ref, tag):
    """Error series of run tag against run ref (their field dumps, named by fields, in wd), also
    written to errors.TAG.vs.REF.txt."""
    s = romerror.error_series(read_grid_dump(os.path.join(wd, fields % ref)),
                              read_grid_dump(os.path.join(wd, fields % tag)))
    romerror.write_series(os.path.join(wd, "errors.%s.vs.%s.txt" % (tag, ref)), s)
    return s


def study(scene, a):
    """Runs the study of a scene (an instance of SCENES); returns its record."""
    os.makedirs(scene.wd, exist_ok=True)
    model = scene.train()
    stock = STOCK_TWIN[scene.pair]
    seeds = [int(s) for s in a.seeds.split(",")]
    if len(seeds) < 2:
        raise SystemExit("--seeds: at least two seeds (the noise floor is their pairwise errors)")
    base = "test"

    # 1. the stock style's skin, by a short run at each
    scan = {}
    for skin in (a.skins or scene.skins).split(","):
        tag = "%s.scan.%s.skin%s" % (base, stock.replace("/", "_"), skin)
        scene.run(tag, dict(scene.test(scan=True), pair=stock, skin=skin, seed=seeds[0]))
        scan[skin] = loop_seconds(scene.wd, tag)
    skin = min(scan, key=scan.get)

    # 2.-5. the runs at the test's control and horizon
    stock_tags = ["%s.stock.seed%d" % (base, s) for s in seeds]
    for tag, seed in zip(stock_tags, seeds):
        scene.run(tag, dict(scene.test(), pair=stock, skin=skin, seed=seed))
    ref = "%s.griddem.seed%d" % (base, seeds[0])
    scene.run(ref, dict(scene.test(), seed=seeds[0]))
    rom = dict(scene.test(), **scene.rom(), mode="rom", model=model, seed=seeds[0])
    rom_tags = ["%s.rom.r%d" % (base, k) for k in range(a.repeats)]
    for tag in rom_tags:
        scene.run(tag, rom)
    nothing = "%s.donothing" % base
    scene.run(nothing, dict(rom, freeze="yes"))

    times = {stock: [loop_seconds(scene.wd, t) for t in stock_tags], scene.pair: [loop_seconds(scene.wd, ref)]}
    reduced = [loop_seconds(scene.wd, t) for t in rom_tags]
    style, seconds = pick_baseline(times)
    record = dict(build=a.build, reduced_settings=scene.rom(), model=model,
                  baseline=dict(pair_style=style, loop_s=seconds),
                  speedup=seconds / statistics.median(reduced),
                  loop_s={stock: times[stock], scene.pair: times[scene.pair], "reduced": reduced,
                          "do_nothing": loop_seconds(scene.wd, nothing)},
                  stock_skin=float(skin), skin_scan=dict(steps=a.scan_steps, loop_s=scan),
                  seeds=seeds, reference="%s resolved, seed %d" % (scene.pair, seeds[0]))

    # accuracies against the griddem resolved run of the same seed (the reduced runs repeat one
    # run: the first is measured)
    left_out = {}
    record.update(kinematic_fraction=kinematic_fraction(log_path(scene.wd, rom_tags[0])),
                  near_fraction=near_fraction(log_path(scene.wd, rom_tags[0])),
                  do_nothing_kinematic_fraction=kinematic_fraction(log_path(scene.wd, nothing)))
    s = series_of(scene.wd, scene.fields, ref, rom_tags[0])
    record.update(romerror.accuracies(s), characteristic_speed=s["characteristic_speed"], frames=len(s["steps"]))
    if "characteristic_temperature" in s:
        record["characteristic_temperature"] = s["characteristic_temperature"]
    record.update(romerror.accuracies(series_of(scene.wd, scene.fields, ref, nothing), "do_nothing_"))
    # the noise floor: every pair of stock seeds, and the griddem run against stock of its seed
    pairs = [(stock_tags[i], stock_tags[j]) for i in range(len(seeds)) for j in range(i + 1, len(seeds))]
    floors = [romerror.accuracies(series_of(scene.wd, scene.fields, p, q)) for p, q in pairs]
    for key in floors[0]:
        record["noise_" + key] = [f[key] for f in floors]
    record.update(romerror.accuracies(series_of(scene.wd, scene.fields, stock_tags[0], ref), "griddem_vs_stock_"))
    if "temperature_accuracy" not in record:
        left_out["temperature_accuracy"] = "the field dumps hold no temperature column"

    if isinstance(scene, Blade):
        # open loop: the reference run again (the same trajectory: same seed and binary), with a
        # snapshot every 100 steps; not timed
        openloop = "%s.openloop" % ref
        scene.run(openloop, dict(scene.test(), seed=seeds[0], adump=100))
        with in_folder(scene.wd):
            for which in ("measured", "predicted"):
                record.update(force_accuracy(ref, rom_tags[0], which))
            record["noise_force_accuracy"] = force_accuracy(stock_tags[0], stock_tags[1], "measured")[
                "force_accuracy_measured"]
            record.update(open_loop_accuracy(model, openloop, a.controls))
        # the stock and reduced runs again without the fields and atoms the errors are measured on
        # (the force on the blade still sampled): the method's speed-up apart from that output
        quiet = ["%s.stock.nofields.seed%d" % (base, s) for s in seeds]
        for tag, seed in zip(quiet, seeds):
            scene.run(tag, dict(scene.test(), pair=stock, skin=skin, seed=seed, fields="no"))
        quiet_rom = ["%s.rom.nofields.r%d" % (base, k) for k in range(a.repeats)]
        for tag in quiet_rom:
            scene.run(tag, dict(rom, fields="no"))
        stock_s, reduced_s = [loop_seconds(scene.wd, t) for t in quiet], [loop_seconds(scene.wd, t) for t in quiet_rom]
        record["without_fields"] = dict(loop_s={stock: stock_s, "reduced": reduced_s},
                                        speedup=statistics.median(stock_s) / statistics.median(reduced_s))
    record["left_out"] = left_out
    text = log.text_of(log_path(scene.wd, ref))
    runs = log.loop_times(text)
    return dict(date=datetime.date.today().isoformat(), device=benchlib.device(), scene=scene.name,
                natoms=runs[-1].atoms, steps=sum(r.steps for r in runs), ranks=1, threads=1, **record)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=os.path.join(ROOT, "build", "lmp"))
    ap.add_argument("--scene", choices=sorted(SCENES), default="pile")
    ap.add_argument("--seeds", default="8172,3391,5807", help="seeds of the stock resolved runs; the first also "
                    "the griddem, reduced and do-nothing runs'")
    ap.add_argument("--skins", help="the stock run's skins to scan (default pile 0.1,0.2,0.4; hopper, blade "
                    "0.03,0.06,0.12)")
    ap.add_argument("--scan-steps", type=int, default=2000, help="steps of each run of the skin scan")
    ap.add_argument("--repeats", type=int, default=3, help="reduced runs (timing repeats)")
    ap.add_argument("--build", help="the build's name in the record (default: git describe of this repository)")
    ap.add_argument("--seg", type=int, default=10000, help="hopper: steps per control segment")
    ap.add_argument("--train-feed", default="0.1,0.1,0.05,0.05,0,0/0.075,0.1,0.1,0,0.05,0/0.1,0.05,0.075,0.025,0,0.05",
                    help="hopper: the training runs' feed-rate histories (segments by commas, runs by /)")
    ap.add_argument("--train-outlet", default="0,0.1,0.2,0.4,0.3,0/0,0,0.3,0.2,0.4,0.1/0.1,0.4,0,0.3,0.2,0.4",
                    help="hopper: the training runs' outlet-speed histories, segment by segment with --train-feed")
    ap.add_argument("--test-feed", default="0.1,0.1,0.075,0.025,0,0", help="hopper: the test's feed-rate history")
    ap.add_argument("--test-outlet", default="0,0,0.2,0.3,0.4,0.55",
                    help="hopper: the test's outlet-speed history (the last segment beyond the trained 0-0.4)")
    ap.add_argument("--form", choices=("occupancy", "linear"),
                    help="the model's form (train_rom.py's, train_blade.py's --form; default pile linear: each "
                    "voxel's velocity a linear function of every density and the controls; the others occupancy: "
                    "its density times a linear function of the controls)")
    ap.add_argument("--controls", choices=sorted(CONTROLS), default="cut",
                    help="blade, plates: the model's controls (in.blade's -var controls; default cut: the blade's "
                    "velocity times its depth below the bed's surface, and that depth; velocity: the blade's)")
    ap.add_argument("--components", default="xz",
                    help="hopper: the velocity components the model predicts (train_rom.py --components; default xz: "
                    "the slice's mean vy is noise that would drive atoms into its front and rear walls)")
    ap.add_argument("--v0", type=float, help="hopper, blade, plates: velocity scale of the threshold (default 0.36, 0.45)")
    ap.add_argument("--train-traj",
                    help="blade, plates: the training runs' trajectories, ZLOW:PUSH (the blade's lowest bottom "
                    "and push speed; default blade 1.0:0.6,1.0:1.2,1.4:0.6,1.4:1.2, plates "
                    "0.6:0.6,0.6:1.2,0.8:0.6,0.8:1.2: cuts of one to two diameters below the bed's surface near 1.0)")
    ap.add_argument("--test-traj", help="blade, plates: the test's trajectory (default 1.2:0.9, 0.7:0.9)")
    ap.add_argument("--drive", choices=("match", "box", "dense"),
                    help="hopper, blade, plates: fix griddem/rom keyword drive (default hopper match: those the field "
                    "matches; blade box: every atom in the model's grid is driven, as the paper's blade; dense: the "
                    "atoms where the material is dense are driven, DEM resolves the gas-like rest)")
    ap.add_argument("--dense", type=float, default=0.5,
                    help="with --drive dense: the density from which the model drives an atom (default 0.5)")
    ap.add_argument("--guard", choices=("yes", "no"), default="no",
                    help="blade, plates: keep the atoms near the blade resolved (in.blade's region guard; default no, as "
                    "the paper's blade)")
    ap.add_argument("--overlap", type=float,
                    help="hopper, blade, plates: fix griddem/rom keyword overlap, the overlap with another atom that "
                    "releases a kinematic one, over the smaller radius (default hopper 0.1, fix griddem/rom's own; blade "
                    "1.0: the field drives the heap ahead of the blade into itself)")
    ap.add_argument("--W", type=int, default=20, help="pile: container width (even)")
    ap.add_argument("--H", type=int, default=26, help="pile: box top above the plate (H+6 even)")
    ap.add_argument("--fill", type=float, default=9, help="pile: initial pile height")
    ap.add_argument("--inlet", type=float, help="pile: width of the feed region (default W - 2)")
    ap.add_argument("--steps", type=int, help="pile, blade, plates: every run's horizon (default 30000, 10000)")
    ap.add_argument("--train", default="3,4,5,6", help="pile: outlet widths of the training runs")
    ap.add_argument("--test", type=float, default=4.5, help="pile: outlet width of the test")
    ap.add_argument("--eps", type=float, help="default pile 0.1, hopper 0.3, blade and plates 0.1")
    ap.add_argument("--every", type=int, help="default pile 10, hopper 50, blade and plates 500 (the CFL rule shortens it)")
    ap.add_argument("--block", type=float, default=0.0, help="pile: fix griddem/rom keyword block (0: atom by atom)")
    ap.add_argument("--walls", default="rom_dynamic", help="pile: group of the walls in the reduced run (all: the "
                    "force rule watches kinematic atoms at walls)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "rom.jsonl"))
    ap.add_argument("--figure", help="the errors-over-time figure (default: the example's reference/errors.png)")
    ap.add_argument("--work", default=os.path.join(HERE, "work-rom"), help="folder of the scenes' work folders")
    a = ap.parse_args()
    a.build = a.build or benchlib.commit(dirty=True)    # the build the study starts with
    defaults = dict(pile=dict(steps=30000, eps=0.1, every=10, v0=1.0, drive="match"),
                    hopper=dict(steps=0, eps=0.3, every=50, v0=0.36, drive="match", overlap=0.1),
                    blade=dict(steps=10000, eps=0.1, every=500, v0=0.45, drive="box", overlap=1.0,
                               train_traj="1.0:0.6,1.0:1.2,1.4:0.6,1.4:1.2", test_traj="1.2:0.9"),
                    plates=dict(steps=10000, eps=0.1, every=500, v0=0.45, drive="box", overlap=1.0,
                                train_traj="0.6:0.6,0.6:1.2,0.8:0.6,0.8:1.2", test_traj="0.7:0.9"))[a.scene]
    for k, v in dict(defaults, form=SCENES[a.scene].form).items():
        if getattr(a, k) is None:
            setattr(a, k, v)
    a.work = os.path.abspath(a.work)
    scene = SCENES[a.scene](a, os.path.abspath(a.lmp))
    line = study(scene, a)
    print(json.dumps(line))
    with open(a.out, "a") as f:
        f.write(json.dumps(line) + "\n")
    figure = a.figure or os.path.join(scene.example, "reference", getattr(scene, "figure", "errors.png"))
    romfigure.draw(scene.wd, figure, "%s: speed-up %.2f over %s" % (scene.name, line["speedup"],
                                                                   line["baseline"]["pair_style"]))
    print("errors over time:", figure)


if __name__ == "__main__":
    main()
