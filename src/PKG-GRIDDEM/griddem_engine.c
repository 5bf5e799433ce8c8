/* The GRIDDEM engine; see griddem_engine.h. */
#include "griddem_engine.h"
#include "griddem_points_avx2.h"
#include "griddem_search.h"
#include "griddem_threads.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void griddem_engine_init(griddem_engine *e)
{
  memset(e, 0, sizeof(*e));
}

void griddem_engine_free(griddem_engine *e)
{
  for (int c = 0; c < GRIDDEM_MAX_GRIDS; c++) griddem_bins_free(&e->bins[c]);
  free(e->member), free(e->order), free(e->xc), free(e->keyc);
  griddem_channels_free(&e->channels);
  memset(e, 0, sizeof(*e));
}

int griddem_class_count(double rmin, double rmax)
{
  if (!(rmin > 0.0) || !(rmax > rmin)) return 1;
  const int n = (int) floor(log2(rmax / rmin) / GRIDDEM_CLASS_SHIFT) + 1;
  return n < 1 ? 1 : (n > GRIDDEM_MAX_CLASSES ? GRIDDEM_MAX_CLASSES : n);
}

void griddem_class_bounds(double rmax, int ncls, double *upper)
{
  for (int c = 0; c <= GRIDDEM_MAX_CLASSES; c++) upper[c] = c < ncls ? ldexp(rmax, -GRIDDEM_CLASS_SHIFT * c) : 0.0;
}

/* one owned particle's squared speed into the largest and the non-finite bit (a component that is
 * not finite, or one too large to square) */
#define SPEED_OF(i)                                                                              \
  do {                                                                                           \
    const double *u = v + 3 * (size_t) (i), q = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];         \
    most = q > most ? q : most;                                                                  \
    bad |= griddem_nonfinite_bit(q);                                                             \
  } while (0)

/* The largest squared speed of n particles (3n doubles at v), and whether some squared speed is
 * not finite */
GRIDDEM_VECTOR_COPIES static int speed_of_plain(const double *v, int n, double *vmax2)
{
  double most = 0.0;
  uint64_t bad = 0;
  if (griddem_threaded(n)) {
#pragma omp parallel for simd schedule(static) reduction(max : most) reduction(| : bad)
    for (int i = 0; i < n; i++) SPEED_OF(i);
  } else {
#pragma omp simd reduction(max : most) reduction(| : bad)
    for (int i = 0; i < n; i++) SPEED_OF(i);
  }
  *vmax2 = most;
  return bad != 0;
}

#ifdef GRIDDEM_POINTS_AVX2
/* Four particles a pass, their squared speeds summed as the plain loop sums them (this library is
 * compiled as ISO C, without contraction); one not finite makes q * 0 + bad NaN */
__attribute__((target("avx2,fma"))) static int speed_of_avx2(const double *v, int n, double *vmax2)
{
  const __m256d zero = _mm256_setzero_pd();
  __m256d most4 = zero, bad4 = zero;
  const int n4 = n & ~3;
  for (int i = 0; i < n4; i += 4) {
    __m256d x, y, z;
    griddem_points4_avx2(v + 3 * (size_t) i, &x, &y, &z);
    const __m256d q = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(x, x), _mm256_mul_pd(y, y)), _mm256_mul_pd(z, z));
    most4 = _mm256_max_pd(q, most4), bad4 = _mm256_fmadd_pd(q, zero, bad4);
  }
  double M[4], B[4];
  _mm256_storeu_pd(M, most4), _mm256_storeu_pd(B, bad4);
  /* the lanes folded, then the particles past the last four as the plain loop takes them */
  double most = 0.0;
  uint64_t bad = 0;
  for (int k = 0; k < 4; k++) most = M[k] > most ? M[k] : most, bad |= B[k] != B[k];
  for (int i = n4; i < n; i++) SPEED_OF(i);
  *vmax2 = most;
  return bad != 0;
}
#endif

static int speed_of(const double *v, int n, double *vmax2)
{
#ifdef GRIDDEM_POINTS_AVX2
  if (!griddem_threaded(n) && griddem_vector_reads()) return speed_of_avx2(v, n, vmax2);
#endif
  return speed_of_plain(v, n, vmax2);
}
#undef SPEED_OF

