/* GRIDDEM contact law: the sub-models of one type pair (one header per axis: griddem_normal.h,
 * griddem_damping.h, griddem_tangential.h, griddem_rolling.h, griddem_twisting.h, griddem_heat.h)
 * composed in the order of LAMMPS's GranularModel::calculate_forces, written operation for
 * operation as the stock styles so that results agree to round-off. Static inline functions shared
 * by the C core, the LAMMPS styles and the Kokkos kernels. Which sub-models exist, their coefficients, history sizes
 * and mixing rules are listed in one table (griddem_submodels.c). */
#ifndef GRIDDEM_CONTACT_H
#define GRIDDEM_CONTACT_H

#include "griddem_classic.h"
#include "griddem_damping.h"
#include "griddem_heat.h"
#include "griddem_normal.h"
#include "griddem_rolling.h"
#include "griddem_tangential.h"
#include "griddem_twisting.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GRIDDEM_MAX_HISTORY 8 /* tangential 4 + rolling 3 + twisting 1 */

/* The contact law of one pair of atom types. */
typedef struct griddem_pair_params {
  griddem_normal_params normal;
  griddem_damping_params damping;
  griddem_tangential_params tangential;
  griddem_rolling_params rolling;
  griddem_twisting_params twisting;
  griddem_heat_params heat;
  int limit_damping;        /* 1: no attractive normal force from damping */
  int need_contact_radius;  /* some sub-model reads c->contact_radius */
  int classic;              /* 1: gran/hooke(/history)'s own arithmetic (griddem_classic.h) */
  int hist_rolling, hist_twisting; /* offsets of the rolling and twisting history values */
  double parity[GRIDDEM_MAX_HISTORY]; /* a history value seen from j = parity * seen from i (0
                                         past the pair's own values) */
} griddem_pair_params;


/* What a sweep evaluates: the laws of all type pairs and the room for their history (each type
 * pair lays its values out in it as its sub-models say, griddem_pair_params). */
typedef struct griddem_model {
  int ntypes;
  const griddem_pair_params *pair; /* [(ntypes+1)^2], [itype*(ntypes+1)+jtype] */
  int history_size;                /* values per contact, the most of any type pair; 0: none */
  int track_contacts;              /* keep who touched whom even without values (jkr) */
  double reach_extra;              /* largest distance beyond touching at which pairs interact */
} griddem_model;

GRIDDEM_INLINE const griddem_pair_params *griddem_model_pair(const griddem_model *m, int itype,
                                                             int jtype)
{
  return m->pair + itype * (m->ntypes + 1) + jtype;
}

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

/* The inputs of the contact of i with j, set as every caller sets them (the CPU sweep, single()
 * and the Kokkos kernels): separation dx = x_i - x_j and its squared length rsq, radii, velocities
 * v and spins w of each, masses (frozen: held by fix freeze), the step, and whether the history
 * advances. */
GRIDDEM_INLINE void griddem_contact_setup(griddem_contact *c, const double *dx, double rsq, double radi,
                                          double radj, const double *vi, const double *vj, const double *wi,
                                          const double *wj, double mi, double mj, int frozen_i, int frozen_j,
                                          double dt, int history_update)
{
  for (int d = 0; d < 3; d++) {
    c->dx[d] = dx[d];
    c->vr[d] = vi[d] - vj[d];
    c->wi[d] = wi[d], c->wj[d] = wj[d];
  }
  c->rsq = rsq;
  c->radi = radi, c->radj = radj;
  c->meff = griddem_effective_mass(mi, mj, frozen_i, frozen_j);
  c->dt = dt;
  c->history_update = history_update;
}

/* Whether atoms at squared distance rsq interact; touched: they did on the previous step. */
GRIDDEM_INLINE int griddem_contact_touch(const griddem_pair_params *p, double rsq, double radi,
                                         double radj, int touched)
{
  const double radsum = radi + radj;
  return griddem_normal_touch(&p->normal, rsq, radsum, radi * radj / radsum, touched);
}

/* griddem_contact_eval of a pair whose law is classic (p->classic): called directly by a sweep
 * that knows every pair is, so that the composed sub-models are not compiled into it; hertz: the
 * pair's normal model is hertz (gran/hertz/history), which a sweep passes as a constant */
GRIDDEM_INLINE double griddem_classic_eval(const griddem_pair_params *p, griddem_contact *c,
                                           double *hist, double *f, double *ti, double *tj, const int hertz)
{
  c->energy = 0.0;
  griddem_classic_contact(&p->normal, &p->damping, &p->tangential, p->limit_damping, hertz, c, hist, f, ti, tj);
  return c->energy;
}

/* Whether a classic pair's law is gran/hertz/history's */
GRIDDEM_INLINE int griddem_classic_hertz(const griddem_pair_params *p)
{
  return p->normal.model == GRIDDEM_NORMAL_HERTZ;
}

/* The sub-model of each axis of a law. A caller that knows them at compile time passes them to
 * griddem_contact_eval_models as constants, and the axes' switches fold away. */
