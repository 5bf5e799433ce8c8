/* Reduced-order model core: the voxel weights sum to 1, the deposit keeps the mass of the points
 * inside the box (and skips the others), interpolation reproduces a linear velocity field away
 * from the boundary voxels and a uniform one everywhere, and the prediction is the plain
 * matrix-vector product; the classification's contact checks and the reach test of lagging
 * kinematic atoms equal brute-force searches; the separation of released particles by hand and
 * against a brute-force sum; the voxel of a point; a grid placed at a moving origin sees a shifted point set
 * exactly as the frame's grid sees the unshifted one. */
#include "check.h"
#include "griddem_rom.h"

#include <math.h>

static const griddem_rom_grid G = {{4, 3, 5}, {-1.0, 0.0, 2.0}, {3.0, 1.5, 7.0}, {0, 1, 0}};

static void check_weights_and_deposit(void)
{
  double density[60] = {0}, x[3 * 100], mass[100], total = 0.0;
  const double vol = (4.0 / 4) * (1.5 / 3) * (5.0 / 5);
  for (int i = 0; i < 100; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = G.lo[d] + check_uniform() * (G.hi[d] - G.lo[d]);
    mass[i] = 0.5 + check_uniform();
    int voxel[8];
    double weight[8], sum = 0.0;
    griddem_rom_weights(&G, &x[3 * i], voxel, weight);
    for (int c = 0; c < 8; c++) {
      sum += weight[c];
      CHECK(voxel[c] >= 0 && voxel[c] < 60, "voxel %d in range", voxel[c]);
    }
    CHECK_CLOSE(sum, 1.0, 1e-14, 0.0);
    if (i < 90) total += mass[i];
    else x[3 * i] = 3.5;    /* outside the box: skipped */
  }
  griddem_rom_deposit(&G, 100, x, 3, mass, NULL, density);
  double sum = 0.0;
  for (int m = 0; m < 60; m++) sum += density[m] * vol;
  CHECK_CLOSE(sum, total, 1e-13, 0.0);
}

static void check_interpolation(void)
{
  double field[3 * 60];
  /* linear in x and z, uniform in y */
  for (int k = 0; k < 5; k++)
    for (int j = 0; j < 3; j++)
      for (int i = 0; i < 4; i++) {
        const int m = i + 4 * (j + 3 * k);
        const double xc = -1.0 + (i + 0.5) * 1.0, zc = 2.0 + (k + 0.5) * 1.0;
        field[3 * m] = 2.0 * xc - zc;
        field[3 * m + 1] = 0.7;
        field[3 * m + 2] = 0.25 * zc;
      }
  for (int t = 0; t < 50; t++) {
    /* between the first and last voxel centres along x and z: no clamping */
    const double p[3] = {-0.5 + check_uniform() * 3.0, check_uniform() * 1.5, 2.5 + check_uniform() * 4.0};
    double v[3];
    griddem_rom_interpolate(&G, field, 3, p, v);
    CHECK_CLOSE(v[0], 2.0 * p[0] - p[2], 1e-12, 1e-12);
    CHECK_CLOSE(v[1], 0.7, 1e-14, 0.0);
    CHECK_CLOSE(v[2], 0.25 * p[2], 1e-12, 1e-12);
    /* one component (a density): the x component's values alone */
    double scalar[60], s;
    for (int m = 0; m < 60; m++) scalar[m] = field[3 * m];
    griddem_rom_interpolate(&G, scalar, 1, p, &s);
    CHECK_CLOSE(s, 2.0 * p[0] - p[2], 1e-12, 1e-12);
  }
  const double corner[3] = {-0.99, 0.01, 6.99};
  double v[3];
  griddem_rom_interpolate(&G, field, 3, corner, v);
  CHECK_CLOSE(v[1], 0.7, 1e-14, 0.0);
  CHECK(griddem_rom_inside(&G, corner) && !griddem_rom_inside(&G, (const double[3]){3.0, 0.5, 3.0}) &&
            griddem_rom_inside(&G, (const double[3]){0.0, 1.6, 3.0}),
        "inside: lo <= x < hi, any y along the periodic axis");
}

static void check_predict(void)
{
  const double w[6] = {1, 2, 3, -1, 0.5, 4}, f[3] = {1, -2, 0.5};
  double out[2];
  griddem_rom_predict(2, 3, w, f, out);
  CHECK_CLOSE(out[0], 1.0 - 4.0 + 1.5, 1e-15, 0.0);
  CHECK_CLOSE(out[1], -1.0 - 1.0 + 2.0, 1e-15, 1e-15);

  /* the occupancy form: two voxels, one control; row r = 3 m + d is density(m) (w0 + w1 c) */
  const double w2[12] = {1, 2, 0, 1, -1, 0.5, 0.25, 4, 3, 0, 2, -2}, density[2] = {0.5, 2.0}, control[1] = {3.0};
  const double expected[6] = {0.5 * 7, 0.5 * 3, 0.5 * 0.5, 2.0 * 12.25, 2.0 * 3, 2.0 * -4};
  double scratch[2], field[6];
  griddem_rom_predict_occupancy(2, 1, w2, control, density, scratch, field);
  for (int r = 0; r < 6; r++) CHECK_CLOSE(field[r], expected[r], 1e-15, 0.0);
}