void griddem_engine_scan(const griddem_particles *p, int radii, griddem_scan *scan)
{
  const double *x = p->x;
  /* the owned particles' box, then the ghosts' added */
  double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0}, ghost_lo[3], ghost_hi[3];
  int suspect = p->nlocal > 0 && griddem_box_of(x, p->nlocal, lo, hi);
  for (int d = 0; d < 3; d++) scan->owned_lo[d] = lo[d], scan->owned_hi[d] = hi[d];
  if (p->nall > p->nlocal) {
    suspect |= griddem_box_of(x + 3 * (size_t) p->nlocal, p->nall - p->nlocal, ghost_lo, ghost_hi);
    for (int d = 0; d < 3; d++) {
      lo[d] = p->nlocal > 0 && lo[d] < ghost_lo[d] ? lo[d] : ghost_lo[d];
      hi[d] = p->nlocal > 0 && hi[d] > ghost_hi[d] ? hi[d] : ghost_hi[d];
    }
  }
  /* owned particles: speed and radius */
  double vmax2 = 0.0, rmin = INFINITY, rmax = 0.0;
  const int nonfinite_speed = p->nlocal > 0 && speed_of(p->v, p->nlocal, &vmax2);
  for (int i = 0; radii && i < p->nlocal; i++) {
    const double r = p->radius[i];
    rmin = r < rmin ? r : rmin;
    rmax = r > rmax ? r : rmax;
  }
  scan->first_nonfinite = -1;
  if (suspect) /* name the first one (a fault: the run stops) */
    for (int i = 0; i < p->nall && scan->first_nonfinite < 0; i++)
      if (!(isfinite(x[3 * i]) && isfinite(x[3 * i + 1]) && isfinite(x[3 * i + 2]))) scan->first_nonfinite = i;
  for (int d = 0; d < 3; d++) scan->lo[d] = lo[d], scan->hi[d] = hi[d];
  scan->vmax2 = vmax2;
  scan->nonfinite_velocity = nonfinite_speed;
  scan->rmin = radii ? rmin : NAN, scan->rmax = radii ? rmax : NAN;
}

static int grow_work(griddem_engine *e, int n)
{
  if (n <= e->work_cap) return 0;
  const int cap = n + n / 4 + 16;
  free(e->member), free(e->order), free(e->xc), free(e->keyc);
  e->member = (int *) malloc(sizeof(int) * (size_t) cap);
  e->order = (int *) malloc(sizeof(int) * (size_t) cap);
  e->xc = (double *) malloc(sizeof(double) * 3 * (size_t) cap);
  e->keyc = (int64_t *) malloc(sizeof(int64_t) * (size_t) cap);
  e->work_cap = (e->member && e->order && e->xc && e->keyc) ? cap : 0;
  return e->work_cap ? 0 : -1;
}

/* What sorts particles into grids for bin_gathered */
typedef struct gather_plan {
  const griddem_particles *p;
  const double *lo, *hi;    /* the box around the owned centres */
  double reach;             /* ghosts farther from it are left out */
  const double *upper;      /* the classes' radius bounds, zero past the last class */
  int ncls, stride, apart_bit, kinematic_bit;
} gather_plan;

/* The grid of each particle i0 .. i1 - 1 into grid[] (-1: left out). A ghost is kept within reach
 * (its radius, the largest radius and the pull-off distance) of the box around the owned centres;
 * a particle with the apart bit is left out. Without branches, so that the loop runs in vector
 * lanes: the distance to the box is the sum of the parts below and above it (one is zero). */
