/* Rolling resistance sub-model sds of LAMMPS's pair granular (gran_sub_mod_rolling.cpp): a spring,
 * dashpot and slider on the rolling displacement (3 history values, even under i <-> j). */
#ifndef GRIDDEM_ROLLING_H
#define GRIDDEM_ROLLING_H

#include "griddem_contact_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum griddem_rolling_model { GRIDDEM_ROLLING_NONE = 0, GRIDDEM_ROLLING_SDS = 1 };

typedef struct griddem_rolling_params {
  enum griddem_rolling_model model;
  double k, gamma, mu;
} griddem_rolling_params;

/* Sets c->fr from the rolling velocity vrl (Wang et al. 2015, eq. 31) and the history at h. */
GRIDDEM_INLINE void griddem_rolling_force(const griddem_rolling_params *p, griddem_contact *c,
                                         const double *vrl, double *h)
{
  switch (p->model) {
    case GRIDDEM_ROLLING_NONE: c->fr[0] = c->fr[1] = c->fr[2] = 0.0; return;
    case GRIDDEM_ROLLING_SDS: break;
  }
  const double frcrit = p->mu * c->fncrit;
  double ht[3] = {h[0], h[1], h[2]};
  if (c->history_update) {
    griddem_rotate_rescale(ht, c->n, p->k, frcrit);
    for (int m = 0; m < 3; m++) ht[m] += c->dt * vrl[m];
  }
  for (int m = 0; m < 3; m++) c->fr[m] = (-p->k) * ht[m] + (-p->gamma) * vrl[m];
  const double magfr = griddem_len3(c->fr);
  if (magfr > frcrit) {
    if (griddem_len3(ht) != 0.0) {
      const double kinv = 1.0 / p->k, magfr_inv = 1.0 / magfr;
      for (int m = 0; m < 3; m++) {
        ht[m] = (-frcrit * kinv * magfr_inv) * c->fr[m] + (-p->gamma * kinv) * vrl[m];
        c->fr[m] *= frcrit * magfr_inv;
      }
    } else {
      c->fr[0] = c->fr[1] = c->fr[2] = 0.0;
    }
  }
  if (c->history_update) h[0] = ht[0], h[1] = ht[1], h[2] = ht[2];
  c->energy += 0.5 * p->k * griddem_dot3(ht, ht);
}

#ifdef __cplusplus
}
#endif

#endif
