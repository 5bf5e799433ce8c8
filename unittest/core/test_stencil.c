/* The stencil of a grid (griddem_grid.h), against a brute-force loop over all pairs of random
 * polydisperse points: the runs of the full stencil of a point's cell hold every binned centre
 * closer than the distance to that point exactly once (for points binned or not); the runs of the
 * forward stencil of every occupied cell, taken in its own row after a centre's own slot, hold
 * every pair of centres closer than the distance exactly once over all cells. On grids of several
 * edges: one cell a side, a distance of exactly one edge, corners pruned, a whole number of edges,
 * many cells a side, and an edge coarsened for a cap on the cells. A stencil reaching past
 * GRIDDEM_MAX_REACH cells is refused. */
#include "check.h"
#include "griddem_grid.h"

#include <string.h>

#define N 800
static double X[3 * N], R[N];
static unsigned char seen[N][N]; /* times a pair was found */

static double distance2(int i, int j)
{
  const double dx = X[3 * i] - X[3 * j], dy = X[3 * i + 1] - X[3 * j + 1], dz = X[3 * i + 2] - X[3 * j + 2];
  return dx * dx + dy * dy + dz * dz;
}

/* Every pair (i, j) (with i < j if ordered) of i < ni, j < nj, j != i is found exactly once when
 * closer than cut, at most once otherwise. Returns how many pairs were closer than cut. */
static long check_pairs(const char *what, double h, double cut, int ni, int nj, int ordered)
{
  long close = 0, missed = 0, twice = 0;
  for (int i = 0; i < ni; i++)
    for (int j = ordered ? i + 1 : 0; j < nj; j++) {
      if (j == i) continue;
      const int within = distance2(i, j) < cut * cut;
      close += within;
      missed += within && seen[i][j] != 1;
      twice += seen[i][j] > 1;
    }
  CHECK(missed == 0 && twice == 0, "%s, edge %g, distance %g: %ld of %ld close pairs not found once, %ld pairs found twice",
        what, h, cut, missed, close, twice);
  return close;
}

/* The full stencil of the cell of each of the N points over the first N/2 points binned, on a
 * grid covering all N. */
static long check_full(double h, double cut, long max_cells)
{
  const double anchor[3] = {0.1, -0.3, 0.2};
  griddem_grid g;
  griddem_bins b = {0};
  griddem_stencil s;
  griddem_grid_cover(&g, anchor, N, X, h, max_cells);
  CHECK(griddem_bin_points(&b, &g, N / 2, X, NULL, 0) == 0, "binned");
  CHECK(griddem_stencil_build(&s, g.h, cut, GRIDDEM_STENCIL_FULL) == 0, "full stencil of edge %g", g.h);
  memset(seen, 0, sizeof(seen));
  int lo[GRIDDEM_STENCIL_MAX_ROWS], hi[GRIDDEM_STENCIL_MAX_ROWS];
  for (int i = 0; i < N; i++) {
    const int nruns = griddem_stencil_runs(&s, &g, &b, griddem_cell_of(&g, X[3 * i], X[3 * i + 1], X[3 * i + 2]), lo, hi);
    for (int q = 0; q < nruns; q++)
      for (int t = lo[q]; t < hi[q]; t++) seen[i][b.order[t]]++;
  }
  const long close = check_pairs("full", g.h, cut, N, N / 2, 0);
  griddem_bins_free(&b);
  return close;
}

/* The forward stencil of each occupied cell of a grid of all N points. */
static long check_forward(double h, double cut, long max_cells)
{
  const double anchor[3] = {-0.05, 0.4, 0.0};
  griddem_grid g;
  griddem_bins b = {0};
  griddem_stencil s;
  griddem_grid_cover(&g, anchor, N, X, h, max_cells);
  CHECK(griddem_bin_points(&b, &g, N, X, NULL, 0) == 0, "binned");
  CHECK(griddem_stencil_build(&s, g.h, cut, GRIDDEM_STENCIL_FORWARD) == 0, "forward stencil of edge %g", g.h);
  memset(seen, 0, sizeof(seen));
  int lo[GRIDDEM_STENCIL_MAX_ROWS], hi[GRIDDEM_STENCIL_MAX_ROWS];
  for (int first = 0; first < N;) {
    const long cell = b.cell[b.order[first]];
    const int last = b.cell_start[cell + 1];
    const int nruns = griddem_stencil_runs(&s, &g, &b, cell, lo, hi);
    CHECK(lo[0] == first, "run 0 starts at the cell's first slot");
    for (int slot = first; slot < last; slot++)
      for (int q = 0; q < nruns; q++)
        for (int t = q == 0 ? slot + 1 : lo[q]; t < hi[q]; t++) {
          const int i = b.order[slot], j = b.order[t];
          seen[i < j ? i : j][i < j ? j : i]++;
        }
    first = last;
  }
  const long close = check_pairs("forward", g.h, cut, N, N, 1);
  griddem_bins_free(&b);
  return close;
}

int main(void)
{
  /* polydisperse spheres in a box of 3 x 2 x 2.5; the distance is the longest contact distance */
  double rmax = 0.0, rmin = 1.0;
  const double side[3] = {3.0, 2.0, 2.5};
  for (int i = 0; i < N; i++) {
    for (int d = 0; d < 3; d++) X[3 * i + d] = side[d] * check_uniform();
    R[i] = 0.04 + 0.2 * check_uniform() * check_uniform();
    rmax = R[i] > rmax ? R[i] : rmax;
    rmin = R[i] < rmin ? R[i] : rmin;
  }
  const double cut = 2.0 * rmax;
  /* one cell a side; exactly one edge; corners pruned; whole edges; exact mode's edge; coarsened */
  const double edges[] = {cut * (1.0 + 1e-9), cut, cut / 2.5, cut / 3.0, 2.0 * rmin / sqrt(3.0), 0.05};
  const long caps[] = {1000000, 1000000, 1000000, 1000000, 1000000, 200};
  for (size_t k = 0; k < sizeof(edges) / sizeof(edges[0]); k++) {
    const long full = check_full(edges[k], cut, caps[k]), forward = check_forward(edges[k], cut, caps[k]);
    CHECK(full > 2000 && forward > 2000, "edge %g: %ld and %ld close pairs", edges[k], full, forward);
  }

  griddem_stencil s;
  CHECK(griddem_stencil_build(&s, 1.0, 32.0, GRIDDEM_STENCIL_FULL) == 0, "a stencil of GRIDDEM_MAX_REACH cells");
  CHECK(griddem_stencil_build(&s, 1.0, 32.5, GRIDDEM_STENCIL_FORWARD) == -1 && s.nrows == 0,
        "a stencil past GRIDDEM_MAX_REACH cells is refused");
  return check_summary();
}
