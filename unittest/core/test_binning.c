/* Binning: the counting sort is a permutation, cells are in order, slots within a cell are in
 * key order (a cell's sort agrees with libc's qsort, for cells of every size and tied tags), occupancy statistics match a direct count, and dilute boxes are coarsened; output
 * grids over a box put points in the cell that holds them; points on and near the cells' faces go to the cells
 * their faces' numbers say; the box of a set of points is the point-by-point one, and flags a non-finite
 * coordinate wherever it is. Each by the AVX2 passes (griddem_vector_reads) and by the plain ones. */
#include "check.h"
#include "griddem_grid.h"
#include "griddem_search.h"
#include "griddem_threads.h"

#ifdef _OPENMP
#include <omp.h>
#endif
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* qsort's comparison of (tag, x, y, z): the reference order for griddem_sort_cell */
static const int *ref_tag;
static const double *ref_x;
static int by_tag_then_position(const void *pa, const void *pb)
{
  const int a = *(const int *) pa, b = *(const int *) pb;
  if (ref_tag[a] != ref_tag[b]) return ref_tag[a] < ref_tag[b] ? -1 : 1;
  for (int d = 0; d < 3; d++)
    if (ref_x[3 * a + d] != ref_x[3 * b + d]) return ref_x[3 * a + d] < ref_x[3 * b + d] ? -1 : 1;
  return 0;
}

/* cells of 0..400 points, tags drawn from a few values (ties: periodic images share a tag) */
static void check_cell_sort(void)
{
  enum { M = 400 };
  static double x[3 * M];
  static int tag[M], slot[M], expect[M];
  ref_tag = tag, ref_x = x;
  int agree = 1, sizes = 0;
  for (int n = 0; n <= M; n += n < 40 ? 1 : 61) {
    for (int i = 0; i < n; i++) {
      tag[i] = (int) (check_uniform() * (n / 3 + 1));
      for (int d = 0; d < 3; d++) x[3 * i + d] = (double) (int) (4.0 * check_uniform());
      slot[i] = expect[i] = n - 1 - i;
    }
    griddem_sort_cell(slot, n, tag, 4, x);
    qsort(expect, (size_t) n, sizeof(int), by_tag_then_position);
    for (int s = 0; s < n; s++)
      if (by_tag_then_position(&slot[s], &expect[s]) != 0) agree = 0;
    sizes++;
  }
  CHECK(agree, "cell sort of %d cell sizes equals qsort by (tag, position)", sizes);
}

#ifdef _OPENMP
/* binning of GRIDDEM_THREADED_MIN points and more on two threads (the cells, and the order within
 * each cell, in parallel loops): one thread's cells and order, with tags tied in many cells */
