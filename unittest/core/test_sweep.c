/* The stencil sweep finds every contact: forces, torques, virial, energy and history match an
 * all-pairs evaluation of the same contact law from both sides of every pair (the sweep evaluates
 * each pair once and hands the partner the mirrored result) on a dense polydisperse (1:4)
 * configuration of two types, in every cell mode, for the gran/hooke(/history) laws and pair
 * granular sub-models (a per-type-pair table; jkr's contacts past touching included; the laws the
 * sweep compiles with constant sub-models, and laws one sub-model away from them), with
 * excluded type pairs and with 1 or 3 threads, and on spheres of one radius; through the engine, size classes and idle particles
 * (all their pairs excluded) left out of the grid; momentum balance holds; a particle's history row
 * grows with its contacts; faults name the particles. */
#include "check.h"
#include "complete_history.h"
#include "griddem_engine.h"
#include "griddem_search.h"
#include "griddem_sweep.h"
#include "griddem_threads.h"
#include "spec_text.h"

#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <string.h>

enum { N = 400 };
static double x[3 * N], v[3 * N], w[3 * N], rad[N], mass[N], temp[N];
static int tag[N], type[N], mask[N];

static void make_configuration(double rlo, double rhi)
{
  for (int i = 0; i < N; i++) {
    rad[i] = rlo + (rhi - rlo) * check_uniform();
    mass[i] = 4.0 * rad[i] * rad[i] * rad[i];
    temp[i] = 1.0 + check_uniform();
    for (int d = 0; d < 3; d++) {
      x[3 * i + d] = 2.0 * check_uniform(); /* dense: many overlaps */
      v[3 * i + d] = check_uniform() - 0.5;
      w[3 * i + d] = 4.0 * (check_uniform() - 0.5);
    }
    tag[i] = 1 + (i * 7919) % N; /* tags unrelated to storage order */
    type[i] = 1 + (i % 3 == 0);
    mask[i] = 1;
  }
}

/* All ordered pairs from i's view, history in a dense matrix of nv values per ordered pair and
 * whether the pair interacted in touched (jkr holds pairs that touched before); heat (NULL: not
 * wanted): the heat into each particle by laws with a heat model. */
static void all_pairs(const griddem_model *m, const unsigned char *excluded, int both_bit, int apart_bit, double dt,
                      int update,
                      double *hist, unsigned char *touched, double *f, double *t, double *vir,
                      double *energy, long *contacts, double *heat)
{
  if (heat) memset(heat, 0, sizeof(double) * N);
  const int nv = m->history_size;
  memset(f, 0, sizeof(double) * 3 * N);
  memset(t, 0, sizeof(double) * 3 * N);
  memset(vir, 0, sizeof(double) * 6);
  *energy = 0.0;
  *contacts = 0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      if (i == j || (excluded && excluded[type[i] * 3 + type[j]]) || (mask[i] & mask[j] & both_bit) ||
          ((mask[i] | mask[j]) & apart_bit))
        continue;
      griddem_contact c;
      for (int d = 0; d < 3; d++) {
        c.dx[d] = x[3 * i + d] - x[3 * j + d];
        c.vr[d] = v[3 * i + d] - v[3 * j + d];
        c.wi[d] = w[3 * i + d], c.wj[d] = w[3 * j + d];
      }
      c.rsq = griddem_dot3(c.dx, c.dx);
      const size_t ij = (size_t) i * N + j;
      double *h = hist + GRIDDEM_MAX_HISTORY * ij;
      const griddem_pair_params *law = griddem_model_pair(m, type[i], type[j]);
      if (!griddem_contact_touch(law, c.rsq, rad[i], rad[j], touched[ij])) {
        for (int k = 0; k < GRIDDEM_MAX_HISTORY; k++) h[k] = 0.0;
        touched[ij] = 0;
        continue;
      }
      touched[ij] = 1;
      c.radi = rad[i], c.radj = rad[j];
      c.meff = griddem_effective_mass(mass[i], mass[j], 0, 0);
      c.dt = dt, c.history_update = update;
      c.temp_i = temp[i], c.temp_j = temp[j];
      double fc[3], ti[3], tj[3], hv[GRIDDEM_MAX_HISTORY] = {0};
      for (int k = 0; k < nv; k++) hv[k] = h[k];
      *energy += 0.5 * griddem_contact_eval(law, &c, hv, fc, ti, tj);
      for (int k = 0; k < nv; k++) h[k] = hv[k];
      for (int d = 0; d < 3; d++) f[3 * i + d] += fc[d], t[3 * i + d] += ti[d];
      if (heat && law->heat.model != GRIDDEM_HEAT_NONE) heat[i] += c.heat;
      vir[0] += 0.5 * c.dx[0] * fc[0], vir[1] += 0.5 * c.dx[1] * fc[1];
      vir[2] += 0.5 * c.dx[2] * fc[2], vir[3] += 0.5 * c.dx[0] * fc[1];
      vir[4] += 0.5 * c.dx[0] * fc[2], vir[5] += 0.5 * c.dx[1] * fc[2];
      (*contacts)++;
    }
}

