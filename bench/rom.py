#!/usr/bin/python3
"""Adaptive reduced-order DEM against resolved DEM, in one job.

    /usr/bin/python3 bench/rom.py [--lmp build/lmp] [--W 20 --H 26 --fill 9 --inlet 18] [--steps 30000]
                                  [--train 3,4,5,6] [--test 4.5] [--eps 0.1] [--every 10] [--block 0] [--walls rom_dynamic]
    /usr/bin/python3 bench/rom.py --scene hopper [--seg 1500] [--train-feed R,R,R,R/R,R,R,R/...]
                                  [--test-feed R,R,R,R] [--eps 0.3] [--v0 0.36] [--every 50]
    /usr/bin/python3 bench/rom.py --scene blade [--train-traj Z:P,Z:P,...] [--test-traj Z:P]
                                  [--eps 0.3] [--v0 0.45] [--every 50]

Scene pile (examples/rom-pile, the default): the outlet width is the control.

Runs (in bench/work-rom/W<W>H<H>[I<inlet>], kept between calls: training runs and the model are reused
when present) the resolved training runs at the outlet widths --train, fits the ridge model
(examples/rom-pile/train_rom.py), then the test width resolved and reduced back to back, and
appends one JSON line to bench/results/rom.jsonl: date, machine, scene, atoms, loop times,
speed-up (and the same from the runs' CPU times), the mean fraction of kinematic atoms (the reduction), surface-height accuracy,
velocity-field and granular-temperature errors (examples/rom-pile/compare.py defines them), and
with --noise-seed the same accuracies of a resolved run with another seed (the noise floor);
--plot draws examples/rom-pile/plot_rom.py's figure.

Scene hopper (examples/rom-hopper, 22,000 polydisperse spheres): the pile is built once
(in.build, pile.restart in bench/work-rom/hopper) and every run starts from it; the control is the
feed rate, a history of --seg-step segments; training runs at the --train-feed histories, the test
at --test-feed (a history not trained).

Scene blade (examples/rom-blade, 5,200 polydisperse spheres): the bed is built once (in.build,
bed.restart in bench/work-rom/blade); a blade is lowered to its bottom at z = Z, pushed at speed P
and raised (a trajectory Z:P); the controls are its velocity, the model's grid moves with it
(train_blade.py). Training at --train-traj, the test at --test-traj (not trained). Adds the
blade-force accuracies: 1 - time-mean |F - F_resolved| / time-mean |F_resolved| of the force the
reduced run measures on the blade and of the force its model predicts (examples/rom-blade/blade_force.py)."""
import argparse
import json
import os
import resource
import subprocess
import sys

import benchlib

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
EXAMPLE = os.path.join(ROOT, "examples", "rom-pile")
HOPPER = os.path.join(ROOT, "examples", "rom-hopper")
BLADE = os.path.join(ROOT, "examples", "rom-blade")
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
# the examples' measures of a reduced run against a resolved one
sys.path.insert(0, EXAMPLE)
sys.path.insert(0, BLADE)
from blade_force import force_accuracy  # noqa: E402
from compare import compare  # noqa: E402
from griddemtools import lammps, log  # noqa: E402


