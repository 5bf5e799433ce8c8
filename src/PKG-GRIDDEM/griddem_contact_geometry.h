/* The state of one contact that every contact sub-model reads and adds to, in the order LAMMPS's
 * GranularModel::calculate_forces composes them: geometry and relative velocities first, then the
 * normal force, damping, tangential, rolling and twisting parts. Sign convention: dx = x_i - x_j,
 * forces act on i; seen from j every odd quantity changes sign exactly. */
#ifndef GRIDDEM_CONTACT_GEOMETRY_H
#define GRIDDEM_CONTACT_GEOMETRY_H

#include "griddem_portable.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct griddem_contact {
  /* set by the caller */
  double dx[3], rsq;        /* x_i - x_j and its squared length (> 0) */
  double radi, radj, meff;
  double vr[3];             /* v_i - v_j */
  double wi[3], wj[3];      /* angular velocities */
  double dt;
  int history_update;       /* 1: advance the history values by dt */
  double temp_i, temp_j;    /* temperatures (read by a heat model only) */
  /* geometry and kinematics (griddem_contact_kinematics) */
  double r, rinv, radsum, reff, delta, dR, n[3];
  double vnnr, vt[3], vtr[3], vrel;
  double contact_radius;    /* set when a sub-model needs it */
  /* forces, filled in by the sub-models */
  double fnormal;           /* normal model's force (with adhesion for dmt/jkr) */
  double fpulloff;          /* dmt/jkr pull-off force */
  double damp_prefactor;    /* damping model's coefficient of -vnnr */
  double fntot, fncrit;     /* total normal force; the force that caps friction */
  double damp_tangential;   /* tangential model's damping coefficient */
  double fs[3], fr[3];      /* tangential and rolling forces */
  double magtwist, magtortwist;
  double energy;            /* elastic energy stored in the contact's springs */
  double heat;              /* heat flowing into i (a heat model's; else 0) */
} griddem_contact;

GRIDDEM_INLINE double griddem_dot3(const double *a, const double *b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* a*b + c*d with the same bits whichever pair comes first. Seen from j, a contact's sums such as
 * radi wi + radj wj swap their terms, and the Kokkos styles evaluate a contact once from each atom
 * and rely on equal bits. Where the hardware fuses multiply-adds (FMA: GPUs, -mfma), a compiler
 * may fuse either product into the add (nvcc does by default, and it sees through a swap of the
 * operands), so the fused form is written out in an order set by the operands' values; without
 * FMA nothing is fused and the rounded sum is commutative. */
GRIDDEM_INLINE double griddem_symmetric_sum(double a, double b, double c, double d)
{
#if defined(FP_FAST_FMA) || defined(__CUDA_ARCH__) || defined(__HIP_DEVICE_COMPILE__)
  return (a > c || (a == c && b > d)) ? fma(c, d, a * b) : fma(a, b, c * d);
#else
  return a * b + c * d;
#endif
}

GRIDDEM_INLINE double griddem_len3(const double *a)
{
  return sqrt(griddem_dot3(a, a));
}

/* Distances, normal and relative velocities of a contact whose inputs are set. */
GRIDDEM_INLINE void griddem_contact_kinematics(griddem_contact *c)
{
  c->r = sqrt(c->rsq);
  c->rinv = 1.0 / c->r;
  c->radsum = c->radi + c->radj;
  c->reff = c->radi * c->radj / c->radsum;
  c->delta = c->radsum - c->r;
  c->dR = c->delta * c->reff;
  for (int k = 0; k < 3; k++) c->n[k] = c->rinv * c->dx[k];
  c->vnnr = griddem_dot3(c->vr, c->n);
  for (int k = 0; k < 3; k++) c->vt[k] = c->vr[k] - c->vnnr * c->n[k];
  double wr[3];
  for (int k = 0; k < 3; k++) wr[k] = griddem_symmetric_sum(c->radi, c->wi[k], c->radj, c->wj[k]);
  c->vtr[0] = c->vt[0] - (wr[1] * c->n[2] - wr[2] * c->n[1]);
  c->vtr[1] = c->vt[1] - (wr[2] * c->n[0] - wr[0] * c->n[2]);
  c->vtr[2] = c->vt[2] - (wr[0] * c->n[1] - wr[1] * c->n[0]);
  c->vrel = griddem_len3(c->vtr);
}

/* Keep h's length while removing its part along n, unless that part is negligible against the
 * critical force (|h.n| k <= 1e-10 Fcrit), as LAMMPS's history-frame update does. */
GRIDDEM_INLINE void griddem_rotate_rescale(double *h, const double *n, double k, double fcrit)
{
  const double hn = griddem_dot3(h, n);
  if (fabs(hn) * k > 1e-10 * fcrit) {
    const double mag = griddem_len3(h);
    for (int m = 0; m < 3; m++) h[m] -= hn * n[m];
    const double prj = griddem_len3(h);
    const double scale = prj > 0 ? mag / prj : 0;
    for (int m = 0; m < 3; m++) h[m] *= scale;
  }
}

#ifdef __cplusplus
}
#endif

#endif
