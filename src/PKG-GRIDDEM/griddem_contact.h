/* GRIDDEM contact laws: one header of static inline functions shared by the C core, the LAMMPS
 * styles and the Kokkos kernels, so CPU and GPU evaluate the same arithmetic.
 *
 * The linear spring-dashpot of LAMMPS's gran/hooke and gran/hooke/history, written operation for
 * operation as in the stock styles so that results agree to round-off. All quantities are in the
 * units of the calling script. Sign convention: del = x_i - x_j; the returned force acts on i, the
 * returned tor is the quantity stock styles call (tor1,tor2,tor3): torque_i -= radi * tor. */
#ifndef GRIDDEM_CONTACT_H
#define GRIDDEM_CONTACT_H

#include <math.h>

#ifndef GRIDDEM_INLINE
#if defined(KOKKOS_INLINE_FUNCTION)
#define GRIDDEM_INLINE KOKKOS_INLINE_FUNCTION
#else
#define GRIDDEM_INLINE static inline
#endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Tangential sub-model. */
enum griddem_tangential {
  GRIDDEM_TANGENTIAL_NONE = 0,    /* normal force only */
  GRIDDEM_TANGENTIAL_DAMPED = 1,  /* gran/hooke: -meff*gammat*vtr capped at xmu*|Fn| (no memory) */
  GRIDDEM_TANGENTIAL_HISTORY = 2  /* gran/hooke/history: spring on accumulated shear + damping */
};

typedef struct griddem_hooke_params {
  double kn, kt;         /* normal and tangential spring constants (force/distance) */
  double gamman, gammat; /* damping coefficients (1/time), multiplied by meff as in stock */
  double xmu;            /* Coulomb friction coefficient */
  int limit_damping;     /* 1: no attractive normal force from damping */
  int tangential;        /* enum griddem_tangential */
} griddem_hooke_params;

/* Contact kinematics for the pair (i,j); all inputs as stored on the atoms. */
typedef struct griddem_contact_in {
  double delx, dely, delz, rsq; /* x_i - x_j and its squared length (> 0) */
  double radi, radj;
  double vr1, vr2, vr3;         /* v_i - v_j */
  double wi1, wi2, wi3, wj1, wj2, wj3;
  double meff;
} griddem_contact_in;

/* What compute pair/local reports of a contact (pair styles' single()): the normal force divided
 * by the distance (the force on i is del times it, plus the tangential force), the tangential
 * and rolling forces, and the normal and tangential relative velocities. */
typedef struct griddem_contact_detail {
  double fnormal_over_r;
  double fs[3], fr[3];
  double vn[3], vt[3];
} griddem_contact_detail;

/* Effective mass as stock: a frozen partner acts as infinitely heavy. For two frozen atoms stock
 * takes the mass of whichever atom its neighbor list puts first; that depends on storage order,
 * so here it is 2 mi mj / (mi + mj): the same for equal masses, and the same from both sides.
 * (Fix freeze zeroes the forces on frozen atoms; only the virial of such pairs depends on it.) */
GRIDDEM_INLINE double griddem_effective_mass(double mi, double mj, int frozen_i, int frozen_j)
{
  if (frozen_i && frozen_j) return 2.0 * mi * mj / (mi + mj);
  if (frozen_i) return mj;
  if (frozen_j) return mi;
  return mi * mj / (mi + mj);
}

/* Force on i (f[3], j gets -f), the torques on i and j (ti[3], tj[3]) of one overlapping pair;
 * returns the elastic energy stored in the pair's springs; d, if not NULL, receives the parts of
 * the contact (see griddem_contact_detail). shear[3] is the pair's tangential
 * displacement seen from i (read and, if shearupdate, advanced by dt); it is ignored unless
 * p->tangential == GRIDDEM_TANGENTIAL_HISTORY. Seen from j, every output and the shear change sign
 * exactly (each operation is odd in the inputs that flip), so one evaluation serves both atoms. */
