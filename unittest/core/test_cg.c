/* Coarse-graining core: cloud-in-cell weights keep totals and first moments; the kernel equals
 * brute-force sums of the Gaussian over the lattice and its periodic images on both sides of the
 * switches between the direct and Poisson forms, sums to 1 on a periodic axis, pads at most the
 * box along a non-periodic one and costs the same for any W (a Gaussian wider than the box is
 * flat); the direct circular convolution equals the convolution theorem done with a naive DFT,
 * and zero padding keeps mass at one wall from reaching the other; the coordination channel's
 * contacts equal a brute-force count over all pairs, also when two far points coarsen the grid. */
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

/* Reference sums by brute force over |d| <= span, far beyond where exp(-a d^2) underflows. */
static double brute_lattice_sum(double a, long span)
{
  double sum = 0.0;
  for (long d = -span; d <= span; d++) sum += exp(-a * (double) d * (double) d);
  return sum;
}

static double brute_periodic(double a, int m, int i, long span)
{
  double sum = 0.0;
  for (long d = -span; d <= span; d++)
    if (((d - i) % m + m) % m == 0) sum += exp(-a * (double) d * (double) d);
  return sum;
}

static void check_kernel_axis(void)
{
  /* W/h on both sides of the switches between the direct and Poisson forms (a = h^2/(2 W^2) = pi
   * at W/h = 0.399, a m^2 = pi at W/h = 0.399 m) and far beyond the box */
  const double h = 0.25, ratios[] = {0.1, 0.398, 0.4, 1.0, 2.0, 2.4, 2.5, 3.0, 8.0, 60.0};
  const int sizes[] = {1, 2, 6, 7};
  double k[64];
  for (unsigned r = 0; r < sizeof ratios / sizeof ratios[0]; r++) {
    const double width = ratios[r] * h, a = h * h / (2 * width * width);
    const long span = (long) (12.0 * ratios[r]) + 100;
    const double norm = brute_lattice_sum(a, span);
    for (unsigned s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
      const int m = sizes[s];
      griddem_cg_kernel_axis(m, GRIDDEM_CG_PERIODIC, h, width, k);
      double sum = 0.0;
      for (int i = 0; i < m; i++) {
        CHECK_CLOSE(k[i], brute_periodic(a, m, i, span) / norm, 1e-13, 1e-18);
        sum += k[i];
      }
      CHECK_CLOSE(sum, 1.0, 1e-14, 0.0);
    }
    /* non-periodic: the Gaussian at |d| <= reach over the whole lattice sum, zero elsewhere */
    const int n = 9, m = griddem_cg_fft_size(n, 0, width, h), reach = m - n;
    CHECK(reach == griddem_cg_padding(n, width, h) && 2 * reach + 1 <= m, "W/h %g: reach %d, m %d",
          ratios[r], reach, m);
    griddem_cg_kernel_axis(m, reach, h, width, k);
    for (int i = 0; i < m; i++) {
      const int d = i <= reach ? i : i - m;
      const double expect = (d >= -reach && d <= reach) ? exp(-a * d * d) / norm : 0.0;
      CHECK_CLOSE(k[i], expect, 1e-13, 1e-18);
    }
  }
}

static void check_padding_bounds(void)
{
  const double cut = griddem_cg_cutoff(0.3);
  CHECK_CLOSE(exp(-cut * cut / (2 * 0.3 * 0.3)), GRIDDEM_CG_NEGLIGIBLE, 1e-12, 0.0);
  /* the dropped tail is below rounding of the sum: beyond the cutoff, sum_d>R exp(-a d^2) */
  const double h = 0.01, width = 0.3, a = h * h / (2 * width * width);
  const int reach = griddem_cg_padding(1000000, width, h);
  CHECK(reach == (int) floor(cut / h), "padding %d inside a large box is the cutoff", reach);
  double tail = 0.0;
  for (long d = reach + 1; d < 10 * reach; d++) tail += exp(-a * (double) d * (double) d);
  CHECK(2 * tail <= 1e-17 * brute_lattice_sum(a, 10 * reach), "dropped tail %g", 2 * tail);
  /* a kernel wider than the box pads to the farthest offset, n - 1, for any W */
  const double wide[] = {3.0, 1e4, 1e300};
  for (int w = 0; w < 3; w++) {
    CHECK(griddem_cg_padding(8, wide[w], 1.0) == 7, "W %g: padding %d", wide[w], griddem_cg_padding(8, wide[w], 1.0));
    CHECK(griddem_cg_fft_size(8, 0, wide[w], 1.0) == 15 && griddem_cg_fft_size(8, 1, wide[w], 1.0) == 8,
          "W %g: FFT sizes", wide[w]);
  }
  CHECK(griddem_cg_padding(8, 1e-300, 1.0) == 0, "a kernel narrower than the spacing needs no padding");
}

