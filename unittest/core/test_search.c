/* The candidate search kernels (griddem_search.h): each kernel this processor runs finds, on
 * random polydisperse scenes and on ties at the contact distance, exactly the slots of the
 * documented test in run order; spheres clearly inside or outside the contact distance are
 * found or not whatever the rounding; lanes past a run are never counted; nothing is written
 * past the returned slots' room; the widest kernel the processor runs is the one chosen. */
#include "check.h"
#include "griddem_search.h"

#include <stdlib.h>
#include <string.h>

#define NSPHERE 3000
#define MAX_RUNS 16
#define MAX_RUN 40
#define CANARY (-12345)

static const char *const KERNELS[] = {"scalar", "avx2", "avx512"};
static double X[NSPHERE], Y[NSPHERE], Z[NSPHERE], R[NSPHERE];

/* The documented test, written out pair by pair (this file is built without contraction) */
static int reference(const double *c, const int *lo, const int *hi, int nruns, int *slot)
{
  int n = 0;
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t++) {
      const double dx = c[0] - X[t], dy = c[1] - Y[t], dz = c[2] - Z[t], s = c[3] + R[t];
      const double d2 = (dx * dx + dy * dy) + dz * dz;
      if (d2 < s * s) slot[n++] = t;
    }
  return n;
}

/* Run kernel fn on the runs; check its slots against the reference's and its writes against the
 * room it was given. Returns the count. */
static int compare(const char *name, griddem_touching_fn fn, const double *c, const int *lo, const int *hi,
                   int nruns, int *expect_n)
{
  static int got[NSPHERE + GRIDDEM_SEARCH_SLACK + 8], want[NSPHERE];
  const griddem_spheres sp = {X, Y, Z, R};
  int total = 0;
  for (int q = 0; q < nruns; q++) total += hi[q] - lo[q];
  for (size_t k = 0; k < sizeof(got) / sizeof(got[0]); k++) got[k] = CANARY;
  const int n = fn(&sp, c, lo, hi, nruns, got), m = reference(c, lo, hi, nruns, want);
  CHECK(n == m, "kernel %s: %d slots, reference %d", name, n, m);
  CHECK(memcmp(got, want, sizeof(int) * (size_t) (n < m ? n : m)) == 0, "kernel %s: other slots or order", name);
  int untouched = 1;
  for (size_t k = (size_t) total + GRIDDEM_SEARCH_SLACK; k < sizeof(got) / sizeof(got[0]); k++)
    untouched &= got[k] == CANARY;
  CHECK(untouched, "kernel %s wrote past its room (%d candidates)", name, total);
  *expect_n = m;
  return n;
}

/* Random runs of random lengths (0..MAX_RUN) at random offsets */
static int random_runs(int *lo, int *hi)
{
  const int nruns = (int) (check_uniform() * (MAX_RUNS + 1));
  for (int q = 0; q < nruns; q++) {
    const int len = (int) (check_uniform() * (MAX_RUN + 1));
    lo[q] = (int) (check_uniform() * (NSPHERE - len));
    hi[q] = lo[q] + len;
  }
  return nruns;
}

/* Polydisperse spheres (radius ratio 1:10) in a box where a centre has tens of candidates in
 * reach; centres of the scene's spheres and of random points */
static void random_scenes(const char *name, griddem_touching_fn fn)
{
  long found = 0, tested = 0;
  int lo[MAX_RUNS], hi[MAX_RUNS];
  for (int scene = 0; scene < 200; scene++) {
    const double box = 2.0 + 6.0 * check_uniform();
    for (int t = 0; t < NSPHERE; t++) {
      X[t] = 100.0 + box * check_uniform(), Y[t] = -50.0 + box * check_uniform(), Z[t] = box * check_uniform();
      R[t] = 0.05 + 0.45 * check_uniform();
    }
    for (int probe = 0; probe < 50; probe++) {
      const int nruns = random_runs(lo, hi);
      const int a = (int) (check_uniform() * NSPHERE);
      const double c[4] = {probe % 2 ? X[a] : 100.0 + box * check_uniform(), Y[a], Z[a],
                           R[a] + (probe % 3 == 0 ? 0.1 : 0.0)};
      int m;
      found += compare(name, fn, c, lo, hi, nruns, &m);
      for (int q = 0; q < nruns; q++) tested += hi[q] - lo[q];
    }
  }
  CHECK(found > 1000 && found < tested, "kernel %s: %ld touching of %ld candidates (the scenes test both outcomes)",
        name, found, tested);
}

/* Spheres at the contact distance exactly (not touching: the test is strict) and one ulp inside
 * it (touching), along each axis and in runs of every length and alignment */