GRIDDEM_VECTOR_COPIES static void grids_of(const gather_plan *restrict g, int i0, int i1, int *restrict grid)
{
  const griddem_particles *p = g->p;
  const double *restrict x = p->x, *restrict radius = p->radius;
  const int *restrict mask = p->mask;
  const double lo0 = g->lo[0], lo1 = g->lo[1], lo2 = g->lo[2], hi0 = g->hi[0], hi1 = g->hi[1], hi2 = g->hi[2];
  const int nlocal = p->nlocal, ncls = g->ncls, twin = g->stride == 2, apart = g->apart_bit, kin = g->kinematic_bit;
  for (int i = i0; i < i1; i++) {
    const double x0 = x[3 * (size_t) i], x1 = x[3 * (size_t) i + 1], x2 = x[3 * (size_t) i + 2];
    double b0 = lo0 - x0, a0 = x0 - hi0, b1 = lo1 - x1, a1 = x1 - hi1, b2 = lo2 - x2, a2 = x2 - hi2;
    b0 = b0 > 0.0 ? b0 : 0.0, a0 = a0 > 0.0 ? a0 : 0.0, b1 = b1 > 0.0 ? b1 : 0.0;
    a1 = a1 > 0.0 ? a1 : 0.0, b2 = b2 > 0.0 ? b2 : 0.0, a2 = a2 > 0.0 ? a2 : 0.0;
    const double o0 = b0 + a0, o1 = b1 + a1, o2 = b2 + a2;
    const double d2 = o0 * o0 + o1 * o1 + o2 * o2, r = (radius[i] + g->reach) * (1.0 + 1e-10);
    const int kept = ((i < nlocal) | (d2 < r * r)) & ((mask[i] & apart) == 0);
    const int c = griddem_class_of(radius[i], g->upper, ncls);
    grid[i] = kept ? c * g->stride + (twin & ((mask[i] & kin) != 0)) : -1;
  }
}

/* The grid of each particle i0 .. i1 - 1 into e->order (-1: left out), counted per grid into
 * count[]; returns how many of them are kinematic */
static int classify_range(griddem_engine *e, const gather_plan *g, int i0, int i1, int *count)
{
  const int *mask = g->p->mask;
  int kinematic = 0;
  for (int c = 0; c < e->ngrid; c++) count[c] = 0;
  grids_of(g, i0, i1, e->order);
  for (int i = i0; i < i1; i++) {
    const int c = e->order[i];
    if (c < 0) continue;
    count[c]++;
    kinematic += (mask[i] & g->kinematic_bit) != 0;
  }
  return kinematic;
}

/* From the counts of nt ranges of particles per grid: each grid's first slot (base[ngrid + 1]),
 * and each range's count turned into its first place in each grid; returns the kinematic ones */
static int places_of(int ngrid, int nt, int (*count)[GRIDDEM_MAX_GRIDS], const int *kinematic_of, int *base)
{
  int kinematic = 0;
  for (int c = 0; c < ngrid; c++)
    for (int u = 0; u < nt; u++) base[c + 1] += count[u][c];
  for (int c = 0; c < ngrid; c++) base[c + 1] += base[c];
  for (int c = 0; c < ngrid; c++)
    for (int u = 0, at = base[c]; u < nt; u++) {
      const int here = count[u][c];
      count[u][c] = at, at += here;
    }
  for (int u = 0; u < nt; u++) kinematic += kinematic_of[u];
  return kinematic;
}

/* Particles i0 .. i1 - 1 gathered into their grids' slots from place[] on */
static void gather_range(griddem_engine *e, const griddem_particles *p, int i0, int i1, int *place)
{
  for (int i = i0; i < i1; i++) {
    if (e->order[i] < 0) continue;
    const int m = place[e->order[i]]++;
    e->member[m] = i;
    for (int d = 0; d < 3; d++) e->xc[3 * (size_t) m + d] = p->x[3 * (size_t) i + d];
    e->keyc[m] = griddem_key_at(p->tag, p->tag_bytes, i);
  }
}

/* The gathered particles' positions read again from theirs, in slot order */
static void gather_positions(griddem_engine *e, const griddem_particles *p, int n)
{
  const int *member = e->member;
  double *xc = e->xc;
  const double *x = p->x;
#pragma omp parallel for schedule(static) if (griddem_threaded(n))
  for (int m = 0; m < n; m++)
    for (int d = 0; d < 3; d++) xc[3 * (size_t) m + d] = x[3 * (size_t) member[m] + d];
}