static double max_abs(const double *a, int n)
{
  double m = 0.0;
  for (int i = 0; i < n; i++) m = fabs(a[i]) > m ? fabs(a[i]) : m;
  return m;
}

/* One class of particles all owned: any cell of g may hold one */
static griddem_class_grid all_owned(const griddem_grid *g, const griddem_bins *b, double rmax)
{
  const griddem_class_grid k = {g, b, 0, rmax, 0, {0, 0, 0}, {g->n[0] - 1, g->n[1] - 1, g->n[2] - 1}};
  return k;
}

static void compare_mode(int mode, const char *law, const griddem_model *m, const unsigned char *excluded,
                         int threads)
{
  const double dt = 1e-4, anchor[3] = {0.0, 0.0, 0.0};
  double rmin = 1e30, rmax = 0.0;
  for (int i = 0; i < N; i++) rmin = rad[i] < rmin ? rad[i] : rmin, rmax = rad[i] > rmax ? rad[i] : rmax;
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif

  griddem_grid g;
  griddem_bins b = {0};
  griddem_channels ch = {0};
  griddem_particles part = {.nlocal = N, .nall = N, .x = x, .v = v, .omega = w, .radius = rad,
      .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  static double heatflow[N], heat_ref[N];
  part.temperature = temp, part.heatflow = heatflow;
  griddem_exclusions excl = {.type_pair = excluded, .ntypes = 2};

  griddem_history hist;
  griddem_history_init(&hist, m->history_size);
  int row_of[N];
  for (int i = 0; i < N; i++) row_of[i] = -1;
  static double dense[GRIDDEM_MAX_HISTORY * N * N];
  static unsigned char touched[N * N];
  memset(dense, 0, sizeof(dense));
  memset(touched, 0, sizeof(touched));

  static double f[3 * N], t[3 * N], va[6 * N], fr[3 * N], tr[3 * N];
  double vr[6], energy_ref;
  long contacts_ref;
  /* steps with history: it accumulates and is rotated the same way in both; the particles drift
     apart, so that jkr pairs that touched hold on past touching, and move by a fraction of a cell,
     so that pairs change cells and are found from their other side */
  long beyond = 0;
  static double x_start[3 * N];
  memcpy(x_start, x, sizeof(x));
  const double edge = griddem_cell_edge(mode, rmin, rmax, 0.13);
  for (int step = 0; step < 4; step++) {
    memset(f, 0, sizeof(f)), memset(t, 0, sizeof(t)), memset(va, 0, sizeof(va)), memset(heatflow, 0, sizeof(heatflow));
    if (step > 0)
      for (int k = 0; k < 3 * N; k++) x[k] = x[k] * 1.003 + (0.37 - 0.13 * (k % 3)) * edge;
    griddem_grid_cover(&g, anchor, N, x, edge, 1L << 26);
    griddem_bin_points(&b, &g, N, x, tag, 4);
    griddem_channels_fill(&ch, &b, &part);
    CHECK(ch.same_radius == (rmin == rmax), "%s mode %d: one radius %d marked for radii %g to %g", law, mode,
          ch.same_radius, rmin, rmax);
    griddem_sweep_result res;
    const griddem_class_grid one = all_owned(&g, &b, rmax);
    griddem_sweep(&one, 1, b.order, &ch, N, m, &excl, dt, 1, &hist, row_of, f, t, va,
                  GRIDDEM_TALLY_VIRIAL | GRIDDEM_TALLY_ENERGY, &res);
    /* the rows completed every other step, as migrations do: the steps between find a pair's
       contact in the row of its other particle where the pair changed sides */
    const int completed = step % 2 == 1;
    CHECK(!completed || (complete_history(&hist, m, N, row_of, tag, type) == 0 && !hist.one_sided),
          "%s: history completed", law);
    all_pairs(m, excluded, 0, 0, dt, 1, dense, touched, fr, tr, vr, &energy_ref, &contacts_ref, heat_ref);
    for (int i = 0; i < N; i++)
      for (int j = 0; j < N; j++) {
        const double dx = x[3 * i] - x[3 * j], dy = x[3 * i + 1] - x[3 * j + 1], dz = x[3 * i + 2] - x[3 * j + 2];
        beyond += touched[(size_t) i * N + j] && dx * dx + dy * dy + dz * dz >= (rad[i] + rad[j]) * (rad[i] + rad[j]);
      }
    CHECK(res.fault == GRIDDEM_FAULT_NONE, "%s mode %d: fault %d", law, mode, res.fault);
    CHECK(res.contacts == contacts_ref && contacts_ref > N, "%s mode %d step %d: %ld contacts, all-pairs %ld",
          law, mode, step, res.contacts, contacts_ref);
    const double fscale = max_abs(fr, 3 * N), tscale = max_abs(tr, 3 * N);
    double ferr = 0.0, terr = 0.0, verr = 0.0;
    for (int k = 0; k < 3 * N; k++) {
      ferr = fmax(ferr, fabs(f[k] - fr[k]));
      terr = fmax(terr, fabs(t[k] - tr[k]));
    }
    double vsum[6] = {0};
    for (int i = 0; i < N; i++)
      for (int k = 0; k < 6; k++) vsum[k] += va[6 * i + k];
    for (int k = 0; k < 6; k++) verr = fmax(verr, fabs(res.virial[k] - vr[k]) + fabs(vsum[k] - vr[k]));
    CHECK(ferr <= 1e-12 * fscale, "%s mode %d step %d: force error %g of %g", law, mode, step, ferr, fscale);
    if (terr > 1e-12 * tscale && step == 0) {
      int worst = 0; double we = 0;
      for (int k = 0; k < 3 * N; k++) if (fabs(t[k] - tr[k]) > we) we = fabs(t[k] - tr[k]), worst = k / 3;
      printf("%s mode %d worst %d: t %g %g %g ref %g %g %g f %.17g ref %.17g\n", law, mode, worst, t[3*worst], t[3*worst+1], t[3*worst+2], tr[3*worst], tr[3*worst+1], tr[3*worst+2], f[3*worst], fr[3*worst]);
      for (int j = 0; j < N; j++) { double dx=x[3*worst]-x[3*j], dy=x[3*worst+1]-x[3*j+1], dz=x[3*worst+2]-x[3*j+2]; double r2=dx*dx+dy*dy+dz*dz; if (j!=worst && r2 < 0.04) printf("  partner %d r %g\n", j, sqrt(r2)); }
    }
    CHECK(terr <= 1e-12 * tscale, "%s mode %d step %d: torque error %g of %g", law, mode, step, terr, tscale);
    CHECK(verr <= 1e-12 * max_abs(vr, 6), "%s mode %d step %d: virial error %g", law, mode, step, verr);
    const double qscale = max_abs(heat_ref, N);
    double qerr = 0.0;
    for (int i = 0; i < N; i++) qerr = fmax(qerr, fabs(heatflow[i] - heat_ref[i]));
    CHECK(qerr <= 1e-12 * qscale && (qscale > 0.0) == (strstr(law, " heat ") != NULL),
          "%s mode %d step %d: heat error %g of %g", law, mode, step, qerr, qscale);
    CHECK(fabs(res.energy - energy_ref) <= 1e-12 * energy_ref && energy_ref > 0.0,
          "%s mode %d step %d: energy %g, all-pairs %g", law, mode, step, res.energy, energy_ref);

    /* history rows hold what the all-pairs evaluation holds for each ordered pair, every contact
       in both particles' rows once completed */
    double herr = 0.0, hscale = 0.0;
    long missing = 0;
    for (int i = 0; completed && i < N; i++) {
      int touching = 0;
      for (int j = 0; j < N; j++) touching += touched[(size_t) i * N + j];
      missing += m->track_contacts && griddem_history_count(&hist, row_of[i]) != touching;
      static double row[GRIDDEM_HISTORY_ENTRY(GRIDDEM_MAX_HISTORY) * N];
      griddem_history_get_row(&hist, row_of[i], row);
      for (int k = 0; k < griddem_history_count(&hist, row_of[i]); k++) {
        const double *e = row + (1 + m->history_size) * k;
        int j = 0;
        while (tag[j] != (int) e[0]) j++;
        for (int q = 0; q < m->history_size; q++) {
          const double ref = dense[GRIDDEM_MAX_HISTORY * ((size_t) i * N + j) + q];
          herr = fmax(herr, fabs(e[1 + q] - ref));
          hscale = fmax(hscale, fabs(ref));
        }
      }
    }
    CHECK(herr <= 1e-12 * hscale, "%s mode %d step %d: history error %g of %g", law, mode, step, herr, hscale);
    CHECK(missing == 0, "%s mode %d step %d: %ld rows without each of their contacts", law, mode, step, missing);

    /* Newton's third law (the torque lever is the radius, as in stock, so angular momentum is
       not balanced exactly while spheres overlap; no check of it here) */
    double fsum[3] = {0};
    for (int i = 0; i < N; i++)
      for (int d = 0; d < 3; d++) fsum[d] += f[3 * i + d];
    CHECK(max_abs(fsum, 3) <= 1e-11 * fscale, "%s mode %d: net force %g", law, mode, max_abs(fsum, 3));
  }
  CHECK((m->reach_extra > 0.0) == (beyond > 0), "%s mode %d: %ld contacts past touching", law, mode, beyond);
  memcpy(x, x_start, sizeof(x));
  griddem_history_free(&hist);
  griddem_bins_free(&b);
  griddem_channels_free(&ch);
}

/* A law for each of the 2x2 type pairs: text with %g for a factor that differs between pairs,
 * so the per-type-pair table is exercised. */
static griddem_pair_params table[9];

static griddem_model model_of(const char *format)
{
  griddem_model m;
  memset(&m, 0, sizeof(m));
  m.ntypes = 2;
  m.pair = table;
  for (int a = 1; a <= 2; a++)
    for (int b = 1; b <= 2; b++) {
      char text[512];
      snprintf(text, sizeof(text), format, 0.5 * (a + b));
      table[a * 3 + b] = law_from_text(text);
      griddem_pair_spec s;
      spec_from_text(text, &s);
      m.history_size = griddem_spec_history(&s, NULL);
      m.track_contacts = m.history_size > 0 || griddem_spec_beyond_contact(&s);
      m.reach_extra = fmax(m.reach_extra, griddem_pair_reach_extra(&table[a * 3 + b], 0.2, 0.2));
    }
  return m;
}

static const char *const LAWS[] = {
    "hooke 2000 50 damping mass_velocity tangential gran/hooke/history 571.4 25 %g",
    "hooke 2000 50 damping mass_velocity tangential gran/hooke 25 %g",
    "hooke 2000 50 damping mass_velocity tangential none",
    "hertz 8e4 5 tangential linear_history 1500 0.5 %g rolling sds 20 0.1 0.05",
    "hertz/material 1e5 5 0.3 tangential mindlin_rescale NULL 0.5 %g twisting marshall",
    "jkr 1e5 5 0.3 %g damping mass_velocity tangential mindlin NULL 0.5 0.4 rolling sds 20 0.1 0.05 twisting sds 1 0.01 0.1",
};

/* Laws with the sub-models of each row of the sweep's compiled laws (griddem_sweep.c's
 * COMPILED_LAWS), evaluated with their models as constants, and laws that differ from a row on one
 * axis, which must take the composed law with its models read at run time: a sweep that took them
 * for the row would evaluate the row's model on that axis. */
static const char *const COMPILED_ROWS[] = {
    "hooke 2000 0.3 damping coeff_restitution tangential linear_history 1500 0.5 %g rolling sds 20 0.1 0.05",
    "hooke 2000 50 damping velocity tangential linear_nohistory 1.0 %g",
    "hertz 8e4 5 tangential linear_nohistory 1.0 %g heat radius 1.0",
};
static const char *const NEAR_ROWS[] = {
    "hertz 8e4 0.3 damping coeff_restitution tangential linear_history 1500 0.5 %g rolling sds 20 0.1 0.05",
    "hooke 2000 50 damping mass_velocity tangential linear_history 1500 0.5 %g rolling sds 20 0.1 0.05",
    "hooke 2000 0.3 damping coeff_restitution tangential linear_history 1500 0.5 %g rolling sds 20 0.1 0.05 "
    "twisting sds 1 0.01 0.1",
    "hooke 2000 50 damping mass_velocity tangential linear_nohistory 1.0 %g",
    "hertz 2000 50 damping velocity tangential linear_nohistory 1.0 %g",
    "hertz 8e4 5 tangential linear_nohistory 1.0 %g heat area 1.0",
    "hertz 8e4 5 tangential linear_nohistory 1.0 %g",
};

/* The same law for every type pair (model_of's friction argument not used) */
static const char ONE_LAW[] = "hooke 2000 50 damping mass_velocity tangential gran/hooke/history 571.4 25 0.5";

/* Two particles sharing a position, and one particle touching many: the fault names the
 * coincident pair; the crowded particle keeps all its contacts in a row that grows. With a law
 * per type pair (law's %g) and with one law for all (the sweep's batches). */
static void check_faults(const char *law)
{
  const griddem_model m = model_of(law);
  const double anchor[3] = {0.0, 0.0, 0.0};
  enum { M = 41 };
  double px[3 * M] = {0, 0, 0, 1, 1, 1, 1, 1, 1}, pv[3 * M] = {0}, pw[3 * M] = {0}, pr[M], pm[M];
  int ptag[M], ptype[M], pmask[M];
  for (int i = 0; i < M; i++) pr[i] = 1, pm[i] = 1, ptag[i] = 10 * (i + 1), ptype[i] = 1, pmask[i] = 1;
  griddem_grid g;
  griddem_bins b = {0};
  griddem_channels ch = {0};
  griddem_particles part = {.nlocal = 3, .nall = 3, .x = px, .v = pv, .omega = pw, .radius = pr,
      .rmass = pm, .tag = ptag, .tag_bytes = 4, .type = ptype, .mask = pmask};
  double f[3 * M] = {0}, t[3 * M] = {0};
  int row_of[M];
  for (int i = 0; i < M; i++) row_of[i] = -1;
  griddem_history hist;
  griddem_history_init(&hist, 3);
  griddem_sweep_result res;

  griddem_grid_cover(&g, anchor, 3, px, 1.0, 1000);
  griddem_bin_points(&b, &g, 3, px, ptag, 4);
  griddem_channels_fill(&ch, &b, &part);
  griddem_class_grid one = all_owned(&g, &b, 1.0);
  griddem_sweep(&one, 1, b.order, &ch, 3, &m, NULL, 1e-3, 1, &hist, row_of, f, t, NULL, 0, &res);
  CHECK(res.fault == GRIDDEM_FAULT_COINCIDENT, "coincident centres reported: %d", res.fault);
  CHECK(res.fault_i == 1 || res.fault_i == 2, "first particle of the coincident pair");
  CHECK(res.fault_j == 3 - res.fault_i, "second particle of the coincident pair");
  CHECK(!isnan(f[0]) && !isnan(f[3]), "no NaN forces");

  /* particle 0 at the centre of a shell of 40 that each overlap it */
  for (int k = 1; k < M; k++) {
    const double zc = 1.0 - (2.0 * k - 1.0) / (M - 1), phi = k * 2.39996322972865332, rho = sqrt(1.0 - zc * zc);
    px[3 * k] = 1.9 * rho * cos(phi), px[3 * k + 1] = 1.9 * rho * sin(phi), px[3 * k + 2] = 1.9 * zc;
  }
  px[0] = px[1] = px[2] = 0.0;
  part.nlocal = part.nall = M;
  for (int step = 0; step < 2; step++) {
    griddem_grid_cover(&g, anchor, M, px, 2.0, 1000);
    griddem_bin_points(&b, &g, M, px, ptag, 4);
    griddem_channels_fill(&ch, &b, &part);
    one = all_owned(&g, &b, 1.0);
    griddem_sweep(&one, 1, b.order, &ch, M, &m, NULL, 1e-3, 1, &hist, row_of, f, t, NULL, 0, &res);
    CHECK(complete_history(&hist, &m, M, row_of, ptag, ptype) == 0, "history completed");
    CHECK(res.fault == GRIDDEM_FAULT_NONE && res.max_contacts == M - 1,
          "step %d: a particle with %d contacts, no fault (%d)", step, res.max_contacts, res.fault);
    CHECK(griddem_history_count(&hist, row_of[0]) == M - 1 && hist.max_count == M - 1,
          "step %d: its row holds all %d contacts", step, griddem_history_count(&hist, row_of[0]));
  }
  griddem_history_free(&hist);
  griddem_bins_free(&b);
  griddem_channels_free(&ch);
}

/* The engine against the all-pairs evaluation: every contact, force, torque, the virial and the
 * history, over steps in which the history accumulates and the packing loosens.
 * Size classes (three classes, pairs within each on its own grid and across classes the spheres of
 * one class searched in the other's grid, whichever direction the sweep finds cheaper): radii
 * log-uniform in 0.012-0.24 (SIZES_SPREAD); three large spheres among small ones (SIZES_FEW_LARGE,
 * where the large ones search the small ones' grid); three small among large (SIZES_FEW_SMALL, the
 * small ones search the large ones' grid); 1 and 3 threads.
 * Kinematic and lagging particles (fix griddem/rom's: the exclusions' both_bit, here x > 0.6, pairs
 * of two excluded; and its apart_bit, here x > 0.75, every pair with one excluded): the same forces
 * as the all-pairs evaluation with those pairs skipped, the kinematic particles binned on grids of
 * their own over the same cells (which only the others search) from the step after one where they
 * were most of those binned (here x > 0.3), and with the others where fewer (x > 0.6), every lagging particle left out of the grid, and a
 * lagging particle's speed still enters the motion check. */
enum { SIZES_ONE_CLASS, SIZES_SPREAD, SIZES_FEW_LARGE, SIZES_FEW_SMALL };

static void engine_against_all_pairs(const char *law, int threads, int sizes, int idle)
{
  const int size_classes = sizes != SIZES_ONE_CLASS;
  if (size_classes) {
    make_configuration(0.012, 0.24);
    for (int i = 0; i < N; i++) {
      /* radius 0.012 (one sphere) sets the three classes; 0.24 the largest */
      const double spread = 0.24 * pow(0.05, check_uniform()), small = 0.012 + 0.003 * check_uniform(),
                   large = 0.2 + 0.04 * check_uniform();
      rad[i] = i == 0 ? 0.012 : (i == 1 ? 0.24 : (sizes == SIZES_SPREAD ? spread : (sizes == SIZES_FEW_LARGE) == (i < 4) ? large : small));
      mass[i] = 4.0 * rad[i] * rad[i] * rad[i];
    }
    /* the small ones packed closer, so that each large one touches tens of them */
    if (sizes == SIZES_FEW_LARGE)
      for (int k = 0; k < 3 * N; k++) x[k] *= 0.4;
  } else
    make_configuration(0.05, 0.2);
  /* idle 1: few kinematic particles (they share the others' grids); 2: mostly kinematic (grids of
     their own) */
  const int kinematic_bit = idle ? 2 : 0, lagging_bit = idle ? 4 : 0;
  const double kinematic_from = idle == 2 ? 0.3 : 0.6;
  for (int i = 0; i < N; i++)
    mask[i] = 1 | (x[3 * i] > kinematic_from ? kinematic_bit : 0) | (x[3 * i] > 0.75 ? lagging_bit : 0);
  const griddem_exclusions excl = {.ntypes = 2, .both_bit = kinematic_bit, .apart_bit = lagging_bit};
  const griddem_model m = model_of(law);
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  static double dense[GRIDDEM_MAX_HISTORY * N * N], f[3 * N], t[3 * N], fr[3 * N], tr[3 * N];
  static unsigned char touched[N * N];
  memset(dense, 0, sizeof(dense));
  memset(touched, 0, sizeof(touched));
  int row_of[N];
  for (int i = 0; i < N; i++) row_of[i] = -1;
  griddem_engine e;
  griddem_engine_init(&e);
  griddem_history hist;
  griddem_history_init(&hist, m.history_size);
  griddem_step st;
  memset(&st, 0, sizeof(st));
  const griddem_particles part = {.nlocal = N, .nall = N, .x = x, .v = v, .omega = w,
      .radius = rad, .rmass = mass, .tag = tag, .tag_bytes = 4, .type = type, .mask = mask};
  st.particles = part;
  st.size_classes = size_classes, st.rmin = 1e30, st.rmax = 0.0;
  for (int i = 0; i < N; i++) st.rmin = fmin(st.rmin, rad[i]), st.rmax = fmax(st.rmax, rad[i]);
  st.cell_edge = griddem_cell_edge(size_classes ? GRIDDEM_CELL_CLASSES : GRIDDEM_CELL_MULTI, st.rmin, st.rmax, 0.0);
  st.max_cells = 1L << 26, st.model = &m, st.excl = &excl, st.dt = 1e-4, st.history_update = 1;
  st.hist = &hist, st.row_of = row_of, st.f = f, st.torque = t, st.tally = GRIDDEM_TALLY_VIRIAL | GRIDDEM_TALLY_ENERGY;
  char what[256];
  static const char *const SIZES[] = {"", ", classes", ", classes, few large", ", classes, few small"};
  snprintf(what, sizeof(what), "%s%s%s, %d threads", law, SIZES[sizes], idle ? (idle == 2 ? ", mostly kinematic" : ", idle") : "", threads);
  int mostly_kinematic = 0;    /* of the last step's binned particles */
  for (int step = 0; step < 3; step++) {
    memset(f, 0, sizeof(f)), memset(t, 0, sizeof(t));
    griddem_sweep_result res;
    int coarsened;
    double vr[6], energy_ref;
    long contacts_ref;
    griddem_engine_step(&e, &st, &res, &coarsened);
    CHECK(complete_history(&hist, &m, N, row_of, tag, type) == 0, "%s: history completed", what);
    all_pairs(&m, NULL, kinematic_bit, lagging_bit, st.dt, 1, dense, touched, fr, tr, vr, &energy_ref, &contacts_ref,
              NULL);
    CHECK(e.nclass == (size_classes ? 3 : 1) && res.fault == GRIDDEM_FAULT_NONE, "%s: %d classes, fault %d", what,
          e.nclass, res.fault);
    CHECK(res.contacts == contacts_ref && contacts_ref > (idle ? N / 8 : sizes == SIZES_FEW_LARGE ? N / 4 : N),
          "%s step %d: %ld contacts, all-pairs %ld", what, step, res.contacts, contacts_ref);
    double ferr = 0.0, terr = 0.0, verr = 0.0, herr = 0.0, hscale = 0.0;
    for (int k = 0; k < 3 * N; k++) ferr = fmax(ferr, fabs(f[k] - fr[k])), terr = fmax(terr, fabs(t[k] - tr[k]));
    for (int k = 0; k < 6; k++) verr = fmax(verr, fabs(res.virial[k] - vr[k]));
    for (int i = 0; i < N; i++)
      for (int j = 0; j < N; j++) {
        const double *h = griddem_history_find(&hist, row_of[i], tag[j]);
        for (int q = 0; h && q < m.history_size; q++) {
          const double ref = dense[GRIDDEM_MAX_HISTORY * ((size_t) i * N + j) + q];
          herr = fmax(herr, fabs(h[q] - ref)), hscale = fmax(hscale, fabs(ref));
        }
      }
    CHECK(ferr <= 1e-12 * max_abs(fr, 3 * N), "%s step %d: force error %g", what, step, ferr);
    CHECK(terr <= 1e-12 * max_abs(tr, 3 * N), "%s step %d: torque error %g", what, step, terr);
    CHECK(verr <= 1e-12 * max_abs(vr, 6), "%s step %d: virial error %g", what, step, verr);
    CHECK(herr <= 1e-12 * hscale, "%s step %d: history error %g of %g", what, step, herr, hscale);
    CHECK(fabs(res.energy - energy_ref) <= 1e-12 * energy_ref, "%s step %d: energy", what, step);
    if (idle) {
      int lagging = 0;
      double vmax = 0.0;
      for (int i = 0; i < N; i++) {
        vmax = fmax(vmax, sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]));
        lagging += (mask[i] & lagging_bit) != 0;
      }
      CHECK(lagging > N / 10 && e.channels.n == N - lagging, "%s step %d: %d particles binned, %d lagging", what,
            step, e.channels.n, lagging);
      int kinematic = 0;
      long on_kinematic_grids = 0;
      for (int i = 0; i < N; i++) kinematic += (mask[i] & kinematic_bit) && !(mask[i] & lagging_bit);
      for (int c = 1; e.ngrid == 2 * e.nclass && c < e.ngrid; c += 2) on_kinematic_grids += e.bins[c].n;    /* twins */
      /* grids of their own from the step after one that binned mostly kinematic particles */
      const int own_grids = mostly_kinematic;
      mostly_kinematic = kinematic >= e.channels.n - kinematic;
      int twins_share_cells = 1;    /* each class's kinematic grid over the class's own cells */
      for (int c = 0; own_grids && c < e.nclass; c++) {
        const griddem_grid *a = &e.grid[2 * c], *k = &e.grid[2 * c + 1];
        twins_share_cells &= a->h == k->h && memcmp(a->k0, k->k0, sizeof(a->k0)) == 0 && memcmp(a->n, k->n, sizeof(a->n)) == 0;
      }
      CHECK(kinematic >= 10 && (own_grids ? e.ngrid == 2 * e.nclass && on_kinematic_grids == kinematic : e.ngrid == e.nclass) &&
                mostly_kinematic == (idle == 2) && twins_share_cells,
            "%s step %d: %d of %d binned particles kinematic, %d grids, %ld on the kinematic ones", what, step,
            kinematic, e.channels.n, e.ngrid, on_kinematic_grids);
      for (int i = 0; i < N; i++)
        CHECK(!(mask[i] & lagging_bit) || griddem_history_count(&hist, row_of[i]) == 0,
              "%s step %d: lagging particle %d keeps %d contacts", what, step, i, griddem_history_count(&hist, row_of[i]));
      CHECK_CLOSE(e.stats.max_speed, vmax, 1e-15, 0.0);
    }
    for (int k = 0; k < 3 * N; k++) x[k] *= 1.002; /* the packing loosens: contacts change */
  }
  for (int i = 0; i < N; i++) mask[i] = 1;
  griddem_engine_free(&e);
  griddem_history_free(&hist);
}

