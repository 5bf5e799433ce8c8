/* GRIDDEM coarse-graining: particle quantities assigned to a grid by cloud-in-cell weights and
 * smoothed by a Gaussian. The grid has n points per axis at the cell centres boxlo + (i + 1/2) h.
 * The kernel is the Gaussian exp(-r^2 / (2 W^2)) sampled at the grid offsets, a product of one
 * factor per axis, normalised to sum 1 over all offsets of the infinite lattice. The smoothing is
 * a circular convolution on an "FFT grid" of m points per axis: m = n along a periodic axis (the
 * kernel summed over its periodic images), m = n + padding along a non-periodic one (zero
 * padding, so a kernel that leaves the box at one wall never re-enters at the other). Every cost
 * is bounded independently of W: the lattice sums are theta functions, summed directly or by
 * Poisson's formula, whichever converges in a few terms, and the padding never exceeds n - 1.
 * The glue does the convolution by FFT; griddem_cg_convolve_direct is the same sum in real
 * space, for tests. */
#ifndef GRIDDEM_CG_H
#define GRIDDEM_CG_H

#include "griddem_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Beyond the radius where the Gaussian falls below this fraction of its peak its lattice sum is
 * below double-precision rounding of the total (about 1e-18 of it), so the padding stops there. */
#define GRIDDEM_CG_NEGLIGIBLE 1e-17

/* reach of a periodic axis in griddem_cg_kernel_axis: every periodic image of every offset */
#define GRIDDEM_CG_PERIODIC (-1)

/* Cloud-in-cell (trilinear, done per axis) weights of a coordinate x: the two grid points index[0]
 * and index[0] + 1 around it get 1 - f and f. Along a non-periodic axis an index outside 0..n-1
 * is moved onto the boundary point (nothing leaves the box); along a periodic one it is left as
 * is, for ghost points (or the caller's wrap) to fold. */
void griddem_cg_cic(double x, double boxlo, double h, int n, int periodic, int index[2],
                    double weight[2]);

/* Radius where the Gaussian of width W falls to GRIDDEM_CG_NEGLIGIBLE of its peak (8.85 W). */
double griddem_cg_cutoff(double width);

/* Zero points padding a non-periodic axis of n points and spacing h: the offsets inside the
 * cutoff, floor(cutoff / h), but at most n - 1, the largest offset between two points of the
 * box (so a kernel wider than the box costs 2n - 1 FFT points, no more). */
int griddem_cg_padding(int n, double width, double h);

/* FFT grid points along an axis of n points: n if periodic, else n + padding. */
int griddem_cg_fft_size(int n, int periodic, double width, double h);

/* The normalised kernel along one axis of spacing h on its m-point FFT grid: k[i] is the
 * Gaussian factor exp(-(d h)^2 / (2 W^2)) divided by its sum over all integer d, taken at the
 * offsets d = i (mod m) with |d| <= reach, or at all of them (every periodic image) when reach is
 * GRIDDEM_CG_PERIODIC. A non-periodic axis needs m >= 2 reach + 1 (no offset meets another's
 * image). Cost O(m) for any W. */
void griddem_cg_kernel_axis(int m, int reach, double h, double width, double *k);

/* The kernel on the m grid over the brick lo..hi (inclusive, x fastest): the product of the
 * axis kernels, reach[d] as in griddem_cg_kernel_axis. It sums to 1 over the whole grid when
 * every axis is periodic (a convolution then keeps totals). */
void griddem_cg_kernel_brick(const int m[3], const int reach[3], const int lo[3], const int hi[3],
                             const double h[3], double width, double *out);

/* out[i] = sum_j kernel[(i - j) mod m] field[j] over the whole m grid (x fastest): the circular
 * convolution an FFT computes, done point by point. Cost (m0 m1 m2)^2: small grids only. */
void griddem_cg_convolve_direct(const int m[3], const double *kernel, const double *field,
                                double *out);

/* The coordination channel: for each of the first nlocal of nall points (owned first, then
 * ghosts), count[i] = the other points touching it (squared centre distance below the squared sum
 * of radii), found through the full stencil of a grid of all nall points (griddem_touching_pairs).
 * g and b are the caller's scratch, kept between calls (griddem_bins_free b at the end). 0, or -1 without memory. */
int griddem_cg_contacts(int nlocal, int nall, const double *x, const double *radius, double *count,
                        griddem_grid *g, griddem_bins *b);

#ifdef __cplusplus
}
#endif
#endif
