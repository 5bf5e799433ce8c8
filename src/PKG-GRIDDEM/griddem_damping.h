/* Normal damping sub-models of LAMMPS's pair granular (gran_sub_mod_damping.cpp). Each sets the
 * prefactor of -vnnr, which the tangential models scale for their own damping. tsuji and
 * coeff_restitution share the force; their coefficients differ in how they are derived from the
 * restitution coefficient (see griddem_submodels.c). */
#ifndef GRIDDEM_DAMPING_H
#define GRIDDEM_DAMPING_H

#include "griddem_contact_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum griddem_damping_model {
  GRIDDEM_DAMPING_VELOCITY = 0,         /* damp */
  GRIDDEM_DAMPING_MASS_VELOCITY = 1,    /* damp * meff */
  GRIDDEM_DAMPING_VISCOELASTIC = 2,     /* damp * meff * contact radius */
  GRIDDEM_DAMPING_TSUJI = 3,            /* damp * sqrt(meff * Fnormal / overlap) */
  GRIDDEM_DAMPING_COEFF_RESTITUTION = 4 /* as tsuji */
};

typedef struct griddem_damping_params {
  enum griddem_damping_model model;
  double damp; /* converted coefficient */
} griddem_damping_params;

/* Sets c->damp_prefactor; returns the damping force along n. */
GRIDDEM_INLINE double griddem_damping_force(const griddem_damping_params *p, griddem_contact *c)
{
  c->damp_prefactor = 0.0; /* for the compiler: every case sets it */
  switch (p->model) {
    case GRIDDEM_DAMPING_VELOCITY: c->damp_prefactor = p->damp; break;
    case GRIDDEM_DAMPING_MASS_VELOCITY: c->damp_prefactor = p->damp * c->meff; break;
    case GRIDDEM_DAMPING_VISCOELASTIC: c->damp_prefactor = p->damp * c->meff * c->contact_radius; break;
    case GRIDDEM_DAMPING_TSUJI:
    case GRIDDEM_DAMPING_COEFF_RESTITUTION: {
      /* the argument may round below zero */
      const double arg = c->delta > 0.0 ? fmax(0.0, c->meff * c->fnormal / c->delta) : 0.0;
      c->damp_prefactor = p->damp * sqrt(arg);
    }
  }
  return -c->damp_prefactor * c->vnnr;
}

#ifdef __cplusplus
}
#endif

#endif
