#!/usr/bin/python3
"""Speed against accuracy of GRIDDEM's modes, per scene, against stock gran/hooke/history.

usage: bench/tradeoff.py [--quick] [--lmp build/lmp] [--only dense,squeeze,...]

Scenes: dense (4000 random overlapping polydisperse spheres at solid fraction ~0.6, periodic,
damped), pour (a bed poured under gravity, ~1200 spheres), chute (LAMMPS's chute, 32,000
spheres), cascade (a sphere shot into a cubic block of 1000 nearly touching spheres), oblique
(two spheres meeting at 45 degrees: the tangential restitution), and two polydisperse ones:
squeeze (the 1:4 bidisperse packing of bench/squeeze.py compressed by fix deform) and bed (the
1:10 poured bed of bench/poured_bed.py). Modes: cell geometry exact|multi|classes x tangential
history|simple|none, plus stock gran/hooke/history (the reference) and stock gran/hooke. Each run is timed on one rank; errors are measured against the
reference: the force error on the scene's initial state (where it has contacts: dense, chute),
the largest relative deviation of the kinetic-energy trajectory, and the scene's own number
(kinetic energy left in the dense box and after the cascade; packing fraction of the poured bed;
kinetic energy of the chute's flow; tangential restitution), at the end and along the run. Writes
results/tradeoff.jsonl, results/tradeoff.md and doc/tradeoff-<scene>.png."""
import argparse
import datetime
import json
import os
import shutil
import sys
import tempfile

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "..", "python"))  # griddemtools
import benchlib  # noqa: E402
from griddemtools import dump, lammps, log, squeeze  # noqa: E402
from griddemtools.spheres import write_random_spheres  # noqa: E402
import poured_bed  # noqa: E402

# (label, pair style, tangential arguments replacing "xmu dampflag", fix griddem cell)
HOOKE = "{kn} NULL {gn} NULL {xmu} 1"
MODES = [
    ("stock history", "gran/hooke/history", None, None),
    ("stock simple", "gran/hooke", None, None),
    ("exact history", "griddem/hooke/history", None, "exact"),
    ("multi history", "griddem/hooke/history", None, "multi"),
    ("exact simple", "griddem/hooke", None, "exact"),
    ("multi simple", "griddem/hooke", None, "multi"),
    ("exact none", "griddem/hooke", 0.0, "exact"),
    ("multi none", "griddem/hooke", 0.0, "multi"),
    ("classes history", "griddem/hooke/history", None, "classes"),
    ("classes simple", "griddem/hooke", None, "classes"),
    ("classes none", "griddem/hooke", 0.0, "classes"),
]
REFERENCE = "stock history"

COMMON_TAIL = """
compute         ke all ke
thermo_style    custom step atoms c_ke {extra_thermo}
thermo_modify   format float %.12g norm no lost ignore
thermo          {{every}}
{{dump}}
run             {{steps}}
"""


# packing fraction of the lower half of a bed
LOWER_BED_PHI = """compute         height all reduce max z
variable        zcut equal 0.5*c_height
variable        insidevol atom (z<v_zcut)*4.0/3.0*PI*radius^3
compute         solid all reduce sum v_insidevol
variable        phi equal c_solid/(lx*ly*v_zcut)
"""


def dense_scene(steps, data):
    text = """
units           lj
atom_style      sphere
boundary        p p p
comm_modify     vel yes
read_data       {data}
pair_style      {style} {args}
pair_coeff      * *
{grid}
timestep        2e-5
fix             integrate all nve/sphere
""" + COMMON_TAIL.format(extra_thermo="")
    return dict(name="dense", text=text.replace("{data}", data), kn=1e4, gn=50.0, xmu=0.5, steps=steps,
                number="c_ke", number_label="kinetic energy left", force_probe=True)


def pour_scene(steps):
    text = """
units           lj
atom_style      sphere
boundary        p p fm
comm_modify     vel yes
region          box block 0 10 0 10 0 40 units box
create_box      1 box
pair_style      {style} {args}
pair_coeff      * *
{grid}
timestep        0.001
fix             integrate all nve/sphere
fix             gravity all gravity 1.0 vector 0 0 -1
fix             floor all wall/gran hooke/history 2000.0 NULL 50.0 NULL 0.5 0 zplane 0.0 NULL
region          slab block 0.5 9.5 0.5 9.5 15 35 units box
fix             feed all pour 1500 1 4767548 vol 0.3 20 diam range 0.8 1.2 region slab
""" + LOWER_BED_PHI + COMMON_TAIL.format(extra_thermo="v_phi")
    return dict(name="pour", text=text, kn=2000.0, gn=50.0, xmu=0.5, steps=steps, number="v_phi",
                number_label="packing fraction of the lower bed", force_probe=False)


