/* The candidate search kernels (griddem_search.h): each kernel this processor runs finds exactly
 * the pairs of a cluster's spheres and candidates of the documented test, in its order (run,
 * candidate, sphere), on random polydisperse scenes with random clusters, runs and own runs, and
 * on ties at the contact distance; spheres clearly inside or outside the contact distance are
 * found or not whatever the rounding; nothing is written past the pairs; every kernel has one
 * width (the same clusters); the widest kernel the processor runs is chosen. Each
 * of those checks runs twice: with every scene's spheres read as of any radii, and with scenes of
 * one radius marked so (same_radius), which the vector kernels test by another path.
 * griddem_touching_pairs with each kernel: the touching pairs of random polydisperse spheres binned
 * for their contacts, each query's in the documented order, against the pairs written out; a visit
 * that returns nonzero ends its sphere's pairs; spheres that are not queries get none. */
#include "check.h"
#include "griddem_search.h"
#include "griddem_touching_pairs.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NSPHERE 3000
#define MAX_RUNS 16
#define MAX_RUN 40
#define CANARY (-12345)

static const char *const KERNELS[] = {"scalar", "avx2", "avx512"};
static double X[NSPHERE], Y[NSPHERE], Z[NSPHERE], R[NSPHERE];
static float XF[NSPHERE + GRIDDEM_SEARCH_PAD], YF[NSPHERE + GRIDDEM_SEARCH_PAD], ZF[NSPHERE + GRIDDEM_SEARCH_PAD],
    RF[NSPHERE + GRIDDEM_SEARCH_PAD];

/* Whether spheres() marks spheres of one radius so, and how many times it did */
static int mark_same_radius;
static long marked_same_radius;

/* The spheres as the kernels read them: the float copies and the slack for their coordinates,
 * radii and reach; one radius marked where mark_same_radius */
static griddem_spheres spheres(double reach)
{
  double extent = 0.0, rmax = 0.0;
  int same = 1;
  for (int t = 0; t < NSPHERE; t++) {
    XF[t] = (float) X[t], YF[t] = (float) Y[t], ZF[t] = (float) Z[t], RF[t] = (float) R[t];
    extent = fmax(extent, fmax(fabs(X[t]), fmax(fabs(Y[t]), fabs(Z[t])))), rmax = fmax(rmax, R[t]);
    same &= R[t] == R[0];
  }
  griddem_spheres sp = {X, Y, Z, R, XF, YF, ZF, RF, (float) griddem_search_slack(extent, rmax, reach), 0, 0.0f, 0.0f};
  if (same && mark_same_radius) griddem_spheres_one_radius(&sp, reach);
  marked_same_radius += sp.same_radius;
  return sp;
}

/* The documented test, written out pair by pair (this file is built without contraction), in
 * the documented order: run by run, candidate by candidate, a candidate's spheres by k */
static int reference(double reach, int i0, int ni, int own, const int *lo, const int *hi, int nruns, int *sphere,
                     int *slot)
{
  int n = 0;
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t++)
      for (int k = 0; k < ni; k++) {
        const int i = i0 + k;
        if (own && q == 0 && t <= i) continue;
        const double dx = X[i] - X[t], dy = Y[i] - Y[t], dz = Z[i] - Z[t], s = (R[i] + reach) + R[t];
        const double d2 = (dx * dx + dy * dy) + dz * dz;
        if (d2 < s * s) sphere[n] = k, slot[n++] = t;
      }
  return n;
}

/* Room for a cluster's pairs, and a canary past what a kernel may write */
#define MAX_PAIRS (GRIDDEM_CLUSTER_MAX * MAX_RUNS * MAX_RUN + GRIDDEM_CLUSTER_MAX * NSPHERE)

/* Run kernel fn on a cluster and its runs; check its pairs against the reference's, in order, and
 * that it writes nothing past them. Returns the pairs found. */
static long compare(const char *name, griddem_touching_fn fn, double reach, int i0, int ni, int own, const int *lo,
                    const int *hi, int nruns)
{
  static int got_sphere[MAX_PAIRS + 1], got_slot[MAX_PAIRS + 1], want_sphere[MAX_PAIRS], want_slot[MAX_PAIRS];
  const int m = reference(reach, i0, ni, own, lo, hi, nruns, want_sphere, want_slot);
  got_sphere[m] = got_slot[m] = CANARY;
  const griddem_spheres sp = spheres(reach);
  griddem_cluster_hits hits = {got_sphere, got_slot, 0};
  fn(&sp, reach, i0, ni, own, lo, hi, nruns, &hits);
  CHECK(hits.n == m, "kernel %s: cluster of %d: %d pairs, reference %d", name, ni, hits.n, m);
  const size_t same = sizeof(int) * (size_t) (hits.n < m ? hits.n : m);
  CHECK(memcmp(got_sphere, want_sphere, same) == 0 && memcmp(got_slot, want_slot, same) == 0,
        "kernel %s: cluster of %d: other pairs or order", name, ni);
  CHECK(hits.n != m || (got_sphere[m] == CANARY && got_slot[m] == CANARY), "kernel %s wrote past its pairs", name);
  return hits.n;
}