def cpu_time_of(lmp, args, wd):
    """Runs lmp with args in wd on one thread; returns the CPU time it took."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    lammps.run(lmp, args, wd, output=None, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def run_pile(lmp, wd, scene, steps, w, tag, extra=()):
    args = ["-in", os.path.join(EXAMPLE, "in.rom-pile"), "-var", "w", str(w), "-var", "steps", str(steps),
            "-var", "tag", tag, "-log", "log." + tag, "-echo", "none", "-screen", "none"]
    for k, v in scene.items():
        args += ["-var", k, str(v)]
    return cpu_time_of(lmp, args + list(extra), wd)


def run_lammps(lmp, wd, inp, tag, variables, example=HOPPER, scene="in.hopper-scene"):
    """Runs an input of an example folder (rom-hopper, rom-blade) in wd; returns the CPU time it took."""
    args = ["-in", os.path.join(example, inp), "-var", "scene", os.path.join(example, scene),
            "-log", "log." + tag, "-echo", "none", "-screen", "none"]
    for k, v in variables.items():
        args += ["-var", k] + (v if isinstance(v, list) else [str(v)])
    return cpu_time_of(lmp, args, wd)


def blade_runs(a, lmp):
    """The blade study's runs, as hopper_runs returns them."""
    wd = os.path.join(HERE, "work-rom", "blade")
    os.makedirs(wd, exist_ok=True)

    def run(inp, tag, variables):
        return run_lammps(lmp, wd, inp, tag, variables, BLADE, "in.blade-scene")

    if not os.path.exists(os.path.join(wd, "bed.restart")):
        run("in.build", "build", {})
    tags = []
    for traj in a.train_traj.split(","):
        zlow, push = traj.split(":")
        tag = "train.z%s.p%s" % (zlow, push)
        if not os.path.exists(os.path.join(wd, "force.%s.txt" % tag)):
            run("in.blade", tag, dict(zlow=zlow, push=push, tag=tag, adump=100))
        tags.append(tag)
    model = "rom.%s.model" % a.train_traj.replace(":", "_").replace(",", "-")
    if not os.path.exists(os.path.join(wd, model)):
        subprocess.run([sys.executable, os.path.join(BLADE, "train_blade.py"), model] + tags, cwd=wd, check=True,
                       stdout=subprocess.DEVNULL)
    zlow, push = a.test_traj.split(":")
    name = "z%s.p%s" % (zlow, push)
    res, rom = "test.%s.resolved" % name, "test.%s.rom.e%g.n%d" % (name, a.eps, a.every)
    cpu_res = run("in.blade", res, dict(zlow=zlow, push=push, tag=res))
    cpu_rom = run("in.blade", rom, dict(zlow=zlow, push=push, tag=rom, mode="rom", model=model, eps=a.eps,
                                        v0=a.v0, every=a.every))
    noise = None
    if a.noise_seed is not None:
        noise = "test.%s.resolved.seed%d" % (name, a.noise_seed)
        if not os.path.exists(os.path.join(wd, "cg.%s.txt" % noise)):    # its timing is not used
            run("in.blade", noise, dict(zlow=zlow, push=push, tag=noise, seed=a.noise_seed))
    scene = "rom-blade train %s test %s" % (a.train_traj, a.test_traj)
    return wd, res, rom, noise, cpu_res, cpu_rom, scene


def hopper_runs(a, lmp):
    """The hopper study's runs: (work folder, resolved tag, reduced tag, noise tag or None, CPU times,
    scene name). Built pile, training runs and model are reused when present."""
    wd = os.path.join(HERE, "work-rom", "hopper")
    os.makedirs(wd, exist_ok=True)
    if not os.path.exists(os.path.join(wd, "pile.restart")):
        run_lammps(lmp, wd, "in.build", "build", {})
    specs = []
    for history in a.train_feed.split("/"):
        tag = "train.f%s.s%d" % (history.replace(",", "_"), a.seg)
        rates = history.split(",")
        with open(os.path.join(wd, "ctl.%s.txt" % tag), "w") as f:
            f.write("# until_step feed_rate\n")
            f.writelines("%d %s\n" % ((k + 1) * a.seg, r) for k, r in enumerate(rates))
        if not os.path.exists(os.path.join(wd, "cg.%s.txt" % tag)):
            run_lammps(lmp, wd, "in.feed", tag, dict(rate=rates, seg=a.seg, tag=tag))
        specs.append("cg.%s.txt:@ctl.%s.txt" % (tag, tag))
    model = "rom.%s.s%d.model" % (a.train_feed.replace(",", "_").replace("/", "-"), a.seg)
    if not os.path.exists(os.path.join(wd, model)):
        subprocess.run([sys.executable, os.path.join(EXAMPLE, "train_rom.py"), model] + specs, cwd=wd, check=True,
                       stdout=subprocess.DEVNULL)
    test = a.test_feed.split(",")
    name = "f%s" % a.test_feed.replace(",", "_")
    res, rom = "test.%s.resolved" % name, "test.%s.rom.e%g.n%d" % (name, a.eps, a.every)
    cpu_res = run_lammps(lmp, wd, "in.feed", res, dict(rate=test, seg=a.seg, tag=res))
    cpu_rom = run_lammps(lmp, wd, "in.feed", rom, dict(rate=test, seg=a.seg, tag=rom, mode="rom", model=model,
                                                       eps=a.eps, v0=a.v0, every=a.every))
    noise = None
    if a.noise_seed is not None:
        noise = "test.%s.resolved.seed%d" % (name, a.noise_seed)
        if not os.path.exists(os.path.join(wd, "cg.%s.txt" % noise)):    # its timing is not used
            run_lammps(lmp, wd, "in.feed", noise, dict(rate=test, seg=a.seg, tag=noise, seed=a.noise_seed))
    scene = "rom-hopper seg %d train %s test %s" % (a.seg, a.train_feed, a.test_feed)
    return wd, res, rom, noise, cpu_res, cpu_rom, scene