/* The cost of W: a Gaussian much wider than a 4 x 4 x 8 grid (periodic x, y; z not) is flat
 * along the periodic axes, 1/m exactly, and h / (W sqrt(2 pi)) along z. W = 1e4 spacings once
 * took time growing as W^3; the widest finite W underflows to a zero kernel along z. */
static void check_wide_kernel(void)
{
  const int n[3] = {4, 4, 8}, lo[3] = {0, 0, 0};
  const double h[3] = {0.5, 0.5, 1.0};
  const double widths[] = {1e4, 1e12, 1e300};
  for (int w = 0; w < 3; w++) {
    const double width = widths[w];
    int m[3], reach[3], hi[3];
    for (int d = 0; d < 3; d++) {
      m[d] = griddem_cg_fft_size(n[d], d < 2, width, h[d]);
      reach[d] = d < 2 ? GRIDDEM_CG_PERIODIC : m[d] - n[d];
      hi[d] = m[d] - 1;
    }
    CHECK(m[2] == 15, "W %g: FFT grid 2n - 1 = 15 along z (%d)", width, m[2]);
    double kernel[4 * 4 * 15];
    griddem_cg_kernel_brick(m, reach, lo, hi, h, width, kernel);
    const double flat = 1.0 / 16 * h[2] / (width * sqrt(2.0 * 3.14159265358979323846));
    double worst = 0.0;
    for (int i = 0; i < 4 * 4 * 15; i++) worst = fmax(worst, fabs(kernel[i] - flat));
    CHECK(worst <= 1e-6 * flat || (flat < 1e-290 && worst <= 1e-300), "W %g: flat kernel %g (off by %g)",
          width, flat, worst);
  }
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
  const int periodic[3] = {GRIDDEM_CG_PERIODIC, GRIDDEM_CG_PERIODIC, GRIDDEM_CG_PERIODIC};
  const double h[3] = {0.2, 0.25, 0.2};
  double kernel[120], field[120], direct[120], spectral[120];
  griddem_cg_kernel_brick(m, periodic, lo, hi, h, 0.22, kernel);
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
  const int n = 6, reach = griddem_cg_padding(n, width, h[0]);
  CHECK(reach == 5 && griddem_cg_fft_size(n, 1, width, h[0]) == n, "reach %d (the box), periodic size", reach);
  const int size = griddem_cg_fft_size(n, 0, width, h[0]);
  CHECK(size == n + reach, "padded size %d", size);
  const int m[3] = {size, 1, 1}, lo[3] = {0, 0, 0}, hi[3] = {size - 1, 0, 0};
  const int reaches[3] = {reach, GRIDDEM_CG_PERIODIC, GRIDDEM_CG_PERIODIC};
  double kernel[32], field[32] = {1.0}, out[32];
  griddem_cg_kernel_brick(m, reaches, lo, hi, h, width, kernel);
  griddem_cg_convolve_direct(m, kernel, field, out);
  /* the open-boundary answer: the Gaussian at offset i over its sum over all offsets */
  const double a = h[0] * h[0] / (2 * width * width);
  const double norm = brute_lattice_sum(a, 1000);
  for (int i = 0; i < n; i++) CHECK_CLOSE(out[i], exp(-a * i * i) / norm, 1e-14, 0.0);
  /* the same field on the unpadded (periodic) grid folds the left tail onto point n-1 */
  const int mp[3] = {n, 1, 1}, hip[3] = {n - 1, 0, 0};
  const int periodic[3] = {GRIDDEM_CG_PERIODIC, GRIDDEM_CG_PERIODIC, GRIDDEM_CG_PERIODIC};
  griddem_cg_kernel_brick(mp, periodic, lo, hip, h, width, kernel);
  griddem_cg_convolve_direct(mp, kernel, field, out);
  CHECK(out[n - 1] > 1.5 * exp(-a * (n - 1) * (n - 1)) / norm, "periodic folds: %g", out[n - 1]);
}