/* The channels filled from particles in a shuffled order, with 32- and 64-bit keys (the latter
 * past 2^32) and images, slot by slot as the particles hold them: through the kernel's reading
 * (four at a time, the last slots one by one) and, on a team of threads, by blocks */
static void check_fill(int threads)
{
  enum { M = 3 * GRIDDEM_THREADED_MIN + 3 };
  static double px[3 * M], pr[M];
  static int ptag32[M], pimage[M], order[M];
  static int64_t ptag64[M];
  /* values and a permutation of their own (the other checks' random scenes stay as they are) */
  uint64_t state = 88172645463325252ull;
#define NEXT_UNIFORM() (state ^= state << 13, state ^= state >> 7, state ^= state << 17, (double) (state >> 11) * 0x1p-53)
  for (int i = 0; i < M; i++) {
    for (int d = 0; d < 3; d++) px[3 * i + d] = NEXT_UNIFORM();
    pr[i] = NEXT_UNIFORM(), ptag32[i] = 3 * i + 1, ptag64[i] = ((int64_t) 5 << 32) + 7 * i, pimage[i] = i % 4096;
    order[i] = i;
  }
  for (int i = M - 1; i > 0; i--) {
    const int j = (int) (NEXT_UNIFORM() * (i + 1)), k = order[i];
    order[i] = order[j], order[j] = k;
  }
#undef NEXT_UNIFORM
#ifdef _OPENMP
  omp_set_num_threads(threads);
#endif
  for (int wide = 0; wide < 2; wide++) {
    griddem_particles part = {.nlocal = M, .nall = M, .x = px, .radius = pr, .tag_bytes = 4,
        .image = pimage};
    part.tag = wide ? (const void *) ptag64 : (const void *) ptag32, part.tag_bytes = wide ? 8 : 4;
    griddem_bins b = {0};
    b.n = M, b.order = order;
    griddem_channels ch = {0};
    CHECK(griddem_channels_fill(&ch, &b, &part) == 0, "channels filled");
    long wrong = 0;
    for (int s = 0; s < M; s++) {
      const int i = order[s];
      wrong += ch.x[s] != px[3 * i] || ch.y[s] != px[3 * i + 1] || ch.z[s] != px[3 * i + 2] || ch.r[s] != pr[i] ||
               ch.tag[s] != (wide ? ptag64[i] : ptag32[i]) || ch.image[s] != pimage[i] || ch.ncontact[s] != 0;
    }
    CHECK(wrong == 0, "%d-bit keys, %d thread(s): %ld of %d slots filled wrong", wide ? 64 : 32, threads, wrong, M);
    griddem_channels_free(&ch);
  }
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
}

