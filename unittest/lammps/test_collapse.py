"""examples/column-collapse: the 2D mu(I) VOF solver (continuum.py), the deposit rule (deposit.py) and
the DEM input (in.collapse). Each number has its own reason:
- steady inclined layer (periodic, Jop et al. 2006 mu(I), 25 deg, grains under air): the velocity
  reaches the analytic Bagnold profile (with the air's weight in the pressure) within 1 % rms of the
  surface velocity on 5 and 10 cells over the depth, and the error falls by more than 2x from 5 to
  10 cells (the scheme is second order in space: measured 4.8e-3 -> 1.2e-3);
- a grain layer at rest on a flat base stays at rest, and its pressure is the weight above: the base
  cell's p = rho_g g (H - h/2) + rho_air g A (the pressure equation with the same face densities as
  gravity balances it exactly); the same with the side x = nx h open to a layer at rest beyond (its
  ghost cells' pressure is the weight above them), whose open faces are unknowns; an open side of
  the wrong length, or on a periodic box, is refused (ValueError naming it);
- the free surface conserves mass: a collapsing column keeps sum(c) h^2 = L0 H0 (its initial grain
  area) to round-off, with 0 <= c <= 1 within 1e-9, and its front advances (it does collapse);
- the banded solves (GramSystem; unknowns ordered along the box's longer side) solve the system: the
  residual of A(w) x = b, with A assembled directly as sum E^T diag(w) E, is below 1e-9 of |b| for
  a wide and a tall box, the factorization (band_cholesky.c) gives LAPACK's banded Cholesky solve
  (SciPy's cholesky_banded) to 1e-12 of |x|, and an indefinite system raises LinAlgError;
- the solver on a box that follows the grains (FollowingBox, its top 4-8 rows above the highest
  grains) conserves the grain area to round-off as its top comes down under the collapsing column, and
  its front stays within 0.1 d of the whole box's (the air above the box top carries no grains);
  so does a box whose length follows the front too, open to the air beyond (no grains cross its
  open side, and the air ahead of the front leaves through it as it moves on in the whole box);
- HeldMu holds mu at I_max above it (no extrapolation);
- deposit.front: on a linear profile h = 3 - x the farthest x with h >= 1 is 2, interpolated; the
  released column 8 d wide and 6 d high, on cells of 0.5, 1 and 2 d (collapse.run_continuum bins
  them in columns of 1 d), is 6 d high with its front at 9 d (the 3-column average: 2 d at 8.5,
  0 at 9.5); cells of 0.7 d, which tile no columns of 1 d, are refused;
- the on-the-fly coupling (coupling.AdaptiveRheology, with a stand-in for the RVE): cells above the
  sampled range (0.3) ask for the next grid point 0.3 f (f = 2: 0.6), run once, after which the
  sampled range ends there and I_cap (1.0) stops the next (1.2); with policy "hold" nothing runs;
  an RVE that fails is recorded and its grid point is not asked again; one whose measured I falls
  short of the request by more than 10 % (0.3 for 0.6) is reported, not used, and nothing higher
  is asked;
- in.collapse (a small column: 4 columns of spheres, 9 layers): it settles (kinetic energy per
  sphere below 1e-6), the settled packing fraction lies between a simple-cubic lattice (0.52) and
  random close packing (0.64), no sphere is lost, and the deposit runs out beyond the gate;
- `test_collapse.py kk` (ctest lammps.collapse.kk): the same with the kk styles (`-k on t 2 -sf kk`),
  and their kinetic energy 2 time units into the settling equals the CPU styles' to 1e-6 (the same
  forces to 1e-10, test_kokkos; later, collisions amplify round-off); skipped (exit 77) when
  GRIDDEM_LMP has no KOKKOS package.
The Python part needs NumPy/SciPy: without them this script re-runs itself under /usr/bin/python3."""
import math
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "examples", "column-collapse")
sys.path.insert(0, HERE)

import griddem_testlib as t

