/* GRIDDEM stencil sweep on the CPU. Contacts are found by scanning, per stencil row, the
 * contiguous slot range of the row's cells that can hold a centre within contact distance; only
 * the forward half of the stencil in sorted order is visited, so each pair is evaluated once.
 * Threads take slabs of cell layers along z in two colours (a slab's pairs reach at most the
 * next slab), so no two threads write the same particle and no atomics are needed. */
#ifndef GRIDDEM_SWEEP_H
#define GRIDDEM_SWEEP_H

#include "griddem_contact.h"
#include "griddem_exclusions.h"
#include "griddem_grid.h"
#include "griddem_history.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Particles as the host code stores them: owned first (nlocal), then ghosts, up to nall;
 * vectors are interleaved xyz. tag is 32- or 64-bit per tag_bytes; type is 1-based. */
typedef struct griddem_particles {
  int nlocal, nall;
  const double *x, *v, *omega, *radius, *rmass;
  const void *tag;
  int tag_bytes;
  const int *type;
  const int *mask;   /* group bits */
  int frozen_bit;    /* mask & frozen_bit marks a frozen particle (infinite mass); 0: none */
  const int *image;  /* per particle: its periodic image (griddem_image_code), where the box has
                        image axes; NULL: contacts are keyed by partner tag alone */
  const void *molecule; /* per particle, tag_bytes wide: its molecule, where the exclusions name
                           molecules; NULL otherwise */
  const double *temperature; /* per particle, where some type pair conducts heat; NULL otherwise */
  double *heatflow;          /* per particle, with temperature: the contacts' heat added (owned ones) */
} griddem_particles;

/* The particles in sorted order (the channels): centre and radius per slot, one array each, which
 * the candidate search reads in runs of slots a vector at a time; a pair that touches reads the
 * rest (velocities, mass, type, mask) from the particles through the slot's index. Also the
 * cross-class pass's scratch, kept between steps. */
typedef struct griddem_channels {
  int n, cap;
  const griddem_particles *p;  /* of the last fill */
  double *x, *y, *z, *r;       /* per slot */
  float *xf, *yf, *zf, *rf;    /* the same rounded to float, for the search's float test */
  int same_radius;             /* every slot of the last fill has one radius */
  int64_t *tag;
  int *image;                  /* per slot: its particle's image code, if keyed_by_image */
  int keyed_by_image, image_cap; /* the particles had images: contacts keyed by partner and image */
  int *ncontact;               /* per slot: contacts evaluated (of owned particles) */
  int *slab, *slots, *first;   /* cross-class pass: small spheres by slab of the coarse grid */
  int across_cap, first_cap;
} griddem_channels;

int griddem_channels_fill(griddem_channels *ch, const griddem_bins *b, const griddem_particles *p);
void griddem_channels_free(griddem_channels *ch);


enum griddem_fault {
  GRIDDEM_FAULT_NONE = 0,
  GRIDDEM_FAULT_COINCIDENT = 1,      /* two centres at distance 0 */
  GRIDDEM_FAULT_STENCIL = 2,         /* contact distance above GRIDDEM_MAX_REACH cell edges */
  GRIDDEM_FAULT_MEMORY = 3           /* no memory for the history or the grid */
};

typedef struct griddem_sweep_result {
  double virial[6];    /* xx yy zz xy xz yz; a pair with one owned atom counts half */
  double energy;       /* elastic energy stored in the contacts' springs, counted as the virial
                          (tallied only with GRIDDEM_TALLY_ENERGY, else 0) */
  long contacts;       /* contacts summed over owned particles (an owned pair counts twice) */
  int max_contacts;    /* most contacts of one owned particle */
  int fault;           /* enum griddem_fault; the first one met */
  int fault_i, fault_j;/* original indices of the particles involved */
} griddem_sweep_result;

/* What a sweep sums besides forces and torques (bits): the global virial, the elastic energy. A
 * host asks for each only on the steps that read it, as LAMMPS's eflag and vflag do. */
#define GRIDDEM_TALLY_VIRIAL 1
#define GRIDDEM_TALLY_ENERGY 2

/* One size class: its particles binned on its own grid g (b's slots are slots base.. of the
 * channels), and the largest radius it may hold. One class is the plain single grid. kinematic:
 * its particles are kinematic, and no pair of two kinematic particles interacts (the sweep
 * searches no such pair: neither within the class nor across two kinematic classes). owned_lo ..
 * owned_hi: a box of g's cells (inclusive, empty where lo > hi along an axis) outside which no
 * owned particle's centre lies; a ghost's candidates outside it are ghosts, whose pairs with it are
 * not evaluated, so the sweep tests none of them (griddem_owned_cells makes it). */
typedef struct griddem_class_grid {
  const griddem_grid *g;
  const griddem_bins *b;
  int base;
  double rmax;
  int kinematic;
  int owned_lo[3], owned_hi[3];
} griddem_class_grid;

/* The cells of g that the box lo..hi of the owned particles' centres covers, into owned_lo ..
 * owned_hi (an empty box where there is no owned particle: nowned 0). */
void griddem_owned_cells(const griddem_grid *g, const double lo[3], const double hi[3], int nowned, int owned_lo[3],
                         int owned_hi[3]);

/* One sweep over ncls size classes, cls[0] holding the largest spheres: pairs within a class on
 * its own grid (forward half stencil in sorted order), pairs across two classes by searching the
 * spheres of one in the other's grid, whichever direction costs fewer block rows and candidates
 * (a few large spheres among many small ones search the small ones' grid), and a class with its
 * kinematic twin (the class after it, laid over the same cells) through the class's cell rows and
 * the full stencil;
 * order: the particle of each slot of the channels. Each pair in
 * contact is evaluated once and its force and torques go to whichever of its two particles are
 * owned, so ghosts receive nothing (newton off across processes). Adds into f and torque
 * (3*nlocal), and half of del*f of each contact into vatom (6*nlocal) if not NULL; sums the virial
 * and the energy into result only as tally (GRIDDEM_TALLY_*) asks. If model->track_contacts, particle i's history is row
 * row_of[i] of hist (-1: none), which the sweep updates in place (griddem_history_end: rows may
 * be given, moved or laid out afresh, and row_of with them). excl may be NULL. Returns
 * result->fault. */
int griddem_sweep(const griddem_class_grid *cls, int ncls, const int *order, griddem_channels *ch,
                  int nlocal, const griddem_model *model, const griddem_exclusions *excl, double dt,
                  int history_update, griddem_history *hist, int *row_of, double *f,
                  double *torque, double *vatom, int tally, griddem_sweep_result *result);

/* Candidate pairs griddem_sweep tests on the classes cls (what a grid layout costs): per class,
 * each cell's centres against its forward half stencil; across two classes, each sphere of the
 * searching class against the other grid's cells within the contact distance of its cell (a bound
 * on the sweep's blocks around the sphere itself). Needs the bins only, not the channels. */
double griddem_sweep_candidates(const griddem_class_grid *cls, int ncls, double reach_extra);

#ifdef __cplusplus
}
#endif

#endif
