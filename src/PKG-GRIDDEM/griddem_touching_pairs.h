/* GRIDDEM touching pairs of a set of spheres binned for their contacts: the sweep's candidate
 * search (griddem_search.h) run over a grid's cells for the contact checks that are not the
 * pair's: fix griddem/rom's classification and compute griddem/cg's contact count. */
#ifndef GRIDDEM_TOUCHING_PAIRS_H
#define GRIDDEM_TOUCHING_PAIRS_H

#include "griddem_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One touching pair: sphere i (a query) and sphere j. Nonzero ends i's pairs. */
typedef int (*griddem_pair_visit)(void *ctx, int i, int j);

/* The touching pairs of the n spheres binned in b (griddem_bin_for_contacts: grid g, its full
 * stencil s; centres x interleaved, radii radius): for each sphere i < nquery with query[i] != 0
 * (query NULL: each of them), visit(ctx, i, j) for every other sphere j with
 * dx dx + dy dy + dz dz < (ri + rj) (ri + rj), in the order of the stencil's runs and of the slots
 * within each, until a visit returns nonzero. Spheres of one cell are tested together by the
 * widest kernel the processor runs. Returns 0, or -1 without memory. */
int griddem_touching_pairs(const griddem_grid *g, const griddem_bins *b, const griddem_stencil *s, const double *x,
                           const double *radius, int nquery, const int *query, griddem_pair_visit visit, void *ctx);

#ifdef __cplusplus
}
#endif

#endif