t.require_modules(("numpy", "scipy"), "test_collapse: needs NumPy and SciPy (Debian: /usr/bin/python3)", skip=True)

import numpy as np
from scipy.linalg import cho_solve_banded, cholesky_banded

sys.path.insert(0, EXAMPLE)
import continuum as C
import deposit as D
import layer_check as LC


def layer_checks():
    errs = []
    for n in (5, 10):
        r = LC.run_layer(n, t_end=400.0, dt=0.5)
        errs.append(r["rms_rel"])
        t.check(r["drift_last_10"] < 1e-4, "layer steady: largest change of u over the last 10 time units "
                "%.2e of the surface velocity" % r["drift_last_10"])
    t.check(max(errs) < 0.01 and errs[1] < 0.5 * errs[0],
            "2D solver reaches Bagnold (Jop mu(I), 25 deg): rms error / u_surface %s on 5, 10 cells over H" % errs)


def rest_checks():
    H, A, h, phi = 6.0, 2.0, 0.5, 0.6
    f = C.MuIFlow(4, int((H + A) / h), h, LC.mu_jop, phi)
    f.set_layer(H)
    for _ in range(20):
        f.step(0.1)
    expect = phi * (H - 0.5 * h) + f.rho_air * A
    t.check(abs(f.p[0, 0] / expect - 1) < 1e-9, "layer at rest: base pressure %.12g, weight above %.12g"
            % (f.p[0, 0], expect))
    t.check(np.abs(f.U).max() < 1e-9, "layer at rest stays at rest: largest velocity %.2e" % np.abs(f.U).max())
    # the same layer open at x = nx h to a layer at rest beyond (the ghost cells' p is its weight above)
    side = C.GrainFields(1, int((H + A) / h), h, phi)
    side.set_layer(H)
    f = C.MuIFlow(4, int((H + A) / h), h, LC.mu_jop, phi, open_pressure=side.p[0])
    f.set_layer(H)
    for _ in range(20):
        f.step(0.1)
    t.check(f.nu == 4 * f.ny and abs(f.p[0, 0] / expect - 1) < 1e-9 and np.abs(f.U).max() < 1e-9,
            "layer at rest, open side: %d u unknowns (the open faces' included), base pressure %.12g, largest "
            "velocity %.2e" % (f.nu, f.p[0, 0], np.abs(f.U).max()))
    for bad, why in (((np.zeros(3), False), "3 values for 16 rows"), ((side.p[0], True), "periodic box")):
        try:
            C.MuIFlow(4, int((H + A) / h), h, LC.mu_jop, phi, open_pressure=bad[0], periodic_x=bad[1])
            said = ""
        except ValueError as e:
            said = str(e)
        t.check(why in said, "open_pressure refused: %s" % said)


def mass_checks():
    h, L0, H0 = 1.0, 6.0, 8.0
    f = C.MuIFlow(24, 10, h, C.HeldMu(LC.mu_jop, 0.3), 0.6)
    f.set_column(L0, H0)
    area0 = f.c.sum() * h * h
    front0 = D.front((np.arange(24) + 0.5) * h, f.thickness())
    cmin, cmax = 0.0, 1.0
    while f.t < 6.0:
        f.step(f.stable_dt())
        cmin, cmax = min(cmin, f.c.min()), max(cmax, f.c.max())
    area = f.c.sum() * h * h
    t.check(abs(area0 - L0 * H0) < 1e-12 and abs(area / area0 - 1) < 1e-12,
            "grain area conserved: %.15g -> %.15g (L0 H0 = %g)" % (area0, area, L0 * H0))
    t.check(cmin > -1e-9 and cmax < 1 + 1e-9, "VOF fraction bounded: min %.3g max %.3g" % (cmin, cmax))
    front = D.front((np.arange(24) + 0.5) * h, f.thickness())
    t.check(front > front0 + 2.0, "the column collapses: front %.2f -> %.2f" % (front0, front))


