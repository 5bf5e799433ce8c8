/* Grid geometry and counting-sort binning; see griddem_grid.h. */
#include "griddem_grid.h"
#include "griddem_points_avx2.h"
#include "griddem_search.h"
#include "griddem_threads.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

double griddem_cell_edge(int mode, double rmin, double rmax, double value)
{
  switch (mode) {
    case GRIDDEM_CELL_EXACT: return 2.0 * rmin / sqrt(3.0);
    /* a hair above the contact distance, so that the sweep's 3^3 stencil provably suffices */
    case GRIDDEM_CELL_MULTI:
    case GRIDDEM_CELL_AUTO:
    case GRIDDEM_CELL_CLASSES: return 2.0 * rmax * (1.0 + 1e-9); /* classes: of the largest */
    default: return value;
  }
}

int griddem_stencil_reach(double h, double cut)
{
  int reach = (int) ceil(cut / h);
  return reach < 1 ? 1 : reach;
}

int griddem_stencil_build(griddem_stencil *s, double h, double cut, int part)
{
  const double c2 = cut * cut;
  const int reach = griddem_stencil_reach(h, cut);
  s->nrows = 0;
  if (reach > GRIDDEM_MAX_REACH) return -1;
  for (int dz = -reach; dz <= reach; dz++)
    for (int dy = -reach; dy <= reach; dy++) {
      const int own = dy == 0 && dz == 0;
      if (part == GRIDDEM_STENCIL_FORWARD && (dz < 0 || (dz == 0 && dy < 0))) continue;
      /* the smallest distance between a point of the cell and one of the row, across x */
      const double gz = abs(dz) > 1 ? (abs(dz) - 1) * h : 0.0;
      const double gy = abs(dy) > 1 ? (abs(dy) - 1) * h : 0.0;
      const double g2 = gy * gy + gz * gz;
      if (g2 >= c2) continue;
      int dx = (int) ceil(sqrt(c2 - g2) / h);
      if (dx > reach) dx = reach;
      griddem_stencil_row *row = &s->row[s->nrows++];
      row->dy = dy, row->dz = dz;
      row->dxlo = (own && part == GRIDDEM_STENCIL_FORWARD) ? 0 : -dx;
      row->dxhi = dx;
    }
  return 0;
}

static long axis_index(double x, double anchor, double hinv)
{
  return griddem_floor_index((x - anchor) * hinv);
}

static long cells_for(const griddem_grid *g, const double *lo, const double *hi, double h, long *k0,
                      int *n)
{
  const double hinv = 1.0 / h;
  long total = 1;
  for (int d = 0; d < 3; d++) {
    k0[d] = axis_index(lo[d], g->anchor[d], hinv);
    const long cells = axis_index(hi[d], g->anchor[d], hinv) - k0[d] + 1;
    n[d] = cells > 1000000000L ? 1000000000 : (int) cells;
    total = (total < 4000000000000L / n[d]) ? total * n[d] : 4000000000000L;
  }
  return total;
}

/* one point into the box and the non-finite bit (the box may leave out a NaN: the bit says so) */
#define BOX_OF_POINT(i)                                                                            \
  do {                                                                                             \
    const double a = x[3 * (size_t) (i)], b = x[3 * (size_t) (i) + 1], c = x[3 * (size_t) (i) + 2]; \
    l0 = a < l0 ? a : l0, h0 = a > h0 ? a : h0;                                                    \
    l1 = b < l1 ? b : l1, h1 = b > h1 ? b : h1;                                                    \
    l2 = c < l2 ? c : l2, h2 = c > h2 ? c : h2;                                                    \
    bad |= griddem_nonfinite_bit(a) | griddem_nonfinite_bit(b) | griddem_nonfinite_bit(c);         \
  } while (0)

/* The reductions are OpenMP's, whose order is free, so the points run in vector lanes. */
GRIDDEM_VECTOR_COPIES static int box_of_plain(const double *x, int n, double *lo, double *hi)
{
  double l0 = x[0], l1 = x[1], l2 = x[2], h0 = l0, h1 = l1, h2 = l2;
  uint64_t bad = 0;
  if (griddem_threaded(n)) {
#pragma omp parallel for simd schedule(static) reduction(min : l0, l1, l2) reduction(max : h0, h1, h2) \
    reduction(| : bad)
    for (int i = 0; i < n; i++) BOX_OF_POINT(i);
  } else {
#pragma omp simd reduction(min : l0, l1, l2) reduction(max : h0, h1, h2) reduction(| : bad)
    for (int i = 0; i < n; i++) BOX_OF_POINT(i);
  }
  lo[0] = l0, lo[1] = l1, lo[2] = l2, hi[0] = h0, hi[1] = h1, hi[2] = h2;
  return bad != 0;
}

