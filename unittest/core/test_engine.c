/* The engine's face: a step bins, sweeps and points each owned particle at its new row of the
 * history it is given; rows travel as messages (count, then tag and values per contact) that
 * put_message takes back unchanged, also across a change of values per contact; the longest
 * message is known; the step's statistics count contacts, the fastest motion and non-finite
 * velocities; the scan's box and speeds by the AVX2 passes (griddem_vector_reads) and the plain ones. */
#include "check.h"
#include "complete_history.h"
#include "griddem_engine.h"
#include "griddem_search.h"
#include "griddem_threads.h"
#include "spec_text.h"

#ifdef _OPENMP
#include <omp.h>
#endif

/* What a layout costs (griddem_engine_candidates). One grid of multi's edge: the sweep's forward
 * half of the 27 cells, so every unordered pair in neighbouring cells (Chebyshev distance 1) is
 * a candidate once, counted here pair by pair. A 1:100 scene (one large sphere and a cloud of
 * small ones): multi's cells sized for the large one hold the whole cloud, a grid per size class
 * does not, which is what the pair styles warn about. */
static void candidates(const griddem_model *m)
{
  enum { N = 400 };
  static double x[3 * N], v[3 * N], w[3 * N], rad[N], mass[N];
  static int tag[N], type[N], mask[N];
  for (int i = 0; i < N; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = 6.0 * check_uniform(), v[3 * i + d] = w[3 * i + d] = 0.0;
    rad[i] = 0.1 + 0.4 * check_uniform(), mass[i] = 1.0, tag[i] = i + 1, type[i] = 1, mask[i] = 1;
  }
  griddem_particles part = {.nlocal = N, .nall = N, .x = x, .v = v, .omega = w, .radius = rad,
      .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  griddem_step s;
  memset(&s, 0, sizeof(s));
  s.particles = part, s.model = m, s.rmin = 0.1, s.rmax = 0.5, s.max_cells = 1000000;
  s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_MULTI, s.rmin, s.rmax, 0.0);
  griddem_engine e;
  griddem_engine_init(&e);
  const double counted = griddem_engine_candidates(&e, &s);
  long pairs = 0;
  for (int i = 0; i < N; i++)
    for (int j = i + 1; j < N; j++) {
      int near = 1;
      for (int d = 0; d < 3; d++) {
        const long ci = (long) floor(x[3 * i + d] / s.cell_edge), cj = (long) floor(x[3 * j + d] / s.cell_edge);
        near = near && labs(ci - cj) <= 1;
      }
      pairs += near;
    }
  CHECK(counted == (double) pairs, "multi: %g candidates counted, %ld pairs in neighbouring cells", counted, pairs);

  /* 1:100: the large sphere at the centre, the small ones (radius 0.1) around it */
  rad[0] = 10.0;
  for (int d = 0; d < 3; d++) x[d] = 3.0;
  for (int i = 1; i < N; i++) rad[i] = 0.1;
  s.rmin = 0.1, s.rmax = 10.0;
  s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_MULTI, s.rmin, s.rmax, 0.0);
  const double multi = griddem_engine_candidates(&e, &s);
  CHECK(multi == 0.5 * N * (N - 1) && e.stats.max_occupancy == N, "multi 1:100: one cell holds all %d (%d), every pair a candidate (%g)",
        N, e.stats.max_occupancy, multi);
  s.size_classes = 1;
  s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_AUTO, s.rmin, s.rmax, 0.0);
  const double classes = griddem_engine_candidates(&e, &s);
  /* the small spheres' class grid of edge 0.2 over the 6^3 box: about 400 / 27000 per cell, so
     each tests a few neighbours and the large sphere's cells */
  CHECK(classes > 0.0 && classes < multi / 8.0 && e.stats.max_occupancy < 16,
        "auto 1:100: %g candidates (multi %g), at most %d in a cell", classes, multi, e.stats.max_occupancy);
  griddem_engine_free(&e);
}

/* The periodic images of owned particles 0 .. nown - 1 (box [0, L) on each axis) that lie within
 * shell of the box, appended after them as ghosts: positions, radii and each ghost's owned
 * particle (owner, 0 .. nown - 1). Returns the particle count. */
