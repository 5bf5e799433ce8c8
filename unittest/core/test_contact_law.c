/* The composed contact law. Analytic: a linear spring-dashpot head-on collision integrated with
 * velocity Verlet has restitution e = exp(-pi z / sqrt(1 - z^2)), z = eta / (2 sqrt(k meff)),
 * eta = meff*gamman, and lasts pi / sqrt(k/meff - (eta/(2 meff))^2); undamped Hertz rebounds at
 * the approach speed after 2.9432 delta_max / v; coeff_restitution damping gives the restitution
 * it is asked for. Exact: every sub-model of the table (in the laws of the rows' examples), seen
 * from j, mirrors i's view bit for bit
 * (force odd, torques swapped, history odd or even as its row says), which the sweep's single
 * evaluation per pair relies on; friction never exceeds the Coulomb cap; jkr holds a pair past
 * touching only if it touched before, up to its pull-off distance. */
#include "check.h"
#include "griddem_contact.h"
#include "spec_text.h"

static void set_head_on(griddem_contact *c, double gap_x, double vrel, double m, double dt)
{
  memset(c, 0, sizeof(*c));
  c->dx[0] = gap_x, c->rsq = gap_x * gap_x, c->radi = c->radj = 0.5;
  c->vr[0] = vrel, c->meff = griddem_effective_mass(m, m, 0, 0);
  c->dt = dt, c->history_update = 1;
}

/* Two equal spheres of mass m (diameter 1) approach head on at relative speed v0; velocity Verlet
 * in the relative coordinate. Returns the relative speed after the collision and sets the time
 * spent in contact. */
static double collide(const griddem_pair_params *law, double m, double dt, double v0, double *duration)
{
  double s = 1.0, vs = -v0, h[GRIDDEM_MAX_HISTORY] = {0}, f[3], ti[3], tj[3];
  double t = 0.0, t_in = -1.0, t_out = -1.0, a = 0.0;
  while (t < 1.0 && t_out < 0.0) {
    vs += 0.5 * dt * a;
    s += dt * vs;
    t += dt;
    if (s < 1.0) {
      if (t_in < 0.0) t_in = t;
      griddem_contact c;
      set_head_on(&c, s, vs, m, dt);
      griddem_contact_eval(law, &c, h, f, ti, tj);
      a = 2.0 * f[0] / m; /* relative acceleration: f/m on each, opposite */
    } else {
      if (t_in >= 0.0) t_out = t;
      a = 0.0;
    }
    vs += 0.5 * dt * a;
  }
  *duration = t_out - t_in;
  return vs;
}

static void hooke_restitution(double gamman)
{
  const double k = 5e4, m = 1.0;
  char text[128];
  snprintf(text, sizeof(text), "hooke %.17g %.17g damping mass_velocity tangential linear_nohistory 0 0", k, gamman);
  const griddem_pair_params law = law_from_text(text);
  double duration_seen;
  const double v = collide(&law, m, 1e-6, 1.0, &duration_seen);
  const double meff = m / 2.0, eta = meff * gamman, z = eta / (2.0 * sqrt(k * meff));
  const double e = exp(-M_PI * z / sqrt(1.0 - z * z));
  const double duration = M_PI / sqrt(k / meff - (eta / (2.0 * meff)) * (eta / (2.0 * meff)));
  CHECK_CLOSE(v, e, 1e-3, 0.0);
  CHECK_CLOSE(duration_seen, duration, 1e-3, 0.0);
}

/* hooke + coeff_restitution: the damping is derived so that a collision rebounds with e */
static void asked_restitution(double e)
{
  char text[128];
  snprintf(text, sizeof(text), "hooke 5e4 %.17g damping coeff_restitution tangential linear_nohistory 0 0", e);
  const griddem_pair_params law = law_from_text(text);
  double duration;
  CHECK_CLOSE(collide(&law, 1.0, 1e-6, 1.0, &duration), e, 2e-3, 0.0);
}

/* Hertz without damping conserves energy in a head-on collision: the rebound speed equals the
 * approach speed v, and for meff s'' = -K delta^(3/2) the contact lasts 2.9432 delta_max / v with
 * delta_max = (5 meff v^2 / (4 K))^(2/5) (2 * integral_0^1 dx / sqrt(1 - x^(5/2)) = 2.9432). */