def chute_scene(steps):
    text = """
units           lj
atom_style      sphere
boundary        p p fs
newton          off
comm_modify     vel yes
read_data       {data_chute}
pair_style      {style} {args}
pair_coeff      * *
{grid}
neighbor        0.1 bin
neigh_modify    every 1 delay 0
timestep        0.0001
group           bottom type 2
group           active subtract all bottom
neigh_modify    exclude group bottom bottom
fix             1 all gravity 1.0 chute 26.0
fix             2 bottom freeze
fix             3 active nve/sphere
""" + COMMON_TAIL.format(extra_thermo="")
    return dict(name="chute", text=text, kn=200000.0, gn=50.0, xmu=0.5, steps=steps, number="c_ke",
                number_label="kinetic energy after the run", force_probe=True)


def cascade_scene(steps):
    text = """
units           lj
atom_style      sphere
boundary        f f f
comm_modify     vel yes
region          box block -2 14 -2 14 -2 14 units box
create_box      1 box
lattice         sc 1.0
region          block block 0 9.99 0 9.99 0 9.99 units box
create_atoms    1 region block
create_atoms    1 single -1.2 -1.1 -1.05 units box
set             type 1 diameter 0.999
set             type 1 density 1.9099
group           shot id 1001
velocity        shot set 20 19 18 units box
pair_style      {style} {args}
pair_coeff      * *
{grid}
neighbor        0.3 bin
timestep        0.0005
fix             integrate all nve/sphere
""" + COMMON_TAIL.format(extra_thermo="")
    return dict(name="cascade", text=text, kn=1e5, gn=20.0, xmu=0.3, steps=steps, number="c_ke",
                number_label="kinetic energy left after the cascade", force_probe=False)


def oblique_scene(steps):
    # sphere A (diameter 1) moving along +x hits sphere B at rest; the centres' line at contact is
    # 45 degrees from the motion: tangential restitution depends on the tangential model
    text = """
units           lj
atom_style      sphere
atom_modify     map array
boundary        f f f
comm_modify     vel yes
region          box block -5 5 -5 5 -5 5 units box
create_box      1 box
create_atoms    1 single -1.5 0 0.70710678118654752 units box
create_atoms    1 single 0 0 0 units box
set             type 1 diameter 1.0
set             type 1 density 1.9099
velocity        all set 0 0 0 units box
set             atom 1 vx 1.0
pair_style      {style} {args}
pair_coeff      * *
{grid}
timestep        1e-4
fix             integrate all nve/sphere
# tangential velocity of the contact point along t = (cos45, 0, sin45) (n = (-sin45, 0, cos45)
# points from B to A at contact): g_t = (v_A - v_B).t - (R_A w_A + R_B w_B).(n x t)
compute         wy all property/atom omegay
compute         wsum all reduce sum c_wy
variable        gt equal ((vx[1]-vx[2])+(vz[1]-vz[2]))*0.70710678118654752-0.5*c_wsum
variable        beta equal -v_gt/0.70710678118654752
""" + COMMON_TAIL.format(extra_thermo="v_beta")
    return dict(name="oblique", text=text, kn=1e5, gn=50.0, xmu=0.3, steps=steps, number="v_beta",
                number_label="tangential restitution of a 45 degree impact", force_probe=False)


def squeeze_scene(steps, data):
    text = squeeze.TEMPLATE.format(data=data, pair="{style}", scale=squeeze.SCALE, most="", steps=steps,
                                   name="squeeze")
    text = text.replace("pair_style {style} 1000 NULL 50 NULL 0.5 1", "pair_style {style} {args}")
    text = text.replace("pair_coeff * *", "pair_coeff * *\n{grid}")
    text = text[:text.index("compute c all contact/atom")] + COMMON_TAIL.format(extra_thermo="press")
    return dict(name="squeeze", text=text, kn=1000.0, gn=50.0, xmu=0.5, steps=steps, number="Press",
                number_label="pressure of the squeezed packing", force_probe=True)


