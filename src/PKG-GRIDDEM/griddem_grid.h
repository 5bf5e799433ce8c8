/* GRIDDEM grid geometry and binning: a uniform grid over a box, and a counting sort of particle
 * centres by cell (compressed rows: cell c holds sorted slots cell_start[c] .. cell_start[c+1]-1).
 * The sorted order is the "image channel" layout: slots of one cell are contiguous, and so are the
 * slots of a whole row of cells along x, which the stencil sweep scans as one range. */
#ifndef GRIDDEM_GRID_H
#define GRIDDEM_GRID_H

#include "griddem_portable.h"

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Element i of an array of 32- or 64-bit integers (key_bytes 4 or 8), such as LAMMPS's tags. */
GRIDDEM_INLINE int64_t griddem_key_at(const void *key, int key_bytes, int i)
{
  return key_bytes == 8 ? ((const int64_t *) key)[i] : (int64_t) ((const int *) key)[i];
}

/* Whether point a comes before point b in a cell: by key (tags), then by position (x, y, z:
 * periodic images of one particle share its tag), so the order within a cell does not depend on
 * how the host stores its particles. x: 3 interleaved coordinates per point. */
GRIDDEM_INLINE int griddem_slot_before(int a, int b, const void *key, int key_bytes,
                                       const double *x)
{
  const int64_t ka = griddem_key_at(key, key_bytes, a), kb = griddem_key_at(key, key_bytes, b);
  if (ka != kb) return ka < kb;
  const double *xa = x + 3 * (size_t) a, *xb = x + 3 * (size_t) b;
  for (int d = 0; d < 3; d++)
    if (xa[d] != xb[d]) return xa[d] < xb[d];
  return 0;
}

/* Cells up to this many centres are sorted by insertion, larger ones by heapsort. */
#define GRIDDEM_CELL_SORT_SMALL 16

/* Sorts the n points of one cell (their indices in slot[]) by griddem_slot_before. Insertion for
 * the few centres a cell holds; heapsort above GRIDDEM_CELL_SORT_SMALL, so that a crowded cell (a
 * coarsened grid, a cell of a given edge) costs O(n log n), not O(n^2). No memory beyond slot[],
 * no recursion: it runs as one GPU thread per cell. The key's width is a constant of each inlined
 * copy (griddem_sort_cell below), and a cell of two, the most common crowded cell, takes one
 * comparison. */
GRIDDEM_INLINE void griddem_sort_cell_keyed(int *slot, int n, const void *key, const int key_bytes,
                                            const double *x)
{
  if (n == 2) {
    if (griddem_slot_before(slot[1], slot[0], key, key_bytes, x)) {
      const int first = slot[1];
      slot[1] = slot[0], slot[0] = first;
    }
    return;
  }
  if (n <= GRIDDEM_CELL_SORT_SMALL) {
    for (int s = 1; s < n; s++) {
      const int moving = slot[s];
      int t = s;
      while (t > 0 && griddem_slot_before(moving, slot[t - 1], key, key_bytes, x)) {
        slot[t] = slot[t - 1];
        t--;
      }
      slot[t] = moving;
    }
    return;
  }
  /* heapsort: a max-heap in slot[0, end), its root swapped to the end until the heap is empty */
  for (int end = n, build = n / 2; end > 1;) {
    int root;
    if (build > 0) {
      root = --build;
    } else {
      const int top = slot[0];
      slot[0] = slot[--end];
      slot[end] = top;
      root = 0;
    }
    for (;;) {
      int child = 2 * root + 1;
      if (child >= end) break;
      if (child + 1 < end && griddem_slot_before(slot[child], slot[child + 1], key, key_bytes, x))
        child++;
      if (!griddem_slot_before(slot[root], slot[child], key, key_bytes, x)) break;
      const int held = slot[root];
      slot[root] = slot[child];
      slot[child] = held;
      root = child;
    }
  }
}

