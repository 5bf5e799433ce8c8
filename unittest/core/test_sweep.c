/* The stencil sweep finds every contact: forces, torques, virial and history match an all-pairs
 * evaluation of the same contact law on a dense polydisperse (1:4) configuration, in every cell
 * mode; momentum balance holds; faults name the particles. */
#include "check.h"
#include "griddem_sweep.h"

#include <stdlib.h>
#include <string.h>

enum { N = 400, SLOTS = 64 };
static double x[3 * N], v[3 * N], w[3 * N], rad[N], mass[N];
static int tag[N];

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
  }
}

/* All pairs, i's view, history in a dense matrix. */
static void all_pairs(const griddem_hooke_params *p, double dt, int update, double *shear,
                      double *f, double *t, double *vir, long *contacts)
{
  memset(f, 0, sizeof(double) * 3 * N);
  memset(t, 0, sizeof(double) * 3 * N);
  memset(vir, 0, sizeof(double) * 6);
  *contacts = 0;
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      if (i == j) continue;
      griddem_contact_in c;
      c.delx = x[3 * i] - x[3 * j], c.dely = x[3 * i + 1] - x[3 * j + 1];
      c.delz = x[3 * i + 2] - x[3 * j + 2];
      c.rsq = c.delx * c.delx + c.dely * c.dely + c.delz * c.delz;
      double *s = shear + 3 * ((size_t) i * N + j);
      if (c.rsq >= (rad[i] + rad[j]) * (rad[i] + rad[j])) {
        s[0] = s[1] = s[2] = 0.0;
        continue;
      }
      c.radi = rad[i], c.radj = rad[j];
      c.vr1 = v[3 * i] - v[3 * j], c.vr2 = v[3 * i + 1] - v[3 * j + 1];
      c.vr3 = v[3 * i + 2] - v[3 * j + 2];
      c.wi1 = w[3 * i], c.wi2 = w[3 * i + 1], c.wi3 = w[3 * i + 2];
      c.wj1 = w[3 * j], c.wj2 = w[3 * j + 1], c.wj3 = w[3 * j + 2];
      c.meff = griddem_effective_mass(mass[i], mass[j], 0, 0);
      double fc[3], tor[3];
      griddem_hooke_contact(p, &c, dt, update, s, fc, tor);
      for (int d = 0; d < 3; d++) f[3 * i + d] += fc[d], t[3 * i + d] -= rad[i] * tor[d];
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

static void compare_mode(int mode, int tangential)
{
  griddem_hooke_params p = {2000.0, 2000.0 * 2.0 / 7.0, 50.0, 25.0, 0.5, 0, tangential};
  const double dt = 1e-4, anchor[3] = {0.0, 0.0, 0.0};
  double rmin = 1e30, rmax = 0.0;
  for (int i = 0; i < N; i++) rmin = rad[i] < rmin ? rad[i] : rmin, rmax = rad[i] > rmax ? rad[i] : rmax;

  griddem_grid g;
  griddem_bins b = {0};
  griddem_channels ch = {0};
  griddem_grid_cover(&g, anchor, N, x, griddem_cell_edge(mode, rmin, rmax, 0.13), 1L << 26);
  griddem_bin_points(&b, &g, N, x, tag, 4);
  griddem_particles part = {N, N, x, v, w, rad, mass, tag, 4, NULL, 0};
  griddem_channels_fill(&ch, &b, &part);

  static double hist_rows[N * GRIDDEM_HISTORY_STRIDE(SLOTS)];
  memset(hist_rows, 0, sizeof(hist_rows));
  griddem_history hist = {hist_rows, GRIDDEM_HISTORY_STRIDE(SLOTS), SLOTS};
  static double shear[3 * N * N];
  memset(shear, 0, sizeof(shear));

  static double f[3 * N], t[3 * N], va[6 * N], fr[3 * N], tr[3 * N];
  double vr[6];
  long contacts_ref;
  /* three steps with history: shear accumulates and is rotated the same way in both */
  for (int step = 0; step < 3; step++) {
    memset(f, 0, sizeof(f)), memset(t, 0, sizeof(t)), memset(va, 0, sizeof(va));
    griddem_sweep_result res;
    griddem_sweep(&g, &b, &ch, N, rmax, &p, dt, 1, &hist, f, t, va, 1, &res);
    all_pairs(&p, dt, 1, shear, fr, tr, vr, &contacts_ref);
    CHECK(res.fault == GRIDDEM_FAULT_NONE, "mode %d: fault %d", mode, res.fault);
    CHECK(res.contacts == contacts_ref, "mode %d step %d: %ld contacts, all-pairs %ld", mode, step,
          res.contacts, contacts_ref);
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
    CHECK(ferr <= 1e-12 * fscale, "mode %d step %d: force error %g of %g", mode, step, ferr, fscale);
    CHECK(terr <= 1e-12 * tscale, "mode %d step %d: torque error %g of %g", mode, step, terr, tscale);
    CHECK(verr <= 1e-12 * max_abs(vr, 6), "mode %d step %d: virial error %g", mode, step, verr);

    /* Newton's third law (the torque lever is the radius, as in stock, so angular momentum is
       not balanced exactly while spheres overlap; no check of it here) */
    double fsum[3] = {0};
    for (int i = 0; i < N; i++)
      for (int d = 0; d < 3; d++) fsum[d] += f[3 * i + d];
    CHECK(max_abs(fsum, 3) <= 1e-11 * fscale, "mode %d: net force %g", mode, max_abs(fsum, 3));
  }
  griddem_bins_free(&b);
  griddem_channels_free(&ch);
}

static void check_faults(void)
{
  griddem_hooke_params p = {1.0, 1.0, 0.0, 0.0, 0.5, 0, GRIDDEM_TANGENTIAL_HISTORY};
  const double anchor[3] = {0.0, 0.0, 0.0};
  double px[9] = {0, 0, 0, 1, 1, 1, 1, 1, 1}, pv[9] = {0}, pw[9] = {0}, pr[3] = {1, 1, 1},
         pm[3] = {1, 1, 1};
  int ptag[3] = {10, 20, 30};
  griddem_grid g;
  griddem_bins b = {0};
  griddem_channels ch = {0};
  griddem_particles part = {3, 3, px, pv, pw, pr, pm, ptag, 4, NULL, 0};
  double rows[3 * GRIDDEM_HISTORY_STRIDE(4)] = {0}, f[9] = {0}, t[9] = {0};
  griddem_history hist = {rows, GRIDDEM_HISTORY_STRIDE(4), 4};
  griddem_sweep_result res;

  griddem_grid_cover(&g, anchor, 3, px, 1.0, 1000);
  griddem_bin_points(&b, &g, 3, px, ptag, 4);
  griddem_channels_fill(&ch, &b, &part);
  griddem_sweep(&g, &b, &ch, 3, 1.0, &p, 1e-3, 1, &hist, f, t, NULL, 0, &res);
  CHECK(res.fault == GRIDDEM_FAULT_COINCIDENT, "coincident centres reported: %d", res.fault);
  CHECK(res.fault_i == 1 || res.fault_i == 2, "first particle of the coincident pair");
  CHECK(res.fault_j == 3 - res.fault_i, "second particle of the coincident pair");
  CHECK(!isnan(f[0]) && !isnan(f[3]), "no NaN forces");

  /* particle 0 touches both others but has one slot */
  hist.slots = 1;
  px[3] = 1.5, px[4] = 0.0, px[5] = 0.0, px[6] = 0.0, px[7] = 1.5, px[8] = 0.0;
  griddem_grid_cover(&g, anchor, 3, px, 1.0, 1000);
  griddem_bin_points(&b, &g, 3, px, ptag, 4);
  griddem_channels_fill(&ch, &b, &part);
  griddem_sweep(&g, &b, &ch, 3, 1.0, &p, 1e-3, 1, &hist, f, t, NULL, 0, &res);
  CHECK(res.fault == GRIDDEM_FAULT_HISTORY_FULL && res.fault_i == 0,
        "history overflow reported for particle 0: fault %d i %d", res.fault, res.fault_i);
  griddem_bins_free(&b);
  griddem_channels_free(&ch);
}

int main(void)
{
  make_configuration();
  for (int mode = GRIDDEM_CELL_EXACT; mode <= GRIDDEM_CELL_FIXED; mode++) {
    compare_mode(mode, GRIDDEM_TANGENTIAL_HISTORY);
    compare_mode(mode, GRIDDEM_TANGENTIAL_DAMPED);
    compare_mode(mode, GRIDDEM_TANGENTIAL_NONE);
  }
  check_faults();
  return check_summary();
}