def bed_scene(steps):
    text = poured_bed.SCENE.replace("pair_style {style} 2000.0 NULL 50.0 NULL 0.5 1", "pair_style {style} {args}")
    text = text.replace("{fix}", "{grid}")
    text = text[:text.index("thermo 5000")] + LOWER_BED_PHI + COMMON_TAIL.format(extra_thermo="v_phi")
    return dict(name="bed", text=text, kn=2000.0, gn=50.0, xmu=0.5, steps=steps, number="v_phi",
                number_label="packing fraction of the lower bed (1:10 radii)", force_probe=False)


def run(scene, mode, wd, lmp, data_chute, dump_step):
    label, style, xmu, cell = mode
    args = HOOKE.format(kn=scene["kn"], gn=scene["gn"], xmu=scene["xmu"] if xmu is None else xmu)
    grid = "fix grid all griddem cell %s" % cell if cell else ""
    dump = ""
    if dump_step is not None:
        dump = ("dump forces all custom {s} dump.forces id fx fy fz\ndump_modify forces sort id "
                "format float %.17g").format(s=dump_step)
    text = scene["text"].format(style=style, args=args, grid=grid, every=max(1, scene["steps"] // 50) if scene["steps"] else 1,
                                dump=dump, steps=scene["steps"], data_chute=data_chute)
    with open(os.path.join(wd, "in.run"), "w") as f:
        f.write(text)
    out = lammps.run(lmp, ["-in", "in.run", "-log", "none"], wd).stdout
    loop, _, atoms = benchlib.loop_time(out, "%s %s" % (scene["name"], label))
    return out, loop, atoms


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="short runs, to try the harness")
    ap.add_argument("--lmp", default=os.path.join(TOP, "build", "lmp"))
    ap.add_argument("--only", default=None, help="comma-separated scenes to run")
    ap.add_argument("--lammps-bench", default=os.path.join(TOP, ".deps", "lammps-4Feb2025", "bench"))
    args = ap.parse_args()
    scale = 0.1 if args.quick else 1.0
    wd0 = tempfile.mkdtemp(prefix="griddem-tradeoff-")
    dense_data = os.path.join(wd0, "data.dense")
    write_random_spheres(dense_data, 4000, (6.3, 6.3, 6.3), 0.1, 0.2, seed=41, vscale=1.0, wscale=3.0)
    squeeze_data = os.path.join(wd0, "data.squeeze")
    squeeze.write_packing(squeeze_data)
    scenes = [dense_scene(int(2000 * scale), dense_data), pour_scene(int(25000 * scale)),
              chute_scene(int(1000 * scale)), cascade_scene(int(4000 * scale)),
              oblique_scene(int(20000 * scale)), squeeze_scene(int(3000 * scale), squeeze_data),
              bed_scene(int(20000 * scale))]
    only = args.only.split(",") if args.only else None
    scenes = [sc for sc in scenes if not only or sc["name"] in only]
    data_chute = os.path.join(args.lammps_bench, "data.chute")
    device = benchlib.device()
    today = datetime.date.today().isoformat()
    records = []
    for scene in scenes:
        wd = tempfile.mkdtemp(prefix="griddem-tradeoff-")
        results = {}
        for mode in MODES:
            forces = None
            if scene["force_probe"]:
                # forces on the scene's initial state, the same for every mode
                run(dict(scene, steps=0), mode, wd, args.lmp, data_chute, 1)
                snapshot = dump.read_dump(os.path.join(wd, "dump.forces"))[0]
                forces = (snapshot.columns[1:], snapshot.by_id())    # (fx fy fz, {id: values}) as dump.max_rel_diff takes
            out, loop, atoms = run(scene, mode, wd, args.lmp, data_chute, None)
            results[mode[0]] = dict(forces=forces, ke=log.thermo(out, "c_ke"),
                                    numbers=log.thermo(out, scene["number"]), loop=loop, atoms=atoms)
        ref = results[REFERENCE]
        kescale = max(abs(v) for v in ref["ke"]) or 1.0
        for label, r in results.items():
            ferr = dump.max_rel_diff(r["forces"], ref["forces"], ["fx", "fy", "fz"]) if r["forces"] else None
            keerr = max(abs(a - b) for a, b in zip(r["ke"], ref["ke"])) / kescale
            # the scene's number at the end, and its largest deviation along the run
            number, ref_number = r["numbers"][-1], ref["numbers"][-1]
            trajectory = max(abs(a - b) for a, b in zip(r["numbers"], ref["numbers"])) / (
                max(abs(v) for v in ref["numbers"]) or 1.0)
            record = dict(date=today, device=device, scene=scene["name"], natoms=r["atoms"], steps=scene["steps"],
                          mode=label, loop_s=r["loop"], atom_steps_per_s=r["atoms"] * scene["steps"] / r["loop"],
                          force_error=ferr, ke_error=keerr, number=number,
                          number_error=abs(number - ref_number) / (abs(ref_number) or 1.0),
                          number_trajectory_error=trajectory, number_label=scene["number_label"])
            records.append(record)
            print(json.dumps(record))
        shutil.rmtree(wd, ignore_errors=True)
    if args.quick:
        return
    path = os.path.join(HERE, "results", "tradeoff.jsonl")
    with open(path, "a") as f:
        for r in records:
            f.write(json.dumps(r) + "\n")
    # the table holds each scene's latest run, so a run of some scenes keeps the others' rows
    latest = {}
    with open(path) as f:
        for line in f:
            r = json.loads(line)
            rows = latest.setdefault(r["scene"], [])
            if any(q["mode"] == r["mode"] for q in rows):    # a mode again: a later run begins
                rows.clear()
            rows.append(r)
    write_table([r for rows in latest.values() for r in rows], os.path.join(HERE, "results", "tradeoff.md"))
    for scene in scenes:
        plot(scene["name"], [r for r in records if r["scene"] == scene["name"]], device, today)