GRIDDEM_INLINE void griddem_sort_cell(int *slot, int n, const void *key, int key_bytes, const double *x)
{
  if (key_bytes == 8) griddem_sort_cell_keyed(slot, n, key, 8, x);
  else griddem_sort_cell_keyed(slot, n, key, 4, x);
}

/* How the cell edge is chosen. */
enum griddem_cell_mode {
  GRIDDEM_CELL_EXACT = 0, /* NN4DEM: edge d_min/sqrt(3), so a cell holds one centre unless overlapping */
  GRIDDEM_CELL_MULTI = 1, /* edge = largest contact distance 2*r_max (+1e-9): 3^3 stencil, several per cell */
  GRIDDEM_CELL_FIXED = 2, /* edge given by the user */
  GRIDDEM_CELL_AUTO = 3,  /* the default: the geometry measured fastest (now classes, see doc/fix_griddem.md) */
  GRIDDEM_CELL_CLASSES = 4 /* a grid per size class, each with multi's edge for its largest radius */
};

typedef struct griddem_grid {
  double anchor[3]; /* cell faces lie at anchor + k*h for integer k, whatever the points */
  long k0[3];       /* k of the first cell on each axis */
  double lo[3];     /* lower corner: anchor + k0*h */
  double h;      /* cell edge */
  double hinv;
  int n[3];      /* cells per axis */
  long ncell;
} griddem_grid;

/* Cell edge for a mode; value is the edge for GRIDDEM_CELL_FIXED. */
double griddem_cell_edge(int mode, double rmin, double rmax, double value);

/* Cells a stencil must reach on each side so that every centre within distance cut of a centre
 * in the middle cell is visited: ceil(cut/h), at least 1. */
int griddem_stencil_reach(double h, double cut);

/* Most cells a stencil reaches on each side (exact mode handles radius ratios up to 1:18), and
 * most rows of a stencil (the full one at that reach). */
#define GRIDDEM_MAX_REACH 32
#define GRIDDEM_STENCIL_MAX_ROWS ((2 * GRIDDEM_MAX_REACH + 1) * (2 * GRIDDEM_MAX_REACH + 1))

/* Which of the cells around a cell a stencil holds. */
enum griddem_stencil_part {
  GRIDDEM_STENCIL_FULL = 0,   /* all of them: every partner of a centre (or of a point) */
  GRIDDEM_STENCIL_FORWARD = 1 /* the cell and those after it in sorted order: each pair once */
};

/* One row of a stencil: the cells (dx, dy, dz) from a cell for dx = dxlo..dxhi, whose slots are
 * contiguous. */
typedef struct griddem_stencil_row {
  int dy, dz, dxlo, dxhi;
} griddem_stencil_row;

/* The rows of cells that can hold a centre within a distance of a point in a cell, in sorted
 * order (by dz, then dy); the corners are pruned by the smallest distance between the two cells.
 * The forward part is the full stencil's rows from the cell's own row on, that row starting at
 * the cell itself: the own row is its row 0. */
typedef struct griddem_stencil {
  int nrows;
  griddem_stencil_row row[GRIDDEM_STENCIL_MAX_ROWS];
} griddem_stencil;

/* The stencil of part for cells of edge h and the distance cut (centres closer than cut). 0, or -1
 * (and no rows) when it would reach more than GRIDDEM_MAX_REACH cells. */
int griddem_stencil_build(griddem_stencil *s, double h, double cut, int part);

/* Whether a double is not finite, as a bit: its exponent's bits are all set exactly where adding
 * one to the exponent carries into the sign bit (integer arithmetic, which vector lanes run) */
GRIDDEM_INLINE uint64_t griddem_nonfinite_bit(double v)
{
  uint64_t bits;
  memcpy(&bits, &v, sizeof(bits));
  return ((bits & 0x7ff0000000000000ull) + 0x0010000000000000ull) >> 63;
}

/* Box lo, hi of n > 0 points (3n doubles at x), and whether some of their coordinates are not
 * finite (the box then means nothing) */
int griddem_box_of(const double *x, int n, double *lo, double *hi);

