/* GRIDDEM reduced-order model: voxel mass field, linear prediction, interpolation. */
#include "griddem_rom.h"

#include "griddem_cg.h"
#include "griddem_touching_pairs.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

int griddem_rom_nvoxel(const griddem_rom_grid *g)
{
  return g->n[0] * g->n[1] * g->n[2];
}

void griddem_rom_place(const griddem_rom_grid *frame, const double origin[3], griddem_rom_grid *placed)
{
  *placed = *frame;
  for (int d = 0; d < 3; d++) {
    placed->lo[d] = frame->lo[d] + origin[d];
    placed->hi[d] = frame->hi[d] + origin[d];
  }
}

int griddem_rom_inside(const griddem_rom_grid *g, const double x[3])
{
  for (int d = 0; d < 3; d++)
    if (!g->periodic[d] && !(x[d] >= g->lo[d] && x[d] < g->hi[d])) return 0;
  return 1;
}

static int wrap(int i, int n)
{
  i %= n;
  return i < 0 ? i + n : i;
}

int griddem_rom_voxel(const griddem_rom_grid *g, const double x[3])
{
  if (!griddem_rom_inside(g, x)) return -1;
  int idx[3];
  for (int d = 0; d < 3; d++) {
    idx[d] = (int) floor((x[d] - g->lo[d]) / (g->hi[d] - g->lo[d]) * g->n[d]);
    if (g->periodic[d]) idx[d] = wrap(idx[d], g->n[d]);
    else if (idx[d] >= g->n[d]) idx[d] = g->n[d] - 1; /* rounding at hi */
  }
  return idx[0] + g->n[0] * (idx[1] + g->n[1] * idx[2]);
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

void griddem_rom_predict_occupancy(int nvoxel, int ncontrol, const double *w, const double *control,
                                   const double *density, double *scratch, double *out)
{
  scratch[0] = 1.0;
  for (int c = 0; c < ncontrol; c++) scratch[1 + c] = control[c];
  griddem_rom_predict(3 * nvoxel, 1 + ncontrol, w, scratch, out);
  for (int m = 0; m < nvoxel; m++)
    for (int d = 0; d < 3; d++) out[3 * m + d] *= density[m];
}

void griddem_rom_interpolate(const griddem_rom_grid *g, const double *field, int ncomp, const double x[3],
                             double *out)
{
  int voxel[8];
  double weight[8];
  griddem_rom_weights(g, x, voxel, weight);
  for (int d = 0; d < ncomp; d++) out[d] = 0.0;
  for (int c = 0; c < 8; c++)
    for (int d = 0; d < ncomp; d++) out[d] += weight[c] * field[(long) ncomp * voxel[c] + d];
}

/* The classification's rules for one touching pair (i would be kinematic) */
typedef struct contact_check {
  const double *x, *v, *radius, *u;
  const int *kinematic;
  double threshold, overlap_max;
  int *next, *hits, *overlaps;
} contact_check;

static int check_pair(void *ctx, int i, int j)
{
  contact_check *c = (contact_check *) ctx;
  const double *xi = c->x + 3 * (long) i, *xj = c->x + 3 * (long) j;
  const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
  const double r = sqrt(dx * dx + dy * dy + dz * dz);
  const double ri = c->radius[i], rj = c->radius[j];
  const double rmin = ri < rj ? ri : rj;
  if ((ri + rj) - r > c->overlap_max * rmin) {
    c->next[i] = 0;
    *c->overlaps += c->kinematic[i];
    return 1;
  }
  if (c->kinematic[j]) return 0;
  const double *vi = c->kinematic[i] ? c->v + 3 * (long) i : c->u + 3 * (long) i, *vj = c->v + 3 * (long) j;
  const double rx = vi[0] - vj[0], ry = vi[1] - vj[1], rz = vi[2] - vj[2];
  if (sqrt(rx * rx + ry * ry + rz * rz) > c->threshold) {
    c->next[i] = 0;
    *c->hits += c->kinematic[i];
    return 1;
  }
  return 0;
}

int griddem_rom_check_contacts(int nlocal, int nall, const double *x, const double *v,
                               const double *radius, const int *kinematic, const double *u,
                               double threshold, double overlap_max, int *next, int *hits,
                               int *overlaps, griddem_grid *g, griddem_bins *b)
{
  griddem_stencil stencil;
  const int binned = griddem_bin_for_contacts(g, b, &stencil, nall, x, radius);
  if (binned != 0) return binned < 0 ? -1 : 0;
  contact_check c = {x, v, radius, u, kinematic, threshold, overlap_max, next, hits, overlaps};
  return griddem_touching_pairs(g, b, &stencil, x, radius, nlocal, next, check_pair, &c);
}

/* One touching pair of a released particle i: its share of their overlap, away from j */
typedef struct separation {
  const double *x, *radius;
  const int *released;
  double *shift;
} separation;

static int push_apart(void *ctx, int i, int j)
{
  separation *s = (separation *) ctx;
  const double *xi = s->x + 3 * (long) i, *xj = s->x + 3 * (long) j;
  const double dx[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
  const double r = sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
  if (r == 0.0) return 0; /* no line of centres: left to the contact law */
  const double move = (s->radius[i] + s->radius[j] - r) * (s->released[j] ? 0.5 : 1.0) / r;
  for (int d = 0; d < 3; d++) s->shift[3 * (long) i + d] += move * dx[d];
  return 0;
}

int griddem_rom_separate(int nlocal, int nall, double *x, const double *radius, const int *released,
                         double *shift, const griddem_grid *g, const griddem_bins *b)
{
  int any = 0;
  for (int i = 0; i < nlocal; i++) any |= released[i] != 0;
  griddem_stencil stencil;
  if (!any || griddem_stencil_for_contacts(g, &stencil, nall, radius) != 0) return 0;
  for (long k = 0; k < 3L * nlocal; k++) shift[k] = 0.0;
  separation s = {x, radius, released, shift};
  if (griddem_touching_pairs(g, b, &stencil, x, radius, nlocal, released, push_apart, &s) != 0) return -1;
  int moved = 0;
  for (int i = 0; i < nlocal; i++) {
    double *si = shift + 3 * (long) i;
    const double len = sqrt(si[0] * si[0] + si[1] * si[1] + si[2] * si[2]);
    if (!released[i] || len == 0.0) continue;
    const double scale = len > radius[i] ? radius[i] / len : 1.0;
    for (int d = 0; d < 3; d++) x[3 * (long) i + d] += scale * si[d];
    moved++;
  }
  return moved;
}

int griddem_rom_mark_near(int nlocal, int nall, const double *x, const double *radius,
                          const int *kinematic, double reach, double cap, int *near,
                          double *budget, griddem_grid *g, griddem_bins *b)
{
  double rmax = 0.0;
  for (int j = 0; j < nall; j++) rmax = radius[j] > rmax ? radius[j] : rmax;
  for (int i = 0; i < nlocal; i++) {
    near[i] = 0;
    budget[i] = cap;
  }
  if (nall == 0) return 0;
  /* only the kinematic atoms are binned; each dynamic atom (owned or ghost) visits them: every
   * pair of the two kinds is seen once, from its dynamic side */
  int nkin = 0;
  for (int j = 0; j < nall; j++) nkin += kinematic[j] != 0;
  if (nkin == 0) return 0;
  double *xk = (double *) malloc(sizeof(double) * 3 * (size_t) nkin);
  int *which = (int *) malloc(sizeof(int) * (size_t) nkin);
  if (!xk || !which) {
    free(xk);
    free(which);
    return -1;
  }
  for (int j = 0, k = 0; j < nall; j++)
    if (kinematic[j]) {
      for (int d = 0; d < 3; d++) xk[3 * k + d] = x[3 * (long) j + d];
      which[k++] = j;
    }
  const double anchor[3] = {0.0, 0.0, 0.0};
  /* the grid covers every atom (the dynamic ones look up their cells); the edge may grow for a
   * dilute set, and the stencil of the pairs with gap < cap follows it */
  const double cut = 2.0 * rmax + cap;
  griddem_grid_cover(g, anchor, nall, x, cut * (1.0 + 1e-12) + 1e-300, 8L * nall + 1024L);
  if (griddem_bin_points(b, g, nkin, xk, NULL, 0) != 0) {
    free(xk);
    free(which);
    return -1;
  }
  griddem_stencil stencil;    /* reaches one cell: the edge is at least the distance */
  griddem_stencil_build(&stencil, g->h, cut, GRIDDEM_STENCIL_FULL);
  int lo[GRIDDEM_STENCIL_MAX_ROWS], hi[GRIDDEM_STENCIL_MAX_ROWS];
  for (int j = 0; j < nall; j++) {
    if (kinematic[j]) continue;
    const double *xj = x + 3 * (long) j;
    const int owned = j < nlocal;
    const int nruns = griddem_stencil_runs(&stencil, g, b, griddem_cell_of(g, xj[0], xj[1], xj[2]), lo, hi);
    for (int q = 0; q < nruns; q++)
      for (int s = lo[q]; s < hi[q]; s++) {
        const int i = which[b->order[s]];
        if (!owned && (i >= nlocal || near[i])) continue;
        const double *xi = x + 3 * (long) i;
        const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
        /* only gaps below the budget so far (owned j; >= reach) or below reach count */
        const double limit = radius[i] + radius[j] + (owned ? budget[j] : reach);
        const double r2 = dx * dx + dy * dy + dz * dz;
        if (r2 >= limit * limit) continue;
        const double gap = sqrt(r2) - (radius[i] + radius[j]);
        if (gap < reach) {
          if (i < nlocal) near[i] = 1;
        } else if (owned)
          budget[j] = gap;
      }
  }
  free(xk);
  free(which);
  return 0;
}
