/* Tangential (friction) sub-models of LAMMPS's pair granular (gran_sub_mod_tangential.cpp); the
 * laws of gran/hooke and gran/hooke/history are in griddem_classic.h. Each sets c->fs from the history values
 * at h (3 values: the tangential displacement, or the force for the mindlin .../force forms; the
 * rescale forms add a 4th, the contact radius of the previous step) and caps it by Coulomb. */
#ifndef GRIDDEM_TANGENTIAL_H
#define GRIDDEM_TANGENTIAL_H

#include "griddem_contact_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

enum griddem_tangential_model {
  GRIDDEM_TANGENTIAL_NONE = 0,
  GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY = 1,   /* also gran/hooke */
  GRIDDEM_TANGENTIAL_LINEAR_HISTORY = 2,
  GRIDDEM_TANGENTIAL_LINEAR_HISTORY_CLASSIC = 3, /* stock scales its k by the contact radius */
  GRIDDEM_TANGENTIAL_HOOKE_HISTORY = 4,      /* gran/hooke/history (griddem_classic.h) */
  GRIDDEM_TANGENTIAL_MINDLIN = 5,
  GRIDDEM_TANGENTIAL_MINDLIN_FORCE = 6,
  GRIDDEM_TANGENTIAL_MINDLIN_RESCALE = 7,
  GRIDDEM_TANGENTIAL_MINDLIN_RESCALE_FORCE = 8,
  GRIDDEM_TANGENTIAL_MINDLIN_CLASSIC = 9 /* gran/hertz/history's; stock gives it linear_history_classic's law */
};

typedef struct griddem_tangential_params {
  enum griddem_tangential_model model;
  double k, xt, mu;   /* damping = xt * the normal damping prefactor */
  double gamma_mass;  /* gran/hooke styles: damping = meff * gamma_t, independent of the normal's */
} griddem_tangential_params;

/* Coulomb cap of a history force: shrink fs to fscrit and set the history to what gives it;
 * kinv converts force to history (-1/k, or -1 for the force forms) */
GRIDDEM_INLINE void griddem_tangential_cap(griddem_contact *c, double *h, double fscrit, double damp,
                                          double kinv, int history_nonzero)
{
  const double magfs = griddem_len3(c->fs);
  if (!(magfs > fscrit)) return;
  if (history_nonzero) {
    const double s = fscrit * (1.0 / magfs);
    for (int m = 0; m < 3; m++) {
      h[m] = (s * c->fs[m] + damp * c->vtr[m]) * kinv;
      c->fs[m] *= s;
    }
  } else {
    c->fs[0] = c->fs[1] = c->fs[2] = 0.0;
  }
}

/* Sets c->fs and c->damp_tangential; h: the model's history values (may be NULL for none and
 * linear_nohistory). */
GRIDDEM_INLINE void griddem_tangential_force(const griddem_tangential_params *p, griddem_contact *c,
                                            double *h)
{
  const double damp = p->xt * c->damp_prefactor;
  const double fscrit = p->mu * c->fncrit;
  c->damp_tangential = damp;
  c->fs[0] = c->fs[1] = c->fs[2] = 0.0; /* none's; every other case sets them */
  switch (p->model) {
    case GRIDDEM_TANGENTIAL_NONE:
      return;
    case GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY: {
      const double fsmag = damp * c->vrel;
      const double ft = c->vrel != 0.0 ? (fscrit < fsmag ? fscrit : fsmag) / c->vrel : 0.0;
      for (int m = 0; m < 3; m++) c->fs[m] = -ft * c->vtr[m];
      return;
    }
    case GRIDDEM_TANGENTIAL_LINEAR_HISTORY:
      if (c->history_update) {
        griddem_rotate_rescale(h, c->n, p->k, fscrit);
        for (int m = 0; m < 3; m++) h[m] += c->dt * c->vtr[m];
      }
      for (int m = 0; m < 3; m++) c->fs[m] = -p->k * h[m] - damp * c->vtr[m];
      griddem_tangential_cap(c, h, fscrit, damp, -1.0 / p->k, griddem_len3(h) != 0.0);
      c->energy += 0.5 * p->k * griddem_dot3(h, h);
      return;
    case GRIDDEM_TANGENTIAL_LINEAR_HISTORY_CLASSIC:
    case GRIDDEM_TANGENTIAL_MINDLIN_CLASSIC: {
      /* advance, then project onto the tangent plane without restoring the length */
      if (c->history_update)
        for (int m = 0; m < 3; m++) h[m] += c->dt * c->vtr[m];
      const double shrmag = griddem_len3(h);
      if (c->history_update) {
        const double rsht = griddem_dot3(h, c->n);
        for (int m = 0; m < 3; m++) h[m] -= rsht * c->n[m];
      }
      const double k = p->k * c->contact_radius;
      for (int m = 0; m < 3; m++) c->fs[m] = -k * h[m] - damp * c->vtr[m];
      griddem_tangential_cap(c, h, fscrit, damp, -1.0 / p->k, shrmag != 0.0);
      c->energy += 0.5 * k * griddem_dot3(h, h);
      return;
    }
    case GRIDDEM_TANGENTIAL_HOOKE_HISTORY:
      /* gran/hooke/history's law is griddem_classic_contact, which its setup selects (classic) */
      return;
    case GRIDDEM_TANGENTIAL_MINDLIN:
    case GRIDDEM_TANGENTIAL_MINDLIN_FORCE:
    case GRIDDEM_TANGENTIAL_MINDLIN_RESCALE:
    case GRIDDEM_TANGENTIAL_MINDLIN_RESCALE_FORCE: {
      const int force_form = p->model == GRIDDEM_TANGENTIAL_MINDLIN_FORCE ||
          p->model == GRIDDEM_TANGENTIAL_MINDLIN_RESCALE_FORCE;
      const int rescale = p->model == GRIDDEM_TANGENTIAL_MINDLIN_RESCALE ||
          p->model == GRIDDEM_TANGENTIAL_MINDLIN_RESCALE_FORCE;
      const double k_scaled = p->k * c->contact_radius;
      /* on unloading, shrink the history with the contact radius */
      if (rescale && c->contact_radius < h[3]) {
        const double s = c->contact_radius / h[3];
        for (int m = 0; m < 3; m++) h[m] *= s;
      }
      if (c->history_update) {
        griddem_rotate_rescale(h, c->n, force_form ? 1.0 : k_scaled, fscrit);
        const double step = force_form ? -k_scaled * c->dt : c->dt;
        for (int m = 0; m < 3; m++) h[m] += step * c->vtr[m];
        if (rescale) h[3] = c->contact_radius;
      }
      for (int m = 0; m < 3; m++)
        c->fs[m] = -damp * c->vtr[m] + (force_form ? h[m] : -(k_scaled * h[m]));
      griddem_tangential_cap(c, h, fscrit, damp, force_form ? 1.0 : -1.0 / k_scaled,
                             griddem_len3(h) != 0.0);
      c->energy += force_form ? (k_scaled > 0.0 ? 0.5 * griddem_dot3(h, h) / k_scaled : 0.0)
                              : 0.5 * k_scaled * griddem_dot3(h, h);
    }
  }
}

#ifdef __cplusplus
}
#endif

#endif