def banded_checks():
    rng = np.random.default_rng(7)
    for nx, ny in ((9, 5), (5, 9)):
        f = C.MuIFlow(nx, ny, 1.0, LC.mu_jop, 0.6)
        for system in (f.viscous_system, f.pressure_system):
            w = [rng.uniform(0.1, 10.0, E.shape[0]) for E in system.blocks]
            A = sum(E.T @ (wk[:, None] * E.toarray()) for E, wk in zip(system.blocks, w))
            b = rng.standard_normal(system.n)
            x = system.factor(w)(b)
            t.check(np.abs(A @ x - b).max() < 1e-9 * np.abs(b).max(), "%d x %d box, bandwidth %d: residual %.1e"
                    % (nx, ny, system.bw, np.abs(A @ x - b).max()))
            # the same system through LAPACK's banded Cholesky (dpbtrf/dpbtrs, SciPy), in the same order
            o, bw = system.order, system.bw
            Ao = A[np.ix_(o, o)]
            upper = np.zeros((bw + 1, system.n))
            for k in range(bw + 1):
                upper[bw - k, k:] = np.diagonal(Ao, k)
            lapack = np.empty(system.n)
            lapack[o] = cho_solve_banded((cholesky_banded(upper), False), b[o])
            t.check(np.abs(x - lapack).max() < 1e-12 * np.abs(lapack).max(),
                    "%d x %d box: band_cholesky.c equals LAPACK's banded solve to %.1e (relative)"
                    % (nx, ny, np.abs(x - lapack).max() / np.abs(lapack).max()))
        # an indefinite system (a negative mass) is refused, not solved
        w = [rng.uniform(0.1, 10.0, E.shape[0]) for E in f.viscous_system.blocks]
        w[-1][3] = -1e3
        try:
            f.viscous_system.factor(w)
            refused = ""
        except np.linalg.LinAlgError as e:
            refused = str(e)
        t.check("not positive" in refused, "%d x %d box: an indefinite viscous system is refused (%s)" % (nx, ny, refused))


def following_box_checks():
    h, L0, H0, nx, ny = 1.0, 6.0, 12.0, 30, 24
    mu = C.HeldMu(LC.mu_jop, 0.3)
    whole, follow = C.MuIFlow(nx, ny, h, mu, 0.6), C.FollowingBox(nx, ny, h, mu, 0.6, quantum=1)
    # and one whose length follows the front too, open to the air beyond
    along = C.FollowingBox(nx, ny, h, mu, 0.6, quantum=1, margin_x=4, quantum_x=2)
    for f in (whole, follow, along):
        f.set_column(L0, H0)
    area0, boxes, lengths = follow.c.sum(), set(), set()
    while follow.t < 10.0:
        dt = whole.stable_dt()
        for f in (whole, follow, along):
            f.step(dt)
        boxes.add(follow.box)
        lengths.add(along.box[0])
    x = (np.arange(nx) + 0.5) * h
    fw, ff, fa = (D.front(x, f.thickness()) for f in (whole, follow, along))
    t.check(len(boxes) > 1 and max(b[1] for b in boxes) < ny and abs(follow.c.sum() / area0 - 1) < 1e-12,
            "following box: tops %s of %d rows, grain area %.15g -> %.15g"
            % (sorted({b[1] for b in boxes}), ny, area0, follow.c.sum()))
    t.check(abs(ff - fw) < 0.1 and ff > L0 + 2.0, "following box front %.3f, whole box %.3f" % (ff, fw))
    t.check(len(lengths) > 1 and min(lengths) < nx and abs(along.c.sum() / area0 - 1) < 1e-12
            and along.c.min() >= 0.0 and abs(fa - fw) < 0.1,
            "box following the front (open side): lengths %s of %d columns, grain area %.15g -> %.15g, "
            "front %.3f (whole box %.3f)" % (sorted(lengths), nx, area0, along.c.sum(), fa, fw))


