/* The GRIDDEM engine: what a CPU pair style keeps between steps (grids, bins, channels, scratch)
 * behind a narrow face. A step bins the particles, sweeps the stencil and leaves each owned
 * particle pointing at its new row of the contact history it is given (griddem_history.h, which
 * fix griddem keeps: the history lives as long as the atoms, the engine as long as the pair). */
#ifndef GRIDDEM_ENGINE_H
#define GRIDDEM_ENGINE_H

#include "griddem_contact.h"
#include "griddem_grid.h"
#include "griddem_history.h"
#include "griddem_sweep.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct griddem_engine_stats {
  long occupied_cells;  /* cells holding a centre (-1 after a step: griddem_engine_count_occupancy) */
  int max_occupancy;    /* most centres in one cell (likewise) */
  double cell_edge;     /* edge used (a dilute scene may coarsen it) */
  long contacts;        /* contacts of owned particles (an owned pair counts twice) */
  int max_contacts;     /* most contacts of one owned particle */
  double elastic_energy; /* tallied on steps that asked for it (energy_tallied), else 0 */
  int energy_tallied;
  double max_speed;       /* of an owned particle */
  double max_cells_moved; /* max_speed * dt in cells */
  int nonfinite_velocity; /* 1: some owned particle has a non-finite velocity */
} griddem_engine_stats;

/* Size classes: class c holds radii in (rmax/4^(c+1), rmax/4^c] (a factor 4 per class measured
 * faster than 2 on the 1:4 squeeze and a 1:10 pour); the last class takes all smaller ones. */
#define GRIDDEM_CLASS_SHIFT 2
#define GRIDDEM_MAX_CLASSES 8
/* Grids of a step: one per size class, and as many again where the particles binned last are
 * mostly kinematic (the exclusions' both_bit: fix griddem/rom's model-driven particles), which touch
 * only the others: each class's kinematic particles then get a grid of their own, which the sweep
 * searches only from the other particles, so no pair of two kinematic particles is a candidate. */
#define GRIDDEM_MAX_GRIDS (2 * GRIDDEM_MAX_CLASSES)
/* Most cells of the one grid (no size classes) over n particles, owned and ghosts: a dilute
 * scene gets larger cells rather than a grid it does not fill (cleared every step); the edge
 * grows until the grid fits (griddem_grid_fit). */
#define GRIDDEM_ONE_GRID_MAX_CELLS(n) (32L * (n) + 65536L)
/* Most cells of a class's grid holding n centres: a sparse class gets larger cells rather than a
 * grid it does not fill (cleared every step); the stencils follow the edge. */
#define GRIDDEM_CLASS_MAX_CELLS(n) (8L * (n) + 1024L)

/* Number of size classes for radii in [rmin, rmax]: one per factor 2^GRIDDEM_CLASS_SHIFT. */
int griddem_class_count(double rmin, double rmax);

/* The classes' bounds for a largest radius rmax: upper[c] = rmax / 4^c for c < ncls, and 0 from
 * upper[ncls] to upper[GRIDDEM_MAX_CLASSES] (upper holds GRIDDEM_MAX_CLASSES + 1 values). */
void griddem_class_bounds(double rmax, int ncls, double *upper);

/* Size class of radius r: class c holds radii in (upper[c+1], upper[c]], the last class all
 * smaller ones; as the bounds decrease, that is how many of upper[1..ncls-1] are at or above r.
 * Counted over every class a grid may have, without branches, so that a loop over particles runs
 * in vector lanes (upper as griddem_class_bounds fills it). How both the CPU engine and the
 * Kokkos styles sort a sphere into its grid. */
GRIDDEM_INLINE int griddem_class_of(double r, const double *upper, int ncls)
{
  int c = 0;
  for (int k = 1; k < GRIDDEM_MAX_CLASSES; k++) c += (k < ncls) & (r <= upper[k]);
  return c;
}

typedef struct griddem_engine {
  int nclass;                           /* size classes of the last step (1: one grid) */
  int ngrid;                            /* its grids: nclass, or twice that with kinematic ones */
  int kinematic_grids;                  /* 1: the last step binned at least as many kinematic
                                           particles as others; this one gives them grids */
  griddem_grid grid[GRIDDEM_MAX_GRIDS]; /* one per size class, largest spheres first, each
                                           followed by its kinematic twin where there are twins */
  griddem_bins bins[GRIDDEM_MAX_GRIDS];
  int one_grid_binned;                  /* 1: the last step binned the particles as they are on
                                           one grid (bins[0] indexes them) */
  griddem_channels channels;
  griddem_engine_stats stats;
  /* size classes' scratch: particles grouped by class, their positions and tags, the channels'
   * order of particles */
  int *member, *order;
  double *xc;
  int64_t *keyc;
  int work_cap;
  /* where size classes gathered particles held since the host last replaced them (member and
   * keyc, gathered_base[grid] their first slot in each grid; gathered 0: none held), the ghosts
   * kept within the reach widened by ghost_margin: the same ones until it replaces them again */
  int gathered;
  int gathered_base[GRIDDEM_MAX_GRIDS + 1];
  int gathered_n, gathered_ncls;
  double gathered_rmax;
} griddem_engine;