/* Grid with edge h, faces aligned to anchor, covering the bounding box of n interleaved points.
 * Aligning to a fixed anchor makes a point's cell depend on its position only, not on which other
 * points (ghosts) a process holds, so sums come out in the same order on any decomposition.
 * If more than max_cells cells would be needed, the edge is enlarged until they fit (dilute scenes
 * must not allocate space they do not fill); returns 1 then, 0 otherwise. Points must be finite. */
int griddem_grid_cover(griddem_grid *g, const double anchor[3], int n, const double *x, double h,
                       long max_cells);
/* The same for the box lo..hi (the points' bounding box, known to the caller). */
int griddem_grid_fit(griddem_grid *g, const double anchor[3], const double lo[3], const double hi[3],
                     double h, long max_cells);

/* Whether g is a grid of edge h aligned to anchor whose cells cover the box lo..hi. Points within
 * it are binned on g into the cells and the order that a grid fitted to them gives (cells are
 * ordered by their faces, z, y, then x, whatever the grid's extent), so a grid kept while its
 * points move inside it lets them be binned again (griddem_bin_points_again). */
int griddem_grid_contains_box(const griddem_grid *g, const double anchor[3], double h, const double lo[3],
                              const double hi[3]);
/* griddem_grid_fit and griddem_grid_cover for points binned again: g is kept as it is (returns 0)
 * where it contains their box (griddem_grid_contains_box), else fitted to it. */
int griddem_grid_fit_again(griddem_grid *g, const double anchor[3], const double lo[3], const double hi[3],
                           double h, long max_cells);
int griddem_grid_cover_again(griddem_grid *g, const double anchor[3], int n, const double *x, double h,
                             long max_cells);

/* Cell of a point; points on or past the upper faces go to the last cell. */
long griddem_cell_of(const griddem_grid *g, double x, double y, double z);

/* floor(v) as an integer, for finite v within the range of long: the truncation, one less for a
 * negative non-integer (exactly floor's value, without a call into libm) */
GRIDDEM_INLINE long griddem_floor_index(double v)
{
  const long t = (long) v;
  return t - (v < (double) t);
}

/* The cell along one axis of a grid (faces at anchor + k / hinv, n cells from k = k0) that holds
 * coordinate x, clamped to the grid: points on or past the upper faces go to the last cell. How
 * both the CPU engine (griddem_cell_of) and the Kokkos styles place a point. In double, where
 * the grid's integers are exact, so that a loop over points vectorizes (floor, min and max of
 * lanes). */
GRIDDEM_INLINE int griddem_axis_cell(double x, double anchor, double hinv, long k0, int n)
{
  double c = floor((x - anchor) * hinv) - (double) k0;
  c = c < 0.0 ? 0.0 : c;
  c = c > (double) (n - 1) ? (double) (n - 1) : c;
  return (int) c;
}

/* The cells along one axis of a grid (as griddem_axis_cell) that hold coordinates within d of x:
 * *lo..*hi, clamped to the grid. How every search bounds the cells within reach of a point or of
 * a box (lo of its lower corner, hi of its upper one). */
GRIDDEM_INLINE void griddem_axis_cells_within(double xlo, double xhi, double d, double anchor, double hinv, long k0,
                                              int n, int *lo, int *hi)
{
  *lo = griddem_axis_cell(xlo - d, anchor, hinv, k0, n);
  *hi = griddem_axis_cell(xhi + d, anchor, hinv, k0, n);
}

/* The face k of a grid along one axis (faces at anchor + k h): the lower corner of the CPU grid
 * (k = k0) and of a Kokkos cell (k = k0 + its index) alike. */
GRIDDEM_INLINE double griddem_cell_face(double anchor, double h, long k)
{
  return anchor + (double) k * h;
}

/* Cell of a point in a box [lo, lo + prd) split into n[d] cells along each axis (x fastest), as
 * output grids are laid out; points outside go to the nearest cell. */
long griddem_box_cell(const double lo[3], const double prd[3], const int n[3], const double *x);