GRIDDEM_INLINE double griddem_hooke_contact(const griddem_hooke_params *p, const griddem_contact_in *c,
                                            double dt, int shearupdate, double *shear, double *f,
                                            double *ti, double *tj, griddem_contact_detail *d)
{
  const double r = sqrt(c->rsq);
  const double rinv = 1.0 / r;
  const double rsqinv = 1.0 / c->rsq;
  const double radsum = c->radi + c->radj;
  const double delx = c->delx, dely = c->dely, delz = c->delz;

  /* normal and tangential relative velocity */
  const double vnnr = c->vr1 * delx + c->vr2 * dely + c->vr3 * delz;
  const double vn1 = delx * vnnr * rsqinv;
  const double vn2 = dely * vnnr * rsqinv;
  const double vn3 = delz * vnnr * rsqinv;
  const double vt1 = c->vr1 - vn1;
  const double vt2 = c->vr2 - vn2;
  const double vt3 = c->vr3 - vn3;

  /* relative rotational velocity */
  const double wr1 = (c->radi * c->wi1 + c->radj * c->wj1) * rinv;
  const double wr2 = (c->radi * c->wi2 + c->radj * c->wj2) * rinv;
  const double wr3 = (c->radi * c->wi3 + c->radj * c->wj3) * rinv;

  /* normal force = Hookean contact + normal velocity damping */
  const double damp = c->meff * p->gamman * vnnr * rsqinv;
  double ccel = p->kn * (radsum - r) * rinv - damp;
  if (p->limit_damping && (ccel < 0.0)) ccel = 0.0;

  double fs1 = 0.0, fs2 = 0.0, fs3 = 0.0;
  if (p->tangential != GRIDDEM_TANGENTIAL_NONE) {
    /* relative tangential velocity at the contact point */
    const double vtr1 = vt1 - (delz * wr2 - dely * wr3);
    const double vtr2 = vt2 - (delx * wr3 - delz * wr1);
    const double vtr3 = vt3 - (dely * wr1 - delx * wr2);
    const double fn = p->xmu * fabs(ccel * r);

    if (p->tangential == GRIDDEM_TANGENTIAL_HISTORY) {
      if (shearupdate) {
        shear[0] += vtr1 * dt;
        shear[1] += vtr2 * dt;
        shear[2] += vtr3 * dt;
      }
      const double shrmag = sqrt(shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]);

      /* rotate shear displacements into the current tangent plane */
      double rsht = shear[0] * delx + shear[1] * dely + shear[2] * delz;
      rsht *= rsqinv;
      if (shearupdate) {
        shear[0] -= rsht * delx;
        shear[1] -= rsht * dely;
        shear[2] -= rsht * delz;
      }

      /* tangential forces = shear + tangential velocity damping */
      fs1 = -(p->kt * shear[0] + c->meff * p->gammat * vtr1);
      fs2 = -(p->kt * shear[1] + c->meff * p->gammat * vtr2);
      fs3 = -(p->kt * shear[2] + c->meff * p->gammat * vtr3);

      /* Coulomb cap: rescale frictional displacements and forces */
      const double fs = sqrt(fs1 * fs1 + fs2 * fs2 + fs3 * fs3);
      if (fs > fn) {
        if (shrmag != 0.0) {
          shear[0] = (fn / fs) * (shear[0] + c->meff * p->gammat * vtr1 / p->kt) -
              c->meff * p->gammat * vtr1 / p->kt;
          shear[1] = (fn / fs) * (shear[1] + c->meff * p->gammat * vtr2 / p->kt) -
              c->meff * p->gammat * vtr2 / p->kt;
          shear[2] = (fn / fs) * (shear[2] + c->meff * p->gammat * vtr3 / p->kt) -
              c->meff * p->gammat * vtr3 / p->kt;
          fs1 *= fn / fs;
          fs2 *= fn / fs;
          fs3 *= fn / fs;
        } else {
          fs1 = fs2 = fs3 = 0.0;
        }
      }
    } else {
      /* velocity-only friction, capped by Coulomb */
      const double vrel = sqrt(vtr1 * vtr1 + vtr2 * vtr2 + vtr3 * vtr3);
      const double fs = c->meff * p->gammat * vrel;
      const double ft = (vrel != 0.0) ? ((fn < fs ? fn : fs) / vrel) : 0.0;
      fs1 = -ft * vtr1;
      fs2 = -ft * vtr2;
      fs3 = -ft * vtr3;
    }
  }

  f[0] = delx * ccel + fs1;
  f[1] = dely * ccel + fs2;
  f[2] = delz * ccel + fs3;
  if (d) {
    d->fnormal_over_r = ccel;
    d->fs[0] = fs1, d->fs[1] = fs2, d->fs[2] = fs3;
    d->fr[0] = d->fr[1] = d->fr[2] = 0.0;
    d->vn[0] = vn1, d->vn[1] = vn2, d->vn[2] = vn3;
    d->vt[0] = vt1, d->vt[1] = vt2, d->vt[2] = vt3;
  }
  const double tor1 = rinv * (dely * fs3 - delz * fs2);
  const double tor2 = rinv * (delz * fs1 - delx * fs3);
  const double tor3 = rinv * (delx * fs2 - dely * fs1);
  ti[0] = -(c->radi * tor1), ti[1] = -(c->radi * tor2), ti[2] = -(c->radi * tor3);
  tj[0] = -(c->radj * tor1), tj[1] = -(c->radj * tor2), tj[2] = -(c->radj * tor3);

  const double overlap = radsum - r;
  return 0.5 * (p->kn * overlap * overlap +
                p->kt * (shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]));
}

