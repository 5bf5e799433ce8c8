/* The classic laws over a batch of contacts (griddem_classic_batch.h) against the scalar law
 * (griddem_classic_eval), contact by contact, bit for bit: gran/hooke/history's and
 * gran/hertz/history's, with and without limit_damping, on random contacts that exercise every
 * branch of the law (Coulomb cap with and without stored shear, attractive damping cut by
 * limit_damping, frozen partners), in batches of every length up to a full one (the vector copies'
 * remainders). */
#include "check.h"
#include "griddem_classic_batch.h"
#include "spec_text.h"

#include <string.h>

/* Random contact k of a batch: radii 0.3-0.6, overlap up to a third of the radius sum, speeds
 * and spins up to 2 (up to 200 in one contact of eight: sliding past the Coulomb cap), stored
 * shear up to 0.05 (none in one contact of four), masses 0.5-2, one partner frozen in one of
 * ten, both in one of fifty */
static void random_contact(griddem_classic_batch *b, int k)
{
  b->radi[k] = 0.3 + 0.3 * check_uniform(), b->radj[k] = 0.3 + 0.3 * check_uniform();
  double n[3], norm = 0.0;
  for (int d = 0; d < 3; d++) n[d] = 2.0 * check_uniform() - 1.0, norm += n[d] * n[d];
  norm = sqrt(norm);
  const double r = (b->radi[k] + b->radj[k]) * (1.0 - check_uniform() / 3.0);
  b->rsq[k] = 0.0;
  for (int d = 0; d < 3; d++) b->dx[d][k] = r * n[d] / norm, b->rsq[k] += b->dx[d][k] * b->dx[d][k];
  const double speed = check_uniform() < 0.125 ? 200.0 : 2.0, no_shear = check_uniform() < 0.25;
  for (int d = 0; d < 3; d++) {
    b->vi[d][k] = speed * (2.0 * check_uniform() - 1.0), b->vj[d][k] = speed * (2.0 * check_uniform() - 1.0);
    b->wi[d][k] = speed * (2.0 * check_uniform() - 1.0), b->wj[d][k] = speed * (2.0 * check_uniform() - 1.0);
    b->shear[d][k] = no_shear ? 0.0 : 0.05 * (2.0 * check_uniform() - 1.0);
  }
  b->mi[k] = 0.5 + 1.5 * check_uniform(), b->mj[k] = 0.5 + 1.5 * check_uniform();
  const double frozen = check_uniform();
  b->frozen_i[k] = frozen < 0.05 || frozen > 0.99, b->frozen_j[k] = frozen > 0.9;
}

static int same_bits(double a, double b)
{
  return memcmp(&a, &b, sizeof(a)) == 0;
}

/* Branches the random contacts went through, over all laws */
static int capped, capped_without_shear, damping_cut;

static void check_law(const char *text, double dt)
{
  const griddem_pair_params law = law_from_text(text);
  CHECK(griddem_classic_batchable(&law), "%s is a classic law with shear history", text);
  for (int n = 1; n <= GRIDDEM_CLASSIC_BATCH; n++) {
    griddem_classic_batch b;
    memset(&b, 0, sizeof(b));
    b.n = n;
    for (int k = 0; k < n; k++) random_contact(&b, k);
    griddem_classic_batch scalar = b, without_energy = b;
    griddem_classic_batch_eval(&law, &b, dt, 1);
    /* a copy without the energy: the same forces, torques and shear to the bit, no energy set */
    for (int k = 0; k < n; k++) without_energy.energy[k] = -1.0;
    griddem_classic_batch_eval(&law, &without_energy, dt, 0);
    for (int k = 0; k < n; k++) {
      double dx[3], vi[3], vj[3], wi[3], wj[3], shear[3], f[3], ti[3], tj[3];
      for (int d = 0; d < 3; d++) {
        dx[d] = scalar.dx[d][k], vi[d] = scalar.vi[d][k], vj[d] = scalar.vj[d][k];
        wi[d] = scalar.wi[d][k], wj[d] = scalar.wj[d][k], shear[d] = scalar.shear[d][k];
      }
      griddem_contact c;
      griddem_contact_setup(&c, dx, scalar.rsq[k], scalar.radi[k], scalar.radj[k], vi, vj, wi, wj, scalar.mi[k],
                            scalar.mj[k], scalar.frozen_i[k], scalar.frozen_j[k], dt, 1);
      const double energy = griddem_classic_eval(&law, &c, shear, f, ti, tj, griddem_classic_hertz(&law));
      int same = same_bits(b.energy[k], energy);
      for (int d = 0; d < 3; d++)
        same &= same_bits(b.shear[d][k], shear[d]) && same_bits(b.f[d][k], f[d]) && same_bits(b.ti[d][k], ti[d]) &&
                same_bits(b.tj[d][k], tj[d]);
      CHECK(same, "%s, batch of %d, lane %d: force %.17g %.17g %.17g against the scalar law's %.17g %.17g %.17g", text, n,
            k, b.f[0][k], b.f[1][k], b.f[2][k], f[0], f[1], f[2]);
      int same_without = without_energy.energy[k] == -1.0;
      for (int d = 0; d < 3; d++)
        same_without &= same_bits(without_energy.shear[d][k], shear[d]) && same_bits(without_energy.f[d][k], f[d]) &&
                        same_bits(without_energy.ti[d][k], ti[d]) && same_bits(without_energy.tj[d][k], tj[d]);
      CHECK(same_without, "%s, batch of %d, lane %d, without energy: force %.17g %.17g %.17g against %.17g %.17g %.17g",
            text, n, k, without_energy.f[0][k], without_energy.f[1][k], without_energy.f[2][k], f[0], f[1], f[2]);
      const double fs = sqrt(c.fs[0] * c.fs[0] + c.fs[1] * c.fs[1] + c.fs[2] * c.fs[2]);
      if (fs >= law.tangential.mu * c.fncrit * (1.0 - 1e-12) && fs > 0.0) {
        capped++;
        capped_without_shear += scalar.shear[0][k] == 0.0 && scalar.shear[1][k] == 0.0 && scalar.shear[2][k] == 0.0;
      }
      damping_cut += law.limit_damping && c.fntot == 0.0;
    }
  }
}

int main(void)
{
  check_law("hooke 2000 50 damping mass_velocity tangential gran/hooke/history 571.4 25 0.5", 1e-3);
  check_law("hooke 2000 500 damping mass_velocity tangential gran/hooke/history 571.4 25 0.5 limit_damping", 1e-3);
  check_law("hertz 2e5 50 damping mass_velocity tangential gran/hooke/history 5e4 25 0.3", 1e-4);
  check_law("hertz 2e5 500 damping mass_velocity tangential gran/hooke/history 5e4 25 0.3 limit_damping", 1e-4);
  CHECK(capped > 100 && capped_without_shear > 20 && damping_cut > 20,
        "the contacts went through every branch: %d capped (%d without stored shear), %d with damping cut", capped,
        capped_without_shear, damping_cut);
  return check_summary();
}
