/* The stencil sweep finds every contact: forces, torques, virial, energy and history match an
 * all-pairs evaluation of the same contact law from both sides of every pair (the sweep evaluates
 * each pair once and hands the partner the mirrored result) on a dense polydisperse (1:4)
 * configuration of two types, in every cell mode, for the hooke and granular laws, with excluded
 * type pairs and with 1 or 3 threads; momentum balance holds; faults name the particles. */
#include "check.h"
#include "griddem_sweep.h"

#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <string.h>

enum { N = 400, SLOTS = 64 };
static double x[3 * N], v[3 * N], w[3 * N], rad[N], mass[N];
static int tag[N], type[N], mask[N];

static void make_configuration(void)
{
  for (int i = 0; i < N; i++) {
    rad[i] = 0.05 + 0.15 * check_uniform(); /* radius ratio up to 1:4 */
    mass[i] = 4.0 * rad[i] * rad[i] * rad[i];
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

/* All ordered pairs from i's view, history in a dense matrix of nv values per ordered pair. */
static void all_pairs(const griddem_model *m, const unsigned char *excluded, double dt, int update,
                      double *hist, double *f, double *t, double *vir, double *energy, long *contacts)
{
  const int nv = m->history_size;
  memset(f, 0, sizeof(double) * 3 * N);
  memset(t, 0, sizeof(double) * 3 * N);
  memset(vir, 0, sizeof(double) * 6);
  *energy = 0.0;
  *contacts = 0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      if (i == j || (excluded && excluded[type[i] * 3 + type[j]])) continue;
      griddem_contact_in c;
      c.delx = x[3 * i] - x[3 * j], c.dely = x[3 * i + 1] - x[3 * j + 1];
      c.delz = x[3 * i + 2] - x[3 * j + 2];
      c.rsq = c.delx * c.delx + c.dely * c.dely + c.delz * c.delz;
      double *h = hist + GRIDDEM_MAX_HISTORY * ((size_t) i * N + j);
      if (c.rsq >= (rad[i] + rad[j]) * (rad[i] + rad[j])) {
        for (int k = 0; k < GRIDDEM_MAX_HISTORY; k++) h[k] = 0.0;
        continue;
      }
      c.radi = rad[i], c.radj = rad[j];
      c.vr1 = v[3 * i] - v[3 * j], c.vr2 = v[3 * i + 1] - v[3 * j + 1];
      c.vr3 = v[3 * i + 2] - v[3 * j + 2];
      c.wi1 = w[3 * i], c.wi2 = w[3 * i + 1], c.wi3 = w[3 * i + 2];
      c.wj1 = w[3 * j], c.wj2 = w[3 * j + 1], c.wj3 = w[3 * j + 2];
      c.meff = griddem_effective_mass(mass[i], mass[j], 0, 0);
      double fc[3], ti[3], tj[3], hv[GRIDDEM_MAX_HISTORY] = {0};
      for (int k = 0; k < nv; k++) hv[k] = h[k];
      *energy += 0.5 * griddem_pair_contact(m, type[i], type[j], &c, dt, update, hv, fc, ti, tj, NULL);
      for (int k = 0; k < nv; k++) h[k] = hv[k];
      for (int d = 0; d < 3; d++) f[3 * i + d] += fc[d], t[3 * i + d] += ti[d];
      vir[0] += 0.5 * c.delx * fc[0], vir[1] += 0.5 * c.dely * fc[1];
      vir[2] += 0.5 * c.delz * fc[2], vir[3] += 0.5 * c.delx * fc[1];
      vir[4] += 0.5 * c.delx * fc[2], vir[5] += 0.5 * c.dely * fc[2];
      (*contacts)++;
    }
}

static double max_abs(const double *a, int n)
{
  double m = 0.0;
  for (int i = 0; i < n; i++) m = fabs(a[i]) > m ? fabs(a[i]) : m;
  return m;
}

static void compare_mode(int mode, const griddem_model *m, const unsigned char *excluded, int threads)
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
  griddem_grid_cover(&g, anchor, N, x, griddem_cell_edge(mode, rmin, rmax, 0.13), 1L << 26);
  griddem_bin_points(&b, &g, N, x, tag, 4);
  griddem_particles part = {N, N, x, v, w, rad, mass, tag, 4, type, mask, 0};
  griddem_exclusions excl = {excluded, 2, 0, NULL};

  griddem_history hist;
  griddem_history_init(&hist, m->history_size, SLOTS);
  int row_of[N];
  for (int i = 0; i < N; i++) row_of[i] = -1;
  static double dense[GRIDDEM_MAX_HISTORY * N * N];
  memset(dense, 0, sizeof(dense));

  static double f[3 * N], t[3 * N], va[6 * N], fr[3 * N], tr[3 * N];
  double vr[6], energy_ref;
  long contacts_ref;
  /* three steps with history: it accumulates and is rotated the same way in both */
  for (int step = 0; step < 3; step++) {
    memset(f, 0, sizeof(f)), memset(t, 0, sizeof(t)), memset(va, 0, sizeof(va));
    griddem_channels_fill(&ch, &b, &part);
    griddem_sweep_result res;
    griddem_sweep(&g, &b, &ch, N, rmax, m, &excl, dt, 1, &hist, row_of, f, t, va, 1, &res);
    for (int k = 0; k < N; k++) row_of[b.order[k]] = k;
    all_pairs(m, excluded, dt, 1, dense, fr, tr, vr, &energy_ref, &contacts_ref);
    const char *law = m->law == GRIDDEM_LAW_HOOKE ? "hooke" : "granular";
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
    CHECK(terr <= 1e-12 * tscale, "%s mode %d step %d: torque error %g of %g", law, mode, step, terr, tscale);
    CHECK(verr <= 1e-12 * max_abs(vr, 6), "%s mode %d step %d: virial error %g", law, mode, step, verr);
    CHECK(fabs(res.energy - energy_ref) <= 1e-12 * energy_ref && energy_ref > 0.0,
          "%s mode %d step %d: energy %g, all-pairs %g", law, mode, step, res.energy, energy_ref);

    /* history rows hold what the all-pairs evaluation holds for each ordered pair */
    double herr = 0.0, hscale = 0.0;
    for (int i = 0; i < N; i++) {
      const double *row = griddem_history_row(&hist, row_of[i]);
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

    /* Newton's third law (the torque lever is the radius, as in stock, so angular momentum is
       not balanced exactly while spheres overlap; no check of it here) */
    double fsum[3] = {0};
    for (int i = 0; i < N; i++)
      for (int d = 0; d < 3; d++) fsum[d] += f[3 * i + d];
    CHECK(max_abs(fsum, 3) <= 1e-11 * fscale, "%s mode %d: net force %g", law, mode, max_abs(fsum, 3));
  }
  griddem_history_free(&hist);
  griddem_bins_free(&b);
  griddem_channels_free(&ch);
}

static griddem_model hooke_model(int tangential)
{
  griddem_model m = {0};
  m.law = GRIDDEM_LAW_HOOKE;
  const griddem_hooke_params p = {2000.0, 2000.0 * 2.0 / 7.0, 50.0, 25.0, 0.5, 0, tangential};
  m.hooke = p;
  m.history_size = tangential == GRIDDEM_TANGENTIAL_HISTORY ? 3 : 0;
  for (int k = 0; k < 3; k++) m.history_parity[k] = -1.0;
  return m;
}

static void check_faults(void)
{
  griddem_model m = hooke_model(GRIDDEM_TANGENTIAL_HISTORY);
  m.hooke.kn = m.hooke.kt = 1.0, m.hooke.gamman = m.hooke.gammat = 0.0;
  const double anchor[3] = {0.0, 0.0, 0.0};
  double px[9] = {0, 0, 0, 1, 1, 1, 1, 1, 1}, pv[9] = {0}, pw[9] = {0}, pr[3] = {1, 1, 1},
         pm[3] = {1, 1, 1};
  int ptag[3] = {10, 20, 30}, ptype[3] = {1, 1, 1}, pmask[3] = {1, 1, 1};
  griddem_grid g;
  griddem_bins b = {0};
  griddem_channels ch = {0};
  griddem_particles part = {3, 3, px, pv, pw, pr, pm, ptag, 4, ptype, pmask, 0};
  double f[9] = {0}, t[9] = {0};
  int row_of[3] = {-1, -1, -1};
  griddem_history hist;
  griddem_history_init(&hist, 3, 4);
  griddem_sweep_result res;

  griddem_grid_cover(&g, anchor, 3, px, 1.0, 1000);
  griddem_bin_points(&b, &g, 3, px, ptag, 4);
  griddem_channels_fill(&ch, &b, &part);
  griddem_sweep(&g, &b, &ch, 3, 1.0, &m, NULL, 1e-3, 1, &hist, row_of, f, t, NULL, 0, &res);
  CHECK(res.fault == GRIDDEM_FAULT_COINCIDENT, "coincident centres reported: %d", res.fault);
  CHECK(res.fault_i == 1 || res.fault_i == 2, "first particle of the coincident pair");
  CHECK(res.fault_j == 3 - res.fault_i, "second particle of the coincident pair");
  CHECK(!isnan(f[0]) && !isnan(f[3]), "no NaN forces");

  /* particle 0 touches both others but has one slot */
  griddem_history_free(&hist);
  griddem_history_init(&hist, 3, 1);
  px[3] = 1.5, px[4] = 0.0, px[5] = 0.0, px[6] = 0.0, px[7] = 1.5, px[8] = 0.0;
  griddem_grid_cover(&g, anchor, 3, px, 1.0, 1000);
  griddem_bin_points(&b, &g, 3, px, ptag, 4);
  griddem_channels_fill(&ch, &b, &part);
  griddem_sweep(&g, &b, &ch, 3, 1.0, &m, NULL, 1e-3, 1, &hist, row_of, f, t, NULL, 0, &res);
  CHECK(res.fault == GRIDDEM_FAULT_HISTORY_FULL && (res.fault_i == 0 || res.fault_j == 0),
        "history overflow reported for particle 0: fault %d i %d j %d", res.fault, res.fault_i, res.fault_j);
  griddem_history_free(&hist);
  griddem_bins_free(&b);
  griddem_channels_free(&ch);
}

/* hertz + viscoelastic + linear_history + sds for types 1-1, other stiffness and friction for
 * the pairs with type 2, so the per-type-pair table is exercised */
static griddem_granular_params granular_table[9];

static griddem_model granular_model(void)
{
  griddem_model m = {0};
  m.law = GRIDDEM_LAW_GRANULAR;
  m.ntypes = 2;
  m.granular = granular_table;
  for (int a = 1; a <= 2; a++)
    for (int b = 1; b <= 2; b++) {
      griddem_granular_params *p = &granular_table[a * 3 + b];
      memset(p, 0, sizeof(*p));
      p->normal = GRIDDEM_NORMAL_HERTZ, p->damping = GRIDDEM_DAMPING_VISCOELASTIC;
      p->tangential = GRIDDEM_TANGENTIAL_HISTORY, p->rolling = GRIDDEM_ROLLING_SDS;
      p->kn = 4e4 * (a + b), p->damp = 5.0, p->kt = 1500.0, p->xt = 0.5, p->mu = 0.2 * (a + b);
      p->kroll = 20.0, p->gammaroll = 0.1, p->muroll = 0.05;
    }
  m.history_size = 6;
  for (int k = 0; k < 6; k++) m.history_parity[k] = k < 3 ? -1.0 : 1.0;
  return m;
}

int main(void)
{
  make_configuration();
  static const unsigned char exclude_22[9] = {0, 0, 0, 0, 0, 0, 0, 0, 1};
  for (int mode = GRIDDEM_CELL_EXACT; mode <= GRIDDEM_CELL_FIXED; mode++) {
    for (int tangential = GRIDDEM_TANGENTIAL_NONE; tangential <= GRIDDEM_TANGENTIAL_HISTORY; tangential++) {
      const griddem_model m = hooke_model(tangential);
      compare_mode(mode, &m, NULL, 1);
    }
    const griddem_model m = granular_model();
    compare_mode(mode, &m, NULL, 1);
    compare_mode(mode, &m, exclude_22, 1);
    compare_mode(mode, &m, NULL, 3);
  }
  check_faults();
  return check_summary();
}