static void check_threaded(void)
{
  enum { M = 2 * GRIDDEM_THREADED_MIN };
  static double x[3 * M];
  static int tag[M];
  for (int i = 0; i < M; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = -5.0 + 10.0 * check_uniform();
    tag[i] = (int) (check_uniform() * M / 4);
  }
  const double anchor[3] = {0.0, 0.0, 0.0};
  griddem_grid g;
  griddem_bins one = {0}, two = {0};
  griddem_grid_cover(&g, anchor, M, x, 0.6, 1L << 30);
  omp_set_num_threads(1);
  CHECK(!griddem_threaded(M) && griddem_bin_points(&one, &g, M, x, tag, 4) == 0, "binned on one thread");
  omp_set_num_threads(2);
  CHECK(griddem_threaded(M) && !griddem_threaded(GRIDDEM_THREADED_MIN - 1) &&
            griddem_bin_points(&two, &g, M, x, tag, 4) == 0, "binned on two threads");
  long occupied_one, occupied_two;
  int most_one, most_two;
  griddem_bins_occupancy(&one, &occupied_one, &most_one);
  griddem_bins_occupancy(&two, &occupied_two, &most_two);
  int same = occupied_one == occupied_two && most_one == most_two && most_one > 1;
  for (int s = 0; s < M; s++) same &= one.order[s] == two.order[s] && one.cell[s] == two.cell[s];
  for (long c = 0; c <= g.ncell; c++) same &= one.cell_start[c] == two.cell_start[c];
  CHECK(same, "two threads bin %d points into one thread's cells and order (%ld cells, up to %d a cell)", M,
        g.ncell, most_one);
  /* without keys the order within a cell is the points' order, on any number of threads */
  omp_set_num_threads(1);
  CHECK(griddem_bin_points(&one, &g, M, x, NULL, 0) == 0, "binned without keys on one thread");
  omp_set_num_threads(2);
  CHECK(griddem_bin_points(&two, &g, M, x, NULL, 0) == 0, "binned without keys on two threads");
  int stable = 1;
  for (int s = 0; s < M; s++) stable &= one.order[s] == two.order[s];
  for (long c = 0; c < g.ncell; c++)
    for (int s = one.cell_start[c] + 1; s < one.cell_start[c + 1]; s++) stable &= one.order[s - 1] < one.order[s];
  CHECK(stable, "without keys, two threads give one thread's order, the points' order within each cell");
  /* a grid of more cells than points (the threads' counts would outweigh them): the same too */
  griddem_grid fine;
  griddem_grid_cover(&fine, anchor, M, x, 0.2, 1L << 30);
  omp_set_num_threads(1);
  CHECK(griddem_bin_points(&one, &fine, M, x, tag, 4) == 0, "fine grid on one thread");
  omp_set_num_threads(2);
  CHECK(griddem_bin_points(&two, &fine, M, x, tag, 4) == 0 && fine.ncell > M, "fine grid (%ld cells) on two threads",
        fine.ncell);
  same = 1;
  for (int s = 0; s < M; s++) same &= one.order[s] == two.order[s];
  for (long c = 0; c <= fine.ncell; c++) same &= one.cell_start[c] == two.cell_start[c];
  CHECK(same, "a grid of %ld cells for %d points binned on two threads as on one", fine.ncell, M);
  omp_set_num_threads(1);
  griddem_bins_free(&one);
  griddem_bins_free(&two);
}
#endif

/* b's slots, cell starts and cells equal ref's */
static int same_bins(const griddem_bins *b, const griddem_bins *ref, const griddem_grid *g, int n)
{
  int same = b->n == ref->n && b->ncell == ref->ncell;
  for (int s = 0; same && s < n; s++) same &= b->order[s] == ref->order[s] && b->cell[s] == ref->cell[s];
  for (long c = 0; same && c <= g->ncell; c++) same &= b->cell_start[c] == ref->cell_start[c];
  return same;
}

/* griddem_bin_points_again after points moved: the slots, cell starts and cells of a binning
 * afresh, round after round, with few points changing cells (along each axis, so across rows and
 * planes of cells), with most of them changing (past the budget of moves), with a point moved
 * into a cell that holds its key already (periodic images: the binning is then not movable, and
 * the next one starts afresh), with 64-bit keys, on another grid, and on threads */
