"""bench/gpu_session.py runs from its bundle alone, as on a bare GPU machine. bench/gpu_bundle.py
bundles GRIDDEM_LMP, compressed as for a GPU session (the session unpacks it into a scratch
folder, away from any build folder); only the bundle is copied into an empty folder, and the
session's dry run (--cpu) runs from there with an empty working folder and no GRIDDEM_ setting of
the caller's. The bundle holds the lmp, list_submodels, LAMMPS's data.chute and in.chute.scaled, the sources of the
sync counter and of the census, and the scripts the steps run; every step is recorded once, in
order, ok or skipped with its reason:

- an lmp without KOKKOS (CI's build/lmp): start ok; kktests skipped by test_kokkos.py itself for
  want of KOKKOS (so the test modules imported, test_granular_parity running the bundle's
  list_submodels); chute, poly, census and largest skipped for want of KOKKOS; bound skipped
  (CUDA only);
- a KOKKOS lmp: the full dry run, every step ok but bound; the kk tests all pass and every
  benchmark run is ok.

Without cc on the PATH the kktests step leaves out the synchronisation section (no KOKKOS: census
is skipped instead), says why, and the next step is still recorded. A GPU session (no --cpu) with
an lmp without CUDA stops after start, its reason recorded."""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import griddem_testlib as t

TOP = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(TOP, "bench"))
from gpu import lmp_info  # noqa: E402
from griddemtools.lammps import list_submodels_program  # noqa: E402 (the test library put python/ first)

STEPS = ["start", "kktests", "chute", "bound", "poly", "census", "largest"]
BUNDLED = ["lmp.xz", "unittest/core/list_submodels", "lammps-bench/data.chute", "lammps-bench/in.chute.scaled",
           "unittest/kokkos_tools/sync_counter.c", "bench/kokkos_census.c", "bench/gpu_session.py",
           "bench/gpu_bundle.py", "bench/gpu.py", "bench/benchlib.py", "unittest/lammps/test_kokkos.py",
           "unittest/lammps/griddem_testlib.py", "unittest/lammps/test_granular_parity.py",
           "unittest/lammps/test_stock_parity.py", "python/griddemtools/__init__.py", "python/griddemtools/log.py",
           "python/griddemtools/lammps.py"]


def session(bundle, wd, name, args, path=None):
    """Run the bundle's gpu_session.py from an empty folder with the caller's GRIDDEM_ settings
    removed (and PATH replaced by path if given): (exit code, the session.jsonl lines)."""
    cwd = os.path.join(wd, "cwd-" + name)
    os.makedirs(cwd)
    env = {k: v for k, v in os.environ.items() if not k.startswith("GRIDDEM_")}
    if path is not None:
        env["PATH"] = path
    out = os.path.join(wd, "out-" + name)
    proc = subprocess.run([sys.executable, os.path.join(bundle, "bench", "gpu_session.py"), "--out", out] + args,
                          cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          universal_newlines=True, timeout=1700)
    t.check(os.listdir(cwd) == [], "%s: the session wrote nothing into its working folder: %s" % (name, os.listdir(cwd)))
    jsonl = os.path.join(out, "session.jsonl")
    if not os.path.exists(jsonl):
        print(proc.stdout[-3000:])
        return proc.returncode, []
    with open(jsonl) as f:
        return proc.returncode, [json.loads(l) for l in f if l.strip()]


def check_steps(label, lines, steps, skipped):
    """Each of steps recorded once, in order: those in skipped ({step: what its reason says})
    skipped with that reason, the others ok, with every benchmark run of theirs ok."""
    got = [l for l in lines if l.get("step") != "session"]
    t.check([l["step"] for l in got] == steps, "%s: steps recorded %s, expected %s" % (
        label, [l["step"] for l in got], steps))
    for l in got:
        if l["step"] in skipped:
            t.check(l.get("status") == "skipped" and skipped[l["step"]] in l.get("reason", ""),
                    "%s: %s skipped, saying '%s': %s" % (label, l["step"], skipped[l["step"]], l))
        else:
            t.check(l.get("status") == "ok", "%s: %s ok: %s" % (label, l["step"], l))
            t.check(set(l.get("runs", {"ok": 1})) == {"ok"}, "%s: %s: every benchmark run ok: %s" % (
                label, l["step"], l.get("runs")))
    return {l["step"]: l for l in got}