/* The classification's contact checks on the grid equal a brute-force check of every pair: the
 * same atoms stay candidates, and each kinematic atom dropped is counted once as a hit or an
 * overlap; also on a dilute set whose grid edge grows (two far outliers). */
static void check_contacts(double spread)
{
  enum { NALL = 400, NLOCAL = 300 };
  static double x[3 * NALL], v[3 * NALL], u[3 * NALL], r[NALL];
  static int kin[NALL], next[NALL], ref[NALL];
  const double threshold = 0.3, overlap_max = 0.2;
  for (int i = 0; i < NALL; i++) {
    for (int d = 0; d < 3; d++) {
      x[3 * i + d] = 4.0 * check_uniform();
      v[3 * i + d] = 0.4 * (check_uniform() - 0.5);
      u[3 * i + d] = 0.4 * (check_uniform() - 0.5);
    }
    r[i] = 0.1 + 0.15 * check_uniform();
    kin[i] = check_uniform() < 0.6;
    next[i] = ref[i] = check_uniform() < 0.8;
  }
  x[3 * (NALL - 1)] = x[3 * (NALL - 2) + 2] = spread; /* ghosts far away */
  int dropped = 0;
  for (int i = 0; i < NLOCAL; i++) {
    if (!ref[i]) continue;
    const double *vi = kin[i] ? &v[3 * i] : &u[3 * i];
    for (int j = 0; j < NALL && ref[i]; j++) {
      if (j == i) continue;
      const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
      const double dist = sqrt(dx * dx + dy * dy + dz * dz), touch = r[i] + r[j];
      if (dist >= touch) continue;
      const double dv[3] = {vi[0] - v[3 * j], vi[1] - v[3 * j + 1], vi[2] - v[3 * j + 2]};
      if (touch - dist > overlap_max * fmin(r[i], r[j]) || (!kin[j] && sqrt(dv[0] * dv[0] + dv[1] * dv[1] + dv[2] * dv[2]) > threshold))
        ref[i] = 0, dropped += kin[i];
    }
  }
  griddem_grid g;
  griddem_bins b = {0};
  int hits = 0, overlaps = 0, same = 1, kept = 0;
  CHECK(griddem_rom_check_contacts(NLOCAL, NALL, x, v, r, kin, u, threshold, overlap_max, next, &hits, &overlaps, &g, &b) == 0,
        "contact check runs");
  for (int i = 0; i < NALL; i++) same &= next[i] == ref[i], kept += ref[i] && i < NLOCAL;
  CHECK(same, "spread %g: candidates kept equal the brute-force check (%d kept)", spread, kept);
  CHECK(hits + overlaps == dropped && hits > 0 && overlaps > 0 && kept > 20,
        "spread %g: %d hits + %d overlaps, brute force drops %d kinematic atoms", spread, hits, overlaps, dropped);
  griddem_bins_free(&b);
}

/* The separation of released particles: two released together each move by half their overlap,
 * one released from a fixed partner by all of it, a shift longer than the radius is cut to it, a
 * particle that touches nothing stays; and on a random set the moves equal a brute-force sum over
 * every pair computed from the positions on entry. */