static void hertz_restitution(void)
{
  const griddem_pair_params law = law_from_text("hertz 1e5 0 tangential linear_nohistory 0 0");
  const double m = 1.0, v0 = 1.0;
  double duration_seen;
  const double v = collide(&law, m, 1e-7, v0, &duration_seen);
  /* F = k a delta with contact radius a = sqrt(R delta), R = 1/4: K = k R^(1/2); meff = m/2 */
  const double meff = 0.5 * m, K = 1e5 * sqrt(0.25);
  const double delta_max = pow(5.0 * meff * v0 * v0 / (4.0 * K), 0.4);
  CHECK_CLOSE(v, v0, 1e-6, 0.0);
  CHECK_CLOSE(duration_seen, 2.9432 * delta_max / v0, 1e-3, 0.0);
}

/* i's and j's views of one contact over several steps with growing tangential loading */
static void mirror(const char *text)
{
  griddem_pair_spec s;
  spec_from_text(text, &s);
  const griddem_pair_params law = law_from_text(text);
  double parity[GRIDDEM_MAX_HISTORY];
  const int nv = griddem_spec_history(&s, parity);
  griddem_contact ij;
  memset(&ij, 0, sizeof(ij));
  const double dx[3] = {0.3, -0.4, 0.5}, vr[3] = {1.1, -0.7, 0.2}, wi[3] = {3.0, -1.0, 2.0},
               wj[3] = {-0.5, 0.25, 1.5};
  for (int d = 0; d < 3; d++) ij.dx[d] = dx[d], ij.vr[d] = vr[d], ij.wi[d] = wi[d], ij.wj[d] = wj[d];
  ij.rsq = griddem_dot3(dx, dx), ij.radi = 0.42, ij.radj = 0.37, ij.meff = 0.8;
  ij.dt = 1e-3, ij.history_update = 1, ij.temp_i = 3.25, ij.temp_j = 1.5;
  double hi[GRIDDEM_MAX_HISTORY] = {1e-3, 2e-3, -1e-3, 0.0, 4e-4, -2e-4, 1e-4, 3e-4}, hj[GRIDDEM_MAX_HISTORY];
  for (int k = 0; k < nv; k++) hj[k] = parity[k] * hi[k];
  int capped = 0;
  for (int step = 0; step < 24; step++) {
    griddem_contact ji = ij;
    for (int d = 0; d < 3; d++) ji.dx[d] = -ij.dx[d], ji.vr[d] = -ij.vr[d], ji.wi[d] = ij.wj[d], ji.wj[d] = ij.wi[d];
    ji.radi = ij.radj, ji.radj = ij.radi, ji.temp_i = ij.temp_j, ji.temp_j = ij.temp_i;
    double fi[3], fj[3], ti[3], tj[3], ti2[3], tj2[3];
    griddem_contact ci = ij, cj = ji;
    const double ei = griddem_contact_eval(&law, &ci, hi, fi, ti, tj);
    const double ej = griddem_contact_eval(&law, &cj, hj, fj, tj2, ti2);
    int same = ei == ej && isfinite(ei);
    for (int d = 0; d < 3; d++)
      same = same && fi[d] == -fj[d] && ti[d] == ti2[d] && tj[d] == tj2[d] && isfinite(fi[d]);
    for (int k = 0; k < nv; k++) same = same && hi[k] == parity[k] * hj[k];
    same = same && ci.heat == -cj.heat && isfinite(ci.heat);
    CHECK(same, "'%s' step %d: j's view mirrors i's", text, step);
    if (law.heat.model != GRIDDEM_HEAT_NONE)    /* i is the hotter: heat flows out of it */
      CHECK(ci.heat < 0.0, "'%s' step %d: heat %g flows out of the hotter i", text, step, ci.heat);
    /* Coulomb: |fs| <= mu * fncrit */
    capped += griddem_len3(ci.fs) >= 0.999999 * law.tangential.mu * ci.fncrit && law.tangential.mu > 0;
    CHECK(griddem_len3(ci.fs) <= law.tangential.mu * ci.fncrit * (1 + 1e-12) + 1e-300,
          "'%s' step %d: friction %g within the cap %g", text, step, griddem_len3(ci.fs), law.tangential.mu * ci.fncrit);
    for (int d = 0; d < 3; d++) ij.wi[d] *= 1.6; /* load the tangential springs harder each step */
  }
  if (law.tangential.model != GRIDDEM_TANGENTIAL_NONE && law.tangential.model != GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY)
    CHECK(capped > 0, "'%s': the Coulomb cap was reached", text);
}