/* ---- pair granular sub-models ----
 * The subset of LAMMPS's pair granular that GRIDDEM evaluates, written operation for operation as
 * granular_model.cpp and gran_sub_mod_*.cpp compose them. hertz/material is hertz with
 * kn = 4/3 E_eff (mixed by the caller); tsuji's coefficient arrives already converted from the
 * restitution coefficient. */

enum griddem_normal { GRIDDEM_NORMAL_HOOKE = 0, GRIDDEM_NORMAL_HERTZ = 1 };
enum griddem_damping {
  GRIDDEM_DAMPING_VELOCITY = 0,      /* damp */
  GRIDDEM_DAMPING_MASS_VELOCITY = 1, /* damp * meff */
  GRIDDEM_DAMPING_VISCOELASTIC = 2,  /* damp * meff * contact radius */
  GRIDDEM_DAMPING_TSUJI = 3          /* damp * sqrt(meff * Fnormal / overlap) */
};
enum griddem_rolling { GRIDDEM_ROLLING_NONE = 0, GRIDDEM_ROLLING_SDS = 1 };

typedef struct griddem_granular_params {
  int normal, damping;
  int tangential;        /* GRIDDEM_TANGENTIAL_DAMPED (linear_nohistory) or _HISTORY (linear_history) */
  int rolling;
  int limit_damping;
  double kn, damp;       /* normal stiffness and damping coefficient */
  double kt, xt, mu;     /* tangential stiffness, damping ratio to normal, friction coefficient */
  double kroll, gammaroll, muroll;
} griddem_granular_params;

/* History values per contact: tangential displacement (3), then rolling displacement (3). */
GRIDDEM_INLINE int griddem_granular_history_size(const griddem_granular_params *p)
{
  return (p->tangential == GRIDDEM_TANGENTIAL_HISTORY ? 3 : 0) +
      (p->rolling == GRIDDEM_ROLLING_SDS ? 3 : 0);
}

/* Project a history vector onto the plane normal to n and restore its length, unless its normal
 * part is negligible against the critical force (as stock: |h.n| k <= 1e-10 Fcrit). */
GRIDDEM_INLINE void griddem_rotate_rescale(double *h, const double *n, double k, double fcrit)
{
  const double hn = h[0] * n[0] + h[1] * n[1] + h[2] * n[2];
  if (fabs(hn) * k > 1e-10 * fcrit) {
    const double mag = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    h[0] -= hn * n[0], h[1] -= hn * n[1], h[2] -= hn * n[2];
    const double prj = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    const double scale = prj > 0 ? mag / prj : 0;
    h[0] *= scale, h[1] *= scale, h[2] *= scale;
  }
}

/* Same contract as griddem_hooke_contact; hist holds griddem_granular_history_size(p) values seen
 * from i (tangential part odd, rolling part even under the exchange of i and j). */