static void check_separate(void)
{
  griddem_grid g;
  griddem_bins b = {0};
  griddem_stencil stencil; /* bin_for_contacts's; separate builds its own again */
  double shift[9];
  {
    double x[6] = {0.0, 0.0, 0.0, 0.8, 0.0, 0.0};
    const double r[2] = {0.5, 0.5};
    const int released[2] = {1, 1};
    CHECK(griddem_bin_for_contacts(&g, &b, &stencil, 2, x, r) == 0, "binned");
    CHECK(griddem_rom_separate(2, 2, x, r, released, shift, &g, &b) == 2, "two released particles moved");
    CHECK_CLOSE(x[0], -0.1, 1e-15, 0.0);
    CHECK_CLOSE(x[3], 0.9, 1e-15, 0.0);
  }
  {
    double x[6] = {0.0, 0.0, 0.0, 0.0, 0.8, 0.0}; /* the partner a ghost, not released */
    const double r[2] = {0.5, 0.5};
    const int released[2] = {1, 0};
    CHECK(griddem_bin_for_contacts(&g, &b, &stencil, 2, x, r) == 0, "binned");
    CHECK(griddem_rom_separate(1, 2, x, r, released, shift, &g, &b) == 1, "one released particle moved");
    CHECK_CLOSE(x[1], -0.2, 1e-15, 0.0);
    CHECK(x[0] == 0.0 && x[2] == 0.0 && x[4] == 0.8, "only along the line of centres, the ghost in place");
  }
  {
    /* three fixed partners deep on one side: 0.45 + 2 x 0.45 cos(angle) > r = 0.5 is cut to 0.5 */
    double x[12] = {0.0, 0.0, 0.0, 0.55, 0.0, 0.0, 0.5, 0.2, 0.0, 0.5, -0.2, 0.0};
    const double r[4] = {0.5, 0.5, 0.5, 0.5};
    const int released[4] = {1, 0, 0, 0};
    CHECK(griddem_bin_for_contacts(&g, &b, &stencil, 4, x, r) == 0, "binned");
    CHECK(griddem_rom_separate(1, 4, x, r, released, shift, &g, &b) == 1, "the deep particle moved");
    CHECK_CLOSE(x[0], -0.5, 1e-15, 0.0);
    CHECK(x[1] == 0.0 && x[2] == 0.0, "cut along the sum's direction");
  }
  {
    double x[6] = {0.0, 0.0, 0.0, 1.5, 0.0, 0.0};
    const double r[2] = {0.5, 0.5};
    const int released[2] = {1, 1};
    CHECK(griddem_bin_for_contacts(&g, &b, &stencil, 2, x, r) == 0, "binned");
    CHECK(griddem_rom_separate(2, 2, x, r, released, shift, &g, &b) == 0 && x[0] == 0.0 && x[3] == 1.5,
          "particles apart stay");
  }
  enum { NALL = 400, NLOCAL = 300 };
  static double x[3 * NALL], x0[3 * NALL], r[NALL], big[3 * NLOCAL], expect[3 * NALL];
  static int released[NALL];
  for (int i = 0; i < NALL; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = x0[3 * i + d] = expect[3 * i + d] = 4.0 * check_uniform();
    r[i] = 0.1 + 0.15 * check_uniform();
    released[i] = check_uniform() < 0.3;
  }
  int expect_moved = 0;
  for (int i = 0; i < NLOCAL; i++) {
    if (!released[i]) continue;
    double si[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < NALL; j++) {
      if (j == i) continue;
      const double dx[3] = {x0[3 * i] - x0[3 * j], x0[3 * i + 1] - x0[3 * j + 1], x0[3 * i + 2] - x0[3 * j + 2]};
      const double dist = sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
      if (dist >= r[i] + r[j]) continue;
      for (int d = 0; d < 3; d++) si[d] += (r[i] + r[j] - dist) * (released[j] ? 0.5 : 1.0) * dx[d] / dist;
    }
    const double len = sqrt(si[0] * si[0] + si[1] * si[1] + si[2] * si[2]);
    if (len == 0.0) continue;
    expect_moved++;
    for (int d = 0; d < 3; d++) expect[3 * i + d] += (len > r[i] ? r[i] / len : 1.0) * si[d];
  }
  CHECK(griddem_bin_for_contacts(&g, &b, &stencil, NALL, x, r) == 0, "binned");
  const int moved = griddem_rom_separate(NLOCAL, NALL, x, r, released, big, &g, &b);
  double worst = 0.0;
  for (int k = 0; k < 3 * NALL; k++) worst = fmax(worst, fabs(x[k] - expect[k]));
  CHECK(moved == expect_moved && expect_moved > 20 && worst <= 1e-12,
        "random set: %d moved (brute force %d), worst position difference %g", moved, expect_moved, worst);
  griddem_bins_free(&b);
}

/* The reach test on the grid equals a brute-force search over every pair: the near kinematic
 * atoms and the budgets of the others; also on a dilute set (far outliers grow the grid edge). */
