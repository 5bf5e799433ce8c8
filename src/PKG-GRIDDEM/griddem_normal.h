/* Normal contact sub-models of LAMMPS's pair granular (gran_sub_mod_normal.cpp): the elastic
 * (and adhesive) normal force, the contact radius, and the force that caps friction.
 * hertz/material is hertz with k = 4/3 E_eff; dmt and jkr are adhesive; jkr keeps a pair in
 * contact beyond touching, up to its pull-off distance, once it has touched. */
#ifndef GRIDDEM_NORMAL_H
#define GRIDDEM_NORMAL_H

#include "griddem_contact_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum griddem_normal_model {
  GRIDDEM_NORMAL_HOOKE = 0,
  GRIDDEM_NORMAL_HERTZ = 1,
  GRIDDEM_NORMAL_DMT = 2,
  GRIDDEM_NORMAL_JKR = 3
};

typedef struct griddem_normal_params {
  enum griddem_normal_model model;
  double k;         /* stiffness (hertz/material, dmt, jkr: 4/3 E_eff) */
  double emix;      /* E_eff (jkr) */
  double cohesion;  /* surface energy (dmt, jkr) */
} griddem_normal_params;

#define GRIDDEM_JKR_PREFIX 1.2277228507842888 /* cbrt(3 pi^2 / 16) */

/* How far beyond touching (centre distance minus radsum) a jkr pair stays in contact. */
GRIDDEM_INLINE double griddem_normal_pulloff_distance(const griddem_normal_params *p, double reff)
{
  if (p->model != GRIDDEM_NORMAL_JKR || reff <= 0.0) return 0.0;
  return GRIDDEM_JKR_PREFIX * cbrt(reff * p->cohesion * p->cohesion / (p->emix * p->emix));
}

/* Whether a pair at squared distance rsq interacts; touched: it did on the previous step. */
GRIDDEM_INLINE int griddem_normal_touch(const griddem_normal_params *p, double rsq, double radsum,
                                        double reff, int touched)
{
  if (p->model == GRIDDEM_NORMAL_JKR && touched) {
    const double dist = radsum + griddem_normal_pulloff_distance(p, reff);
    return rsq < dist * dist;
  }
  return rsq < radsum * radsum;
}

/* JKR contact radius for the overlap dR (negative beyond touching); the max(0, .) guards
 * against round-off below zero */
GRIDDEM_INLINE double griddem_jkr_contact_radius(const griddem_normal_params *p,
                                                const griddem_contact *c)
{
  const double pi = 3.14159265358979323846, E = p->emix, coh = p->cohesion;
  const double R2 = c->reff * c->reff, dR2 = c->dR * c->dR;
  const double t0 = coh * coh * R2 * R2 * E;
  const double t1 = 266.479318829412648029 * t0; /* 27 pi^2 */
  const double t2 = 8.0 * c->dR * dR2 * E * E * E;
  const double t3 = 4.0 * dR2 * E;
  const double sqrt1 = fmax(0.0, t0 * (t1 + 2.0 * t2));
  const double t4 = cbrt(t1 + t2 + 5.19615242270663202362 * pi * sqrt(sqrt1)); /* 3 sqrt 3 */
  const double t5 = t3 / t4 + t4 / E;
  const double t6 = sqrt(fmax(0.0, 2.0 * c->dR + t5));
  const double sqrt3 = fmax(0.0, 4.0 * c->dR - t5 + 14.69693845669906728801 * coh * pi * R2 / (E * t6));
  return 0.40824829046386307274 * (t6 + sqrt(sqrt3)); /* 1/sqrt 6 */
}

GRIDDEM_INLINE double griddem_normal_contact_radius(const griddem_normal_params *p,
                                                   const griddem_contact *c)
{
  switch (p->model) {
    case GRIDDEM_NORMAL_HOOKE:
    case GRIDDEM_NORMAL_HERTZ:
    case GRIDDEM_NORMAL_DMT: return sqrt(c->dR);
    case GRIDDEM_NORMAL_JKR: return griddem_jkr_contact_radius(p, c);
  }
  return 0.0; /* not reached: the cases name every model */
}

/* Sets c->fnormal (and c->fpulloff), adds the elastic energy. */
GRIDDEM_INLINE void griddem_normal_force(const griddem_normal_params *p, griddem_contact *c)
{
  const double pi = 3.14159265358979323846;
  c->fnormal = 0.0; /* for the compiler: every case sets it */
  switch (p->model) {
    case GRIDDEM_NORMAL_HOOKE:
      c->fnormal = p->k * c->delta;
      c->energy += 0.5 * c->fnormal * c->delta;
      break;
    case GRIDDEM_NORMAL_HERTZ:
      c->fnormal = p->k * c->contact_radius * c->delta;
      c->energy += 0.4 * c->fnormal * c->delta;
      break;
    case GRIDDEM_NORMAL_DMT: {
      const double fe = p->k * c->contact_radius * c->delta;
      c->fpulloff = 4.0 * pi * p->cohesion * c->reff;
      c->fnormal = fe - c->fpulloff;
      c->energy += 0.4 * fe * c->delta;
      break;
    }
    case GRIDDEM_NORMAL_JKR: {
      const double a = c->contact_radius, a2 = a * a;
      const double fe = p->k * a * a2 / c->reff;
      c->fnormal = fe - 2.0 * pi * a2 * sqrt(4.0 * p->cohesion * p->emix / (pi * a));
      c->fpulloff = 3.0 * pi * p->cohesion * c->reff;
      c->energy += 0.4 * fe * c->delta;
    }
  }
}

/* The normal force that caps friction, rolling and twisting. */
GRIDDEM_INLINE double griddem_normal_fncrit(const griddem_normal_params *p, const griddem_contact *c)
{
  switch (p->model) {
    case GRIDDEM_NORMAL_HOOKE:
    case GRIDDEM_NORMAL_HERTZ: return fabs(c->fntot);
    case GRIDDEM_NORMAL_DMT:
    case GRIDDEM_NORMAL_JKR: return fabs(c->fnormal + 2.0 * c->fpulloff);
  }
  return 0.0; /* not reached: the cases name every model */
}

#ifdef __cplusplus
}
#endif

#endif