typedef struct griddem_law_models {
  enum griddem_normal_model normal;
  enum griddem_damping_model damping;
  enum griddem_tangential_model tangential;
  enum griddem_rolling_model rolling;
  enum griddem_twisting_model twisting;
  enum griddem_heat_model heat;
} griddem_law_models;

GRIDDEM_INLINE griddem_law_models griddem_law_models_of(const griddem_pair_params *p)
{
  const griddem_law_models m = {p->normal.model, p->damping.model, p->tangential.model,
                                p->rolling.model, p->twisting.model, p->heat.model};
  return m;
}

/* griddem_contact_eval of a composed (not classic) law p whose sub-models are m */
GRIDDEM_INLINE double griddem_contact_eval_models(const griddem_pair_params *p, griddem_law_models m,
                                                  griddem_contact *c, double *hist, double *f, double *ti,
                                                  double *tj)
{
  /* p's coefficients, with the models of m */
  griddem_normal_params normal = p->normal;
  griddem_damping_params damping = p->damping;
  griddem_tangential_params tangential = p->tangential;
  griddem_rolling_params rolling = p->rolling;
  griddem_twisting_params twisting = p->twisting;
  griddem_heat_params heat = p->heat;
  normal.model = m.normal, damping.model = m.damping, tangential.model = m.tangential;
  rolling.model = m.rolling, twisting.model = m.twisting, heat.model = m.heat;

  c->energy = 0.0;
  griddem_contact_kinematics(c);
  if (p->need_contact_radius) c->contact_radius = griddem_normal_contact_radius(&normal, c);
  c->heat = m.heat != GRIDDEM_HEAT_NONE ? griddem_heat_flow(&heat, c) : 0.0;
  griddem_normal_force(&normal, c);
  c->fntot = c->fnormal + griddem_damping_force(&damping, c);
  if (p->limit_damping && c->fntot < 0.0) c->fntot = 0.0;
  c->fncrit = griddem_normal_fncrit(&normal, c);
  griddem_tangential_force(&tangential, c, hist);

  for (int k = 0; k < 3; k++) f[k] = c->fntot * c->n[k] + c->fs[k];
  /* torque of the tangential force about each centre */
  const double *n = c->n, *fs = c->fs;
  const double t1 = -(n[1] * fs[2] - n[2] * fs[1]);
  const double t2 = -(n[2] * fs[0] - n[0] * fs[2]);
  const double t3 = -(n[0] * fs[1] - n[1] * fs[0]);
  const double di = c->radi - 0.5 * c->delta, dj = c->radj - 0.5 * c->delta;
  ti[0] = di * t1, ti[1] = di * t2, ti[2] = di * t3;
  tj[0] = dj * t1, tj[1] = dj * t2, tj[2] = dj * t3;
  if (m.rolling == GRIDDEM_ROLLING_NONE && m.twisting == GRIDDEM_TWISTING_NONE) return c->energy;

  double relrot[3];
  for (int k = 0; k < 3; k++) relrot[k] = c->wi[k] - c->wj[k];
  if (m.rolling != GRIDDEM_ROLLING_NONE) {
    const double vrl[3] = {c->reff * (relrot[1] * n[2] - relrot[2] * n[1]),
                           c->reff * (relrot[2] * n[0] - relrot[0] * n[2]),
                           c->reff * (relrot[0] * n[1] - relrot[1] * n[0])};
    griddem_rolling_force(&rolling, c, vrl, hist + p->hist_rolling);
    const double *fr = c->fr;
    const double tr[3] = {c->reff * (n[1] * fr[2] - n[2] * fr[1]),
                          c->reff * (n[2] * fr[0] - n[0] * fr[2]),
                          c->reff * (n[0] * fr[1] - n[1] * fr[0])};
    for (int k = 0; k < 3; k++) ti[k] += tr[k], tj[k] -= tr[k];
  }
  if (m.twisting != GRIDDEM_TWISTING_NONE) {
    c->magtwist = griddem_dot3(relrot, n);
    griddem_twisting_force(&twisting, c, hist + p->hist_twisting);
    for (int k = 0; k < 3; k++) {
      const double tt = c->magtortwist * n[k];
      ti[k] += tt, tj[k] -= tt;
    }
  }
  return c->energy;
}

/* Force on i (f[3]; j gets -f) and torques on i and j of one interacting pair whose inputs are
 * set in c; returns the elastic energy stored in its springs (c->fr is set only with a rolling
 * model; c->heat is the heat into i from c's temperatures, which only a heat model reads). hist
 * holds the pair's history values seen from i (read, and advanced if c->history_update). Seen from
 * j every output and the odd history values change sign exactly, so one evaluation serves both
 * atoms. */
GRIDDEM_INLINE double griddem_contact_eval(const griddem_pair_params *p, griddem_contact *c,
                                           double *hist, double *f, double *ti, double *tj)
{
  if (p->classic) return griddem_classic_eval(p, c, hist, f, ti, tj, griddem_classic_hertz(p));
  return griddem_contact_eval_models(p, griddem_law_models_of(p), c, hist, f, ti, tj);
}

#ifdef __cplusplus
}
#endif

#endif
