/* GRIDDEM coarse-graining: assignment weights, the Gaussian kernel, direct convolution. */
#include "griddem_cg.h"

#include "griddem_touching_pairs.h"

#include <math.h>
#include <stdlib.h>

#define PI 3.14159265358979323846
/* a theta series stops where its next term is below this fraction of the sum (all terms are
 * positive and fall faster than geometrically with ratio exp(-pi) once summed in its good form) */
#define SERIES_TOLERANCE 1e-18

void griddem_cg_cic(double x, double boxlo, double h, int n, int periodic, int index[2],
                    double weight[2])
{
  const double u = (x - boxlo) / h - 0.5;
  const double below = floor(u);
  const double f = u - below;
  index[0] = (int) below;
  index[1] = index[0] + 1;
  weight[0] = 1.0 - f;
  weight[1] = f;
  if (periodic) return;
  for (int k = 0; k < 2; k++) {
    if (index[k] < 0) index[k] = 0;
    if (index[k] > n - 1) index[k] = n - 1;
  }
}

double griddem_cg_cutoff(double width)
{
  return width * sqrt(-2.0 * log(GRIDDEM_CG_NEGLIGIBLE));
}

int griddem_cg_padding(int n, double width, double h)
{
  const double reach = floor(griddem_cg_cutoff(width) / h);    /* in double: W/h may be huge */
  return reach < n - 1 ? (int) reach : n - 1;
}

int griddem_cg_fft_size(int n, int periodic, double width, double h)
{
  return periodic ? n : n + griddem_cg_padding(n, width, h);
}

/* exp(-a d^2), 1 at d = 0 also for a = inf (a kernel much narrower than the spacing) */
static double gauss(double a, double d)
{
  return d == 0.0 ? 1.0 : exp(-a * d * d);
}

/* The lattice sum theta(a) = sum over integers d of exp(-a d^2) has two forms: this direct one,
 * short for a >= pi, and Poisson's sqrt(pi / a) (1 + 2 sum_q>=1 exp(-pi^2 q^2 / a)), short for
 * a < pi; these return the series in parentheses. */
static double direct_sum(double a)
{
  double sum = 1.0;
  for (int d = 1;; d++) {
    const double term = 2.0 * exp(-a * d * d);
    sum += term;
    if (term <= SERIES_TOLERANCE * sum) return sum;
  }
}

static double poisson_sum(double a)
{
  double sum = 1.0;
  for (int q = 1;; q++) {
    const double term = 2.0 * exp(-PI * PI * q * q / a);
    sum += term;
    if (term <= SERIES_TOLERANCE * sum) return sum;
  }
}

/* 1 / theta(a); 0 when a underflows (a kernel so wide that it is flat to double precision) */
static double inverse_lattice_sum(double a)
{
  return a >= PI ? 1.0 / direct_sum(a) : sqrt(a / PI) / poisson_sum(a);
}

/* The periodic image sum sum_s exp(-a (i + s m)^2) over theta(a), for 0 <= i < m. With
 * b = a m^2 >= pi the images fall off fast: summed directly, outward from the nearest ones.
 * Otherwise Poisson's formula gives sqrt(pi / a) / m (1 + 2 sum_q exp(-pi^2 q^2 / b)
 * cos(2 pi q i / m)), and theta is in its Poisson form too (a <= b < pi): the factors cancel. */
static double periodic_factor(double a, int m, int i)
{
  const double b = a * m * m;
  if (b >= PI) {
    double sum = 0.0;
    for (double d = i;; d += m) {
      const double term = gauss(a, d);
      sum += term;
      if (term <= SERIES_TOLERANCE * sum) break;
    }
    for (double d = i - m;; d -= m) {
      const double term = gauss(a, d);
      sum += term;
      if (term <= SERIES_TOLERANCE * sum) break;
    }
    return sum * inverse_lattice_sum(a);
  }
  double sum = 1.0;
  for (int q = 1;; q++) {
    const double decay = exp(-PI * PI * q * q / b);
    sum += 2.0 * decay * cos(2.0 * PI * q * i / m);
    if (decay <= SERIES_TOLERANCE) break;
  }
  return sum / (m * poisson_sum(a));
}

void griddem_cg_kernel_axis(int m, int reach, double h, double width, double *k)
{
  const double ratio = h / width;
  const double a = 0.5 * ratio * ratio;
  if (reach == GRIDDEM_CG_PERIODIC) {
    for (int i = 0; i < m; i++) k[i] = periodic_factor(a, m, i);
    return;
  }
  const double norm = inverse_lattice_sum(a);
  for (int i = 0; i < m; i++) k[i] = 0.0;
  for (int d = 0; d <= reach; d++) {
    k[d] = gauss(a, d) * norm;
    if (d > 0) k[m - d] = k[d];
  }
}

void griddem_cg_kernel_brick(const int m[3], const int reach[3], const int lo[3], const int hi[3],
                             const double h[3], double width, double *out)
{
  double *axis[3];
  for (int d = 0; d < 3; d++) {
    axis[d] = malloc((size_t) m[d] * sizeof(double));
    griddem_cg_kernel_axis(m[d], reach[d], h[d], width, axis[d]);
  }
  long n = 0;
  for (int k = lo[2]; k <= hi[2]; k++)
    for (int j = lo[1]; j <= hi[1]; j++)
      for (int i = lo[0]; i <= hi[0]; i++) out[n++] = axis[0][i] * axis[1][j] * axis[2][k];
  for (int d = 0; d < 3; d++) free(axis[d]);
}

void griddem_cg_convolve_direct(const int m[3], const double *kernel, const double *field,
                                double *out)
{
  for (int k = 0; k < m[2]; k++)
    for (int j = 0; j < m[1]; j++)
      for (int i = 0; i < m[0]; i++) {
        double sum = 0.0;
        for (int kk = 0; kk < m[2]; kk++)
          for (int jj = 0; jj < m[1]; jj++)
            for (int ii = 0; ii < m[0]; ii++) {
              const int di = (i - ii + m[0]) % m[0], dj = (j - jj + m[1]) % m[1],
                        dk = (k - kk + m[2]) % m[2];
              sum += kernel[di + m[0] * (dj + (long) m[1] * dk)] *
                  field[ii + m[0] * (jj + (long) m[1] * kk)];
            }
        out[i + m[0] * (j + (long) m[1] * k)] = sum;
      }
}

static int count_pair(void *ctx, int i, int j)
{
  (void) j;
  ((double *) ctx)[i] += 1.0;
  return 0;
}

int griddem_cg_contacts(int nlocal, int nall, const double *x, const double *radius, double *count,
                        griddem_grid *g, griddem_bins *b)
{
  for (int i = 0; i < nlocal; i++) count[i] = 0.0;
  griddem_stencil stencil;
  const int binned = griddem_bin_for_contacts(g, b, &stencil, nall, x, radius);
  if (binned != 0) return binned < 0 ? -1 : 0;
  return griddem_touching_pairs(g, b, &stencil, x, radius, nlocal, NULL, count_pair, count);
}
