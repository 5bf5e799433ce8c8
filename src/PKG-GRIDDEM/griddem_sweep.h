/* GRIDDEM stencil sweep on the CPU: gather form (each owned particle sums the forces its
 * neighbours exert on it, newton off), so threads never write the same particle and need no
 * atomics. Contacts are found by scanning, per stencil row, the contiguous slot range of the
 * row's cells that can hold a centre within contact distance. */
#ifndef GRIDDEM_SWEEP_H
#define GRIDDEM_SWEEP_H

#include "griddem_contact.h"
#include "griddem_grid.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Particles as the host code stores them: owned first (nlocal), then ghosts, up to nall;
 * vectors are interleaved xyz. tag is 32- or 64-bit per tag_bytes; frozen may be NULL. */
typedef struct griddem_particles {
  int nlocal, nall;
  const double *x, *v, *omega, *radius, *rmass;
  const void *tag;
  int tag_bytes;
  const int *mask;   /* with frozen_bit: mask & frozen_bit marks a frozen particle; may be NULL */
  int frozen_bit;
} griddem_particles;

/* Sorted structure-of-arrays copy of the particles (the channels). */
typedef struct griddem_channels {
  int n, cap;
  double *x, *y, *z, *vx, *vy, *vz, *wx, *wy, *wz, *rad, *mass;
  int64_t *tag;
  unsigned char *frozen;
} griddem_channels;

int griddem_channels_fill(griddem_channels *ch, const griddem_bins *b, const griddem_particles *p);
void griddem_channels_free(griddem_channels *ch);

/* Per-owned-particle contact history: row i (stride doubles) holds
 * [count, (partner tag, shear x, shear y, shear z) x slots]. */
typedef struct griddem_history {
  double *rows;
  int stride;
  int slots;
} griddem_history;

#define GRIDDEM_HISTORY_STRIDE(slots) (1 + 4 * (slots))

enum griddem_fault {
  GRIDDEM_FAULT_NONE = 0,
  GRIDDEM_FAULT_COINCIDENT = 1,      /* two centres at distance 0 */
  GRIDDEM_FAULT_HISTORY_FULL = 2     /* more contacts than history slots */
};

typedef struct griddem_sweep_result {
  double virial[6];    /* xx yy zz xy xz yz, half of each pair from each side */
  double energy;       /* elastic energy stored in the contacts' springs (normal and shear) */
  long contacts;       /* pair contacts seen from owned particles */
  int max_contacts;    /* most contacts of one owned particle */
  int fault;           /* enum griddem_fault; the first one met */
  int fault_i, fault_j;/* original indices of the particles involved */
} griddem_sweep_result;

/* One sweep. Adds forces and torques of owned particles into f and torque (3*nlocal), and
 * 0.5*del*f of each contact into vatom (6*nlocal) if not NULL. cut_extra is the largest radius
 * any partner can have (contact distance of i is radius_i + cut_extra). hist may be NULL unless
 * params->tangential is GRIDDEM_TANGENTIAL_HISTORY. Returns result->fault. */
int griddem_sweep(const griddem_grid *g, const griddem_bins *b, const griddem_channels *ch,
                  int nlocal, double cut_extra, const griddem_hooke_params *params, double dt,
                  int shearupdate, griddem_history *hist, double *f, double *torque, double *vatom,
                  int want_virial, griddem_sweep_result *result);

#ifdef __cplusplus
}
#endif

#endif
