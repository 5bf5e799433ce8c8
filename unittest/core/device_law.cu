/* The core headers compiled as CUDA device code: every sub-model is reachable from a kernel
 * through griddem_contact_eval, and the engine pieces the Kokkos kernels call (cell of a point,
 * cells within reach, class of a radius, exclusions, the order of a cell's slots, the search's
 * pair test) are too, so the headers the CPU engine uses are the ones a GPU
 * kernel can use (a host-only construct in any of them fails this compile). */
#include "griddem_engine.h"
#include "griddem_search.h"

__global__ void griddem_device_law(const griddem_pair_params *p, griddem_contact *c, double *h,
                                   double *f, double *ti, double *tj, int *touch)
{
  *touch = griddem_contact_touch(p, c->rsq, c->radi, c->radj, 1);
  griddem_contact_eval(p, c, h, f, ti, tj);
}

__global__ void griddem_device_engine(const griddem_exclusions *e, const double *upper, int ncls,
                                      const double *x, const long long *tag, int *slot, int *out)
{
  griddem_sort_cell(slot, out[3], tag, sizeof(*tag), x);
  out[0] = griddem_axis_cell(x[0], 0.0, 2.0, -3, 10);
  out[1] = griddem_class_of(x[1], upper, ncls);
  out[2] = griddem_excluded(e, 1, 3, 2, 5);
  griddem_axis_cells_within(x[0], x[1], x[2], 0.0, 2.0, -3, 10, &out[4], &out[5]);
  out[6] = griddem_search_touches(x, x[0], x[1], x[2]);
}
