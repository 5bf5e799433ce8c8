/* Twisting resistance sub-models of LAMMPS's pair granular (gran_sub_mod_twisting.cpp): sds with
 * its own coefficients, and marshall, whose coefficients follow from the tangential model and the
 * contact radius (Marshall 2009, eq. 32). One history value, the accumulated twist angle, even
 * under i <-> j (stock reserves three and uses the first). */
#ifndef GRIDDEM_TWISTING_H
#define GRIDDEM_TWISTING_H

#include "griddem_contact_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum griddem_twisting_model { GRIDDEM_TWISTING_NONE = 0, GRIDDEM_TWISTING_SDS = 1, GRIDDEM_TWISTING_MARSHALL = 2 };

typedef struct griddem_twisting_params {
  enum griddem_twisting_model model;
  double k, damp, mu; /* marshall: the tangential model's k and mu; damp unused */
} griddem_twisting_params;

/* Sets c->magtortwist from c->magtwist and the history value at h. */
GRIDDEM_INLINE void griddem_twisting_force(const griddem_twisting_params *p, griddem_contact *c, double *h)
{
  double k = p->k, damp = p->damp, mu = p->mu;
  switch (p->model) {
    case GRIDDEM_TWISTING_NONE: c->magtortwist = 0.0; return;
    case GRIDDEM_TWISTING_SDS: break;
    case GRIDDEM_TWISTING_MARSHALL:
      k = 0.5 * p->k * c->contact_radius * c->contact_radius;
      damp = 0.5 * c->damp_tangential * c->contact_radius * c->contact_radius;
      mu = (2.0 / 3.0) * p->mu * c->contact_radius;
      break;
  }
  if (c->history_update) h[0] += c->magtwist * c->dt;
  c->magtortwist = -k * h[0] - damp * c->magtwist;
  const double sign = (c->magtwist > 0) - (c->magtwist < 0);
  const double mtcrit = mu * c->fncrit;
  if (fabs(c->magtortwist) > mtcrit) {
    h[0] = (mtcrit * sign - damp * c->magtwist) / k;
    c->magtortwist = -mtcrit * sign;
  }
  c->energy += 0.5 * k * h[0] * h[0];
}

#ifdef __cplusplus
}
#endif

#endif