static int add_images(double *x, double *rad, int *owner, int nown, double L, double shell)
{
  int n = nown;
  for (int sx = -1; sx <= 1; sx++)
    for (int sy = -1; sy <= 1; sy++)
      for (int sz = -1; sz <= 1; sz++)
        for (int i = 0; i < nown && (sx || sy || sz); i++) {
          const double y[3] = {x[3 * i] + sx * L, x[3 * i + 1] + sy * L, x[3 * i + 2] + sz * L};
          int inside = 1;
          for (int d = 0; d < 3; d++) inside &= y[d] >= -shell && y[d] < L + shell;
          if (!inside) continue;
          for (int d = 0; d < 3; d++) x[3 * n + d] = y[d];
          rad[n] = rad[i], owner[n++] = i;
        }
  for (int i = 0; i < nown; i++) owner[i] = i;
  return n;
}

/* Each owned particle's (0 .. nown - 1) force from Hooke springs of stiffness kn with every particle
 * it overlaps, summed directly into fref (zeroed first); returns the contacts, those with particle
 * j into *with_j */
static long direct_hooke(const double *x, const double *rad, int nown, int n, double kn, int j_counted, long *with_j,
                         double *fref)
{
  long contacts = 0;
  *with_j = 0;
  for (int k = 0; k < 3 * nown; k++) fref[k] = 0.0;
  for (int i = 0; i < nown; i++)
    for (int j = 0; j < n; j++) {
      const double dx[3] = {x[3 * i] - x[3 * j], x[3 * i + 1] - x[3 * j + 1], x[3 * i + 2] - x[3 * j + 2]};
      const double r = sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]);
      if (j == i || r >= rad[i] + rad[j]) continue;
      contacts++, *with_j += j == j_counted;
      for (int d = 0; d < 3; d++) fref[3 * i + d] += kn * (rad[i] + rad[j] - r) * dx[d] / r;
    }
  return contacts;
}

/* The largest difference of the first m values of f from fref's, and fref's largest magnitude */
static double largest_difference(const double *f, const double *fref, int m, double *largest)
{
  double worst = 0.0;
  *largest = 0.0;
  for (int k = 0; k < m; k++) {
    worst = fabs(f[k] - fref[k]) > worst ? fabs(f[k] - fref[k]) : worst;
    *largest = fabs(fref[k]) > *largest ? fabs(fref[k]) : *largest;
  }
  return worst;
}

/* Ghosts as a process holds them: the periodic images of a box of owned particles in a shell as
 * thick as LAMMPS's ghost cutoff (the longest contact distance and a skin). A ghost's pairs with
 * other ghosts are not evaluated, so the sweep tests only its owned candidates; every owned
 * particle's force (Hooke springs between particles at rest) and contacts are still those of a
 * direct sum over every pair with an owned particle, through the shell's faces, edges and corners,
 * on one grid and with size classes (pairs across classes found from either class). */
