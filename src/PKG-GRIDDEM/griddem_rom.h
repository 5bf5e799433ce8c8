/* GRIDDEM reduced-order model (fix griddem/rom): a voxel grid over a box, the voxel mass field of
 * particles by cloud-in-cell weights (the same weights and boundary rule as griddem_cg_cic, so the
 * field equals compute griddem/cg's density with a kernel width far below the voxel edge), a
 * linear (ridge-regression) map from features [1, density of each voxel, controls] to the voxel
 * velocities (or each voxel's density times a linear map of [1, controls]), and the trilinear
 * interpolation of that velocity field at a point (the same weights again). Voxel m = i + nx (j +
 * ny k); its centre is lo + (i + 1/2) h. */
#ifndef GRIDDEM_ROM_H
#define GRIDDEM_ROM_H

#include "griddem_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* the model file's format: version 1 (box = simulation box, velocity rows), version 2 adds the
 * optional lines 'frame moving' and 'force', version 3 the line 'form' (doc/fix_griddem_rom.md) */
#define GRIDDEM_ROM_VERSION 3

/* The model's form. Linear: each voxel velocity is a linear function of the features [1, density
 * of every voxel, controls]. Occupancy: each voxel velocity is the voxel's own density times a
 * linear function of [1, controls] (the material moves where it is, at a rate the controls set). */
enum griddem_rom_form { GRIDDEM_ROM_LINEAR, GRIDDEM_ROM_OCCUPANCY };

typedef struct griddem_rom_grid {
  int n[3];
  double lo[3], hi[3];
  int periodic[3];
} griddem_rom_grid;

/* The grid of a model whose box is given in a frame that moves (model line 'frame moving'): the
 * frame's box shifted by origin, the frame's origin in the simulation box. */
void griddem_rom_place(const griddem_rom_grid *frame, const double origin[3], griddem_rom_grid *placed);

/* Number of voxels. */
int griddem_rom_nvoxel(const griddem_rom_grid *g);

/* 1 if x lies inside the grid's box (lo <= x < hi on every non-periodic axis; along a periodic
 * one every x is inside: between reneighborings LAMMPS leaves atoms past a periodic boundary). */
int griddem_rom_inside(const griddem_rom_grid *g, const double x[3]);

/* The voxel holding x (periodic axes wrapped), or -1 outside the box. */
int griddem_rom_voxel(const griddem_rom_grid *g, const double x[3]);

/* The 8 voxels and their weights (summing to 1) of a point; along a non-periodic axis indices
 * beyond the grid go to the boundary voxel, along a periodic one they wrap. */
void griddem_rom_weights(const griddem_rom_grid *g, const double x[3], int voxel[8],
                         double weight[8]);

/* Adds the mass of each of n points inside the box, divided by the voxel volume, into
 * density[nvoxel] (not zeroed: the caller sums over processes). Points outside are skipped. */
void griddem_rom_deposit(const griddem_rom_grid *g, int n, const double *x, int xstride,
                         const double *mass, const int *use, double *density);

/* out[r] = sum_c w[r * ncol + c] * feature[c] for r < nrow. */
void griddem_rom_predict(int nrow, int ncol, const double *w, const double *feature, double *out);

/* The occupancy form's field: out[3 m + d] = density[m] (w[r][0] + sum_c w[r][1 + c] control[c]),
 * r = 3 m + d, w a [3 nvoxel][1 + ncontrol] matrix; scratch (1 + ncontrol doubles) holds the
 * features [1, controls] on return. */
void griddem_rom_predict_occupancy(int nvoxel, int ncontrol, const double *w, const double *control,
                                   const double *density, double *scratch, double *out);

/* A voxel field of ncomp components (field[ncomp m + d]: the velocity 3, the density 1)
 * interpolated at x with griddem_rom_weights into out[ncomp]. */
void griddem_rom_interpolate(const griddem_rom_grid *g, const double *field, int ncomp, const double x[3],
                             double *out);

/* The contact checks of a classification, on a grid of the particles (edge: the longest contact
 * distance) instead of a neighbor list (griddem_touching_pairs). Particles 0..nall-1 (owned first,
 * then ghosts), kinematic marks their states before the classification. For each owned i with
 * next[i] = 1, every other particle j touching it (squared distance below (ri + rj)^2), in the
 * search's order, until one releases i: next[i] becomes 0 if their overlap exceeds
 * overlap_max min(ri, rj), or if j is not kinematic and its velocity differs from i's (v of i if
 * i is kinematic, else u[3 i..]) by more than threshold; the first such partner found is counted
 * in *overlaps or *hits when i was kinematic. g and b are the caller's scratch, kept between
 * calls (griddem_bins_free b at the end). Returns 0, or -1 without memory. */
int griddem_rom_check_contacts(int nlocal, int nall, const double *x, const double *v,
                               const double *radius, const int *kinematic, const double *u,
                               double threshold, double overlap_max, int *next, int *hits,
                               int *overlaps, griddem_grid *g, griddem_bins *b);

/* The released atoms start DEM without the overlaps the model made (doc/fix_griddem_rom.md): each
 * owned particle i < nlocal with released[i] != 0 is moved by the sum, over the particles j it
 * touches (0..nall-1, owned first, then ghosts), of their overlap along the line of centres away
 * from j, half of it where released[j] != 0 (j moves too), the sum at most ri long; all moves are
 * computed from the positions on entry (one Jacobi pass). g and b: the particles binned for their
 * contacts at these positions (griddem_bin_for_contacts, as griddem_rom_check_contacts leaves
 * them). shift: 3 nlocal doubles of scratch. Returns the number of particles moved, or -1 without
 * memory. */
int griddem_rom_separate(int nlocal, int nall, double *x, const double *radius, const int *released,
                         double *shift, const griddem_grid *g, const griddem_bins *b);

/* The reach test of the kinematic atoms that move only at the model step (a Verlet list's skin
 * rule; doc/fix_griddem_rom.md). Particles 0..nall-1 (owned first, then ghosts); gap(i, j) =
 * |xi - xj| - ri - rj. For each owned kinematic i: near[i] = 1 if some non-kinematic j has
 * gap < reach, else 0. For each owned non-kinematic i: budget[i] = the smallest gap >= reach to a
 * kinematic j, at most cap (>= reach): how far i may move (with the lagging atoms' own travel)
 * before it can touch a kinematic atom that is not near; near[i] = 0. Pairs with gap >= cap are
 * not looked at. g and b are the caller's scratch (as griddem_rom_check_contacts). Returns 0, or
 * -1 without memory. */
int griddem_rom_mark_near(int nlocal, int nall, const double *x, const double *radius,
                          const int *kinematic, double reach, double cap, int *near,
                          double *budget, griddem_grid *g, griddem_bins *b);

#ifdef __cplusplus
}
#endif
#endif