/* A random cluster (its width at most the kernel's) with random runs (0..MAX_RUN long, at random
 * offsets) after it; with own, run 0 starts right after the cluster's first sphere (the sweep's
 * case) or, one time in four, anywhere from 8 slots before the cluster to 3 into it */
static int random_cluster(int width, int *i0, int *ni, int *own, int *lo, int *hi)
{
  *ni = 1 + (int) (check_uniform() * width);
  *i0 = 8 + (int) (check_uniform() * (NSPHERE - MAX_RUN - *ni - 16));
  *own = check_uniform() < 0.5;
  const int own_lo = *i0 + 1 + (check_uniform() < 0.25 ? (int) (check_uniform() * 12) - 9 : 0);
  const int nruns = (int) (check_uniform() * (MAX_RUNS + 1));
  for (int q = 0; q < nruns; q++) {
    const int len = (int) (check_uniform() * (MAX_RUN + 1));
    lo[q] = *own && q == 0 ? own_lo : (int) (check_uniform() * (NSPHERE - len));
    hi[q] = lo[q] + len;
  }
  return nruns;
}

/* Polydisperse spheres (radius ratio 1:10), every fourth scene of one radius, in boxes where a
 * sphere has tens of candidates in reach */
static void random_scenes(const char *name, griddem_touching_fn fn, int width)
{
  long found = 0, tested = 0;
  int lo[MAX_RUNS], hi[MAX_RUNS], i0, ni, own;
  for (int scene = 0; scene < 200; scene++) {
    const double box = 2.0 + 6.0 * check_uniform(), one = 0.05 + 0.45 * check_uniform();
    for (int t = 0; t < NSPHERE; t++) {
      X[t] = 100.0 + box * check_uniform(), Y[t] = -50.0 + box * check_uniform(), Z[t] = box * check_uniform();
      R[t] = scene % 4 == 0 ? one : 0.05 + 0.45 * check_uniform();
    }
    for (int probe = 0; probe < 50; probe++) {
      const int nruns = random_cluster(width, &i0, &ni, &own, lo, hi);
      found += compare(name, fn, probe % 3 == 0 ? 0.1 : 0.0, i0, ni, own, lo, hi, nruns);
      for (int q = 0; q < nruns; q++) tested += (long) ni * (hi[q] - lo[q]);
    }
  }
  CHECK(found > 1000 && found < tested / 2, "kernel %s: %ld touching of %ld tests (the scenes test both outcomes)",
        name, found, tested);
}

/* The cluster's spheres on one centre; the candidates at the contact distance exactly (not
 * touching: the test is strict) or one ulp inside it (touching), along each axis, in runs of
 * every length and alignment, for clusters of every size */
static void ties(const char *name, griddem_touching_fn fn, int width)
{
  const double c[3] = {1.0, 2.0, 3.0};
  for (int t = 0; t < NSPHERE; t++) R[t] = 0.25;
  for (int k = 0; k < width; k++) X[k] = c[0], Y[k] = c[1], Z[k] = c[2];
  for (int len = 0; len <= MAX_RUN; len++)
    for (int offset = width; offset < width + 9; offset++) {
      int expect = 0;
      for (int t = offset; t < offset + len; t++) {
        const int axis = t % 3, inside = (t / 3) % 2;
        double p[3] = {c[0], c[1], c[2]};
        p[axis] += 0.5; /* the contact distance 0.25 + 0.25, exact in these coordinates */
        if (inside) p[axis] = nextafter(p[axis], c[axis]);
        X[t] = p[0], Y[t] = p[1], Z[t] = p[2];
        expect += inside;
      }
      const int lo = offset, hi = offset + len;
      for (int ni = 1; ni <= width; ni++) /* every cluster size: each lays its lanes out its own way */
        CHECK(compare(name, fn, 0.0, 0, ni, 0, &lo, &hi, 1) == (long) ni * expect,
              "kernel %s: not %d ties inside found per sphere of %d (run %d at %d)", name, expect, ni, len, offset);
    }
}

/* Candidates in random directions within a few rounding errors of the contact distance, where
 * the order of the sum decides; around a centre near the origin, and far from it with small
 * spheres, where rounding the coordinates to float moves them by far more than their distances'
 * last bits (a float test without its slack misses some of the touching ones), and so far that
 * the slack exceeds the contact distance (no pair is then sure without its double test); clusters
 * of every size */