/* jkr: a pair past touching interacts only if it touched before, and up to the pull-off distance
 * 1.2277 (R c^2 / E*^2)^(1/3); there the force is attractive */
static void jkr_reach(void)
{
  const griddem_pair_params law = law_from_text("jkr 1e5 0.3 0.3 50 damping mass_velocity tangential linear_history 800 0.5 0.3");
  const double radi = 0.5, radj = 0.5, reff = 0.25, E = 1e5 / (2.0 * (1 - 0.09));
  const double pulloff = 1.2277228507842888 * cbrt(reff * 50.0 * 50.0 / (E * E));
  CHECK_CLOSE(griddem_pair_reach_extra(&law, radi, radj), pulloff, 1e-14, 0.0);
  const double inside = 1.0 + 0.9 * pulloff, outside = 1.0 + 1.1 * pulloff;
  CHECK(griddem_contact_touch(&law, 0.99 * 0.99, radi, radj, 0), "jkr: overlapping pair touches");
  CHECK(!griddem_contact_touch(&law, inside * inside, radi, radj, 0), "jkr: a new pair past touching does not");
  CHECK(griddem_contact_touch(&law, inside * inside, radi, radj, 1), "jkr: a pair that touched holds inside the pull-off distance");
  CHECK(!griddem_contact_touch(&law, outside * outside, radi, radj, 1), "jkr: and lets go beyond it");
  griddem_contact c;
  set_head_on(&c, inside, 0.0, 1.0, 1e-3);
  double h[GRIDDEM_MAX_HISTORY] = {0}, f[3], ti[3], tj[3];
  griddem_contact_eval(&law, &c, h, f, ti, tj);
  CHECK(f[0] < 0.0 && isfinite(f[0]), "jkr: attraction past touching (%g)", f[0]);
  const griddem_pair_params hertz = law_from_text("hertz 1e4 0.3 tangential linear_history 800 0.5 0.3");
  CHECK(griddem_pair_reach_extra(&hertz, radi, radj) == 0.0, "hertz: no reach past touching");
}

/* heat through a head-on contact of two spheres of radius 0.5 overlapping by 0.02 (contact radius
 * a = sqrt(0.02 * 0.25)): radius 2 k a (T_j - T_i), area k pi a^2 (T_j - T_i) */
static void heat_conduction(void)
{
  const double a = sqrt(0.02 * 0.25);
  const struct {
    const char *text;
    double heat;
  } cases[] = {{"hooke 1e4 50 tangential linear_nohistory 0.5 0.5 heat radius 2.5", 2 * 2.5 * a * (1.0 - 4.0)},
               {"hertz 1e5 20 tangential linear_history 3e4 0.5 0.5 heat area 7.0", 7.0 * M_PI * a * a * (1.0 - 4.0)},
               {"hooke 1e4 50 tangential linear_nohistory 0.5 0.5", 0.0}};
  for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
    const griddem_pair_params law = law_from_text(cases[k].text);
    griddem_contact c;
    set_head_on(&c, 0.98, 0.0, 1.0, 1e-3);
    c.temp_i = 4.0, c.temp_j = 1.0;
    double h[GRIDDEM_MAX_HISTORY] = {0}, f[3], ti[3], tj[3];
    griddem_contact_eval(&law, &c, h, f, ti, tj);
    CHECK_CLOSE(c.heat, cases[k].heat, 1e-14, 0.0);
  }
}

int main(void)
{
#if defined(GRIDDEM_TEST_FMA) && GRIDDEM_TEST_FMA
  /* built with -mfma: without the instruction, nothing to test (and nothing could run) */
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("fma")) {
    printf("SKIPPED: this CPU has no FMA instructions; the contraction test needs them\n");
    return 77;
  }
#endif
  hooke_restitution(0.0);   /* elastic: e = 1 */
  hooke_restitution(20.0);  /* z = 0.032 */
  hooke_restitution(100.0); /* z = 0.158 */
  asked_restitution(0.5);
  asked_restitution(0.9);
  hertz_restitution();
  /* the rows' examples, which together name every row (test_submodels.c) */
  for (size_t k = 0; griddem_submodel_at(k); k++)
    for (int type = 0; type < 2; type++)
      if (griddem_submodel_at(k)->example[type]) mirror(griddem_submodel_at(k)->example[type]);
  jkr_reach();
  heat_conduction();
  return check_summary();
}