def pile_runs(a, lmp):
    """The pile study's runs, as hopper_runs returns them."""
    scene = dict(W=a.W, H=a.H, fill=a.fill)
    if a.inlet is not None:
        scene["inlet"] = a.inlet
    wd = os.path.join(HERE, "work-rom", "W%dH%d" % (a.W, a.H) + ("I%g" % a.inlet if a.inlet is not None else ""))
    os.makedirs(wd, exist_ok=True)
    specs = []
    for w in a.train.split(","):
        tag = "train.w%s.s%d" % (w, a.steps)
        if not os.path.exists(os.path.join(wd, "cg.%s.txt" % tag)):
            run_pile(lmp, wd, scene, a.steps, w, tag)
        specs.append("cg.%s.txt:%s" % (tag, w))
    model = "rom.%s.s%d.model" % (a.train.replace(",", "_"), a.steps)
    if not os.path.exists(os.path.join(wd, model)):
        subprocess.run([sys.executable, os.path.join(EXAMPLE, "train_rom.py"), model] + specs, cwd=wd, check=True,
                       stdout=subprocess.DEVNULL)
    res, rom = "test.w%g.resolved" % a.test, "test.w%g.rom.e%g.n%d.b%g.%s" % (a.test, a.eps, a.every, a.block, a.walls)
    cpu_res = run_pile(lmp, wd, scene, a.steps, a.test, res)
    cpu_rom = run_pile(lmp, wd, scene, a.steps, a.test, rom,
             ["-var", "mode", "rom", "-var", "model", model, "-var", "eps", str(a.eps), "-var", "every", str(a.every),
              "-var", "block", str(a.block), "-var", "walls", a.walls])
    noise = None
    if a.noise_seed is not None:
        noise = "test.w%g.resolved.seed%d" % (a.test, a.noise_seed)
        if not os.path.exists(os.path.join(wd, "cg.%s.txt" % noise)):    # its timing is not used
            run_pile(lmp, wd, scene, a.steps, a.test, noise, ["-var", "seed", str(a.noise_seed)])
    name = "rom-pile W%d H%d fill %g inlet %g" % (a.W, a.H, a.fill, a.W - 2 if a.inlet is None else a.inlet)
    return wd, res, rom, noise, cpu_res, cpu_rom, name


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lmp", default=os.path.join(ROOT, "build", "lmp"))
    ap.add_argument("--scene", choices=("pile", "hopper", "blade"), default="pile")
    ap.add_argument("--seg", type=int, default=1500, help="hopper: steps per feed-rate segment")
    ap.add_argument("--train-feed", default="0.05,0.2,0.1,0/0.15,0,0.2,0.05/0,0.1,0.05,0.2",
                    help="hopper: the training runs' feed-rate histories (segments by commas, runs by /)")
    ap.add_argument("--test-feed", default="0.12,0.03,0.18,0.08", help="hopper: the test's feed-rate history")
    ap.add_argument("--v0", type=float, help="hopper, blade: velocity scale of the threshold (default 0.36, 0.45)")
    ap.add_argument("--train-traj", default="1.0:0.6,1.0:1.2,1.4:0.6,1.4:1.2",
                    help="blade: the training runs' trajectories, ZLOW:PUSH (the blade's lowest bottom and "
                    "push speed)")
    ap.add_argument("--test-traj", default="1.2:0.9", help="blade: the test's trajectory")
    ap.add_argument("--W", type=int, default=20, help="container width (even)")
    ap.add_argument("--H", type=int, default=26, help="box top above the plate (H+6 even)")
    ap.add_argument("--fill", type=float, default=9, help="initial pile height")
    ap.add_argument("--inlet", type=float, help="width of the feed region (default W - 2)")
    ap.add_argument("--steps", type=int, default=30000)
    ap.add_argument("--train", default="3,4,5,6", help="outlet widths of the training runs")
    ap.add_argument("--test", type=float, default=4.5, help="outlet width of the test")
    ap.add_argument("--eps", type=float, default=0.1)
    ap.add_argument("--every", type=int, default=10)
    ap.add_argument("--block", type=float, default=0.0, help="fix griddem/rom keyword block (0: atom by atom)")
    ap.add_argument("--walls", default="rom_dynamic", help="group of the walls in the reduced run (all: the force "
                    "rule watches kinematic atoms at walls)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "rom.jsonl"))
    ap.add_argument("--noise-seed", type=int, help="also run the test resolved with this seed: the noise floor")
    ap.add_argument("--plot", help="write the figure (examples/rom-pile/plot_rom.py; blade: "
                    "examples/rom-blade/plot_blade.py) to this path")
    a = ap.parse_args()
    lmp = os.path.abspath(a.lmp)
    if a.v0 is None:
        a.v0 = 0.45 if a.scene == "blade" else 0.36
    runs = dict(pile=pile_runs, hopper=hopper_runs, blade=blade_runs)[a.scene]
    wd, res, rom, noise, cpu_res, cpu_rom, scene = runs(a, lmp)
    here = os.getcwd()
    os.chdir(wd)
    c = compare(res, rom)
    # the CPU time of the whole run (setup and output included): on a shared machine it varies less
    # than the loop's wall time
    c.update(cpu_resolved_s=cpu_res, cpu_reduced_s=cpu_rom, speedup_cpu=cpu_res / cpu_rom)
    if noise:
        n = compare(res, noise)
        c.update(noise_height_accuracy=n["height_accuracy"], noise_velocity_error=n["velocity_error"],
                 height_accuracy_over_floor=c["height_accuracy"] / n["height_accuracy"],
                 velocity_error_over_floor=c["velocity_error"] / n["velocity_error"])
        if "temperature_error" in n:
            c["noise_temperature_error"] = n["temperature_error"]
            c["temperature_error_over_floor"] = c["temperature_error"] / n["temperature_error"]
    if a.scene == "blade":
        c.update(**force_accuracy(res, rom, "measured"), **force_accuracy(res, rom, "predicted"))
        if noise:
            c["noise_force_accuracy"] = force_accuracy(res, noise, "measured")["force_accuracy_measured"]
    if a.plot:
        plot = os.path.join(BLADE, "plot_blade.py") if a.scene == "blade" else os.path.join(EXAMPLE, "plot_rom.py")
        subprocess.run([sys.executable, plot, res, rom] + ([noise] if noise else []) +
                       [os.path.abspath(os.path.join(here, a.plot))], check=True)
    os.chdir(here)
    text = log.text_of(os.path.join(wd, "log." + res))
    _, _, atoms = benchlib.loop_time(text, res)
    steps = sum(run.steps for run in log.loop_times(text))
    line = dict(date=__import__("datetime").date.today().isoformat(), device=benchlib.device(),
                scene=scene, natoms=atoms, steps=steps,
                **(dict(train=a.train, test=a.test, block=a.block, walls=a.walls) if a.scene == "pile" else
                   dict(v0=a.v0)),
                eps=a.eps, every=a.every, ranks=1, threads=1,
                **{k: round(v, 4) for k, v in c.items() if isinstance(v, float)})
    print(json.dumps(line))
    with open(a.out, "a") as f:
        f.write(json.dumps(line) + "\n")


if __name__ == "__main__":
    main()