GRIDDEM_INLINE double griddem_granular_contact(const griddem_granular_params *p,
                                               const griddem_contact_in *c, double dt,
                                               int history_update, double *hist, double *f,
                                               double *ti, double *tj, griddem_contact_detail *d)
{
  const double r = sqrt(c->rsq);
  const double rinv = 1.0 / r;
  const double radsum = c->radi + c->radj;
  const double reff = c->radi * c->radj / radsum;
  const double delta = radsum - r;
  const double dR = delta * reff;
  const double n[3] = {rinv * c->delx, rinv * c->dely, rinv * c->delz};

  const double vnnr = c->vr1 * n[0] + c->vr2 * n[1] + c->vr3 * n[2];
  const double vt1 = c->vr1 - vnnr * n[0];
  const double vt2 = c->vr2 - vnnr * n[1];
  const double vt3 = c->vr3 - vnnr * n[2];
  const double wr1 = c->radi * c->wi1 + c->radj * c->wj1;
  const double wr2 = c->radi * c->wi2 + c->radj * c->wj2;
  const double wr3 = c->radi * c->wi3 + c->radj * c->wj3;
  const double vtr[3] = {vt1 - (wr2 * n[2] - wr3 * n[1]), vt2 - (wr3 * n[0] - wr1 * n[2]),
                         vt3 - (wr1 * n[1] - wr2 * n[0])};

  const int need_radius = p->normal == GRIDDEM_NORMAL_HERTZ || p->damping == GRIDDEM_DAMPING_VISCOELASTIC;
  const double a = need_radius ? sqrt(dR) : 0.0;
  const double fnormal = p->normal == GRIDDEM_NORMAL_HERTZ ? p->kn * a * delta : p->kn * delta;
  double prefactor;
  switch (p->damping) {
    case GRIDDEM_DAMPING_VELOCITY: prefactor = p->damp; break;
    case GRIDDEM_DAMPING_MASS_VELOCITY: prefactor = p->damp * c->meff; break;
    case GRIDDEM_DAMPING_VISCOELASTIC: prefactor = p->damp * c->meff * a; break;
    default: {
      double arg = delta > 0.0 ? c->meff * fnormal / delta : 0.0;
      if (arg < 0.0) arg = 0.0;
      prefactor = p->damp * sqrt(arg);
    }
  }
  double fntot = fnormal + (-prefactor * vnnr);
  if (p->limit_damping && fntot < 0.0) fntot = 0.0;
  const double fncrit = fabs(fntot);
  double energy = p->normal == GRIDDEM_NORMAL_HERTZ ? 0.4 * fnormal * delta : 0.5 * fnormal * delta;

  /* tangential */
  const double damp_t = p->xt * prefactor;
  const double fscrit = p->mu * fncrit;
  double fs[3];
  if (p->tangential == GRIDDEM_TANGENTIAL_HISTORY) {
    double *h = hist;
    if (history_update) {
      griddem_rotate_rescale(h, n, p->kt, fscrit);
      h[0] += dt * vtr[0], h[1] += dt * vtr[1], h[2] += dt * vtr[2];
    }
    fs[0] = -p->kt * h[0] - damp_t * vtr[0];
    fs[1] = -p->kt * h[1] - damp_t * vtr[1];
    fs[2] = -p->kt * h[2] - damp_t * vtr[2];
    const double magfs = sqrt(fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2]);
    if (magfs > fscrit) {
      if (sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]) != 0.0) {
        const double scale = fscrit * (1.0 / magfs);
        const double kinv = -1.0 / p->kt;
        for (int k = 0; k < 3; k++) {
          h[k] = (scale * fs[k] + damp_t * vtr[k]) * kinv;
          fs[k] *= scale;
        }
      } else {
        fs[0] = fs[1] = fs[2] = 0.0;
      }
    }
    energy += 0.5 * p->kt * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    hist += 3;
  } else {
    const double vrel = sqrt(vtr[0] * vtr[0] + vtr[1] * vtr[1] + vtr[2] * vtr[2]);
    const double fsmag = damp_t * vrel;
    const double ft = vrel != 0.0 ? (fscrit < fsmag ? fscrit : fsmag) / vrel : 0.0;
    fs[0] = -ft * vtr[0], fs[1] = -ft * vtr[1], fs[2] = -ft * vtr[2];
  }

  f[0] = fntot * n[0] + fs[0];
  f[1] = fntot * n[1] + fs[1];
  f[2] = fntot * n[2] + fs[2];
  if (d) {
    d->fnormal_over_r = fntot * rinv;
    for (int k = 0; k < 3; k++) d->fs[k] = fs[k], d->fr[k] = 0.0;
    d->vn[0] = vnnr * n[0], d->vn[1] = vnnr * n[1], d->vn[2] = vnnr * n[2];
    d->vt[0] = vt1, d->vt[1] = vt2, d->vt[2] = vt3;
  }
  /* torque from the tangential force, applied at the contact point */
  const double c1 = -(n[1] * fs[2] - n[2] * fs[1]);
  const double c2 = -(n[2] * fs[0] - n[0] * fs[2]);
  const double c3 = -(n[0] * fs[1] - n[1] * fs[0]);
  const double di = c->radi - 0.5 * delta, dj = c->radj - 0.5 * delta;
  ti[0] = di * c1, ti[1] = di * c2, ti[2] = di * c3;
  tj[0] = dj * c1, tj[1] = dj * c2, tj[2] = dj * c3;

  if (p->rolling == GRIDDEM_ROLLING_SDS) {
    const double rr1 = c->wi1 - c->wj1, rr2 = c->wi2 - c->wj2, rr3 = c->wi3 - c->wj3;
    const double vrl[3] = {reff * (rr2 * n[2] - rr3 * n[1]), reff * (rr3 * n[0] - rr1 * n[2]),
                           reff * (rr1 * n[1] - rr2 * n[0])};
    const double frcrit = p->muroll * fncrit;
    double h[3] = {hist[0], hist[1], hist[2]};
    if (history_update) {
      griddem_rotate_rescale(h, n, p->kroll, frcrit);
      h[0] += dt * vrl[0], h[1] += dt * vrl[1], h[2] += dt * vrl[2];
    }
    double fr[3];
    for (int k = 0; k < 3; k++) fr[k] = (-p->kroll) * h[k] + (-p->gammaroll) * vrl[k];
    const double magfr = sqrt(fr[0] * fr[0] + fr[1] * fr[1] + fr[2] * fr[2]);
    if (magfr > frcrit) {
      if (sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]) != 0.0) {
        const double kinv = 1.0 / p->kroll, magfr_inv = 1.0 / magfr;
        for (int k = 0; k < 3; k++) {
          h[k] = (-frcrit * kinv * magfr_inv) * fr[k] + (-p->gammaroll * kinv) * vrl[k];
          fr[k] *= frcrit * magfr_inv;
        }
      } else {
        fr[0] = fr[1] = fr[2] = 0.0;
      }
    }
    if (history_update) hist[0] = h[0], hist[1] = h[1], hist[2] = h[2];
    if (d) d->fr[0] = fr[0], d->fr[1] = fr[1], d->fr[2] = fr[2];
    const double tr1 = reff * (n[1] * fr[2] - n[2] * fr[1]);
    const double tr2 = reff * (n[2] * fr[0] - n[0] * fr[2]);
    const double tr3 = reff * (n[0] * fr[1] - n[1] * fr[0]);
    ti[0] += tr1, ti[1] += tr2, ti[2] += tr3;
    tj[0] -= tr1, tj[1] -= tr2, tj[2] -= tr3;
    energy += 0.5 * p->kroll * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
  }
  return energy;
}