/* The brick is the 3d Gaussian exp(-|r|^2 / (2 W^2)) at the offsets, over its 3d lattice sum. */
static void check_brick(void)
{
  const int m[3] = {5, 4, 11}, lo[3] = {1, 0, 2}, hi[3] = {3, 2, 9};
  const double h[3] = {0.1, 0.15, 0.2}, width = 0.23;
  const int reach[3] = {GRIDDEM_CG_PERIODIC, GRIDDEM_CG_PERIODIC, griddem_cg_padding(6, width, h[2])};
  CHECK(reach[2] == 5 && m[2] == 6 + reach[2], "z padded to %d", reach[2]);
  double out[3 * 3 * 8];
  griddem_cg_kernel_brick(m, reach, lo, hi, h, width, out);
  const int span = 40;
  double total = 0.0;
  for (int k = -span; k <= span; k++)
    for (int j = -span; j <= span; j++)
      for (int i = -span; i <= span; i++) {
        const double x = i * h[0], y = j * h[1], z = k * h[2];
        total += exp(-(x * x + y * y + z * z) / (2 * width * width));
      }
  long n = 0;
  for (int k = lo[2]; k <= hi[2]; k++)
    for (int j = lo[1]; j <= hi[1]; j++)
      for (int i = lo[0]; i <= hi[0]; i++, n++) {
        const int dz = k <= reach[2] ? k : k - m[2];
        double expect = 0.0;
        if (dz >= -reach[2] && dz <= reach[2])
          for (int sy = -span; sy <= span; sy++)
            for (int sx = -span; sx <= span; sx++) {
              const double x = (i + sx * m[0]) * h[0], y = (j + sy * m[1]) * h[1], z = dz * h[2];
              expect += exp(-(x * x + y * y + z * z) / (2 * width * width));
            }
        CHECK_CLOSE(out[n], expect / total, 1e-13, 1e-18);
      }
}

/* The touching partners of each of the first nlocal points equal a brute-force count over all
 * pairs of polydisperse points, some pairs exactly at contact (never counted); a point far away
 * coarsens the grid. */
static void check_contacts(double far)
{
  enum { NALL = 500, NLOCAL = 350 };
  static double x[3 * NALL], r[NALL], count[NLOCAL];
  for (int i = 0; i < NALL; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = 2.0 * check_uniform();
    r[i] = 0.1 + 0.2 * check_uniform() * check_uniform();
  }
  /* pairs at exactly the contact distance: 0.125 + 0.125 apart along x, binary fractions */
  for (int i = 0; i < 20; i += 2) {
    r[i] = r[i + 1] = 0.125;
    x[3 * i] = 0.25 + 0.5 * i / 20.0, x[3 * (i + 1)] = x[3 * i] + 0.25;
    x[3 * (i + 1) + 1] = x[3 * i + 1], x[3 * (i + 1) + 2] = x[3 * i + 2];
  }
  x[3 * (NALL - 1) + 2] = far;
  griddem_grid g;
  griddem_bins b = {0};
  CHECK(griddem_cg_contacts(NLOCAL, NALL, x, r, count, &g, &b) == 0, "contacts counted");
  int same = 1;
  long total = 0;
  for (int i = 0; i < NLOCAL; i++) {
    int touching = 0;
    for (int j = 0; j < NALL; j++) {
      const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
      touching += j != i && sqrt(dx * dx + dy * dy + dz * dz) < r[i] + r[j];
    }
    same &= count[i] == touching;
    total += touching;
  }
  CHECK(same && total > 1000, "far point at %g: contacts equal the brute-force count (%ld in all)", far, total);
  griddem_bins_free(&b);
}

int main(void)
{
  check_contacts(2.0);
  check_contacts(1e6);
  check_cic();
  check_kernel_axis();
  check_padding_bounds();
  check_wide_kernel();
  check_brick();
  check_convolution();
  check_padding();
  return check_summary();
}