static void check_near(double spread)
{
  enum { NALL = 400, NLOCAL = 300 };
  static double x[3 * NALL], r[NALL], budget[NALL];
  static int kin[NALL], near[NALL];
  const double reach = 0.05, cap = 0.3;
  for (int i = 0; i < NALL; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = 4.0 * check_uniform();
    r[i] = 0.1 + 0.15 * check_uniform();
    kin[i] = check_uniform() < 0.7;
  }
  x[3 * (NALL - 1)] = x[3 * (NALL - 2) + 2] = spread;
  griddem_grid g;
  griddem_bins b = {0};
  CHECK(griddem_rom_mark_near(NLOCAL, NALL, x, r, kin, reach, cap, near, budget, &g, &b) == 0, "reach test runs");
  int same = 1, nnear = 0, nfar = 0, capped = 0, tight = 0;
  for (int i = 0; i < NLOCAL; i++) {
    int ref_near = 0;
    double ref_budget = cap;
    for (int j = 0; j < NALL; j++) {
      if (j == i || kin[j] == kin[i]) continue;
      const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
      const double gap = sqrt(dx * dx + dy * dy + dz * dz) - (r[i] + r[j]);
      if (kin[i] && gap < reach) ref_near = 1;
      if (!kin[i] && gap >= reach && gap < ref_budget) ref_budget = gap;
    }
    same &= near[i] == ref_near && (kin[i] || budget[i] == ref_budget);
    if (kin[i]) nnear += ref_near, nfar += !ref_near;
    else capped += ref_budget == cap, tight += ref_budget < cap;
  }
  CHECK(same, "spread %g: near atoms and budgets equal the brute-force search", spread);
  CHECK(nnear > 10 && nfar > 10 && capped > 3 && tight > 10,
        "spread %g: both kinds occur (%d near, %d far; budgets %d capped, %d below the cap)", spread, nnear, nfar,
        capped, tight);
  const double corner[3] = {2.999999, 1.4999999, 6.9999999};
  CHECK(griddem_rom_voxel(&G, corner) == 59 && griddem_rom_voxel(&G, (const double[3]){-1.0, 0.0, 2.0}) == 0 &&
            griddem_rom_voxel(&G, (const double[3]){0.5, 0.6, 4.2}) == 1 + 4 * (1 + 3 * 2) &&
            griddem_rom_voxel(&G, (const double[3]){3.0, 0.5, 3.0}) == -1 &&
            griddem_rom_voxel(&G, (const double[3]){0.5, 0.6 + 1.5, 4.2}) == 1 + 4 * (1 + 3 * 2) &&
            griddem_rom_voxel(&G, (const double[3]){0.5, 0.6 - 1.5, 4.2}) == 1 + 4 * (1 + 3 * 2),
        "voxel of a point: corners, an inner point, outside, past the periodic y boundary");
  griddem_bins_free(&b);
}

/* Points p + origin on the placed grid: the same voxels, weights and deposit as p on the frame's
 * grid (the origin's shift is exactly representable: multiples of 1/8), and p + origin is outside
 * the placed box where p is outside the frame's. */
static void check_place(void)
{
  const double origin[3] = {2.375, 0.0, -1.125};
  griddem_rom_grid placed;
  griddem_rom_place(&G, origin, &placed);
  CHECK(placed.lo[0] == 1.375 && placed.hi[0] == 5.375 && placed.lo[2] == 0.875 && placed.hi[2] == 5.875 &&
            placed.n[0] == 4 && placed.periodic[1] == 1,
        "placed box = the frame's box + origin, same voxels and periodicity");
  double x[3 * 50], xs[3 * 50], mass[50], d0[60] = {0}, d1[60] = {0};
  int same = 1;
  for (int i = 0; i < 50; i++) {
    for (int d = 0; d < 3; d++) {
      /* on a 1/64 lattice: p + origin is exact */
      x[3 * i + d] = G.lo[d] + floor(check_uniform() * (G.hi[d] - G.lo[d]) * 64.0) / 64.0;
      xs[3 * i + d] = x[3 * i + d] + origin[d];
    }
    mass[i] = 1.0;
    int v0[8], v1[8];
    double w0[8], w1[8];
    griddem_rom_weights(&G, &x[3 * i], v0, w0);
    griddem_rom_weights(&placed, &xs[3 * i], v1, w1);
    for (int c = 0; c < 8; c++) same &= v0[c] == v1[c] && fabs(w0[c] - w1[c]) <= 1e-14;
    same &= griddem_rom_voxel(&G, &x[3 * i]) == griddem_rom_voxel(&placed, &xs[3 * i]);
  }
  CHECK(same, "voxels, weights and voxel of shifted points equal the frame's");
  griddem_rom_deposit(&G, 50, x, 3, mass, NULL, d0);
  griddem_rom_deposit(&placed, 50, xs, 3, mass, NULL, d1);
  double diff = 0.0;
  for (int m = 0; m < 60; m++) diff = fmax(diff, fabs(d0[m] - d1[m]));
  CHECK(diff <= 1e-12, "deposit of shifted points equals the frame's (largest difference %g)", diff);
  CHECK(griddem_rom_inside(&placed, (const double[3]){5.0, 0.5, 1.0}) &&
            !griddem_rom_inside(&placed, (const double[3]){1.0, 0.5, 3.0}) &&
            !griddem_rom_inside(&G, (const double[3]){5.0, 0.5, 1.0}),
        "inside follows the placed box");
}

int main(void)
{
  check_place();
  check_weights_and_deposit();
  check_interpolation();
  check_predict();
  check_contacts(4.0);
  check_contacts(1e5);
  check_near(4.0);
  check_near(1e5);
  check_separate();
  return check_summary();
}