static void near_ties(const char *name, griddem_touching_fn fn, int width)
{
  const double centres[3][3] = {{0.3, -0.7, 1.1}, {4321.7, -8765.3, 1234.9}, {1.0e6, -2.0e6, 3.0e6}};
  const double radii[3] = {0.5, 0.01, 0.01};
  for (int scene = 0; scene < 3; scene++) {
    const double *c = centres[scene], r = radii[scene];
    for (int k = 0; k < width; k++) X[k] = c[0], Y[k] = c[1], Z[k] = c[2], R[k] = r;
    for (int t = width; t < NSPHERE; t++) {
      const double u = 2.0 * check_uniform() - 1.0, phi = 6.283185307179586 * check_uniform();
      const double d = 2.0 * r * (1.0 + (double) (t % 9 - 4) * 2.220446049250313e-16);
      X[t] = c[0] + d * sqrt(1.0 - u * u) * cos(phi), Y[t] = c[1] + d * sqrt(1.0 - u * u) * sin(phi), Z[t] = c[2] + d * u;
      R[t] = r;
    }
    const int lo = width, hi = NSPHERE;
    for (int ni = 1; ni <= width; ni++) {
      const long n = compare(name, fn, 0.0, 0, ni, 0, &lo, &hi, 1);
      CHECK(n > ni * (NSPHERE / 10) && n < ni * (NSPHERE - NSPHERE / 10),
            "kernel %s: %ld near ties touch %d spheres at (%g, %g, %g) (both outcomes expected)", name, n, ni, c[0], c[1],
            c[2]);
    }
  }
}

/* Every sphere at the origin, where a lane loaded as zero would touch too: each sphere of a
 * cluster counts exactly the slots of the runs (after itself in an own run); then candidates
 * clearly inside and clearly outside, decided without regard to rounding */
static void run_ends_and_margins(const char *name, griddem_touching_fn fn, int width)
{
  int lo[MAX_RUNS], hi[MAX_RUNS], i0, ni, own;
  for (int t = 0; t < NSPHERE; t++) X[t] = Y[t] = Z[t] = 0.0, R[t] = 0.1;
  for (int probe = 0; probe < 2000; probe++) {
    const int nruns = random_cluster(width, &i0, &ni, &own, lo, hi);
    long total = 0;
    for (int k = 0; k < ni; k++)
      for (int q = 0; q < nruns; q++) {
        const int from = own && q == 0 && lo[q] < i0 + k + 1 ? i0 + k + 1 : lo[q];
        total += hi[q] > from ? hi[q] - from : 0;
      }
    CHECK(compare(name, fn, 0.0, i0, ni, own, lo, hi, nruns) == total, "kernel %s: not every slot of the runs counted", name);
  }
  for (int t = width; t < NSPHERE; t++) {
    const double d = 0.2 * (t % 2 ? 1.001 : 0.999), u = 2.0 * check_uniform() - 1.0, phi = 6.283185307179586 * check_uniform();
    X[t] = d * sqrt(1.0 - u * u) * cos(phi), Y[t] = d * sqrt(1.0 - u * u) * sin(phi), Z[t] = d * u;
  }
  static int sphere[MAX_PAIRS], slot[MAX_PAIRS];
  griddem_cluster_hits hits = {sphere, slot, 0};
  const griddem_spheres sp = spheres(0.0);
  const int lo0 = width, hi0 = NSPHERE;
  fn(&sp, 0.0, 0, width, 0, &lo0, &hi0, 1, &hits);
  for (int k = 0; k < width; k++) {
    int n = 0, ok = 1;
    for (int j = 0; j < hits.n; j++)
      if (sphere[j] == k) n++, ok &= slot[j] % 2 == 0;
    CHECK(ok && n == (NSPHERE - width) / 2,
          "kernel %s: sphere %d: %d found; those at 0.999 of the contact distance expected, none at 1.001", name, k, n);
  }
}

/* griddem_touching_pairs: the visits, in order */
#define NPAIRS_MAX 200000
typedef struct pair_log {
  int n, i[NPAIRS_MAX], j[NPAIRS_MAX];
} pair_log;

static pair_log got_pairs, want_pairs;

static int log_pair(void *ctx, int i, int j)
{
  pair_log *log = (pair_log *) ctx;
  if (log->n < NPAIRS_MAX) log->i[log->n] = i, log->j[log->n] = j;
  log->n++;
  return i % 3 == 0;    /* every third sphere's pairs end at its first */
}

