/* GRIDDEM coarse-graining: assignment weights, the truncated Gaussian kernel, direct convolution. */
#include "griddem_cg.h"

#include <math.h>

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
  return width * sqrt(-2.0 * log(GRIDDEM_CG_TRUNCATION));
}

int griddem_cg_reach(double width, double h)
{
  return (int) floor(griddem_cg_cutoff(width) / h);
}

int griddem_cg_fft_size(int n, int periodic, int reach)
{
  return periodic ? n : n + reach;
}

/* The first offset d = i (mod m) with d >= -reach, for 0 <= i < m. */
static int first_image(int i, int m, int reach)
{
  return i - m * ((i + reach) / m);
}

/* Sum of the Gaussian over the offsets congruent to (i, j, k) modulo m inside the cutoff. */
static double image_sum(const int m[3], const int reach[3], const double h[3], double width,
                        double cut2, int i, int j, int k)
{
  const double c = -0.5 / (width * width);
  double sum = 0.0;
  for (int dz = first_image(k, m[2], reach[2]); dz <= reach[2]; dz += m[2])
    for (int dy = first_image(j, m[1], reach[1]); dy <= reach[1]; dy += m[1])
      for (int dx = first_image(i, m[0], reach[0]); dx <= reach[0]; dx += m[0]) {
        const double x = dx * h[0], y = dy * h[1], z = dz * h[2];
        const double r2 = x * x + y * y + z * z;
        if (r2 <= cut2) sum += exp(c * r2);
      }
  return sum;
}

void griddem_cg_kernel_brick(const int m[3], const int lo[3], const int hi[3], const double h[3],
                             double width, double *out)
{
  const double cut = griddem_cg_cutoff(width);
  const double cut2 = cut * cut;
  int reach[3];
  for (int d = 0; d < 3; d++) reach[d] = griddem_cg_reach(width, h[d]);
  /* the total over the grid is the sum over all offsets inside the cutoff, once each */
  const int whole[3] = {2 * reach[0] + 1, 2 * reach[1] + 1, 2 * reach[2] + 1};
  double total = 0.0;
  for (int k = 0; k < whole[2]; k++)
    for (int j = 0; j < whole[1]; j++)
      for (int i = 0; i < whole[0]; i++)
        total += image_sum(whole, reach, h, width, cut2, i, j, k);
  long n = 0;
  for (int k = lo[2]; k <= hi[2]; k++)
    for (int j = lo[1]; j <= hi[1]; j++)
      for (int i = lo[0]; i <= hi[0]; i++)
        out[n++] = image_sum(m, reach, h, width, cut2, i, j, k) / total;
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