static void ghost_shell(const griddem_model *m, int size_classes)
{
  enum { NOWN = 300, NMAX = 27 * NOWN };
  const double L = 5.0, kn = 1e3;
  static double x[3 * NMAX], v[3 * NMAX], w[3 * NMAX], rad[NMAX], mass[NMAX], f[3 * NMAX], t[3 * NMAX], fref[3 * NMAX];
  static int tag[NMAX], type[NMAX], mask[NMAX], row_of[NMAX], owner[NMAX];
  double rmin = 1e30, rmax = 0.0;
  for (int i = 0; i < NOWN; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = L * check_uniform();
    rad[i] = i % 10 == 0 ? 0.6 + 0.1 * check_uniform() : 0.15 + 0.1 * check_uniform();
    rmin = rad[i] < rmin ? rad[i] : rmin, rmax = rad[i] > rmax ? rad[i] : rmax;
  }
  const int n = add_images(x, rad, owner, NOWN, L, 2.0 * rmax + 0.1);
  for (int i = 0; i < n; i++) {
    for (int d = 0; d < 3; d++) v[3 * i + d] = w[3 * i + d] = f[3 * i + d] = t[3 * i + d] = fref[3 * i + d] = 0.0;
    mass[i] = 1.0, tag[i] = i % NOWN + 1, type[i] = 1, mask[i] = 1, row_of[i] = -1;
  }
  long none;
  const long contacts = direct_hooke(x, rad, NOWN, n, kn, -1, &none, fref);
  griddem_history h;
  griddem_history_init(&h, 3);
  griddem_particles part = {.nlocal = NOWN, .nall = n, .x = x, .v = v, .omega = w, .radius = rad,
      .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  griddem_step s;
  memset(&s, 0, sizeof(s));
  s.particles = part, s.model = m, s.rmin = rmin, s.rmax = rmax, s.max_cells = 1L << 24, s.size_classes = size_classes;
  s.cell_edge = griddem_cell_edge(size_classes ? GRIDDEM_CELL_AUTO : GRIDDEM_CELL_MULTI, rmin, rmax, 0.0);
  s.dt = 1e-4, s.history_update = 1, s.hist = &h, s.row_of = row_of, s.f = f, s.torque = t;
  griddem_engine e;
  griddem_engine_init(&e);
  griddem_sweep_result r;
  int coarsened;
  CHECK(griddem_engine_step(&e, &s, &r, &coarsened) == GRIDDEM_FAULT_NONE, "ghost shell: step runs");
  double largest;
  const double worst = largest_difference(f, fref, 3 * NOWN, &largest);
  CHECK(n > 2 * NOWN && e.ngrid == (size_classes ? 2 : 1) && e.stats.contacts == contacts && worst <= 1e-12 * largest,
        "ghost shell (%d grids): %d owned, %d ghosts; contacts %ld (direct sum %ld); largest force difference %g of %g",
        e.ngrid, NOWN, n - NOWN, e.stats.contacts, contacts, worst, largest);
  griddem_engine_free(&e);
  griddem_history_free(&h);
}

/* Size classes held while the host keeps the same particles (same_particles, fixed radii and a
 * ghost margin, as LAMMPS's skin): over steps that move every particle by less than half the
 * margin, each owned particle's force and contacts are a direct sum's over every pair with an
 * owned particle, the same particles stay in the grids (binned again), and a ghost that was out of
 * reach when they were gathered but comes into contact later is found. Returns 1 where every step's
 * forces and contacts are right (without the margin, margin 0, G's contact is missed). */
static int held_classes(const griddem_model *m, double margin)
{
  enum { NOWN = 300, NMAX = 27 * NOWN + 1, STEPS = 4 };
  const double L = 5.0, kn = 1e3, big = 0.7, small = 0.15;
  static double x[3 * NMAX], v[3 * NMAX], w[3 * NMAX], rad[NMAX], mass[NMAX], f[3 * NMAX], t[3 * NMAX];
  static double fref[3 * NMAX], move[3 * NOWN];
  static int tag[NMAX], type[NMAX], mask[NMAX], row_of[NMAX], owner[NMAX];
  /* owned particle 0 (big) at the box's lowest x, ghost G (small) of another process 0.95 from
     it, 0.1 past the 0.85 that a contact with it reaches; the two close in by 0.08 each at step 1 */
  for (int i = 0; i < NOWN; i++) {
    x[3 * i] = 0.1 + 4.8 * check_uniform(), x[3 * i + 1] = L * check_uniform(), x[3 * i + 2] = L * check_uniform();
    rad[i] = i % 10 == 0 ? big : small;
  }
  x[0] = 0.05, x[1] = x[2] = 2.5;
  int n = add_images(x, rad, owner, NOWN, L, 2.0 * big + margin + 0.1);
  for (int i = 0; i < n; i++) tag[i] = owner[i] + 1;
  const int g = n++;    /* G */
  x[3 * g] = x[0] - (big + small + 0.1), x[3 * g + 1] = x[1], x[3 * g + 2] = x[2];
  rad[g] = small, tag[g] = 100000, owner[g] = -1;
  for (int i = 0; i < n; i++) {
    for (int d = 0; d < 3; d++) v[3 * i + d] = w[3 * i + d] = 0.0;
    mass[i] = 1.0, type[i] = 1, mask[i] = 1, row_of[i] = -1;
  }
  griddem_history h;
  griddem_history_init(&h, 3);
  griddem_particles part = {.nlocal = NOWN, .nall = n, .x = x, .v = v, .omega = w, .radius = rad,
      .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  griddem_step s;
  memset(&s, 0, sizeof(s));
  s.particles = part, s.model = m, s.rmin = small, s.rmax = big, s.max_cells = 1L << 24, s.size_classes = 1;
  s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_AUTO, small, big, 0.0);
  s.dt = 1e-4, s.history_update = 1, s.hist = &h, s.row_of = row_of, s.f = f, s.torque = t;
  s.fixed_radii = 1, s.ghost_margin = margin;
  griddem_engine e;
  griddem_engine_init(&e);
  int held = -1, same_slots = 1, found_g = 0, right = 1;
  for (int step = 0; step < STEPS; step++) {
    s.same_particles = step > 0;
    if (step > 0) {    /* every owned particle (and its images) moves by at most 0.025 an axis */
      for (int i = 0; i < NOWN; i++)
        for (int d = 0; d < 3; d++) move[3 * i + d] = 0.025 * (2.0 * check_uniform() - 1.0);
      move[0] = step == 1 ? -0.08 : 0.0, move[1] = move[2] = 0.0;    /* particle 0: toward G once */
      for (int i = 0; i < n; i++)
        for (int d = 0; d < 3; d++) x[3 * i + d] += owner[i] >= 0 ? move[3 * owner[i] + d] : (step == 1 && d == 0 ? 0.08 : 0.0);
    }
    for (int k = 0; k < 3 * n; k++) f[k] = t[k] = 0.0;
    long with_g;
    const long contacts = direct_hooke(x, rad, NOWN, n, kn, g, &with_g, fref);
    griddem_sweep_result r;
    int coarsened;
    CHECK(griddem_engine_step(&e, &s, &r, &coarsened) == GRIDDEM_FAULT_NONE, "held classes: step runs");
    double largest;
    const double worst = largest_difference(f, fref, 3 * NOWN, &largest);
    int slots = 0;
    for (int c = 0; c < e.ngrid; c++) slots += e.bins[c].n;
    if (step == 0) held = slots;
    same_slots &= slots == held;
    found_g += with_g > 0;
    right &= e.stats.contacts == contacts && worst <= 1e-12 * largest;
    if (!(e.stats.contacts == contacts && worst <= 1e-12 * largest))
      printf("# margin %g, step %d: contacts %ld (direct sum %ld, %ld with G); largest force difference %g of %g\n",
             margin, step, e.stats.contacts, contacts, with_g, worst, largest);
  }
  CHECK(e.ngrid == 2 && e.gathered && same_slots && found_g == STEPS - 1,
        "held classes (margin %g): %d grids held, the same %d slots every step (%d), G in contact at %d of %d steps",
        margin, e.ngrid, held, same_slots, found_g, STEPS - 1);
  griddem_engine_free(&e);
  griddem_history_free(&h);
  return right;
}

#ifdef _OPENMP
/* the scan of GRIDDEM_THREADED_MIN particles and more on two threads (min, max and sum
 * reductions): one thread's box, fastest speed and radius range; a NaN and an infinite speed
 * still found */
static void scan_threaded(void)
{
  enum { N = 3 * GRIDDEM_THREADED_MIN };
  static double x[3 * N], v[3 * N], rad[N];
  for (int i = 0; i < 3 * N; i++) x[i] = -7.0 + 20.0 * check_uniform(), v[i] = -2.0 + 4.0 * check_uniform();
  for (int i = 0; i < N; i++) rad[i] = 0.1 + check_uniform();
  griddem_particles part = {.nlocal = N - 1000, .nall = N, .x = x, .v = v, .radius = rad,
      .tag_bytes = 4};
  griddem_scan one, two;
  omp_set_num_threads(1);
  griddem_engine_scan(&part, 1, &one);
  omp_set_num_threads(2);
  griddem_engine_scan(&part, 1, &two);
  int same = one.vmax2 == two.vmax2 && one.rmin == two.rmin && one.rmax == two.rmax &&
             one.first_nonfinite == -1 && two.first_nonfinite == -1 && !two.nonfinite_velocity;
  for (int d = 0; d < 3; d++) same &= one.lo[d] == two.lo[d] && one.hi[d] == two.hi[d];
  CHECK(same, "two threads scan %d particles as one: box x %g..%g, speed^2 %g, radii %g..%g", N, two.lo[0],
        two.hi[0], two.vmax2, two.rmin, two.rmax);
  x[3 * 40000 + 1] = NAN, v[3 * 30000 + 2] = INFINITY;
  griddem_engine_scan(&part, 1, &two);
  CHECK(two.first_nonfinite == 40000 && two.nonfinite_velocity, "two threads find the NaN position (%d) and the "
        "infinite speed", two.first_nonfinite);
  omp_set_num_threads(1);
}
#endif

#ifdef _OPENMP
/* the gathering of size classes and fix griddem/rom's kinematic particles into their grids, on
 * two threads from GRIDDEM_THREADED_MIN particles on (each counts and gathers one range): one
 * thread's grids, slots and candidates, ghosts out of reach and lagging particles left out */
static void gather_threaded(const griddem_model *m)
{
  enum { N = 3 * GRIDDEM_THREADED_MIN, NLOCAL = N - 4000 };
  static double x[3 * N], v[3 * N], w[3 * N], rad[N], mass[N];
  static int tag[N], type[N], mask[N], order_one[N];
  for (int i = 0; i < N; i++) {
    for (int d = 0; d < 3; d++) x[3 * i + d] = 40.0 * check_uniform(), v[3 * i + d] = w[3 * i + d] = 0.0;
    x[3 * i] += i >= NLOCAL ? 50.0 * (i % 2) : 0.0;    /* half the ghosts far from every owned centre */
    rad[i] = 0.05 * pow(8.0, check_uniform()), mass[i] = 1.0, tag[i] = i % 9000 + 1, type[i] = 1;
    mask[i] = 1 | (i % 5 == 0 ? 2 : 0) | (i % 97 == 0 ? 4 : 0);
  }
  const griddem_exclusions excl = {.ntypes = 1, .both_bit = 2, .apart_bit = 4};
  griddem_particles part = {.nlocal = NLOCAL, .nall = N, .x = x, .v = v, .omega = w, .radius = rad,
      .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  griddem_step s;
  memset(&s, 0, sizeof(s));
  s.particles = part, s.model = m, s.excl = &excl, s.rmin = 0.05, s.rmax = 0.4, s.max_cells = 1L << 26;
  s.size_classes = 1, s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_AUTO, s.rmin, s.rmax, 0.0);
  double counted[2];
  int nslot[2], same = 1;
  for (int k = 0; k < 2; k++) {
    omp_set_num_threads(k + 1);
    griddem_engine e;
    griddem_engine_init(&e);
    counted[k] = griddem_engine_candidates(&e, &s);
    nslot[k] = 0;
    for (int c = 0; c < e.ngrid; c++) nslot[k] += e.bins[c].n;
    for (int q = 0; q < nslot[k]; q++) {
      if (k == 0) order_one[q] = e.order[q];
      else same &= order_one[q] == e.order[q];
    }
    griddem_engine_free(&e);
  }
  omp_set_num_threads(1);
  CHECK(nslot[0] == nslot[1] && nslot[0] < N - 2000 && same && counted[0] == counted[1] && counted[0] > 0,
        "two threads gather %d of %d particles (size classes, kinematic, lagging, far ghosts) into one thread's "
        "slots: %d and %d, %g and %g candidates", nslot[1], N, nslot[0], nslot[1], counted[0], counted[1]);
}
#endif

/* The scan on one thread, the reductions in vector lanes: the box and the largest squared speed
 * of a few hundred points (none left to a remainder loop alone), and what is not finite: an
 * infinite coordinate among owned particles, a NaN among ghosts (the first named), and a speed
 * whose components are finite but whose square is not. */
static void scan_lanes(void)
{
  enum { N = 301, NLOCAL = 250 };
  static double x[3 * N], v[3 * N], rad[N];
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, vmax2 = 0.0;
  for (int i = 0; i < N; i++) {
    double v2 = 0.0;
    for (int d = 0; d < 3; d++) {
      x[3 * i + d] = -3.0 + 10.0 * check_uniform(), v[3 * i + d] = -2.0 + 4.0 * check_uniform();
      lo[d] = fmin(lo[d], x[3 * i + d]), hi[d] = fmax(hi[d], x[3 * i + d]), v2 += v[3 * i + d] * v[3 * i + d];
    }
    if (i < NLOCAL) vmax2 = fmax(vmax2, v2);
    rad[i] = 0.5;
  }
  griddem_particles part = {.nlocal = NLOCAL, .nall = N, .x = x, .v = v, .radius = rad,
      .tag_bytes = 4};
  griddem_scan s;
  griddem_engine_scan(&part, 1, &s);
  int same = s.vmax2 == vmax2 && s.first_nonfinite == -1 && !s.nonfinite_velocity;
  for (int d = 0; d < 3; d++) same &= s.lo[d] == lo[d] && s.hi[d] == hi[d];
  CHECK(same, "scan of %d points: box and speed^2 %.17g as counted one by one (%.17g)", N, s.vmax2, vmax2);
  x[3 * 97] = -INFINITY, x[3 * 280 + 2] = NAN, x[3 * 290] = NAN;
  griddem_engine_scan(&part, 1, &s);
  CHECK(s.first_nonfinite == 97 && !s.nonfinite_velocity, "an infinite coordinate named (%d)", s.first_nonfinite);
  x[3 * 97] = 0.0;
  griddem_engine_scan(&part, 1, &s);
  CHECK(s.first_nonfinite == 280, "a ghost's NaN named (%d)", s.first_nonfinite);
  x[3 * 280 + 2] = x[3 * 290] = 0.0, v[3 * 123 + 1] = 1e200;
  griddem_engine_scan(&part, 1, &s);
  CHECK(s.first_nonfinite == -1 && s.nonfinite_velocity, "a speed whose square overflows is not finite");
}

/* griddem_class_of against its definition, class c holding radii in (upper[c+1], upper[c]] and the
 * last class every smaller one, for each number of classes: radii at each bound, a hair above
 * and below it, and far below the last (the smallest double); bounds as
 * griddem_class_bounds lays them out (zero past the last class). */
static void size_classes_by_definition(void)
{
  long checked = 0, wrong = 0;
  for (int ncls = 1; ncls <= GRIDDEM_MAX_CLASSES; ncls++) {
    double upper[GRIDDEM_MAX_CLASSES + 1];
    griddem_class_bounds(1.7, ncls, upper);
    for (int k = 0; k < ncls; k++) {
      const double radii[5] = {upper[k], nextafter(upper[k], 0.0), nextafter(upper[k], 1e9), upper[k] * 0.5,
                               k == ncls - 1 ? 4.9e-324 : upper[k + 1] * 1.5};
      for (int q = 0; q < 5; q++) {
        const double r = radii[q];
        int want = ncls - 1;    /* the last class unless a bound below r ends a class */
        for (int c = 0; c < ncls - 1; c++)
          if (r > upper[c + 1]) {
            want = c;
            break;
          }
        checked++;
        wrong += griddem_class_of(r, upper, ncls) != want;
      }
    }
  }
  CHECK(wrong == 0, "size classes: %ld of %ld radii in another class than their bounds say", wrong, checked);
}

int main(void)
{
  scan_lanes();
  griddem_touching_use("scalar"); /* the plain passes (griddem_vector_reads) */
  scan_lanes();
  griddem_touching_use("auto");
  size_classes_by_definition();
#ifdef _OPENMP
  scan_threaded();
#endif
  griddem_pair_params table[4];
  const griddem_pair_params law = law_from_text("hooke 1e3 0 damping mass_velocity tangential gran/hooke/history 300 0 0.5");
  for (int k = 0; k < 4; k++) table[k] = law;
  griddem_model m;
  memset(&m, 0, sizeof(m));
  m.ntypes = 1, m.pair = table, m.history_size = 3, m.track_contacts = 1;

  ghost_shell(&m, 0);
  ghost_shell(&m, 1);
  CHECK(held_classes(&m, 0.3), "held classes: every step's forces and contacts those of a direct sum");
  CHECK(!held_classes(&m, 0.0), "held classes without a margin miss a contact (the scene needs the margin)");

  /* a row of three: particle 0 between 1 and 2, 3 apart; 2 and 3 are ghosts */
  double x[12] = {0, 0, 0, 0.9, 0, 0, -0.9, 0, 0, 5, 5, 5}, v[12] = {0, 1, 0, 0, -1, 0, 0, 0, 2, 3, 0, 0};
  double w[12] = {0}, rad[4] = {0.5, 0.5, 0.5, 0.5}, mass[4] = {1, 1, 1, 1}, f[12] = {0}, t[12] = {0};
  int tag[4] = {7, 8, 9, 10}, type[4] = {1, 1, 1, 1}, mask[4] = {1, 1, 1, 1}, row_of[4] = {-1, -1, -1, -1};
  griddem_engine e;
  griddem_engine_init(&e);
  griddem_history h;
  griddem_history_init(&h, 3);
  griddem_step s;
  memset(&s, 0, sizeof(s));
  griddem_particles part = {.nlocal = 2, .nall = 4, .x = x, .v = v, .omega = w, .radius = rad,
      .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  s.particles = part;
  s.cell_edge = griddem_cell_edge(GRIDDEM_CELL_AUTO, 0.5, 0.5, 0.0);
  s.max_cells = 100000, s.rmax = 0.5, s.model = &m, s.dt = 1e-2, s.history_update = 1;
  s.hist = &h, s.row_of = row_of, s.f = f, s.torque = t;
  griddem_sweep_result r;
  int coarsened;
  CHECK(griddem_engine_step(&e, &s, &r, &coarsened) == GRIDDEM_FAULT_NONE && !coarsened, "step runs");
  CHECK(complete_history(&h, &m, 2, row_of, tag, type) == 0, "history completed");
  CHECK(e.stats.contacts == 3 && e.stats.max_contacts == 2, "contacts %ld, most %d", e.stats.contacts, e.stats.max_contacts);
  CHECK(e.stats.nonfinite_velocity == 0, "velocities finite");
  CHECK_CLOSE(e.stats.max_speed, 1.0, 1e-15, 0.0);
  CHECK_CLOSE(e.stats.max_cells_moved, 1.0 * 1e-2 / e.stats.cell_edge, 1e-15, 0.0);
  CHECK(row_of[0] >= 0 && row_of[1] >= 0 && row_of[2] == -1, "owned particles have rows, ghosts none");
  CHECK(griddem_history_longest_message(&h) == 1 + 2 * 4, "longest message: %d", griddem_history_longest_message(&h));

  /* particle 0's row as a message, appended back: same contacts, same values */
  double msg[64], again[64];
  const int n = griddem_history_get_message(&h, row_of[0], msg);
  CHECK(n == griddem_history_message_length(&h, row_of[0]) && msg[0] == 2.0, "message of %d doubles, %g contacts", n, msg[0]);
  const int row = griddem_history_put_message(&h, msg, 3);
  CHECK(row >= 0 && griddem_history_get_message(&h, row, again) == n && memcmp(msg, again, sizeof(double) * n) == 0,
        "a row put back reads the same");
  const double *h8 = griddem_history_find(&h, row_of[0], 8), *h9 = griddem_history_find(&h, row_of[0], 9);
  CHECK(h8 && h9 && h8[1] != 0.0 && h9[2] != 0.0, "shear of both contacts stored");
  CHECK(griddem_history_find(&h, row_of[0], 10) == NULL, "no entry for a partner not touched");
  /* a row written with 3 values read by an engine keeping 4: values kept, the 4th zero */
  CHECK(griddem_history_set_values(&h, 4) == 0, "convert to 4 values");
  const int row4 = griddem_history_put_message(&h, msg, 3);
  CHECK(griddem_history_get_message(&h, row4, again) == 1 + 2 * 5 && again[1] == msg[1] && again[2] == msg[2] &&
            again[4] == msg[4] && again[5] == 0.0, "message converted to 4 values per contact");
  CHECK(griddem_engine_memory(&e) > 0.0, "memory reported");
  /* a non-finite velocity of an owned particle is flagged (a ghost's is its owner's business) */
  v[9] = INFINITY;
  griddem_engine_step(&e, &s, &r, &coarsened);
  CHECK(e.stats.nonfinite_velocity == 0, "a ghost's infinite velocity is not flagged");
  v[3] = NAN;
  griddem_engine_step(&e, &s, &r, &coarsened);
  CHECK(e.stats.nonfinite_velocity == 1, "an owned particle's NaN velocity is flagged");

  /* the first pass: the box of every position, speed and radii of the owned particles only, the
     first non-finite position */
  v[3] = 0.0;
  rad[3] = 2.0, rad[1] = 0.25;
  griddem_scan scan;
  griddem_engine_scan(&part, 1, &scan);
  CHECK(scan.first_nonfinite == -1, "positions finite");
  CHECK(scan.lo[0] == -0.9 && scan.hi[0] == 5.0 && scan.lo[1] == 0.0 && scan.hi[2] == 5.0, "box of all four");
  CHECK(scan.vmax2 == 1.0 && scan.nonfinite_velocity == 0, "fastest owned speed^2 %g (the ghosts' 2 and 3 left out)",
        scan.vmax2);
  CHECK(scan.rmin == 0.25 && scan.rmax == 0.5, "radius range of the owned: %g %g", scan.rmin, scan.rmax);
  griddem_engine_scan(&part, 0, &scan);
  CHECK(isnan(scan.rmin) && isnan(scan.rmax) && scan.vmax2 == 1.0, "no radius range unless asked");
  /* finite positions whose sum overflows, and speeds whose squares do not: none flagged */
  const double x0 = x[0], x3 = x[3], v0 = v[0];
  x[0] = x[3] = 1.5e308, v[0] = 0x1p500;
  griddem_engine_scan(&part, 1, &scan);
  CHECK(scan.first_nonfinite == -1 && scan.hi[0] == 1.5e308, "huge finite positions are finite (%d)", scan.first_nonfinite);
  CHECK(scan.nonfinite_velocity == 0 && scan.vmax2 == 0x1p1000, "a huge finite speed is finite");
  const double v1 = v[1], v3 = v[3], v4 = v[4];
  v[0] = v[1] = v[3] = v[4] = 0x1p511;    /* two finite squared speeds, 2^1023 each, whose sum is not */
  griddem_engine_scan(&part, 1, &scan);
  CHECK(scan.nonfinite_velocity == 0 && scan.vmax2 == 0x1p1023, "finite squared speeds whose sum overflows are finite");
  v[1] = v1, v[3] = v3, v[4] = v4;
  v[0] = 0x1p520;    /* its square is not */
  griddem_engine_scan(&part, 1, &scan);
  CHECK(scan.nonfinite_velocity == 1, "a squared speed past the doubles is flagged");
  x[0] = x0, x[3] = x3, v[0] = v0;
  x[7] = NAN, x[11] = INFINITY;
  griddem_engine_scan(&part, 1, &scan);
  CHECK(scan.first_nonfinite == 2, "first non-finite position: particle %d", scan.first_nonfinite);
  x[7] = 0.0;    /* an infinite coordinate alone */
  griddem_engine_scan(&part, 1, &scan);
  CHECK(scan.first_nonfinite == 3, "first non-finite position: particle %d", scan.first_nonfinite);
  griddem_engine_free(&e);
  griddem_history_free(&h);
  candidates(&m);
#ifdef _OPENMP
  gather_threaded(&m);
#endif
  return check_summary();
}