/* ---- the model a sweep evaluates ---- */

enum griddem_law {
  GRIDDEM_LAW_HOOKE = 0,    /* gran/hooke, gran/hooke/history: one parameter set for all types */
  GRIDDEM_LAW_GRANULAR = 1  /* pair granular sub-models, one parameter set per type pair */
};

#define GRIDDEM_MAX_HISTORY 6 /* history values per contact the laws above may keep */

typedef struct griddem_model {
  int law;
  griddem_hooke_params hooke;
  int ntypes;
  const griddem_granular_params *granular; /* [(ntypes+1)^2], [itype*(ntypes+1)+jtype] */
  int history_size;                        /* values per contact; 0: no history */
  double history_parity[GRIDDEM_MAX_HISTORY]; /* value seen from j = parity * value seen from i */
} griddem_model;

/* Contact of atoms of types itype, jtype: force on i, torques on i and j, energy returned;
 * d (may be NULL) receives the contact's parts. */
GRIDDEM_INLINE double griddem_pair_contact(const griddem_model *m, int itype, int jtype,
                                           const griddem_contact_in *c, double dt,
                                           int history_update, double *hist, double *f,
                                           double *ti, double *tj, griddem_contact_detail *d)
{
  if (m->law == GRIDDEM_LAW_HOOKE)
    return griddem_hooke_contact(&m->hooke, c, dt, history_update, hist, f, ti, tj, d);
  return griddem_granular_contact(m->granular + itype * (m->ntypes + 1) + jtype, c, dt,
                                  history_update, hist, f, ti, tj, d);
}

#ifdef __cplusplus
}
#endif

#endif
