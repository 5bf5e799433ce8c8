/* Reduced-order model core: the voxel weights sum to 1, the deposit keeps the mass of the points
 * inside the box (and skips the others), interpolation reproduces a linear velocity field away
 * from the boundary voxels and a uniform one everywhere, and the prediction is the plain
 * matrix-vector product. */
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
    griddem_rom_interpolate(&G, field, p, v);
    CHECK_CLOSE(v[0], 2.0 * p[0] - p[2], 1e-12, 1e-12);
    CHECK_CLOSE(v[1], 0.7, 1e-14, 0.0);
    CHECK_CLOSE(v[2], 0.25 * p[2], 1e-12, 1e-12);
  }
  const double corner[3] = {-0.99, 0.01, 6.99};
  double v[3];
  griddem_rom_interpolate(&G, field, corner, v);
  CHECK_CLOSE(v[1], 0.7, 1e-14, 0.0);
  CHECK(griddem_rom_inside(&G, corner) && !griddem_rom_inside(&G, (const double[3]){3.0, 0.5, 3.0}),
        "inside: lo <= x < hi");
}

static void check_predict(void)
{
  const double w[6] = {1, 2, 3, -1, 0.5, 4}, f[3] = {1, -2, 0.5};
  double out[2];
  griddem_rom_predict(2, 3, w, f, out);
  CHECK_CLOSE(out[0], 1.0 - 4.0 + 1.5, 1e-15, 0.0);
  CHECK_CLOSE(out[1], -1.0 - 1.0 + 2.0, 1e-15, 1e-15);
}

int main(void)
{
  check_weights_and_deposit();
  check_interpolation();
  check_predict();
  return check_summary();
}
