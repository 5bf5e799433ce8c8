/* Touching pairs of binned spheres; see griddem_touching_pairs.h. */
#include "griddem_touching_pairs.h"

#include "griddem_search.h"

#include <math.h>
#include <stdlib.h>

static int is_query(int i, int nquery, const int *query)
{
  return i < nquery && (!query || query[i]);
}

int griddem_touching_pairs(const griddem_grid *g, const griddem_bins *b, const griddem_stencil *s, const double *x,
                           const double *radius, int nquery, const int *query, griddem_pair_visit visit, void *ctx)
{
  const int n = b->n;
  if (n == 0) return 0;
  griddem_touching_fn touching = griddem_touching();
  const int width = griddem_touching_width();
  /* the kernels read the spheres in slot order, and their float copies (each padded) */
  const size_t nf = (size_t) n + GRIDDEM_SEARCH_PAD;
  double *slots = (double *) malloc(sizeof(double) * 4 * (size_t) n);
  float *rounded = (float *) calloc(4 * nf, sizeof(float));
  int *lo = (int *) malloc(sizeof(int) * 2 * (size_t) GRIDDEM_STENCIL_MAX_ROWS);
  if (!slots || !rounded || !lo) {
    free(slots);
    free(rounded);
    free(lo);
    return -1;
  }
  int *hi = lo + GRIDDEM_STENCIL_MAX_ROWS;
  double extent = 0.0, rmax = 0.0;
  for (int t = 0; t < n; t++) {
    const int j = b->order[t];
    for (int d = 0; d < 3; d++) {
      const double c = x[3 * (long) j + d];
      slots[d * (size_t) n + t] = c, rounded[d * nf + t] = (float) c;
      extent = fabs(c) > extent ? fabs(c) : extent;
    }
    slots[3 * (size_t) n + t] = radius[j], rounded[3 * nf + t] = (float) radius[j];
    rmax = radius[j] > rmax ? radius[j] : rmax;
  }
  const griddem_spheres sp = {slots, slots + n, slots + 2 * (size_t) n, slots + 3 * (size_t) n,
                              rounded, rounded + nf, rounded + 2 * nf, rounded + 3 * nf,
                              (float) griddem_search_slack(extent, rmax, 0.0), 0, 0.0f, 0.0f};
  int *found = NULL;    /* room for the pairs of a cluster: their spheres, then their slots */
  long found_room = 0;
  int status = 0;
  for (long c = 0; c < b->ncell && status == 0; c++) {
    const int first = b->cell_start[c], last = b->cell_start[c + 1];
    int any = 0;
    for (int t = first; t < last && !any; t++) any = is_query(b->order[t], nquery, query);
    if (!any) continue;
    const int nruns = griddem_stencil_runs(s, g, b, c, lo, hi);
    long candidates = 0;
    for (int q = 0; q < nruns; q++) candidates += hi[q] - lo[q];
    if (candidates * width > found_room) {
      found_room = 2 * candidates * width;
      int *more = (int *) realloc(found, 2 * sizeof(int) * (size_t) found_room);
      if (!more) {
        status = -1;
        break;
      }
      found = more;
    }
    for (int i0 = first; i0 < last; i0 += width) {
      const int ni = last - i0 < width ? last - i0 : width;
      griddem_cluster_hits hits = {found, found + found_room, 0};
      touching(&sp, 0.0, i0, ni, 0, lo, hi, nruns, &hits);
      /* each query's pairs, in the order found */
      for (int k = 0; k < ni; k++) {
        const int i = b->order[i0 + k];
        if (!is_query(i, nquery, query)) continue;
        for (int m = 0; m < hits.n; m++)
          if (hits.sphere[m] == k && hits.slot[m] != i0 + k && visit(ctx, i, b->order[hits.slot[m]])) break;
      }
    }
  }
  free(found);
  free(lo);
  free(slots);
  free(rounded);
  return status;
}
