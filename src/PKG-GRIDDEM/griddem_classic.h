/* The laws of gran/hooke, gran/hooke/history and gran/hertz/history, written operation for
 * operation as LAMMPS's pair_gran_hooke_history.cpp and pair_gran_hertz_history.cpp, so that the
 * renamed styles give stock's forces to the last bit pair by pair (the composed law reaches the
 * same values through other roundings, which a long chaotic run amplifies). Reads the normal
 * stiffness, the mass_velocity damping (gamma_n), and the tangential model gran/hooke/history,
 * gran/hooke or none with k = Kt, gamma_mass = gamma_t, mu = xmu. hertz (gran/hertz/history): the
 * normal force and the friction scaled by sqrt(delta R_eff), as that style does (its Coulomb cap's
 * history rescaling is hooke's). Same contract as griddem_contact_eval. */
#ifndef GRIDDEM_CLASSIC_H
#define GRIDDEM_CLASSIC_H

#include "griddem_damping.h"
#include "griddem_normal.h"
#include "griddem_tangential.h"

#ifdef __cplusplus
extern "C" {
#endif

GRIDDEM_INLINE void griddem_classic_contact(const griddem_normal_params *np,
                                           const griddem_damping_params *dp,
                                           const griddem_tangential_params *tp, int limit_damping,
                                           const int hertz, griddem_contact *c, double *shear, double *f,
                                           double *ti, double *tj)
{
  const double r = sqrt(c->rsq), rinv = 1.0 / r, rsqinv = 1.0 / c->rsq;
  const double radsum = c->radi + c->radj;
  const double delx = c->dx[0], dely = c->dx[1], delz = c->dx[2];
  /* what single() reports; nothing else is derived */
  c->r = r, c->rinv = rinv, c->radsum = radsum, c->delta = radsum - r;
  for (int k = 0; k < 3; k++) c->n[k] = c->dx[k] * rinv;

  /* normal and tangential relative velocity */
  const double vnnr = c->vr[0] * delx + c->vr[1] * dely + c->vr[2] * delz;
  const double vn1 = delx * vnnr * rsqinv, vn2 = dely * vnnr * rsqinv, vn3 = delz * vnnr * rsqinv;
  c->vnnr = vnnr * rinv;
  c->vt[0] = c->vr[0] - vn1, c->vt[1] = c->vr[1] - vn2, c->vt[2] = c->vr[2] - vn3;

  /* relative rotational velocity */
  const double wr1 = griddem_symmetric_sum(c->radi, c->wi[0], c->radj, c->wj[0]) * rinv;
  const double wr2 = griddem_symmetric_sum(c->radi, c->wi[1], c->radj, c->wj[1]) * rinv;
  const double wr3 = griddem_symmetric_sum(c->radi, c->wi[2], c->radj, c->wj[2]) * rinv;

  /* normal force = Hookean contact + normal velocity damping */
  const double damp = c->meff * dp->damp * vnnr * rsqinv;
  double ccel = np->k * (radsum - r) * rinv - damp;
  const double polyhertz = hertz ? sqrt((radsum - r) * c->radi * c->radj / radsum) : 1.0;
  if (hertz) ccel *= polyhertz;
  if (limit_damping && (ccel < 0.0)) ccel = 0.0;
  c->fntot = ccel * r;
  c->fncrit = fabs(c->fntot);

  double fs1 = 0.0, fs2 = 0.0, fs3 = 0.0;
  if (tp->model != GRIDDEM_TANGENTIAL_NONE) {
    /* relative tangential velocity at the contact point */
    const double vtr1 = c->vt[0] - (delz * wr2 - dely * wr3);
    const double vtr2 = c->vt[1] - (delx * wr3 - delz * wr1);
    const double vtr3 = c->vt[2] - (dely * wr1 - delx * wr2);
    const double fn = tp->mu * fabs(ccel * r);
    const double mg = c->meff * tp->gamma_mass;

    if (tp->model == GRIDDEM_TANGENTIAL_HOOKE_HISTORY) {
      if (c->history_update) {
        shear[0] += vtr1 * c->dt;
        shear[1] += vtr2 * c->dt;
        shear[2] += vtr3 * c->dt;
      }
      const double shrmag = sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);

      /* rotate shear displacements into the current tangent plane */
      const double rsht = (shear[0] * delx + shear[1] * dely + shear[2] * delz) * rsqinv;
      if (c->history_update) {
        shear[0] -= rsht * delx;
        shear[1] -= rsht * dely;
        shear[2] -= rsht * delz;
      }

      /* tangential forces = shear + tangential velocity damping */
      if (hertz) {
        fs1 = -polyhertz * (tp->k * shear[0] + mg * vtr1);
        fs2 = -polyhertz * (tp->k * shear[1] + mg * vtr2);
        fs3 = -polyhertz * (tp->k * shear[2] + mg * vtr3);
      } else {
        fs1 = -(tp->k * shear[0] + mg * vtr1);
        fs2 = -(tp->k * shear[1] + mg * vtr2);
        fs3 = -(tp->k * shear[2] + mg * vtr3);
      }

      /* Coulomb cap: rescale frictional displacements and forces */
      const double fs = sqrt(fs1 * fs1 + fs2 * fs2 + fs3 * fs3);
      if (fs > fn) {
        if (shrmag != 0.0) {
          shear[0] = (fn / fs) * (shear[0] + mg * vtr1 / tp->k) - mg * vtr1 / tp->k;
          shear[1] = (fn / fs) * (shear[1] + mg * vtr2 / tp->k) - mg * vtr2 / tp->k;
          shear[2] = (fn / fs) * (shear[2] + mg * vtr3 / tp->k) - mg * vtr3 / tp->k;
          fs1 *= fn / fs;
          fs2 *= fn / fs;
          fs3 *= fn / fs;
        } else {
          fs1 = fs2 = fs3 = 0.0;
        }
      }
      c->energy += 0.5 * polyhertz * tp->k * (shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);
    } else {
      /* velocity-only friction, capped by Coulomb */
      const double vrel = sqrt(vtr1 * vtr1 + vtr2 * vtr2 + vtr3 * vtr3);
      const double fs = mg * vrel;
      const double ft = (vrel != 0.0) ? ((fn < fs ? fn : fs) / vrel) : 0.0;
      fs1 = -ft * vtr1;
      fs2 = -ft * vtr2;
      fs3 = -ft * vtr3;
    }
  }

  f[0] = delx * ccel + fs1;
  f[1] = dely * ccel + fs2;
  f[2] = delz * ccel + fs3;
  c->fs[0] = fs1, c->fs[1] = fs2, c->fs[2] = fs3;
  const double tor1 = rinv * (dely * fs3 - delz * fs2);
  const double tor2 = rinv * (delz * fs1 - delx * fs3);
  const double tor3 = rinv * (delx * fs2 - dely * fs1);
  ti[0] = -(c->radi * tor1), ti[1] = -(c->radi * tor2), ti[2] = -(c->radi * tor3);
  tj[0] = -(c->radj * tor1), tj[1] = -(c->radj * tor2), tj[2] = -(c->radj * tor3);
  /* hertz: the integral of k sqrt(R_eff) delta^(3/2), 2/5 k sqrt(delta R_eff) delta^2 */
  c->energy += (hertz ? 0.4 * polyhertz : 0.5) * np->k * c->delta * c->delta;
}

#ifdef __cplusplus
}
#endif

#endif
