/* Coarse-graining core: cloud-in-cell weights keep totals and first moments, the truncated kernel
 * is normalised, symmetric and cut where the Gaussian falls below 1e-6 of its peak, the direct
 * circular convolution equals the convolution theorem done with a naive DFT, and zero padding
 * keeps mass at one wall from reaching the other. */
#include "check.h"
#include "griddem_cg.h"

#include <math.h>
#include <stdlib.h>

static void check_cic(void)
{
  const double boxlo = -1.0, h = 0.25;
  const int n = 8;
  for (int t = 0; t < 100; t++) {
    const double x = boxlo + 0.1 * h + check_uniform() * (n - 0.2) * h;
    int index[2];
    double weight[2];
    griddem_cg_cic(x, boxlo, h, n, 1, index, weight);
    CHECK_CLOSE(weight[0] + weight[1], 1.0, 1e-15, 0.0);
    CHECK(weight[0] >= 0.0 && weight[1] >= 0.0 && index[1] == index[0] + 1, "weights of %g", x);
    /* linear interpolation is exact: the weighted grid point positions give back x */
    const double back = weight[0] * (boxlo + (index[0] + 0.5) * h) + weight[1] * (boxlo + (index[1] + 0.5) * h);
    CHECK_CLOSE(back, x, 1e-14, 1e-15);
  }
  int index[2];
  double weight[2];
  griddem_cg_cic(boxlo + 0.1 * h, boxlo, h, n, 0, index, weight);
  CHECK(index[0] == 0 && index[1] == 0, "near the lower wall, non-periodic: both weights on point 0");
  griddem_cg_cic(boxlo + (n - 0.1) * h, boxlo, h, n, 0, index, weight);
  CHECK(index[0] == n - 1 && index[1] == n - 1, "near the upper wall: both weights on point n-1");
  griddem_cg_cic(boxlo + 0.1 * h, boxlo, h, n, 1, index, weight);
  CHECK(index[0] == -1 && index[1] == 0, "periodic: index -1 left for the ghost points");
}

static void check_kernel(void)
{
  const double width = 0.3;
  const double cut = griddem_cg_cutoff(width);
  CHECK_CLOSE(exp(-cut * cut / (2 * width * width)), GRIDDEM_CG_TRUNCATION, 1e-12, 0.0);
  const double h[3] = {0.1, 0.15, 0.2};
  int m[3], lo[3] = {0, 0, 0}, hi[3];
  for (int d = 0; d < 3; d++) {
    m[d] = 2 * griddem_cg_reach(width, h[d]) + 7; /* room: every offset has one image */
    hi[d] = m[d] - 1;
  }
  CHECK(griddem_cg_reach(width, h[0]) == (int) floor(cut / h[0]), "reach %d", griddem_cg_reach(width, h[0]));
  const long size = (long) m[0] * m[1] * m[2];
  double *k = malloc(size * sizeof(double));
  griddem_cg_kernel_brick(m, lo, hi, h, width, k);
  double sum = 0.0;
  for (long i = 0; i < size; i++) sum += k[i];
  CHECK_CLOSE(sum, 1.0, 1e-13, 0.0);
  /* symmetric: offset d and -d (index m - d) carry the same weight */
  CHECK_CLOSE(k[1 + m[0] * (2 + (long) m[1] * 1)], k[(m[0] - 1) + m[0] * ((m[1] - 2) + (long) m[1] * (m[2] - 1))], 1e-15, 0.0);
  /* Gaussian ratios between points inside the cutoff; zero just beyond it along x */
  const int r = griddem_cg_reach(width, h[0]);
  CHECK_CLOSE(k[1] / k[0], exp(-h[0] * h[0] / (2 * width * width)), 1e-13, 0.0);
  CHECK(k[r] > 0.0 && k[r + 1] == 0.0, "cut after offset %d: %g %g", r, k[r], k[r + 1]);
  /* a grid smaller than the kernel folds the images onto itself and still sums to 1 */
  const int small[3] = {3, 4, 2}, shi[3] = {2, 3, 1};
  double ks[24];
  griddem_cg_kernel_brick(small, lo, shi, h, width, ks);
  sum = 0.0;
  for (int i = 0; i < 24; i++) sum += ks[i];
  CHECK_CLOSE(sum, 1.0, 1e-14, 0.0);
  /* a brick part of the grid gives the same values as the whole grid */
  const int plo[3] = {1, 2, 3}, phi[3] = {3, 2, 4};
  double part[6];
  griddem_cg_kernel_brick(m, plo, phi, h, width, part);
  CHECK(part[0] == k[1 + m[0] * (2 + (long) m[1] * 3)] && part[5] == k[3 + m[0] * (2 + (long) m[1] * 4)],
        "brick values equal the whole grid's");
  free(k);
}