def python_checks():
    held = C.HeldMu(lambda I: 0.4 + 0.1 * np.asarray(I), 0.3)
    v = held(np.array([0.1, 0.3, 2.0]))
    t.check(np.allclose(v, [0.41, 0.43, 0.43]), "HeldMu holds mu(I_max) above I_max: %s" % v)
    x = np.arange(6) + 0.5
    t.check(abs(D.front(x, 3.0 - x) - 2.0) < 1e-12, "front of h = 3 - x: %s" % D.front(x, 3.0 - x))
    # the deposit rule's columns of 1 d from cells of 0.5, 1 and 2 d: a column 8 d wide, 6 d high
    # tiles all three grids exactly, so the released column's thickness and front are the same; its
    # 3-column average reads 2 d at x = 8.5 and 0 at 9.5, so the front (h = 1 d) is at 9
    import collapse as CL
    dem = dict(L0=8.0, H0=6.0, phi0=0.6, Lx=40.0, stopped_at=1e-9)
    starts = [CL.run_continuum(dem, C.HeldMu(LC.mu_jop, 0.3), h=h) for h in (0.5, 1.0, 2.0)]
    t.check(all(abs(r["front"][0] - 9.0) < 1e-12 and abs(r["height"][0] - 6.0) < 1e-12 for r in starts),
            "released column's front and height from cells of 0.5, 1, 2 d: %s"
            % [(r["front"][0], r["height"][0]) for r in starts])
    try:
        CL.run_continuum(dem, C.HeldMu(LC.mu_jop, 0.3), h=0.7)
        said = ""
    except ValueError as e:
        said = str(e)
    t.check("h = 0.7 d" in said, "cells that do not tile 1 d columns refused: %s" % said)


def coupling_checks():
    import coupling as CP
    import learn_mu as L
    asked = []

    def stand_in(I):
        asked.append(I)
        return dict(I=I, dI=0.0, mu=float(L.mu_jop(I, 0.36, 1.0, 1.0)), dmu=0.008, phi=0.6 - 0.1 * I,
                    dphi=0.002, Irequested=I)
    start = [stand_in(I) for I in (0.001, 0.01, 0.3)]
    del asked[:]
    cells = np.array([0.05, 0.2, 0.8])
    r = CP.AdaptiveRheology(stand_in, start, 2.0, tol=1.0, members=2)
    while r.update(cells) is not None:
        pass
    t.check(np.allclose(asked, [0.6]) and abs(r.Ihi - 0.6) < 1e-12,
            "cells up to I 0.8, factor 2: RVEs at %s, sampled up to %s" % (asked, r.Ihi))
    r = CP.AdaptiveRheology(stand_in, start, 2.0, tol=1.0, policy="hold", members=2)
    t.check(r.update(cells) is None and r.I_max == 0.3, "policy hold: no RVE, mu held above 0.3")

    def failing(I):
        asked.append(I)
        raise RuntimeError("RVE at I=%g: pressure control failed" % I)
    del asked[:]
    r = CP.AdaptiveRheology(failing, start, 2.0, tol=1.0, members=2)
    first, second = r.update(cells), r.update(cells)
    t.check(first is not None and "failed" in first and second is None and asked == [0.6],
            "a failed RVE is recorded once and not asked again: %s %s %s" % (first, second, asked))

    def short(I):
        return dict(stand_in(I), I=0.5 * I)           # stand_in records the request
    del asked[:]
    r = CP.AdaptiveRheology(short, start, 1.5, tol=1.0, members=2)
    first = r.update(np.array([0.05, 2.0]))
    second = r.update(np.array([0.05, 2.0]))
    t.check(first is not None and "missed" in first and second is None and np.allclose(asked, [0.45]) and r.Ihi == 0.3
            and len(r.points) == 3, "an RVE short of its I is not used and stops the sampling above: %s %s %s"
            % (first, second, asked))


KOKKOS_ARGS = ["-k", "on", "t", "2", "-sf", "kk", "-pk", "kokkos", "newton", "off", "neigh", "half"]