#ifdef GRIDDEM_POINTS_AVX2
/* Four points are twelve doubles, three vectors whose lanes hold the coordinates in a period of
 * three: each lane's minimum and maximum are taken over the points as they lie, with no
 * reordering, and the lanes of one axis are folded at the end. A coordinate that is not finite
 * makes v * 0 + bad NaN (min and max pass NaN by, as the plain loop's comparisons do). */
__attribute__((target("avx2,fma"))) static int box_of_avx2(const double *x, int n, double *lo, double *hi)
{
  const __m256d first0 = _mm256_setr_pd(x[0], x[1], x[2], x[0]), first1 = _mm256_setr_pd(x[1], x[2], x[0], x[1]),
                first2 = _mm256_setr_pd(x[2], x[0], x[1], x[2]), zero = _mm256_setzero_pd();
  __m256d low0 = first0, low1 = first1, low2 = first2, high0 = first0, high1 = first1, high2 = first2, bad0 = zero,
          bad1 = zero, bad2 = zero;
  const int n4 = n & ~3;
  for (int i = 0; i < n4; i += 4) {
    const double *p = x + 3 * (size_t) i;
    const __m256d a = _mm256_loadu_pd(p), b = _mm256_loadu_pd(p + 4), c = _mm256_loadu_pd(p + 8);
    low0 = _mm256_min_pd(a, low0), low1 = _mm256_min_pd(b, low1), low2 = _mm256_min_pd(c, low2);
    high0 = _mm256_max_pd(a, high0), high1 = _mm256_max_pd(b, high1), high2 = _mm256_max_pd(c, high2);
    bad0 = _mm256_fmadd_pd(a, zero, bad0), bad1 = _mm256_fmadd_pd(b, zero, bad1), bad2 = _mm256_fmadd_pd(c, zero, bad2);
  }
  double L[12], H[12], B[4];
  _mm256_storeu_pd(L, low0), _mm256_storeu_pd(L + 4, low1), _mm256_storeu_pd(L + 8, low2);
  _mm256_storeu_pd(H, high0), _mm256_storeu_pd(H + 4, high1), _mm256_storeu_pd(H + 8, high2);
  _mm256_storeu_pd(B, _mm256_add_pd(_mm256_add_pd(bad0, bad1), bad2));
  /* the lanes of each axis folded, then the points past the last four as the plain loop takes them */
  double l0 = L[0], l1 = L[1], l2 = L[2], h0 = H[0], h1 = H[1], h2 = H[2];
  for (int k = 3; k < 12; k += 3) {
    l0 = L[k] < l0 ? L[k] : l0, l1 = L[k + 1] < l1 ? L[k + 1] : l1, l2 = L[k + 2] < l2 ? L[k + 2] : l2;
    h0 = H[k] > h0 ? H[k] : h0, h1 = H[k + 1] > h1 ? H[k + 1] : h1, h2 = H[k + 2] > h2 ? H[k + 2] : h2;
  }
  uint64_t bad = (B[0] != B[0]) | (B[1] != B[1]) | (B[2] != B[2]) | (B[3] != B[3]);
  for (int i = n4; i < n; i++) BOX_OF_POINT(i);
  lo[0] = l0, lo[1] = l1, lo[2] = l2, hi[0] = h0, hi[1] = h1, hi[2] = h2;
  return bad != 0;
}
#endif

int griddem_box_of(const double *x, int n, double *lo, double *hi)
{
#ifdef GRIDDEM_POINTS_AVX2
  if (!griddem_threaded(n) && griddem_vector_reads())
    return box_of_avx2(x, n, lo, hi);
#endif
  return box_of_plain(x, n, lo, hi);
}
#undef BOX_OF_POINT

/* The box of n points, or the anchor alone without points */
static void points_box(const double anchor[3], int n, const double *x, double lo[3], double hi[3])
{
  if (n > 0) griddem_box_of(x, n, lo, hi);
  else
    for (int d = 0; d < 3; d++) lo[d] = hi[d] = anchor[d];
}