static void check_moved(int n, int key_bytes)
{
  double *x = (double *) malloc(sizeof(double) * 3 * (size_t) n);
  int64_t *key = (int64_t *) malloc(sizeof(int64_t) * (size_t) n);
  int *key32 = (int *) malloc(sizeof(int) * (size_t) n);
  for (int i = 0; i < n; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = 8.0 * check_uniform();
    key[i] = key32[i] = (int) ((i * 7919L) % n) + 1; /* distinct, not in storage order */
  }
  /* points 0 and 1 share a key (periodic images of one particle), in cells far apart */
  key[0] = key32[0] = key32[1], key[1] = key32[1];
  x[0] = x[1] = x[2] = 0.1, x[3] = x[4] = x[5] = 7.9;
  const void *k = key_bytes == 8 ? (const void *) key : (const void *) key32;
  const double anchor[3] = {0.0, 0.0, 0.0};
  griddem_grid g, other;
  griddem_grid_cover(&g, anchor, n, x, 0.7, 1L << 30);
  griddem_grid_cover(&other, anchor, n, x, 0.9, 1L << 30);
  griddem_bins b = {0}, ref = {0};
  CHECK(griddem_bin_points(&b, &g, n, x, k, key_bytes) == 0 && b.movable, "%d points binned, movable", n);
  int rounds = 0, moved_total = 0;
  for (int round = 0; round < 60; round++) {
    const double share = round % 10 == 9 ? 0.9 : 0.01; /* every tenth round moves most points */
    int moved = 0;
    for (int i = 0; i < n; i++) {
      if (check_uniform() >= share) continue;
      const long before = griddem_cell_of(&g, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
      const int d = (int) (3.0 * check_uniform());
      x[3 * i + d] += 0.5 * (check_uniform() - 0.5);
      x[3 * i + d] = x[3 * i + d] < 0.0 ? 0.0 : (x[3 * i + d] > 8.0 ? 8.0 : x[3 * i + d]);
      moved += griddem_cell_of(&g, x[3 * i], x[3 * i + 1], x[3 * i + 2]) != before;
    }
    if (round == 30 || round == 31) /* point 0 into point 1's cell, then out of it again */
      for (int d = 0; d < 3; d++) x[d] = round == 30 ? x[3 + d] + 1e-3 : 0.1;
    const griddem_grid *on = round == 45 ? &other : &g;
    CHECK(griddem_bin_points_again(&b, on, n, x, k, key_bytes) == 0 && griddem_bin_points(&ref, on, n, x, k, key_bytes) == 0,
          "round %d binned", round);
    CHECK(same_bins(&b, &ref, on, n), "round %d (%d points changed cells): slots as binned afresh", round, moved);
    if (round == 30) CHECK(!b.movable && !ref.movable, "a cell holding two points of one key is not movable");
    if (round == 31 || round == 45 || round == 46) CHECK(b.movable && ref.movable, "round %d on grid %g: movable", round, on->h);
    rounds++, moved_total += moved;
  }
  CHECK(moved_total > 60 * 10, "%d rounds moved %d points across cells", rounds, moved_total);
  griddem_bins_free(&b), griddem_bins_free(&ref);
  free(x), free(key), free(key32);
}

/* Points on the cells' faces go to the cell above the face, points just below a face to the cell
 * below it, points past the grid to its end cells: the cells binning puts them in (lanes of
 * points at once where the processor has them) against their faces' numbers. Every coordinate
 * and difference here is a multiple of h / 1024 (h a power of two), exact in double, so the
 * expected cell is the face's k - k0. */
static void check_faces(void)
{
  enum { N = 3 * 41 };
  const double anchor[3] = {-1.0, 0.5, 2.0}, lo[3] = {-3.0, -1.0, 0.0}, hi[3] = {3.0, 1.0, 4.0}, h = 0.25;
  griddem_grid g;
  griddem_bins b = {0};
  CHECK(griddem_grid_fit(&g, anchor, lo, hi, h, 1L << 30) == 0, "no coarsening wanted");
  static double x[3 * N];
  static long expect[N];
  for (int i = 0; i < N; i++) {
    /* face k from 4 below the grid's first to 4 past its last, on it, h / 1024 below it, or
       half a cell above; each axis its own face */
    const int kind = i % 3;
    long cell = 0, stride = 1;
    for (int d = 0; d < 3; d++) {
      const long k = g.k0[d] - 4 + (i / 3 + 7 * d) % (g.n[d] + 8);
      const double face = anchor[d] + (double) k * h;
      x[3 * i + d] = kind == 0 ? face : (kind == 1 ? face - h / 1024.0 : face + 0.5 * h);
      long c = k - g.k0[d] - (kind == 1);
      c = c < 0 ? 0 : (c >= g.n[d] ? g.n[d] - 1 : c);
      cell += stride * c, stride *= g.n[d];
    }
    expect[i] = cell;
  }
  CHECK(griddem_bin_points(&b, &g, N, x, NULL, 0) == 0, "binning");
  int right = 1;
  for (long c = 0; c < g.ncell; c++)
    for (int s = b.cell_start[c]; s < b.cell_start[c + 1]; s++) {
      const int i = b.order[s];
      if (expect[i] != c) right = 0, fprintf(stderr, "point %d (%.17g %.17g %.17g) in cell %ld, not %ld\n", i,
                                              x[3 * i], x[3 * i + 1], x[3 * i + 2], c, expect[i]);
    }
  CHECK(right, "points on, below and past the faces in their cells");
  for (int i = 0; i < N; i++) right &= griddem_cell_of(&g, x[3 * i], x[3 * i + 1], x[3 * i + 2]) == expect[i];
  CHECK(right, "griddem_cell_of agrees");
  griddem_bins_free(&b);
}

/* A grid mostly empty, binned after a dense one into the same bins (stale counts left in its
 * cell starts): every cell's start and count as a direct count says, in spans with and without
 * centres and in the last, partial span */
static void check_sparse(void)
{
  enum { N = 3000, M = 37 };
  static double x[3 * N];
  static int tag[N];
  for (int i = 0; i < 3 * N; i++) x[i] = 4.0 * check_uniform();
  for (int i = 0; i < N; i++) tag[i] = i + 1;
  const double anchor[3] = {0.0, 0.0, 0.0};
  griddem_grid g;
  griddem_bins b = {0};
  CHECK(griddem_grid_cover(&g, anchor, N, x, 0.5, 1L << 30) == 0 && griddem_bin_points(&b, &g, N, x, tag, 4) == 0,
        "dense binning first");
  /* M points: a cluster at one corner, one at the far corner (the last span), a few on the way */
  static double y[3 * M];
  for (int i = 0; i < M; i++)
    for (int d = 0; d < 3; d++) y[3 * i + d] = i == M - 1 ? 29.99 : i < 30 ? 0.5 * check_uniform() : 30.0 * check_uniform();
  CHECK(griddem_grid_cover(&g, anchor, M, y, 0.35, 1L << 30) == 0 && g.ncell % GRIDDEM_BIN_SPAN != 0 &&
            griddem_bin_points(&b, &g, M, y, tag, 4) == 0,
        "sparse binning (%ld cells, %ld spans of %d)", g.ncell, g.ncell / GRIDDEM_BIN_SPAN + 1, GRIDDEM_BIN_SPAN);
  int *count = calloc((size_t) g.ncell, sizeof(int));
  for (int i = 0; i < M; i++) count[griddem_cell_of(&g, y[3 * i], y[3 * i + 1], y[3 * i + 2])]++;
  long wrong = 0, first = 0;
  for (long c = 0; c < g.ncell; c++) {
    wrong += b.cell_start[c] != first || b.cell_start[c + 1] - b.cell_start[c] != count[c];
    first += count[c];
  }
  CHECK(wrong == 0 && b.cell_start[g.ncell] == M, "every cell's start and count as counted (%ld wrong)", wrong);
  free(count);
  griddem_bins_free(&b);
}

/* griddem_box_of against a point-by-point box, for every count of points up to 40 (blocks of
 * points and their tails), the extremes at every point and axis, a non-finite coordinate (NaN,
 * +inf, -inf) at every point and axis flagged; and over many points, threaded where OpenMP is */
static void check_box_of(void)
{
  enum { M = 40, BIG = 3 * GRIDDEM_THREADED_MIN + 7 };
  static double x[3 * BIG];
  long wrong = 0, unflagged = 0, flagged = 0;
  for (int n = 1; n <= M; n++)
    for (int at = 0; at < 3 * n; at++) {
      for (int k = 0; k < 3 * n; k++) x[k] = -1.0 + 2.0 * check_uniform();
      x[at] = at % 2 ? 5.0 + at : -5.0 - at; /* the extreme of its axis */
      double lo[3], hi[3], want_lo[3], want_hi[3];
      for (int d = 0; d < 3; d++) {
        want_lo[d] = want_hi[d] = x[d];
        for (int i = 0; i < n; i++)
          want_lo[d] = fmin(want_lo[d], x[3 * i + d]), want_hi[d] = fmax(want_hi[d], x[3 * i + d]);
      }
      flagged += griddem_box_of(x, n, lo, hi) != 0;
      for (int d = 0; d < 3; d++) wrong += lo[d] != want_lo[d] || hi[d] != want_hi[d];
      const double bad[3] = {NAN, INFINITY, -INFINITY};
      for (int v = 0; v < 3; v++) {
        const double keep = x[at];
        x[at] = bad[v];
        unflagged += griddem_box_of(x, n, lo, hi) == 0;
        x[at] = keep;
      }
    }
  CHECK(wrong == 0, "%ld box faces differ from the point-by-point box", wrong);
  CHECK(flagged == 0, "%ld finite sets flagged non-finite", flagged);
  CHECK(unflagged == 0, "%ld non-finite coordinates not flagged", unflagged);

  for (int k = 0; k < 3 * BIG; k++) x[k] = 10.0 * check_uniform();
  x[3 * (BIG - 1) + 2] = -1.0, x[3 * (BIG / 2)] = 12.0;
  double lo[3], hi[3];
  CHECK(griddem_box_of(x, BIG, lo, hi) == 0, "finite points flagged");
  CHECK(lo[2] == -1.0 && hi[0] == 12.0, "many points: z from %g (want -1), x to %g (want 12)", lo[2], hi[0]);
  x[3 * (BIG - 2) + 1] = NAN;
  CHECK(griddem_box_of(x, BIG, lo, hi) != 0, "a NaN among many points not flagged");
}

/* A grid kept while its points move inside it: griddem_grid_contains_box holds for boxes inside its
 * cells and fails one cell past any face, for another edge or anchor; points binned on a grid that
 * reaches further than theirs take the slots a grid fitted to them gives (cells in z, y, x order
 * whatever the extent), which is what lets a kept grid bin them again. */
static void check_kept_grid(void)
{
  enum { N = 1500 };
  static double x[3 * N];
  static int tag[N];
  for (int i = 0; i < N; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = 1.0 + 6.0 * check_uniform();
    tag[i] = (int) ((i * 7919L) % N) + 1;
  }
  const double anchor[3] = {0.1, -0.2, 0.3}, other[3] = {0.1, -0.2, 0.35}, h = 0.7;
  double lo[3], hi[3], wide_lo[3], wide_hi[3];
  griddem_box_of(x, N, lo, hi);
  for (int d = 0; d < 3; d++) wide_lo[d] = lo[d] - 1.5, wide_hi[d] = hi[d] + 1.5;
  griddem_grid fitted, wide;
  griddem_grid_fit(&fitted, anchor, lo, hi, h, 1L << 30);
  griddem_grid_fit(&wide, anchor, wide_lo, wide_hi, h, 1L << 30);
  int past = 0;
  for (int d = 0; d < 3; d++) {
    double up[3] = {hi[0], hi[1], hi[2]}, down[3] = {lo[0], lo[1], lo[2]};
    up[d] += h, down[d] -= h;
    past += griddem_grid_contains_box(&fitted, anchor, h, lo, up) + griddem_grid_contains_box(&fitted, anchor, h, down, hi);
  }
  CHECK(griddem_grid_contains_box(&fitted, anchor, h, lo, hi) && griddem_grid_contains_box(&wide, anchor, h, lo, hi) &&
            griddem_grid_contains_box(&wide, anchor, h, wide_lo, wide_hi) && past == 0 &&
            !griddem_grid_contains_box(&fitted, anchor, 0.75, lo, hi) && !griddem_grid_contains_box(&fitted, other, h, lo, hi),
        "a grid contains the boxes inside its cells only (%d one cell past a face), for its edge and anchor only", past);
  griddem_bins on_fitted = {0}, on_wide = {0};
  CHECK(griddem_bin_points(&on_fitted, &fitted, N, x, tag, 4) == 0 && griddem_bin_points(&on_wide, &wide, N, x, tag, 4) == 0,
        "binned on both grids");
  int same = wide.ncell > fitted.ncell;
  for (int s = 0; s < N; s++) same &= on_fitted.order[s] == on_wide.order[s];
  CHECK(same, "points binned on a grid of %ld cells take the slots of the %ld cells fitted to them", wide.ncell,
        fitted.ncell);
  griddem_bins_free(&on_fitted), griddem_bins_free(&on_wide);
  /* covered again: the wide grid is kept, a grid the points left is fitted to them */
  const long wide_cells = wide.ncell;
  griddem_grid moved = fitted;
  for (int i = 0; i < N; i++) x[3 * i + 2] += h;
  CHECK(griddem_grid_cover_again(&wide, anchor, N, x, h, 1L << 30) == 0 && wide.ncell == wide_cells &&
            griddem_grid_cover_again(&moved, anchor, N, x, h, 1L << 30) == 0 && moved.k0[2] == fitted.k0[2] + 1,
        "covered again: the wide grid kept (%ld cells), the fitted one moved up a cell (k0 %ld to %ld)", wide.ncell,
        fitted.k0[2], moved.k0[2]);
}

int main(void)
{
  /* the box and the cells by the AVX2 passes where this processor has them, then by the plain ones */
  for (int plain = 0; plain < 2; plain++) {
    griddem_touching_use(plain ? "scalar" : "auto");
    printf("the %s passes\n", griddem_vector_reads() ? "AVX2" : "plain-C");
    check_kept_grid();
    check_box_of();
    check_sparse();
    check_cell_sort();
    check_faces();
    check_moved(3000, 4);
    check_moved(3000, 8);
  }
  griddem_touching_use("auto");
#ifdef _OPENMP
  check_threaded();
  omp_set_num_threads(2);
  check_box_of();
  check_moved(2 * GRIDDEM_THREADED_MIN, 4);
  omp_set_num_threads(1);
#endif

  enum { N = 2000 };
  static double x[3 * N];
  static int tag[N];
  for (int i = 0; i < N; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = -3.0 + 7.0 * check_uniform();
    tag[i] = N - i; /* reverse of storage order */
  }
  const double anchor[3] = {0.1, -0.2, 0.3};
  griddem_grid g;
  griddem_bins b = {0};
  CHECK(griddem_grid_cover(&g, anchor, N, x, 0.5, 1L << 30) == 0, "no coarsening wanted");
  CHECK(g.n[0] == 15 || g.n[0] == 16, "cells along x: %d", g.n[0]);
  CHECK(griddem_bin_points(&b, &g, N, x, tag, 4) == 0, "binning");

  static int seen[N];
  static int count[16 * 16 * 16];
  int monotone = 1, in_cell = 1, keyed = 1;
  for (int s = 0; s < N; s++) seen[b.order[s]]++;
  int perm = 1;
  for (int i = 0; i < N; i++) perm &= seen[i] == 1;
  CHECK(perm, "order is a permutation");
  for (long c = 0; c < g.ncell; c++) {
    if (b.cell_start[c] > b.cell_start[c + 1]) monotone = 0;
    for (int s = b.cell_start[c]; s < b.cell_start[c + 1]; s++) {
      const int i = b.order[s];
      if (griddem_cell_of(&g, x[3 * i], x[3 * i + 1], x[3 * i + 2]) != c) in_cell = 0;
      if (s > b.cell_start[c] && tag[b.order[s - 1]] >= tag[i]) keyed = 0;
    }
  }
  CHECK(monotone && b.cell_start[g.ncell] == N, "cell_start is a prefix sum");
  CHECK(in_cell, "every slot lies in its cell");
  CHECK(keyed, "slots in a cell are in tag order");

  /* a cell's faces are at anchor + k*h: the point's cell follows from its coordinates alone */
  int aligned = 1;
  for (int i = 0; i < N; i++) {
    const long c = griddem_cell_of(&g, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    const long cx = c % g.n[0];
    const double face = anchor[0] + (double) (g.k0[0] + cx) * g.h;
    if (!(x[3 * i] >= face - 1e-12 && x[3 * i] < face + g.h + 1e-12)) aligned = 0;
    count[c]++;
  }
  CHECK(aligned, "cells aligned to the anchor");
  int most = 0;
  long occupied = 0;
  for (long c = 0; c < g.ncell; c++) {
    if (count[c] > most) most = count[c];
    if (count[c]) occupied++;
  }
  long occupied_binned;
  int most_binned;
  griddem_bins_occupancy(&b, &occupied_binned, &most_binned);
  CHECK(most_binned == most, "max occupancy %d vs %d", most_binned, most);
  CHECK(occupied_binned == occupied, "occupied %ld vs %ld", occupied_binned, occupied);

  /* two points far apart: the cap forces a coarser edge instead of a huge allocation */
  const double far[6] = {0.0, 0.0, 0.0, 1000.0, 1000.0, 1000.0};
  CHECK(griddem_grid_cover(&g, anchor, 2, far, 0.01, 1000000) == 1, "coarsened");
  CHECK(g.ncell <= 1000000 && g.h > 0.01, "ncell %ld h %g", g.ncell, g.h);

  /* stencil reach: NN4DEM's exact mode on equal spheres is the 5-wide stencil */
  const double h = griddem_cell_edge(GRIDDEM_CELL_EXACT, 1.0, 1.0, 0.0);
  CHECK_CLOSE(h, 2.0 / sqrt(3.0), 1e-15, 0.0);
  CHECK(2 * griddem_stencil_reach(h, 2.0) + 1 == 5, "stencil width");
  CHECK(2 * griddem_stencil_reach(griddem_cell_edge(GRIDDEM_CELL_MULTI, 1.0, 2.0, 0.0), 4.0) + 1 == 3,
        "multi-slot stencil width");

  /* the exact floor the cells are found with, against libm's */
  const double probes[] = {-2.5, -2.0, -1e-300, -0.0, 0.0, 1e-300, 0.5, 1.0, 3.9999999999999996, -3.0000000000000004, 1e15 + 0.5, -1e15 - 0.5};
  for (size_t k = 0; k < sizeof(probes) / sizeof(probes[0]); k++)
    CHECK(griddem_floor_index(probes[k]) == (long) floor(probes[k]), "floor of %.17g: %ld", probes[k],
          griddem_floor_index(probes[k]));

  /* output grids: a box of 4 x 2 x 5 cells from (-1, 0, 10), edges 0.5, 1.5, 0.2 */
  const double lo[3] = {-1.0, 0.0, 10.0}, prd[3] = {2.0, 3.0, 1.0};
  const int n[3] = {4, 2, 5};
  const double inside[3] = {0.26, 2.9, 10.61}, below[3] = {-3.0, -1.0, 9.0}, above[3] = {1.0, 3.0, 11.0};
  CHECK(griddem_box_cell(lo, prd, n, inside) == 2 + 4 * (1 + 2 * 3), "box cell of an inside point");
  CHECK(griddem_box_cell(lo, prd, n, below) == 0, "points below go to the first cell");
  CHECK(griddem_box_cell(lo, prd, n, above) == 4 * 2 * 5 - 1, "points on the upper faces go to the last cell");

  griddem_bins_free(&b);
  return check_summary();
}