/* Bin the particles that can interact, each size class on its own grid (one class: the step's
 * cell edge), class c holding radii in (upper[c+1], upper[c]], the last the rest; where the last
 * step binned at least as many particles with kinematic_bit (0: none) as without it
 * (e->kinematic_grids), those of class c go on a grid of their own after class c's, over the
 * same cells (grids 2c and 2c + 1 of e->ngrid: so the twin is searched through the class's own
 * cell rows, and the two are gathered next to each other, covered as one). With fewer, their
 * pairs among themselves are too few to pay for the second set of grids and the search across it
 * (measured on fix griddem/rom's blade and hopper), and they share the others' grids. order: the
 * particle of each slot, grids one after the other from the largest spheres. Left out: ghosts
 * out of reach of every owned particle, and particles with apart_bit (0: none), which touch
 * nothing this step (the scan saw the speed of every owned particle). Returns the number of
 * slots, or -1 without memory. */
static int bin_gathered(griddem_engine *e, const griddem_step *s, const griddem_scan *scan, int apart_bit,
                        int kinematic_bit, griddem_class_grid *cls, int *coarsened)
{
  const griddem_particles *p = &s->particles;
  const int n = p->nall, ncls = e->nclass;
  e->ngrid = kinematic_bit && e->kinematic_grids ? 2 * ncls : ncls;
  if (grow_work(e, n) != 0) return -1;
  double upper[GRIDDEM_MAX_CLASSES + 1];
  griddem_class_bounds(s->rmax, ncls, upper);
  /* ghosts farther from every owned centre than any contact reaches are left out (judged
     against the box around the owned centres, which bounds the distance from below) */
  const double *lo = scan->owned_lo, *hi = scan->owned_hi;
  /* where the host replaced the particles, the ghosts within the widened reach are gathered, and
     stay gathered, in the same grids, until it replaces them again: the positions alone are
     read again and each grid binned again */
  const int holdable = s->fixed_radii && !apart_bit && !kinematic_bit;
  const int again = holdable && s->same_particles && e->gathered && e->gathered_n == n && e->gathered_ncls == ncls &&
                    e->gathered_rmax == s->rmax;
  const int hold = holdable && !s->same_particles;
  const double reach = s->rmax + s->model->reach_extra + (hold ? s->ghost_margin : 0.0);
  /* grid of each particle to be binned (-1: left out), counted per grid; then gathered by grid,
     in particle order within each: on threads, each counts and gathers one range of particles
     at the place the counts of the ranges before it give */
  int base[GRIDDEM_MAX_GRIDS + 1] = {0}, kinematic = 0;
  const int stride = e->ngrid / ncls;    /* grids per size class: 2 with kinematic grids */
  const gather_plan plan = {p, lo, hi, reach, upper, ncls, stride, apart_bit, kinematic_bit};
  if (again) {
    memcpy(base, e->gathered_base, sizeof(base));
    gather_positions(e, p, base[e->ngrid]);
  } else if (griddem_threaded(n)) {
    const int nthreads = griddem_max_threads();
    int counts[nthreads][GRIDDEM_MAX_GRIDS], kinematic_of[nthreads];
#pragma omp parallel num_threads(nthreads)
    {
      const int t = griddem_thread_num(), nt = griddem_team_size();
      const int i0 = (int) ((long) n * t / nt), i1 = (int) ((long) n * (t + 1) / nt);
      kinematic_of[t] = classify_range(e, &plan, i0, i1, counts[t]);
#pragma omp barrier
#pragma omp single
      kinematic = places_of(e->ngrid, nt, counts, kinematic_of, base);
      gather_range(e, p, i0, i1, counts[t]);
    }
  } else {
    int counts[1][GRIDDEM_MAX_GRIDS], kinematic_of[1];
    kinematic_of[0] = classify_range(e, &plan, 0, n, counts[0]);
    kinematic = places_of(e->ngrid, 1, counts, kinematic_of, base);
    gather_range(e, p, 0, n, counts[0]);
  }
  if (!again) {
    e->gathered = hold, e->gathered_n = n, e->gathered_ncls = ncls, e->gathered_rmax = s->rmax;
    memcpy(e->gathered_base, base, sizeof(base));
  }
  e->kinematic_grids = kinematic_bit && kinematic >= base[e->ngrid] - kinematic;
  for (int size = 0; size < ncls; size++) {
    /* the class's grids (its kinematic twin's too) cover the class's particles */
    const int first = size * stride, nboth = base[first + stride] - base[first];
    const double *xboth = e->xc + 3 * (size_t) base[first];
    /* held particles that stay within their grid keep it, and are binned again on it */
    int (*const cover)(griddem_grid *, const double *, int, const double *, double, long) =
        again ? griddem_grid_cover_again : griddem_grid_cover;
    if (ncls == 1)
      *coarsened |= cover(&e->grid[first], s->anchor, nboth, xboth, s->cell_edge, s->max_cells);
    else
      cover(&e->grid[first], s->anchor, nboth, xboth, griddem_cell_edge(GRIDDEM_CELL_MULTI, 0.0, upper[size], 0.0),
            GRIDDEM_CLASS_MAX_CELLS(nboth));
    for (int c = first; c < first + stride; c++) {
      const int nc = base[c + 1] - base[c];
      if (c > first) e->grid[c] = e->grid[first];    /* the twin: the same cells */
      if ((again ? griddem_bin_points_again : griddem_bin_points)(&e->bins[c], &e->grid[c], nc,
                                                                  e->xc + 3 * (size_t) base[c], e->keyc + base[c], 8))
        return -1;
      int *order = e->order + base[c];
      const int *member = e->member + base[c], *binned = e->bins[c].order;
      if (griddem_threaded(nc)) {
#pragma omp parallel for schedule(static)
        for (int k = 0; k < nc; k++) order[k] = member[binned[k]];
      } else {
        for (int k = 0; k < nc; k++) order[k] = member[binned[k]];
      }
      cls[c].g = &e->grid[c], cls[c].b = &e->bins[c], cls[c].base = base[c];
      cls[c].rmax = ncls == 1 ? s->rmax : upper[size];
      cls[c].kinematic = c > first;
    }
  }
  return base[e->ngrid];
}