def main():
    wd = t.workdir()
    made = os.path.join(wd, "made")
    subprocess.run([sys.executable, os.path.join(TOP, "bench", "gpu_bundle.py"), "--lmp", t.LMP, "--xz",
                    "--list-submodels", list_submodels_program(t.LMP), "--out", made], check=True)
    bundle = os.path.join(wd, "bare", "bundle")
    shutil.copytree(made, bundle, symlinks=True)
    shutil.rmtree(made)
    for rel in BUNDLED:
        t.check(os.path.isfile(os.path.join(bundle, rel)), "the bundle holds %s" % rel)
    t.check(os.access(os.path.join(bundle, "unittest/core/list_submodels"), os.X_OK),
            "the bundle's list_submodels is executable")

    api = lmp_info(t.LMP)[0]
    threads = "2" if api and {"OpenMP", "Threads"} & set(api.split()) else "1"
    print("%s: Kokkos %s; dry run on %s threads" % (t.LMP, api, threads))
    rc, lines = session(bundle, wd, "dry", ["--cpu", threads, "--deadline", "1500"])
    t.check(rc == 0, "the dry run exits 0 (exit %d)" % rc)
    skipped = {"bound": "needs a GPU"}
    if not api:
        skipped.update({step: "no KOKKOS" for step in STEPS if step not in ("start", "bound")})
    steps = check_steps("dry run", lines, STEPS, skipped)
    if api:
        result = steps.get("kktests", {}).get("result") or ""
        t.check(result.endswith(" 0 failed") and not result.startswith("0 "),
                "the kk tests' sections all pass: %s" % result)
    else:
        t.check("no KOKKOS" in steps.get("start", {}).get("note", ""), "start says the lmp has no KOKKOS")

    # the PATH's programs but cc: the sync counter is not built, the next step still runs
    bin_dir = os.path.join(wd, "bin")
    os.makedirs(bin_dir)
    for folder in filter(os.path.isdir, os.environ["PATH"].split(os.pathsep)):
        for name in os.listdir(folder):
            if name != "cc" and not os.path.lexists(os.path.join(bin_dir, name)):
                os.symlink(os.path.join(folder, name), os.path.join(bin_dir, name))
    only = "census" if api else "kktests,census"
    rc, lines = session(bundle, wd, "nocc", ["--cpu", threads, "--only", only], path=bin_dir)
    steps = check_steps("no cc", lines, ["start"] + only.split(","),
                        {"census": "no C compiler"} if api else {"kktests": "no KOKKOS", "census": "no KOKKOS"})
    if not api:
        kk = steps.get("kktests", {})
        t.check("no C compiler" in kk.get("not_run", {}).get("synchronisation", "") and
                "synchronisation" not in kk.get("sections", "synchronisation"),
                "without cc the kk tests leave out the synchronisation section, saying so: %s" % kk)

    # a GPU session with an lmp without CUDA: start fails and nothing follows
    if not api or "CUDA" not in api.split():
        rc, lines = session(bundle, wd, "gpu", [])
        got = [l for l in lines if l.get("step") != "session"]
        print("GPU session with this lmp:", got)
        t.check(rc == 1 and len(got) == 1 and got[0]["step"] == "start" and got[0]["status"] == "failed" and
                got[0].get("reason"), "a GPU session whose start fails stops after start, with its reason: %s" % got)
    shutil.rmtree(os.path.join(wd, "bare"))
    t.finish()


if __name__ == "__main__":
    main()