int griddem_grid_cover(griddem_grid *g, const double anchor[3], int n, const double *x, double h,
                       long max_cells)
{
  double lo[3], hi[3];
  points_box(anchor, n, x, lo, hi);
  return griddem_grid_fit(g, anchor, lo, hi, h, max_cells);
}

int griddem_grid_cover_again(griddem_grid *g, const double anchor[3], int n, const double *x, double h,
                             long max_cells)
{
  double lo[3], hi[3];
  points_box(anchor, n, x, lo, hi);
  return griddem_grid_fit_again(g, anchor, lo, hi, h, max_cells);
}

int griddem_grid_fit(griddem_grid *g, const double anchor[3], const double lo[3], const double hi[3],
                     double h, long max_cells)
{
  for (int d = 0; d < 3; d++) g->anchor[d] = anchor[d];
  int coarsened = 0;
  long total = cells_for(g, lo, hi, h, g->k0, g->n);
  while (total > max_cells) {
    h *= 1.25;
    coarsened = 1;
    total = cells_for(g, lo, hi, h, g->k0, g->n);
  }
  g->h = h;
  g->hinv = 1.0 / h;
  for (int d = 0; d < 3; d++) g->lo[d] = griddem_cell_face(anchor[d], h, g->k0[d]);
  g->ncell = total;
  return coarsened;
}

int griddem_grid_contains_box(const griddem_grid *g, const double anchor[3], double h, const double lo[3],
                              const double hi[3])
{
  int contains = g->ncell > 0 && g->h == h;
  for (int d = 0; d < 3; d++)
    contains &= g->anchor[d] == anchor[d] && axis_index(lo[d], anchor[d], g->hinv) >= g->k0[d] &&
                axis_index(hi[d], anchor[d], g->hinv) < g->k0[d] + g->n[d];
  return contains;
}

int griddem_grid_fit_again(griddem_grid *g, const double anchor[3], const double lo[3], const double hi[3],
                           double h, long max_cells)
{
  return griddem_grid_contains_box(g, anchor, h, lo, hi) ? 0 : griddem_grid_fit(g, anchor, lo, hi, h, max_cells);
}

static inline long clamp_cell(long c, long n)
{
  return c < 0 ? 0 : (c >= n ? n - 1 : c);
}

static inline long axis_cell(const griddem_grid *g, int d, double x)
{
  return griddem_axis_cell(x, g->anchor[d], g->hinv, g->k0[d], g->n[d]);
}

static inline long cell_index(const griddem_grid *g, double x, double y, double z)
{
  return axis_cell(g, 0, x) + (long) g->n[0] * (axis_cell(g, 1, y) + (long) g->n[1] * axis_cell(g, 2, z));
}

/* The cells of points i0 .. i1 - 1 of x (interleaved) into cell, lanes of points at once where
 * the processor has them: on a grid of fewer than 2^31 cells the index is summed in 32-bit lanes
 * (AVX2 multiplies no 64-bit lanes) */