/* Every check of this file, with the sweep's candidate test done by each kernel this processor runs */
static void all_checks(void)
{
  check_fill(1);
  check_fill(2);
  engine_against_all_pairs(LAWS[0], 1, SIZES_SPREAD, 0);
  engine_against_all_pairs(LAWS[3], 3, SIZES_SPREAD, 0);
  engine_against_all_pairs(LAWS[5], 1, SIZES_SPREAD, 0);
  for (int sizes = SIZES_FEW_LARGE; sizes <= SIZES_FEW_SMALL; sizes++) {
    engine_against_all_pairs(LAWS[0], 1, sizes, 0);
    engine_against_all_pairs(LAWS[3], 3, sizes, 0);
  }
  for (int idle = 1; idle <= 2; idle++) {
    engine_against_all_pairs(ONE_LAW, 1, SIZES_ONE_CLASS, idle);    /* the batches' group-bit exclusions */
    engine_against_all_pairs(LAWS[0], 1, SIZES_ONE_CLASS, idle);
    engine_against_all_pairs(LAWS[5], 3, SIZES_ONE_CLASS, idle);
    engine_against_all_pairs(LAWS[3], 1, SIZES_SPREAD, idle);
  }
  make_configuration(0.05, 0.2); /* radius ratio up to 1:4 */
  static const unsigned char exclude_22[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};
  for (int mode = GRIDDEM_CELL_EXACT; mode <= GRIDDEM_CELL_FIXED; mode++) {
    for (size_t k = 0; k < sizeof(LAWS) / sizeof(LAWS[0]); k++) {
      const griddem_model m = model_of(LAWS[k]);
      compare_mode(mode, LAWS[k], &m, NULL, 1);
    }
    for (size_t k = 0; k < sizeof(COMPILED_ROWS) / sizeof(COMPILED_ROWS[0]); k++) {
      const griddem_model m = model_of(COMPILED_ROWS[k]);
      compare_mode(mode, COMPILED_ROWS[k], &m, NULL, 1 + 2 * (k == 0));
    }
    for (size_t k = 0; k < sizeof(NEAR_ROWS) / sizeof(NEAR_ROWS[0]); k++) {
      const griddem_model m = model_of(NEAR_ROWS[k]);
      compare_mode(mode, NEAR_ROWS[k], &m, NULL, 1);
    }
    const griddem_model m = model_of(LAWS[3]);
    compare_mode(mode, "granular, type pair 2-2 excluded", &m, exclude_22, 1);
    compare_mode(mode, "granular, 3 threads", &m, NULL, 3);
    /* one classic law with shear history for every type pair: the sweep's batches */
    const griddem_model one = model_of(ONE_LAW);
    compare_mode(mode, ONE_LAW, &one, NULL, 1);
    compare_mode(mode, "one law in batches, type pair 2-2 excluded", &one, exclude_22, 1);
    compare_mode(mode, "one law in batches, 3 threads", &one, NULL, 3);
  }
  make_configuration(0.1, 0.1); /* one radius: the vector kernels' own path */
  { const char *keep = getenv("KEEP"); if (keep) { int kk[8], nk = sscanf(keep, "%d,%d,%d,%d", kk, kk+1, kk+2, kk+3);
    for (int i = 0; i < N; i++) { int kept = 0; for (int q = 0; q < nk; q++) kept |= i == kk[q];
      if (!kept) x[3*i] = 3.0 + (i % 20) * 0.3, x[3*i+1] = 3.0 + (i / 20 % 20) * 0.3, x[3*i+2] = 3.0; } } }
  for (int mode = GRIDDEM_CELL_EXACT; mode <= GRIDDEM_CELL_FIXED; mode++) {
    const griddem_model one = model_of(ONE_LAW); /* model_of's laws live in one table: one model at a time */
    compare_mode(mode, "one radius, one law in batches", &one, NULL, 1);
    const griddem_model granular = model_of(LAWS[3]);
    compare_mode(mode, "one radius, granular, 3 threads", &granular, NULL, 3);
  }
  check_faults("hooke 1 0 damping mass_velocity tangential gran/hooke/history 1 0 %g");
  check_faults("hooke 1 0 damping mass_velocity tangential gran/hooke/history 1 0 0.5");
}

int main(void)
{
  static const char *const kernels[] = {"scalar", "avx2", "avx512"};
  for (size_t k = 0; k < sizeof(kernels) / sizeof(kernels[0]); k++) {
    if (griddem_touching_use(kernels[k]) != 0) {
      printf("search kernel %s: not run by this processor\n", kernels[k]);
      continue;
    }
    const int failed = check_failed;
    all_checks();
    printf("search kernel %s: %d failed\n", kernels[k], check_failed - failed);
  }
  return check_summary();
}
