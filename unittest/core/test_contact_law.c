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

static void restitution(double gamman)
{
  const double k = 5e4, m = 1.0, dt = 1e-6;
  const griddem_hooke_params p = {k, 2.0 / 7.0 * k, gamman, 0.0, 0.0, 0, GRIDDEM_TANGENTIAL_NONE};
  /* two equal spheres, relative coordinate s = x_i - x_j, approaching at 1 */
  double s = 1.0, vs = -1.0, shear[3] = {0}, f[3], tor[3];
  double t = 0.0, t_in = -1.0, t_out = -1.0;
  griddem_contact_in c = head_on(s, vs, m);
  griddem_hooke_contact(&p, &c, dt, 0, shear, f, tor);
  double a = (s < 1.0) ? 2.0 * f[0] / m : 0.0; /* relative acceleration: f/m on each, opposite */
  while (t < 1.0 && t_out < 0.0) {
    vs += 0.5 * dt * a;
    s += dt * vs;
    t += dt;
    if (s < 1.0) {
      if (t_in < 0.0) t_in = t;
      c = head_on(s, vs, m);
      griddem_hooke_contact(&p, &c, dt, 0, shear, f, tor);
      a = 2.0 * f[0] / m;
    } else {
      if (t_in >= 0.0) t_out = t;
      a = 0.0;
    }
    vs += 0.5 * dt * a;
  }
  const double meff = m / 2.0, eta = meff * gamman, z = eta / (2.0 * sqrt(k * meff));
  const double e = exp(-M_PI * z / sqrt(1.0 - z * z));
  const double duration = M_PI / sqrt(k / meff - (eta / (2.0 * meff)) * (eta / (2.0 * meff)));
  CHECK_CLOSE(vs, e, 1e-3, 0.0);
  CHECK_CLOSE(t_out - t_in, duration, 1e-3, 0.0);
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
  double si[3] = {1e-3, 2e-3, -1e-3}, sj[3] = {-1e-3, -2e-3, 1e-3}, fi[3], fj[3], ti[3], tj[3];
  for (int step = 0; step < 5; step++) {
    griddem_hooke_contact(&p, &ij, 1e-3, 1, si, fi, ti);
    griddem_hooke_contact(&p, &ji, 1e-3, 1, sj, fj, tj);
    for (int d = 0; d < 3; d++) {
      CHECK(fi[d] == -fj[d], "force mirror step %d axis %d: %.17g %.17g", step, d, fi[d], fj[d]);
      CHECK(ti[d] == tj[d], "torque factor mirror step %d axis %d", step, d);
      CHECK(si[d] == -sj[d], "shear mirror step %d axis %d", step, d);
    }
  }
  /* Coulomb: the tangential force never exceeds xmu * |normal force| */
  const double r = sqrt(ij.rsq), fn = p.kn * (ij.radi + ij.radj - r) / r * r;
  double sh[3] = {0.5, 0.5, 0.5}, f[3], tor[3];
  griddem_hooke_contact(&p, &ij, 1e-3, 1, sh, f, tor);
  const double nx = ij.delx / r, ny = ij.dely / r, nz = ij.delz / r;
  const double fnormal = f[0] * nx + f[1] * ny + f[2] * nz;
  const double ft2 = (f[0] - fnormal * nx) * (f[0] - fnormal * nx) +
      (f[1] - fnormal * ny) * (f[1] - fnormal * ny) + (f[2] - fnormal * nz) * (f[2] - fnormal * nz);
  CHECK(sqrt(ft2) <= p.xmu * fabs(fnormal) * (1 + 1e-12), "Coulomb cap %g > %g", sqrt(ft2),
        p.xmu * fabs(fnormal));
  CHECK(fn > 0.0, "overlapping pair repels");
  return check_summary();
}