GRIDDEM_VECTOR_COPIES static void cells_of_plain(const griddem_grid *restrict g, int i0, int i1,
                                                 const double *restrict x, long *restrict cell)
{
  if (g->ncell <= INT_MAX) {
    const int row = g->n[0], layer = g->n[0] * g->n[1];
    for (int i = i0; i < i1; i++)
      cell[i] = (int) axis_cell(g, 0, x[3 * i]) + row * (int) axis_cell(g, 1, x[3 * i + 1]) +
                layer * (int) axis_cell(g, 2, x[3 * i + 2]);
  } else
    for (int i = i0; i < i1; i++) cell[i] = cell_index(g, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
}

#ifdef GRIDDEM_POINTS_AVX2
/* griddem_axis_cell of four coordinates (the clamps as maximum and minimum: the same cells for
 * every finite coordinate and infinity; a NaN, which the scan reports, goes to cell 0) */
__attribute__((target("avx2"), always_inline)) static inline __m128i axis_cells_avx2(__m256d x, __m256d anchor,
                                                                                    __m256d hinv, __m256d k0,
                                                                                    __m256d last)
{
  const __m256d c = _mm256_sub_pd(_mm256_floor_pd(_mm256_mul_pd(_mm256_sub_pd(x, anchor), hinv)), k0);
  return _mm256_cvttpd_epi32(_mm256_min_pd(_mm256_max_pd(c, _mm256_setzero_pd()), last));
}

/* Four points a pass on a grid of fewer than 2^31 cells, the rest as cells_of_plain */
__attribute__((target("avx2"))) static void cells_of_avx2(const griddem_grid *restrict g, int i0, int i1,
                                                         const double *restrict x, long *restrict cell)
{
  __m256d anchor[3], k0[3], last[3];
  for (int d = 0; d < 3; d++)
    anchor[d] = _mm256_set1_pd(g->anchor[d]), k0[d] = _mm256_set1_pd((double) g->k0[d]),
    last[d] = _mm256_set1_pd((double) (g->n[d] - 1));
  const __m256d hinv = _mm256_set1_pd(g->hinv);
  const __m128i row = _mm_set1_epi32(g->n[0]), layer = _mm_set1_epi32(g->n[0] * g->n[1]);
  int i = i0;
  for (; i + 4 <= i1; i += 4) {
    __m256d px, py, pz;
    griddem_points4_avx2(x + 3 * (size_t) i, &px, &py, &pz);
    const __m128i cx = axis_cells_avx2(px, anchor[0], hinv, k0[0], last[0]);
    const __m128i cy = axis_cells_avx2(py, anchor[1], hinv, k0[1], last[1]);
    const __m128i cz = axis_cells_avx2(pz, anchor[2], hinv, k0[2], last[2]);
    const __m128i c = _mm_add_epi32(_mm_add_epi32(cx, _mm_mullo_epi32(row, cy)), _mm_mullo_epi32(layer, cz));
    _mm256_storeu_si256((__m256i *) (cell + i), _mm256_cvtepi32_epi64(c));
  }
  cells_of_plain(g, i, i1, x, cell);
}
#endif

static void cells_of(const griddem_grid *restrict g, int i0, int i1, const double *restrict x, long *restrict cell)
{
#ifdef GRIDDEM_POINTS_AVX2
  if (g->ncell <= INT_MAX && griddem_vector_reads()) {
    cells_of_avx2(g, i0, i1, x, cell);
    return;
  }
#endif
  cells_of_plain(g, i0, i1, x, cell);
}

long griddem_cell_of(const griddem_grid *g, double x, double y, double z)
{
  return cell_index(g, x, y, z);
}

long griddem_box_cell(const double lo[3], const double prd[3], const int n[3], const double *x)
{
  long index = 0, stride = 1;
  for (int d = 0; d < 3; d++) {
    index += stride * clamp_cell((long) floor((x[d] - lo[d]) / prd[d] * n[d]), n[d]);
    stride *= n[d];
  }
  return index;
}

/* Whether two of the n sorted slots of a cell hold one key (periodic images of one particle) */
static int equal_keys(const int *slot, int n, const void *key, int key_bytes)
{
  for (int k = 1; k < n; k++)
    if (griddem_key_at(key, key_bytes, slot[k - 1]) == griddem_key_at(key, key_bytes, slot[k])) return 1;
  return 0;
}

/* The counting sort on threads: each thread counts the cells of its range of points; per cell,
 * the threads' counts become each one's place in the cell (the ranges in order, so the slots come
 * out as on one thread); one scan over the cells; each thread scatters its range. */
static int bin_threaded(griddem_bins *b, const griddem_grid *g, int n, const double *x)
{
  const int nthreads = griddem_max_threads();
  const long ncell = g->ncell, need = (long) nthreads * ncell;
  if (need > b->thread_count_cap) {
    free(b->thread_count);
    b->thread_count = (int *) malloc(sizeof(int) * (size_t) need);
    b->thread_count_cap = b->thread_count ? need : 0;
    if (!b->thread_count) return -1;
  }
  int *start = b->cell_start, *counts = b->thread_count;
#pragma omp parallel num_threads(nthreads)
  {
    const int t = griddem_thread_num(), nt = griddem_team_size();
    const int i0 = (int) ((long) n * t / nt), i1 = (int) ((long) n * (t + 1) / nt);
    int *mine = counts + (size_t) t * (size_t) ncell;
    memset(mine, 0, sizeof(int) * (size_t) ncell);
    cells_of(g, i0, i1, x, b->cell);
    for (int i = i0; i < i1; i++) mine[b->cell[i]]++;
#pragma omp barrier
#pragma omp for schedule(static)
    for (long c = 0; c < ncell; c++) {
      int sum = 0;
      for (int u = 0; u < nt; u++) {
        int *place = counts + (size_t) u * (size_t) ncell + c;
        const int here = *place;
        *place = sum, sum += here;
      }
      start[c + 1] = sum;
    }
#pragma omp single
    {
      start[0] = 0;
      for (long c = 0; c < ncell; c++) start[c + 1] += start[c];
    }
    for (int i = i0; i < i1; i++) {
      const long c = b->cell[i];
      b->order[start[c] + mine[c]++] = i;
    }
  }
  return 0;
}

int griddem_bin_points(griddem_bins *b, const griddem_grid *g, int n, const double *x,
                       const void *key, int key_bytes)
{
  b->movable = 0;
  /* one int beyond cell_start's ncell + 1: the counts are kept two places up (below) */
  if (g->ncell + 2 > b->ncell_cap) {
    free(b->cell_start);
    b->ncell_cap = g->ncell + 2;
    b->cell_start = (int *) malloc(sizeof(int) * (size_t) b->ncell_cap);
    if (!b->cell_start) return -1;
  }
  if (n > b->n_cap) {
    free(b->order);
    free(b->cell);
    free(b->next_cell);
    b->next_cell = NULL;
    b->n_cap = n + n / 4 + 16;
    b->order = (int *) malloc(sizeof(int) * (size_t) b->n_cap);
    b->cell = (long *) malloc(sizeof(long) * (size_t) b->n_cap);
    if (!b->order || !b->cell) return -1;
  }
  b->ncell = g->ncell;
  b->n = n;
  /* on the threads where there are many points (OpenMP only then: a region allocates its team
     even for one thread), and the threads' counts of the cells (memory and work) are at most two
     per point: not on a grid mostly empty */
  int twins = 0; /* a cell holds two slots with one key */
  if (griddem_threaded(n) && (long) griddem_max_threads() * g->ncell <= 2L * n) {
    if (bin_threaded(b, g, n, x) != 0) return -1;
    /* each crowded cell's centres in key order, the cells on the threads */
    const int *start = b->cell_start;
    if (key) {
#pragma omp parallel for schedule(static) reduction(| : twins)
      for (long c = 0; c < g->ncell; c++)
        if (start[c + 1] - start[c] > 1) {
          griddem_sort_cell(b->order + start[c], start[c + 1] - start[c], key, key_bytes, x);
          twins |= equal_keys(b->order + start[c], start[c + 1] - start[c], key, key_bytes);
        }
    }
  } else {
    int *start = b->cell_start;
    /* cell c's count at start[c + 2]; the scan turns start[c + 1] into c's first slot, and the
       scatter advances it to c's end, which is c + 1's first slot: cell_start without a shift.
       On a grid mostly empty only the spans of GRIDDEM_BIN_SPAN cells that hold centres are
       cleared and scanned, the others take the running start; otherwise the grid is one span. */
    const long span_cells = g->ncell >= GRIDDEM_BIN_SPARSE * (long) n ? GRIDDEM_BIN_SPAN : (g->ncell > 0 ? g->ncell : 1);
    const long nspan = (g->ncell + span_cells - 1) / span_cells;
    if (nspan > b->span_cap) {
      free(b->span_count);
      b->span_count = (int *) malloc(sizeof(int) * (size_t) nspan);
      b->span_cap = b->span_count ? nspan : 0;
      if (!b->span_count) return -1;
    }
    int *span = b->span_count;
    cells_of(g, 0, n, x, b->cell);
    if (nspan > 1) {
      memset(span, 0, sizeof(int) * (size_t) nspan);
      /* several spans are GRIDDEM_BIN_SPAN cells each (span_cells): the constant divides by a shift */
      for (int i = 0; i < n; i++) span[b->cell[i] / GRIDDEM_BIN_SPAN]++;
    } else if (nspan == 1)
      span[0] = n;
    start[0] = start[1] = 0;
    for (long s = 0; s < nspan; s++)
      if (span[s]) {
        const long c0 = s * span_cells, c1 = c0 + span_cells < g->ncell ? c0 + span_cells : g->ncell;
        memset(start + c0 + 2, 0, sizeof(int) * (size_t) (c1 - c0));
      }
    long crowded = 0;
    if (key) {
      /* the crowded cells listed as their second centre is counted (at most n / 2 of them; each
         cell written at the list's end, which its second centre then extends, so the count takes
         no branch on it) */
      if (n / 2 + 1 > b->crowded_cap) {
        free(b->crowded);
        b->crowded = (long *) malloc(sizeof(long) * (size_t) (n / 2 + 1));
        b->crowded_cap = b->crowded ? n / 2 + 1 : 0;
        if (!b->crowded) return -1;
      }
      for (int i = 0; i < n; i++) {
        const long c = b->cell[i];
        b->crowded[crowded] = c, crowded += ++start[c + 2] == 2;
      }
    } else
      for (int i = 0; i < n; i++) start[b->cell[i] + 2]++;
    for (long s = 0; s < nspan; s++) {
      const long c0 = s * span_cells, c1 = c0 + span_cells < g->ncell ? c0 + span_cells : g->ncell;
      if (span[s])
        for (long c = c0; c < c1; c++) start[c + 2] += start[c + 1];
      else
        for (long c = c0, first = start[c0 + 1]; c < c1; c++) start[c + 2] = (int) first;
    }
    for (int i = 0; i < n; i++) b->order[start[b->cell[i] + 1]++] = i;
    /* each crowded cell's centres in key order */
    for (long k = 0; k < crowded; k++) {
      const long c = b->crowded[k];
      griddem_sort_cell(b->order + start[c], start[c + 1] - start[c], key, key_bytes, x);
      twins |= equal_keys(b->order + start[c], start[c + 1] - start[c], key, key_bytes);
    }
  }
  b->grid = *g;
  b->movable = key && !twins;
  return 0;
}

/* Point i's slot moved out of cell `from` to its place in cell `to` (griddem_slot_before's), the
 * slots between shifted by one and the starts of the cells between with them; the number of slots
 * and cells shifted is added to *shifted. Returns 1 where `to` now holds two slots of one key. */
static int move_point(griddem_bins *b, int i, long from, long to, const double *x, const void *key, int key_bytes,
                      long *shifted)
{
  int *order = b->order, *start = b->cell_start;
  int p = start[from];
  while (order[p] != i) p++;
  int q = start[to];
  while (q < start[to + 1] && !griddem_slot_before(i, order[q], key, key_bytes, x)) q++;
  if (to > from) {
    memmove(order + p, order + p + 1, sizeof(int) * (size_t) (q - p - 1));
    order[q - 1] = i;
    for (long c = from + 1; c <= to; c++) start[c]--;
  } else {
    memmove(order + q + 1, order + q, sizeof(int) * (size_t) (p - q));
    order[q] = i;
    for (long c = to + 1; c <= from; c++) start[c]++;
  }
  *shifted += (p > q ? p - q : q - p) + (to > from ? to - from : from - to);
  return equal_keys(order + start[to], start[to + 1] - start[to], key, key_bytes);
}

/* i0 where the cells of some of points i0 .. i1 - 1 differ in a and b, else i1 (compared in
 * vector lanes, without a branch per point) */
GRIDDEM_VECTOR_COPIES static int differing(const long *restrict a, const long *restrict b, int i0, int i1)
{
  long differ = 0;
  for (int i = i0; i < i1; i++) differ |= a[i] ^ b[i];
  return differ ? i0 : i1;
}

static int same_grid(const griddem_grid *a, const griddem_grid *b)
{
  int same = a->h == b->h && a->ncell == b->ncell;
  for (int d = 0; d < 3; d++) same &= a->anchor[d] == b->anchor[d] && a->k0[d] == b->k0[d] && a->n[d] == b->n[d];
  return same;
}

int griddem_bin_points_again(griddem_bins *b, const griddem_grid *g, int n, const double *x,
                             const void *key, int key_bytes)
{
  if (!b->movable || !key || n != b->n || n == 0 || !same_grid(g, &b->grid))
    return griddem_bin_points(b, g, n, x, key, key_bytes);
  if (!b->next_cell) {
    b->next_cell = (long *) malloc(sizeof(long) * (size_t) b->n_cap);
    if (!b->next_cell) return -1;
  }
  long *now = b->next_cell;
  if (griddem_threaded(n)) {
#pragma omp parallel
    {
      const int t = griddem_thread_num(), nt = griddem_team_size();
      cells_of(g, (int) ((long) n * t / nt), (int) ((long) n * (t + 1) / nt), x, now);
    }
  } else
    cells_of(g, 0, n, x, now);
  /* the slots moved one by one while that shifts at most 16 slots or cell starts a point and one a
     cell (a point crossing a plane of cells shifts a plane's): a shift is a fraction of an
     instruction (memmove, a vector loop), where a counting sort pays tens a point for its
     scattered counts and stores; past that, binned afresh */
  enum { BLOCK = 64 }; /* points compared at once before any is looked at */
  long shifted = 0, *was = b->cell;
  int twins = 0;
  const long budget = 16L * n + g->ncell;
  for (int i0 = 0; i0 < n && shifted <= budget; i0 += BLOCK) {
    const int i1 = n - i0 < BLOCK ? n : i0 + BLOCK;
    for (int i = differing(now, was, i0, i1); i < i1; i++)
      if (now[i] != was[i]) twins |= move_point(b, i, was[i], now[i], x, key, key_bytes, &shifted), was[i] = now[i];
  }
  if (shifted > budget) return griddem_bin_points(b, g, n, x, key, key_bytes);
  b->movable = !twins;
  return 0;
}

void griddem_bins_occupancy(const griddem_bins *b, long *occupied, int *most)
{
  long cells = 0;
  int top = 0;
  for (long c = 0; c < b->ncell; c++) {
    const int count = b->cell_start[c + 1] - b->cell_start[c];
    cells += count != 0;
    top = count > top ? count : top;
  }
  *occupied = cells, *most = top;
}

void griddem_bins_free(griddem_bins *b)
{
  free(b->cell_start);
  free(b->order);
  free(b->cell);
  free(b->thread_count);
  free(b->crowded);
  free(b->span_count);
  free(b->next_cell);
  memset(b, 0, sizeof(*b));
}

int griddem_stencil_runs(const griddem_stencil *s, const griddem_grid *g, const griddem_bins *b, long cell,
                         int *lo, int *hi)
{
  const long nx = g->n[0], nxy = nx * g->n[1];
  const int x = (int) (cell % nx), y = (int) (cell / nx % g->n[1]), z = (int) (cell / nxy);
  int n = 0;
  for (int r = 0; r < s->nrows; r++) {
    const griddem_stencil_row *row = &s->row[r];
    const int yy = y + row->dy, zz = z + row->dz;
    if (yy < 0 || yy >= g->n[1] || zz < 0 || zz >= g->n[2]) continue;
    const int x0 = x + row->dxlo < 0 ? 0 : x + row->dxlo;
    const int x1 = x + row->dxhi >= nx ? (int) nx - 1 : x + row->dxhi;
    const long first = nx * yy + nxy * zz;
    lo[n] = b->cell_start[first + x0], hi[n] = b->cell_start[first + x1 + 1];
    n++;
  }
  return n;
}

static double largest_radius(int n, const double *radius)
{
  double rmax = 0.0;
  for (int j = 0; j < n; j++) rmax = radius[j] > rmax ? radius[j] : rmax;
  return rmax;
}

/* The full stencil of the contact distance 2 rmax on g */
static void contact_stencil(const griddem_grid *g, griddem_stencil *s, double rmax)
{
  griddem_stencil_build(s, g->h, 2.0 * rmax, GRIDDEM_STENCIL_FULL);
}

int griddem_bin_for_contacts(griddem_grid *g, griddem_bins *b, griddem_stencil *s, int n, const double *x,
                             const double *radius)
{
  const double rmax = largest_radius(n, radius);
  if (n == 0 || rmax == 0.0) return 1;
  const double anchor[3] = {0.0, 0.0, 0.0};
  /* the edge may grow for a dilute set; the stencil of the partners within 2 rmax follows it */
  griddem_grid_cover(g, anchor, n, x, 2.0 * rmax * (1.0 + 1e-12), 8L * n + 1024L);
  if (griddem_bin_points(b, g, n, x, NULL, 0) != 0) return -1;
  contact_stencil(g, s, rmax);
  return 0;
}

int griddem_stencil_for_contacts(const griddem_grid *g, griddem_stencil *s, int n, const double *radius)
{
  const double rmax = largest_radius(n, radius);
  if (n == 0 || rmax == 0.0) return 1;
  contact_stencil(g, s, rmax);
  return 0;
}