typedef struct griddem_bins {
  long ncell;       /* cells binned into */
  int n;            /* points binned */
  int *cell_start;  /* [ncell+1] (room for ncell+2) */
  int *order;       /* [n] original index of each sorted slot */
  long *cell;       /* [n] cell of each original point */
  long ncell_cap;
  int n_cap;
  int *thread_count;/* binned on threads: each thread's count of each cell, then its place in it */
  long thread_count_cap;
  long *crowded;    /* binned on one thread with keys: the cells holding more than one centre */
  int crowded_cap;
  int *span_count;  /* binned on one thread: centres in each span of GRIDDEM_BIN_SPAN cells */
  long span_cap;
  griddem_grid grid;/* the grid binned into */
  int movable;      /* 1: binned by key with no two equal keys in a cell, so that griddem_bin_points_again
                       can move the slots of the points that changed cells into place */
  long *next_cell;  /* [n] griddem_bin_points_again: the cell of each point now */
} griddem_bins;

/* Cells a span of the one-thread counting sort on a grid of at least GRIDDEM_BIN_SPARSE cells a
 * centre: spans without centres are neither cleared nor scanned cell by cell, so that a grid
 * mostly empty (the few atoms a reduced-order run resolves, a dilute gas) costs about a store per
 * cell; a fuller grid is one span (the extra pass over the centres would not pay) */
#define GRIDDEM_BIN_SPAN 64
#define GRIDDEM_BIN_SPARSE 8

/* Counting sort of n interleaved points into g's cells; within a cell, slots are ordered by key
 * and position (griddem_sort_cell). key is 32- or 64-bit per key_bytes, or NULL to keep input order.
 * Returns 0, or -1 when memory cannot be had. */
int griddem_bin_points(griddem_bins *b, const griddem_grid *g, int n, const double *x,
                       const void *key, int key_bytes);

/* The points of b's last binning binned again after they moved: the same n points, each at the
 * same index with the same key (a LAMMPS step without reneighboring), at their new positions x.
 * Where g is b's last grid, that binning was movable and few points changed cells, each of those
 * leaves its slot for its place in its new cell, and the cells' starts follow: the slots come out
 * as griddem_bin_points orders them, without a pass over every cell and point. Otherwise
 * griddem_bin_points. Returns 0, or -1 when memory cannot be had. */
int griddem_bin_points_again(griddem_bins *b, const griddem_grid *g, int n, const double *x,
                             const void *key, int key_bytes);
void griddem_bins_free(griddem_bins *b);

/* The cells of b holding at least one centre, and the most centres in one cell ("slots used"):
 * counted when asked, not by every binning. */
void griddem_bins_occupancy(const griddem_bins *b, long *occupied, int *most);

/* The runs of slots of b (binned into g) that can hold a centre within stencil s's distance of a
 * point of cell `cell` of g: one run [lo[q], hi[q]) per stencil row inside the grid, in the
 * stencil's order, its cells clamped to the grid along x. Of a forward stencil, run 0 is the cell's
 * own row from the cell's first slot on: a centre's forward partners there are the slots after
 * its own. lo and hi need room for s->nrows runs. Returns the number of runs. */
int griddem_stencil_runs(const griddem_stencil *s, const griddem_grid *g, const griddem_bins *b, long cell,
                         int *lo, int *hi);

/* The n interleaved points binned for their contacts: on a grid of edge twice the largest of
 * their radii (larger for a dilute set), anchored at the origin, with the full stencil of the
 * contact distance. Returns 0, 1 where nothing can touch (no points, or no radius), or -1 without
 * memory. */
int griddem_bin_for_contacts(griddem_grid *g, griddem_bins *b, griddem_stencil *s, int n, const double *x,
                             const double *radius);

/* The full stencil of the contact distance of n spheres (radii radius) on g, the grid
 * griddem_bin_for_contacts made for them: its s again, for another search of the same binning.
 * Returns 0, or 1 where nothing can touch. */
int griddem_stencil_for_contacts(const griddem_grid *g, griddem_stencil *s, int n, const double *radius);

#ifdef __cplusplus
}
#endif

#endif