static void touching_pairs(const char *name)
{
  static double x[3 * NSPHERE], radius[NSPHERE];
  static int query[NSPHERE];
  griddem_grid g = {0};
  griddem_bins b = {0};
  griddem_stencil stencil;
  long pairs = 0;
  for (int scene = 0; scene < 20; scene++) {
    const int n = NSPHERE / 2 + (int) (check_uniform() * NSPHERE / 2), nquery = n - n / 4;
    const double box = 4.0 + 4.0 * check_uniform();
    for (int t = 0; t < n; t++) {
      x[3 * t] = -3.0 + box * check_uniform();
      x[3 * t + 1] = box * check_uniform();
      x[3 * t + 2] = box * check_uniform();
      radius[t] = 0.02 + (scene % 2 ? 0.4 : 0.1) * check_uniform();
      query[t] = check_uniform() < 0.8;
    }
    CHECK(griddem_bin_for_contacts(&g, &b, &stencil, n, x, radius) == 0, "scene %d binned", scene);
    got_pairs.n = 0;
    CHECK(griddem_touching_pairs(&g, &b, &stencil, x, radius, nquery, query, log_pair, &got_pairs) == 0,
          "kernel %s: scene %d searched", name, scene);
    /* written out: the queries in slot order, each one's partners along the stencil's runs */
    want_pairs.n = 0;
    int lo[GRIDDEM_STENCIL_MAX_ROWS], hi[GRIDDEM_STENCIL_MAX_ROWS];
    for (int t = 0; t < n; t++) {
      const int i = b.order[t];
      if (i >= nquery || !query[i]) continue;
      const int nruns = griddem_stencil_runs(&stencil, &g, &b, b.cell[i], lo, hi);
      int stop = 0;
      for (int q = 0; q < nruns && !stop; q++)
        for (int u = lo[q]; u < hi[q] && !stop; u++) {
          const int j = b.order[u];
          const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
          const double s = radius[i] + radius[j];
          if (j != i && (dx * dx + dy * dy) + dz * dz < s * s) stop = log_pair(&want_pairs, i, j);
        }
    }
    int same = got_pairs.n == want_pairs.n && want_pairs.n <= NPAIRS_MAX;
    for (int k = 0; same && k < want_pairs.n; k++)
      same = got_pairs.i[k] == want_pairs.i[k] && got_pairs.j[k] == want_pairs.j[k];
    CHECK(same, "kernel %s: scene %d: %d visits, %d written out", name, scene, got_pairs.n, want_pairs.n);
    pairs += want_pairs.n;
  }
  CHECK(pairs > 10000, "kernel %s: %ld pairs visited (the scenes touch)", name, pairs);
  griddem_bins_free(&b);
}

int main(void)
{
  /* the widest kernel the processor runs is the one the sweep uses */
  const char *widest = griddem_touching_kernel("avx512") ? "avx512" : (griddem_touching_kernel("avx2") ? "avx2" : "scalar");
  CHECK(strcmp(griddem_touching_name(), widest) == 0, "chosen %s, widest %s", griddem_touching_name(), widest);
  CHECK(griddem_touching_use("sse9") != 0 && griddem_touching_kernel("sse9") == NULL, "unknown kernel name accepted");
  CHECK(griddem_touching_kernel("scalar") != NULL, "no plain-C kernel");
  for (size_t k = 0; k < sizeof(KERNELS) / sizeof(KERNELS[0]); k++) {
    griddem_touching_fn fn = griddem_touching_kernel(KERNELS[k]);
    const int width = griddem_touching_kernel_width(KERNELS[k]);
    if (!fn) {
      printf("kernel %s: not run by this processor\n", KERNELS[k]);
      continue;
    }
    CHECK(width == GRIDDEM_CLUSTER_MAX, "kernel %s: width %d", KERNELS[k], width);
    const int failed = check_failed;
    for (mark_same_radius = 0; mark_same_radius < 2; mark_same_radius++) {
      marked_same_radius = 0;
      random_scenes(KERNELS[k], fn, width);
      ties(KERNELS[k], fn, width);
      near_ties(KERNELS[k], fn, width);
      run_ends_and_margins(KERNELS[k], fn, width);
      CHECK(mark_same_radius ? marked_same_radius > 1000 : marked_same_radius == 0,
            "kernel %s: %ld calls on spheres marked of one radius", KERNELS[k], marked_same_radius);
    }
    CHECK(griddem_touching_use(KERNELS[k]) == 0, "kernel %s not chosen", KERNELS[k]);
    touching_pairs(KERNELS[k]);
    CHECK(griddem_touching_use(KERNELS[k]) == 0 && griddem_touching() == fn && griddem_touching_width() == width &&
              strcmp(griddem_touching_name(), KERNELS[k]) == 0, "kernel %s not made the sweep's", KERNELS[k]);
    printf("kernel %s (width %d): %d failed\n", KERNELS[k], width, check_failed - failed);
  }
  return check_summary();
}