/* the convolution theorem with a naive DFT: out = IDFT(DFT(kernel) * DFT(field)) */
static void convolve_by_dft(const int m[3], const double *kernel, const double *field, double *out)
{
  const long n = (long) m[0] * m[1] * m[2];
  double *re = malloc(n * sizeof(double)), *im = malloc(n * sizeof(double));
  const double two_pi = 6.283185307179586;
  for (long q = 0; q < n; q++) {
    const int qx = q % m[0], qy = q / m[0] % m[1], qz = q / ((long) m[0] * m[1]);
    double kr = 0, ki = 0, fr = 0, fi = 0;
    for (long p = 0; p < n; p++) {
      const int px = p % m[0], py = p / m[0] % m[1], pz = p / ((long) m[0] * m[1]);
      const double phase = -two_pi * ((double) qx * px / m[0] + (double) qy * py / m[1] + (double) qz * pz / m[2]);
      kr += kernel[p] * cos(phase), ki += kernel[p] * sin(phase);
      fr += field[p] * cos(phase), fi += field[p] * sin(phase);
    }
    re[q] = kr * fr - ki * fi, im[q] = kr * fi + ki * fr;
  }
  for (long p = 0; p < n; p++) {
    const int px = p % m[0], py = p / m[0] % m[1], pz = p / ((long) m[0] * m[1]);
    double sum = 0;
    for (long q = 0; q < n; q++) {
      const int qx = q % m[0], qy = q / m[0] % m[1], qz = q / ((long) m[0] * m[1]);
      const double phase = two_pi * ((double) qx * px / m[0] + (double) qy * py / m[1] + (double) qz * pz / m[2]);
      sum += re[q] * cos(phase) - im[q] * sin(phase);
    }
    out[p] = sum / n;
  }
  free(re);
  free(im);
}

static void check_convolution(void)
{
  const int m[3] = {5, 4, 6}, lo[3] = {0, 0, 0}, hi[3] = {4, 3, 5};
  const double h[3] = {0.2, 0.25, 0.2};
  double kernel[120], field[120], direct[120], spectral[120];
  griddem_cg_kernel_brick(m, lo, hi, h, 0.22, kernel);
  double total = 0.0;
  for (int i = 0; i < 120; i++) field[i] = check_uniform(), total += field[i];
  griddem_cg_convolve_direct(m, kernel, field, direct);
  convolve_by_dft(m, kernel, field, spectral);
  double worst = 0.0, after = 0.0;
  for (int i = 0; i < 120; i++) {
    worst = fmax(worst, fabs(direct[i] - spectral[i]));
    after += direct[i];
  }
  CHECK(worst <= 1e-12 * total / 120, "direct and DFT convolution differ by %g", worst);
  CHECK_CLOSE(after, total, 1e-14, 0.0);

  /* a unit mass at point 0 gives the kernel itself */
  double delta[120] = {1.0};
  griddem_cg_convolve_direct(m, kernel, delta, direct);
  worst = 0.0;
  for (int i = 0; i < 120; i++) worst = fmax(worst, fabs(direct[i] - kernel[i]));
  CHECK(worst == 0.0, "a delta gives the kernel (%g)", worst);
}

static void check_padding(void)
{
  /* 1d along x: n = 6 points, non-periodic; a mass at point 0 must not appear at point n-1 */
  const double width = 0.3, h[3] = {0.2, 10.0, 10.0}; /* y, z: no neighbours in reach */
  const int n = 6, reach = griddem_cg_reach(width, h[0]);
  CHECK(reach == 7 && griddem_cg_fft_size(n, 1, reach) == n, "reach %d, periodic size", reach);
  const int size = griddem_cg_fft_size(n, 0, reach);
  CHECK(size == n + reach, "padded size %d", size);
  const int m[3] = {size, 1, 1}, lo[3] = {0, 0, 0}, hi[3] = {size - 1, 0, 0};
  double kernel[32], field[32] = {1.0}, out[32];
  griddem_cg_kernel_brick(m, lo, hi, h, width, kernel);
  griddem_cg_convolve_direct(m, kernel, field, out);
  /* the open-boundary answer: the kernel at offset i, with offsets beyond the reach zero */
  const double c = -0.5 / (width * width);
  double norm = 0.0;
  for (int d = -reach; d <= reach; d++) norm += exp(c * d * d * h[0] * h[0]);
  for (int i = 0; i < n; i++) CHECK_CLOSE(out[i], exp(c * i * i * h[0] * h[0]) / norm, 1e-14, 0.0);
  /* the same field on the unpadded (periodic) grid folds the left tail onto point n-1 */
  const int mp[3] = {n, 1, 1}, hip[3] = {n - 1, 0, 0};
  griddem_cg_kernel_brick(mp, lo, hip, h, width, kernel);
  griddem_cg_convolve_direct(mp, kernel, field, out);
  CHECK(out[n - 1] > 1.5 * exp(c * (n - 1) * (n - 1) * h[0] * h[0]) / norm, "periodic folds: %g", out[n - 1]);
}

int main(void)
{
  check_cic();
  check_kernel();
  check_convolution();
  check_padding();
  return check_summary();
}
