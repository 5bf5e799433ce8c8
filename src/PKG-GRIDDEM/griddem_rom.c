/* GRIDDEM reduced-order model: voxel mass field, linear prediction, interpolation. */
#include "griddem_rom.h"

#include "griddem_cg.h"

int griddem_rom_nvoxel(const griddem_rom_grid *g)
{
  return g->n[0] * g->n[1] * g->n[2];
}

int griddem_rom_inside(const griddem_rom_grid *g, const double x[3])
{
  for (int d = 0; d < 3; d++)
    if (!(x[d] >= g->lo[d] && x[d] < g->hi[d])) return 0;
  return 1;
}

static int wrap(int i, int n)
{
  i %= n;
  return i < 0 ? i + n : i;
}

void griddem_rom_weights(const griddem_rom_grid *g, const double x[3], int voxel[8],
                         double weight[8])
{
  int idx[3][2];
  double w[3][2];
  for (int d = 0; d < 3; d++) {
    const double h = (g->hi[d] - g->lo[d]) / g->n[d];
    griddem_cg_cic(x[d], g->lo[d], h, g->n[d], g->periodic[d], idx[d], w[d]);
    for (int k = 0; k < 2; k++) idx[d][k] = wrap(idx[d][k], g->n[d]);
  }
  for (int c = 0; c < 8; c++) {
    const int a = c & 1, b = (c >> 1) & 1, e = (c >> 2) & 1;
    voxel[c] = idx[0][a] + g->n[0] * (idx[1][b] + g->n[1] * idx[2][e]);
    weight[c] = w[0][a] * w[1][b] * w[2][e];
  }
}

void griddem_rom_deposit(const griddem_rom_grid *g, int n, const double *x, int xstride,
                         const double *mass, const int *use, double *density)
{
  double vol = 1.0;
  for (int d = 0; d < 3; d++) vol *= (g->hi[d] - g->lo[d]) / g->n[d];
  for (int i = 0; i < n; i++) {
    const double *xi = x + (long) i * xstride;
    if ((use && !use[i]) || !griddem_rom_inside(g, xi)) continue;
    int voxel[8];
    double weight[8];
    griddem_rom_weights(g, xi, voxel, weight);
    for (int c = 0; c < 8; c++) density[voxel[c]] += weight[c] * mass[i] / vol;
  }
}

void griddem_rom_predict(int nrow, int ncol, const double *w, const double *feature, double *out)
{
  for (int r = 0; r < nrow; r++) {
    const double *row = w + (long) r * ncol;
    double s = 0.0;
    for (int c = 0; c < ncol; c++) s += row[c] * feature[c];
    out[r] = s;
  }
}

void griddem_rom_interpolate(const griddem_rom_grid *g, const double *field, const double x[3],
                             double v[3])
{
  int voxel[8];
  double weight[8];
  griddem_rom_weights(g, x, voxel, weight);
  v[0] = v[1] = v[2] = 0.0;
  for (int c = 0; c < 8; c++)
    for (int d = 0; d < 3; d++) v[d] += weight[c] * field[3 * voxel[c] + d];
}
