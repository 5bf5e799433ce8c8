/* The linear spring-dashpot against its analytic solution: a head-on collision integrated with
 * velocity Verlet has restitution e = exp(-pi z / sqrt(1 - z^2)), z = eta / (2 sqrt(k meff)),
 * eta = meff*gamman, and lasts pi / sqrt(k/meff - (eta/(2 meff))^2). Plus exact antisymmetry
 * of the pair law and the Coulomb cap of the history model. */
#include "check.h"
#include "griddem_contact.h"

static griddem_contact_in head_on(double gap_x, double vrel, double m)
{
  griddem_contact_in c = {0};
  c.delx = gap_x, c.rsq = gap_x * gap_x, c.radi = c.radj = 0.5;
  c.vr1 = vrel, c.meff = griddem_effective_mass(m, m, 0, 0);
  return c;
}

/* Two equal spheres of mass m (diameter 1) approach head on at relative speed v0; velocity Verlet
 * in the relative coordinate. Returns the relative speed after the collision and sets the time
 * spent in contact. */
static double collide(const griddem_model *model, double m, double dt, double v0, double *duration)
{
  double s = 1.0, vs = -v0, h[GRIDDEM_MAX_HISTORY] = {0}, f[3], ti[3], tj[3];
  double t = 0.0, t_in = -1.0, t_out = -1.0, a = 0.0;
  while (t < 1.0 && t_out < 0.0) {
    vs += 0.5 * dt * a;
    s += dt * vs;
    t += dt;
    if (s < 1.0) {
      if (t_in < 0.0) t_in = t;
      griddem_contact_in c = head_on(s, vs, m);
      griddem_pair_contact(model, 0, 0, &c, dt, 1, h, f, ti, tj, NULL);
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

static void restitution(double gamman)
{
  const double k = 5e4, m = 1.0;
  griddem_model model = {0};
  model.law = GRIDDEM_LAW_HOOKE;
  const griddem_hooke_params p = {k, 2.0 / 7.0 * k, gamman, 0.0, 0.0, 0, GRIDDEM_TANGENTIAL_NONE};
  model.hooke = p;
  double duration_seen;
  const double v = collide(&model, m, 1e-6, 1.0, &duration_seen);
  const double meff = m / 2.0, eta = meff * gamman, z = eta / (2.0 * sqrt(k * meff));
  const double e = exp(-M_PI * z / sqrt(1.0 - z * z));
  const double duration = M_PI / sqrt(k / meff - (eta / (2.0 * meff)) * (eta / (2.0 * meff)));
  CHECK_CLOSE(v, e, 1e-3, 0.0);
  CHECK_CLOSE(duration_seen, duration, 1e-3, 0.0);
}

/* The granular law seen from j mirrors the one seen from i: force odd, torques swapped, the
 * tangential history odd and the rolling history even, over several steps with both caps hit. */
static void granular_mirror(const griddem_contact_in *ij, const griddem_contact_in *ji, int normal,
                            int damping, int tangential)
{
  griddem_granular_params p = {0};
  p.normal = normal, p.damping = damping, p.tangential = tangential;
  p.rolling = GRIDDEM_ROLLING_SDS;
  p.kn = 1e4, p.damp = 0.3, p.kt = 800.0, p.xt = 0.5, p.mu = 0.3;
  p.kroll = 50.0, p.gammaroll = 0.2, p.muroll = 0.05;
  double hi[6] = {1e-3, 2e-3, -1e-3, 4e-4, -2e-4, 1e-4}, hj[6];
  const int nt = tangential == GRIDDEM_TANGENTIAL_HISTORY ? 3 : 0;
  const double *hr = hi + nt;
  for (int k = 0; k < 6; k++) hj[k] = k < nt ? -hi[k] : hi[k];
  double *hrj = hj + nt;
  int capped = 0;
  for (int step = 0; step < 6; step++) {
    double fi[3], fj[3], ti[3], tj[3], ti2[3], tj2[3];
    const double ei = griddem_granular_contact(&p, ij, 1e-3, 1, hi, fi, ti, tj, NULL);
    const double ej = griddem_granular_contact(&p, ji, 1e-3, 1, hj, fj, tj2, ti2, NULL);
    for (int d = 0; d < 3; d++) {
      CHECK(fi[d] == -fj[d], "granular %d/%d/%d force mirror step %d", normal, damping, tangential, step);
      CHECK(ti[d] == ti2[d] && tj[d] == tj2[d], "granular torque mirror step %d", step);
      if (nt) CHECK(hi[d] == -hj[d], "tangential history odd, step %d", step);
      CHECK(hr[d] == hrj[d], "rolling history even, step %d", step);
    }
    CHECK(ei == ej, "granular energy mirror step %d", step);
    capped += sqrt(hr[0] * hr[0] + hr[1] * hr[1] + hr[2] * hr[2]) > 0.0;
  }
  CHECK(capped > 0, "rolling history engaged");
}

/* Hertz without damping conserves energy in a head-on collision: the rebound speed equals the
 * approach speed v, and for meff s'' = -K delta^(3/2) the contact lasts 2.9432 delta_max / v with
 * delta_max = (5 meff v^2 / (4 K))^(2/5) (2 * integral_0^1 dx / sqrt(1 - x^(5/2)) = 2.9432). */
static void hertz_restitution(void)
{
  griddem_granular_params p = {0};
  p.normal = GRIDDEM_NORMAL_HERTZ, p.damping = GRIDDEM_DAMPING_VISCOELASTIC;
  p.tangential = GRIDDEM_TANGENTIAL_DAMPED, p.kn = 1e5, p.damp = 0.0;
  griddem_model model = {0};
  model.law = GRIDDEM_LAW_GRANULAR;
  model.granular = &p;
  const double m = 1.0, v0 = 1.0;
  double duration_seen;
  const double v = collide(&model, m, 1e-7, v0, &duration_seen);
  /* F = k a delta with contact radius a = sqrt(R delta), R = 1/4: K = k R^(1/2); meff = m/2 */
  const double meff = 0.5 * m, K = p.kn * sqrt(0.25);
  const double delta_max = pow(5.0 * meff * v0 * v0 / (4.0 * K), 0.4);
  const double duration = 2.9432 * delta_max / v0;
  CHECK_CLOSE(v, v0, 1e-6, 0.0);
  CHECK_CLOSE(duration_seen, duration, 1e-3, 0.0);
}

int main(void)
{
  restitution(0.0);   /* elastic: e = 1 */
  restitution(20.0);  /* z = 0.032 */
  restitution(100.0); /* z = 0.158 */

  /* i's view and j's view of one contact are exact mirrors */
  const griddem_hooke_params p = {1e3, 300.0, 20.0, 10.0, 0.4, 0, GRIDDEM_TANGENTIAL_HISTORY};
  griddem_contact_in ij = {0.3, -0.4, 0.5, 0.5, 0.42, 0.37, 1.1, -0.7, 0.2,
                           3.0, -1.0, 2.0, -0.5, 0.25, 1.5, 0.8};
  ij.rsq = ij.delx * ij.delx + ij.dely * ij.dely + ij.delz * ij.delz;
  griddem_contact_in ji = ij;
  ji.delx = -ij.delx, ji.dely = -ij.dely, ji.delz = -ij.delz;
  ji.radi = ij.radj, ji.radj = ij.radi;
  ji.vr1 = -ij.vr1, ji.vr2 = -ij.vr2, ji.vr3 = -ij.vr3;
  ji.wi1 = ij.wj1, ji.wi2 = ij.wj2, ji.wi3 = ij.wj3, ji.wj1 = ij.wi1, ji.wj2 = ij.wi2, ji.wj3 = ij.wi3;
  double si[3] = {1e-3, 2e-3, -1e-3}, sj[3] = {-1e-3, -2e-3, 1e-3};
  for (int step = 0; step < 5; step++) {
    double fi[3], fj[3], ti[3], tj[3], ti2[3], tj2[3];
    const double ei = griddem_hooke_contact(&p, &ij, 1e-3, 1, si, fi, ti, tj, NULL);
    const double ej = griddem_hooke_contact(&p, &ji, 1e-3, 1, sj, fj, tj2, ti2, NULL);
    for (int d = 0; d < 3; d++) {
      CHECK(fi[d] == -fj[d], "force mirror step %d axis %d: %.17g %.17g", step, d, fi[d], fj[d]);
      CHECK(ti[d] == ti2[d] && tj[d] == tj2[d], "torque mirror step %d axis %d", step, d);
      CHECK(si[d] == -sj[d], "shear mirror step %d axis %d", step, d);
    }
    CHECK(ei == ej && ei > 0.0, "energy mirror step %d", step);
  }
  granular_mirror(&ij, &ji, GRIDDEM_NORMAL_HERTZ, GRIDDEM_DAMPING_VISCOELASTIC, GRIDDEM_TANGENTIAL_HISTORY);
  granular_mirror(&ij, &ji, GRIDDEM_NORMAL_HOOKE, GRIDDEM_DAMPING_TSUJI, GRIDDEM_TANGENTIAL_HISTORY);
  granular_mirror(&ij, &ji, GRIDDEM_NORMAL_HOOKE, GRIDDEM_DAMPING_MASS_VELOCITY, GRIDDEM_TANGENTIAL_DAMPED);
  granular_mirror(&ij, &ji, GRIDDEM_NORMAL_HERTZ, GRIDDEM_DAMPING_VELOCITY, GRIDDEM_TANGENTIAL_DAMPED);
  hertz_restitution();
  /* Coulomb: the tangential force never exceeds xmu * |normal force| */
  const double r = sqrt(ij.rsq), fn = p.kn * (ij.radi + ij.radj - r) / r * r;
  double sh[3] = {0.5, 0.5, 0.5}, f[3], ti[3], tj[3];
  griddem_hooke_contact(&p, &ij, 1e-3, 1, sh, f, ti, tj, NULL);
  const double nx = ij.delx / r, ny = ij.dely / r, nz = ij.delz / r;
  const double fnormal = f[0] * nx + f[1] * ny + f[2] * nz;
  const double ft2 = (f[0] - fnormal * nx) * (f[0] - fnormal * nx) +
      (f[1] - fnormal * ny) * (f[1] - fnormal * ny) + (f[2] - fnormal * nz) * (f[2] - fnormal * nz);
  CHECK(sqrt(ft2) <= p.xmu * fabs(fnormal) * (1 + 1e-12), "Coulomb cap %g > %g", sqrt(ft2),
        p.xmu * fabs(fnormal));
  CHECK(fn > 0.0, "overlapping pair repels");
  return check_summary();
}