/* The engine's first pass: one sweep over the particles finds what the step needs to know before
 * it bins them. Positions and the box cover all particles (nall), velocities and radii the owned
 * ones; the radius range only where radii is 1 (it changes only as atoms come and go). */
typedef struct griddem_scan {
  int first_nonfinite;    /* first particle with a non-finite position, or -1 */
  double lo[3], hi[3];    /* box of the positions (meaningless without particles) */
  double owned_lo[3], owned_hi[3]; /* box of the owned particles' positions (meaningless without) */
  double vmax2;           /* largest squared speed of an owned particle */
  int nonfinite_velocity; /* 1: some owned particle has a non-finite velocity */
  double rmin, rmax;      /* radius range of the owned particles (INFINITY, 0 without; NaN
                             where radii is 0) */
} griddem_scan;

void griddem_engine_scan(const griddem_particles *p, int radii, griddem_scan *scan);

/* One step's input. Particles hold owned ones first, then ghosts. */
typedef struct griddem_step {
  griddem_particles particles;
  double anchor[3];        /* cell faces align to it (the box corner where the host last
                              replaced the particles: fixed while they are the same) */
  double cell_edge;        /* wanted cell edge (one grid) */
  int size_classes;        /* 1: a grid per size class (edge: twice its largest radius); ghosts
                              out of reach of every owned particle are then not binned */
  double rmin;             /* smallest radius of any particle (size classes) */
  long max_cells;          /* the edge grows if the grid would need more cells */
  double rmax;             /* largest radius of any particle */
  const griddem_model *model;
  const griddem_exclusions *excl; /* may be NULL */
  const griddem_scan *scan; /* this step's griddem_engine_scan of the particles; NULL: the step scans */
  int same_particles;      /* 1: the particles of the engine's last step, each at the same index
                              (positions moved: the host did not re-sort, exchange or re-ghost
                              them), so that a grid is binned again by moving the slots of
                              those that changed cells (griddem_bin_points_again) */
  int fixed_radii;         /* 1: every radius as at the engine's last step */
  double ghost_margin;     /* the most a ghost and an owned particle together move between the
                              host's replacements of the particles (LAMMPS: its skin, on which
                              its ghosts rely too): where it replaces them, size classes keep
                              ghosts within this much beyond reach, and keep the same particles in
                              the same grids while they stay the same particles with fixed radii
                              and no exclusion bits */
  double dt;
  int history_update;      /* 1: advance history values */
  griddem_history *hist;   /* the contact history (NULL where the model tracks no contacts) */
  int *row_of;             /* per particle: its history row (-1: none); updated for owned ones */
  double *f, *torque;      /* added into, 3 per owned particle */
  double *vatom;           /* NULL, or 6 per owned particle, added into */
  int tally;               /* what the sweep sums (GRIDDEM_TALLY_*) */
} griddem_step;

void griddem_engine_init(griddem_engine *e);
void griddem_engine_free(griddem_engine *e);

/* One step: bin, sweep, adopt the new history rows. Returns result->fault; 1 in *coarsened if
 * the one grid's cell edge had to grow (then e->stats.cell_edge is the edge used; size classes
 * grow the cells of a sparse class silently, a choice of speed only). With size classes, radius
 * ratios rmax/rmin below 4 keep one grid (the one-grid path, cell_edge), each further factor 4
 * adds a class, up to GRIDDEM_MAX_CLASSES. Particles with the exclusions' apart_bit (in no pair
 * this step) are not binned: their owned rows become -1 and only their speed is checked. Where
 * the exclusions have a both_bit and the last step binned at least as many particles with it as
 * without, those are binned on grids of their own (GRIDDEM_MAX_GRIDS), from which only the others
 * search partners. */
int griddem_engine_step(griddem_engine *e, const griddem_step *s, griddem_sweep_result *result,
                        int *coarsened);

/* What a grid layout costs: bins the particles as s says (no sweep; e->stats.occupied_cells and
 * max_occupancy are set) and returns the candidate pairs the sweep would test on those grids
 * (griddem_sweep_candidates), or -1 without memory. How a pair style compares a cell mode with
 * the default's layout. */
double griddem_engine_candidates(griddem_engine *e, const griddem_step *s);

/* Sets e->stats.occupied_cells and max_occupancy from the grids of e's last step. */
void griddem_engine_count_occupancy(griddem_engine *e);

/* Bytes the engine holds. */
double griddem_engine_memory(const griddem_engine *e);

#ifdef __cplusplus
}
#endif

#endif