static void ties(const char *name, griddem_touching_fn fn)
{
  const double c[4] = {1.0, 2.0, 3.0, 0.25};
  for (int len = 0; len <= 2 * MAX_RUN && len < NSPHERE; len++)
    for (int offset = 0; offset < 9; offset++) {
      int expect = 0;
      for (int t = offset; t < offset + len; t++) {
        const int axis = t % 3, inside = (t / 3) % 2;
        double p[3] = {c[0], c[1], c[2]};
        p[axis] += 0.5; /* the contact distance 0.25 + 0.25, exact in these coordinates */
        if (inside) p[axis] = nextafter(p[axis], c[axis]);
        X[t] = p[0], Y[t] = p[1], Z[t] = p[2], R[t] = 0.25;
        expect += inside;
      }
      const int lo = offset, hi = offset + len;
      int m;
      const int n = compare(name, fn, c, &lo, &hi, len > MAX_RUN ? 0 : 1, &m);
      if (len <= MAX_RUN) CHECK(n == expect, "kernel %s: %d of %d ties inside found (run %d at %d)", name, n, expect, len, offset);
    }
}

/* Spheres in random directions within a few rounding errors of the contact distance, where the
 * order of the sum decides: every kernel agrees with the reference */
static void near_ties(const char *name, griddem_touching_fn fn)
{
  const double c[4] = {0.3, -0.7, 1.1, 0.5};
  for (int t = 0; t < NSPHERE; t++) {
    const double u = 2.0 * check_uniform() - 1.0, phi = 6.283185307179586 * check_uniform();
    const double d = 1.0 * (1.0 + (double) (t % 9 - 4) * 2.220446049250313e-16);
    X[t] = c[0] + d * sqrt(1.0 - u * u) * cos(phi), Y[t] = c[1] + d * sqrt(1.0 - u * u) * sin(phi), Z[t] = c[2] + d * u;
    R[t] = 0.5;
  }
  const int lo = 0, hi = NSPHERE;
  int m;
  const int n = compare(name, fn, c, &lo, &hi, 1, &m);
  CHECK(n > NSPHERE / 10 && n < NSPHERE - NSPHERE / 10, "kernel %s: %d of %d near ties touch (both outcomes expected)",
        name, n, NSPHERE);
}

/* Every sphere on the centre, at the origin, where a lane loaded as zero would touch too: a kernel
 * counts exactly the slots of the runs, whatever lies past their ends; clearly inside and clearly
 * outside are decided without regard to rounding */
static void run_ends_and_margins(const char *name, griddem_touching_fn fn)
{
  int lo[MAX_RUNS], hi[MAX_RUNS];
  const double c[4] = {0.0, 0.0, 0.0, 0.1};
  for (int t = 0; t < NSPHERE; t++) X[t] = c[0], Y[t] = c[1], Z[t] = c[2], R[t] = 0.1;
  for (int probe = 0; probe < 2000; probe++) {
    const int nruns = random_runs(lo, hi);
    int total = 0, m;
    for (int q = 0; q < nruns; q++) total += hi[q] - lo[q];
    CHECK(compare(name, fn, c, lo, hi, nruns, &m) == total, "kernel %s: not every slot of the runs counted", name);
  }
  for (int t = 0; t < NSPHERE; t++) {
    const double d = 0.2 * (t % 2 ? 1.001 : 0.999), u = 2.0 * check_uniform() - 1.0, phi = 6.283185307179586 * check_uniform();
    X[t] = c[0] + d * sqrt(1.0 - u * u) * cos(phi), Y[t] = c[1] + d * sqrt(1.0 - u * u) * sin(phi), Z[t] = c[2] + d * u;
  }
  const griddem_spheres sp = {X, Y, Z, R};
  static int got[NSPHERE + GRIDDEM_SEARCH_SLACK];
  const int lo0 = 0, hi0 = NSPHERE;
  const int n = fn(&sp, c, &lo0, &hi0, 1, got);
  int ok = n == NSPHERE / 2;
  for (int k = 0; ok && k < n; k++) ok = got[k] == 2 * k;
  CHECK(ok, "kernel %s: %d found; the %d spheres at 0.999 of the contact distance expected, none at 1.001", name, n,
        NSPHERE / 2);
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
    if (!fn) {
      printf("kernel %s: not run by this processor\n", KERNELS[k]);
      continue;
    }
    const int failed = check_failed;
    random_scenes(KERNELS[k], fn);
    ties(KERNELS[k], fn);
    near_ties(KERNELS[k], fn);
    run_ends_and_margins(KERNELS[k], fn);
    CHECK(griddem_touching_use(KERNELS[k]) == 0 && griddem_touching() == fn &&
              strcmp(griddem_touching_name(), KERNELS[k]) == 0, "kernel %s not made the sweep's", KERNELS[k]);
    printf("kernel %s: %d failed\n", KERNELS[k], check_failed - failed);
  }
  return check_summary();
}
