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

/* Force on i (f[3]) and the torque factor tor[3] of one overlapping pair.
 * shear[3] is the pair's tangential displacement (read and, if shearupdate, advanced by dt);
 * it is ignored unless p->tangential == GRIDDEM_TANGENTIAL_HISTORY. */
GRIDDEM_INLINE void griddem_hooke_contact(const griddem_hooke_params *p, const griddem_contact_in *c,
                                          double dt, int shearupdate, double *shear, double *f,
                                          double *tor)
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
  tor[0] = rinv * (dely * fs3 - delz * fs2);
  tor[1] = rinv * (delz * fs1 - delx * fs3);
  tor[2] = rinv * (delx * fs2 - dely * fs1);
}

#ifdef __cplusplus
}
#endif

#endif