def write_table(records, path):
    lines = ["# Speed and accuracy of GRIDDEM's modes (1 rank; each scene's latest run, with its date and machine)", "",
             "Errors are relative to stock gran/hooke/history: force error on the scene's initial state (max over "
             "atoms, relative to the largest force), kinetic-energy trajectory (max deviation relative to "
             "the largest value), and the scene's number.", ""]
    for scene in sorted(set(r["scene"] for r in records), key=lambda s: [r["scene"] for r in records].index(s)):
        rows = [r for r in records if r["scene"] == scene]
        lines += ["## %s (%d atoms, %d steps; %s, %s); number: %s" % (
                      scene, rows[0]["natoms"], rows[0]["steps"], rows[0]["date"], rows[0]["device"],
                      rows[0]["number_label"]), "",
                  "| mode | Matom-steps/s | force error | KE trajectory error | number | its error | its trajectory error |",
                  "| --- | --- | --- | --- | --- | --- | --- |"]
        for r in rows:
            ferr = "n/a" if r["force_error"] is None else "%.2g" % r["force_error"]
            lines.append("| %s | %.2f | %s | %.2g | %.5g | %.2g | %.2g |" % (
                r["mode"], r["atom_steps_per_s"] / 1e6, ferr, r["ke_error"], r["number"], r["number_error"],
                r["number_trajectory_error"]))
        lines.append("")
    with open(path, "w") as f:
        f.write("\n".join(lines))


def pareto(points):
    """Points (cost, error) not beaten in both by another point."""
    front = [p for p in points if not any(q[0] <= p[0] and q[1] <= p[1] and q != p for q in points)]
    return sorted(front)


def plot(scene, rows, device, today):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    floor = 1e-17
    pts = []
    for r in rows:
        cost = 1e9 / r["atom_steps_per_s"]    # ns per atom-step
        err = max(r["ke_error"], floor)
        pts.append((cost, err))
        marker = "s" if r["mode"].startswith("stock") else "o"
        ax.scatter(cost, err, marker=marker)
        ax.annotate(r["mode"], (cost, err), textcoords="offset points", xytext=(4, 4), fontsize=8)
    front = pareto(pts)
    ax.plot([p[0] for p in front], [p[1] for p in front], "k--", lw=0.8, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time per atom-step (ns), 1 rank")
    ax.set_ylabel("kinetic-energy trajectory error vs stock history")
    ax.set_title("%s: speed against accuracy (%s, %s)" % (scene, today, device), fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(TOP, "doc", "tradeoff-%s.png" % scene), dpi=100)


if __name__ == "__main__":
    main()