def has_kokkos():
    """Whether GRIDDEM_LMP lists KOKKOS among its installed packages (lmp -h)."""
    out = subprocess.run([t.LMP, "-h"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         universal_newlines=True, timeout=120).stdout
    return "KOKKOS" in out.split("Installed packages:")[-1].split("List of individual")[0].split()


def small_collapse(label, extra=()):
    """The small column (4 columns of spheres, 9 layers) through in.collapse; the physical checks of
    its settling and deposit; returns the screen output (None if it failed)."""
    wd = t.workdir()
    shutil.copy(os.path.join(EXAMPLE, "in.collapse"), wd)
    cmd = [t.LMP, "-in", "in.collapse", "-var", "L0", "4.4", "-var", "H", "10", "-var", "Lx", "20",
           "-var", "tmax", "8", "-log", "none", "-echo", "none"] + list(extra)
    p = subprocess.run(cmd, cwd=wd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"), timeout=600)
    t.check(p.returncode == 0 and "GRIDDEM collapse: released" in p.stdout,
            "%s: in.collapse ran (exit %d): %s" % (label, p.returncode, p.stdout[-1500:]))
    if p.returncode != 0:
        return None
    line = [l for l in p.stdout.splitlines() if l.startswith("GRIDDEM collapse: N")][0]
    t.check(float(line.split()[-1]) < 1e-6, "%s: settled before release: %s" % (label, line))
    settled = D.read_dump(os.path.join(wd, "settled.dump"))[0][1]
    frames = D.read_dump(os.path.join(wd, "collapse.dump"))
    phi0, H0 = D.settled_column(settled, 4.4, 4.4)
    t.check(0.52 < phi0 < 0.64, "%s: settled packing fraction %.3f in (0.52, 0.64)" % (label, phi0))
    t.check(all(len(x) == len(settled) == 4 * 4 * 9 for _, x in frames),
            "%s: no sphere lost: %d spheres in every frame" % (label, len(settled)))
    xc, h = D.dem_thickness(frames[-1][1], 4.4, phi0, 20.0)
    t.check(D.front(xc, h) > 4.4 + 1.0, "%s: deposit runs out beyond the gate: front %.2f" % (label, D.front(xc, h)))
    return p.stdout


def kk_checks():
    """The kk styles against the CPU styles: a ctest entry of its own (lammps.collapse.kk), which
    exits 77 (reported as skipped) when GRIDDEM_LMP has no KOKKOS package."""
    if not has_kokkos():
        print("SKIPPED: %s has no KOKKOS package; configure with -DPKG_KOKKOS=on (README, 'Building with "
              "KOKKOS') and set GRIDDEM_LMP to that lmp" % t.LMP)
        sys.exit(77)
    cpu = small_collapse("CPU styles")
    kk = small_collapse("kk styles (2 threads)", KOKKOS_ARGS)
    if cpu is None or kk is None:
        return
    t.check("KOKKOS mode" in kk, "the kk run has Kokkos enabled")
    # same forces as the CPU styles (to 1e-10, test_kokkos), so the same trajectory until collisions
    # amplify round-off: the kinetic energy 2 time units into the settling (printed to 8 digits)
    ke_cpu, ke_kk = t.thermo_values(cpu, "c_ke"), t.thermo_values(kk, "c_ke")
    t.check(len(ke_cpu) > 1 and len(ke_kk) > 1 and abs(ke_kk[1] / ke_cpu[1] - 1) < 1e-6,
            "kk and CPU styles: kinetic energy at t = 2 %s and %s" % (ke_kk[1:2], ke_cpu[1:2]))


if __name__ == "__main__":
    if sys.argv[1:] == ["kk"]:
        kk_checks()
    else:
        python_checks()
        banded_checks()
        following_box_checks()
        rest_checks()
        mass_checks()
        layer_checks()
        coupling_checks()
        if shutil.which(t.LMP) or os.path.exists(t.LMP):
            small_collapse("CPU styles")
    t.finish()