/* Bin the particles (scanned into scan) into e's grids as s says: cls gets the classes, all the
 * channels' order of particles. Returns 0, or GRIDDEM_FAULT_MEMORY. */
static int engine_bin(griddem_engine *e, const griddem_step *s, const griddem_scan *scan, griddem_class_grid *cls,
                      griddem_bins *all, int *coarsened)
{
  const griddem_particles *p = &s->particles;
  *coarsened = 0;
  e->nclass = e->ngrid = s->size_classes ? griddem_class_count(s->rmin, s->rmax) : 1;
  memset(all, 0, sizeof(*all));
  all->n = p->nall;
  const int apart_bit = s->excl ? s->excl->apart_bit : 0, kinematic_bit = s->excl ? s->excl->both_bit : 0;
  if (e->nclass == 1 && !apart_bit && !kinematic_bit) {
    /* one grid over the scanned box (kept while the same particles stay inside it): the
       particles are binned as they are, nothing gathered */
    const int again = s->same_particles && e->one_grid_binned;
    *coarsened = p->nall > 0 ? (again ? griddem_grid_fit_again : griddem_grid_fit)(&e->grid[0], s->anchor, scan->lo,
                                                                                 scan->hi, s->cell_edge, s->max_cells)
                             : griddem_grid_fit(&e->grid[0], s->anchor, s->anchor, s->anchor, s->cell_edge, s->max_cells);
    e->one_grid_binned = 0, e->gathered = 0;
    if ((again ? griddem_bin_points_again : griddem_bin_points)(&e->bins[0], &e->grid[0], p->nall, p->x, p->tag,
                                                                p->tag_bytes) != 0)
      return GRIDDEM_FAULT_MEMORY;
    e->one_grid_binned = 1;
    cls[0].g = &e->grid[0], cls[0].b = &e->bins[0], cls[0].base = 0, cls[0].rmax = s->rmax, cls[0].kinematic = 0;
    all->order = e->bins[0].order;
  } else {
    e->one_grid_binned = 0;
    all->n = bin_gathered(e, s, scan, apart_bit, kinematic_bit, cls, coarsened);
    all->order = e->order;
    if (all->n < 0) {
      e->gathered = 0;    /* what was held may be freed or half binned */
      return GRIDDEM_FAULT_MEMORY;
    }
  }
  for (int c = 0; c < e->ngrid; c++)
    griddem_owned_cells(cls[c].g, scan->owned_lo, scan->owned_hi, p->nlocal, cls[c].owned_lo, cls[c].owned_hi);
  return GRIDDEM_FAULT_NONE;
}

void griddem_engine_count_occupancy(griddem_engine *e)
{
  e->stats.occupied_cells = 0;
  e->stats.max_occupancy = 0;
  for (int c = 0; c < e->ngrid; c++) {
    long occupied;
    int most;
    griddem_bins_occupancy(&e->bins[c], &occupied, &most);
    e->stats.occupied_cells += occupied;
    if (most > e->stats.max_occupancy) e->stats.max_occupancy = most;
  }
}

double griddem_engine_candidates(griddem_engine *e, const griddem_step *s)
{
  griddem_class_grid cls[GRIDDEM_MAX_GRIDS];
  griddem_bins all;
  int coarsened;
  griddem_scan own_scan;
  const griddem_scan *scan = s->scan;
  if (!scan) griddem_engine_scan(&s->particles, 0, &own_scan), scan = &own_scan;
  if (engine_bin(e, s, scan, cls, &all, &coarsened) != GRIDDEM_FAULT_NONE) return -1.0;
  griddem_engine_count_occupancy(e);
  return griddem_sweep_candidates(cls, e->ngrid, s->model->reach_extra);
}

int griddem_engine_step(griddem_engine *e, const griddem_step *s, griddem_sweep_result *result,
                        int *coarsened)
{
  const griddem_particles *p = &s->particles;
  memset(result, 0, sizeof(*result));
  griddem_class_grid cls[GRIDDEM_MAX_GRIDS];
  griddem_bins all; /* the channels' order of particles */
  griddem_scan own_scan;
  const griddem_scan *scan = s->scan;
  if (!scan) griddem_engine_scan(p, 0, &own_scan), scan = &own_scan;
  result->fault = engine_bin(e, s, scan, cls, &all, coarsened);
  if (result->fault || griddem_channels_fill(&e->channels, &all, p) != 0) {
    result->fault = GRIDDEM_FAULT_MEMORY;
    return result->fault;
  }
  griddem_sweep(cls, e->ngrid, all.order, &e->channels, p->nlocal, s->model, s->excl,
                        s->dt, s->history_update, s->hist, s->row_of, s->f, s->torque, s->vatom,
                        s->tally, result);

  /* how far the fastest owned particle moves in a step, in cells of the finest grid */
  e->stats.max_speed = sqrt(scan->vmax2);
  e->stats.max_cells_moved = e->stats.max_speed * s->dt / e->grid[e->ngrid - 1].h;
  e->stats.nonfinite_velocity = scan->nonfinite_velocity;
  e->stats.occupied_cells = -1; /* griddem_engine_count_occupancy counts them when asked */
  e->stats.max_occupancy = -1;
  e->stats.cell_edge = e->grid[0].h;
  e->stats.contacts = result->contacts;
  e->stats.max_contacts = result->max_contacts;
  e->stats.elastic_energy = result->energy;
  e->stats.energy_tallied = (s->tally & GRIDDEM_TALLY_ENERGY) != 0;
  return result->fault;
}

double griddem_engine_memory(const griddem_engine *e)
{
  const griddem_channels *ch = &e->channels;
  double bins = (double) e->work_cap * (2 * sizeof(int) + 3 * sizeof(double) + sizeof(int64_t));
  for (int c = 0; c < GRIDDEM_MAX_GRIDS; c++)
    bins += (double) e->bins[c].ncell_cap * sizeof(int) + (double) e->bins[c].n_cap * (sizeof(int) + sizeof(long));
  return bins + (double) ch->cap * (4 * sizeof(double) + sizeof(int64_t) + sizeof(int)) +
      (double) ch->image_cap * sizeof(int) + (double) ch->across_cap * 2 * sizeof(int) + (double) ch->first_cap * sizeof(int);
}
