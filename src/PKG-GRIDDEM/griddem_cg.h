/* GRIDDEM coarse-graining: particle quantities assigned to a grid by cloud-in-cell weights and
 * smoothed by a truncated Gaussian. The grid has n points per axis at the cell centres
 * boxlo + (i + 1/2) h. The smoothing is a circular convolution on an "FFT grid" of m points per
 * axis: m = n along a periodic axis, m = n + reach along a non-periodic one (zero padding, so a
 * kernel that leaves the box at one wall never re-enters at the other). The glue does the
 * convolution by FFT; griddem_cg_convolve_direct is the same sum in real space, for tests. */
#ifndef GRIDDEM_CG_H
#define GRIDDEM_CG_H

#ifdef __cplusplus
extern "C" {
#endif

/* The Gaussian exp(-r^2 / (2 W^2)) is dropped where it falls below this fraction of its peak. */
#define GRIDDEM_CG_TRUNCATION 1e-6

/* Cloud-in-cell (trilinear, done per axis) weights of a coordinate x: the two grid points index[0]
 * and index[0] + 1 around it get 1 - f and f. Along a non-periodic axis an index outside 0..n-1
 * is moved onto the boundary point (nothing leaves the box); along a periodic one it is left as
 * is, for ghost points (or the caller's wrap) to fold. */
void griddem_cg_cic(double x, double boxlo, double h, int n, int periodic, int index[2],
                    double weight[2]);

/* Radius where the Gaussian of width W reaches GRIDDEM_CG_TRUNCATION of its peak. */
double griddem_cg_cutoff(double width);

/* Grid points the kernel reaches along an axis of spacing h: floor(cutoff / h). */
int griddem_cg_reach(double width, double h);

/* FFT grid points along an axis of n points (see the header comment). */
int griddem_cg_fft_size(int n, int periodic, int reach);

/* The kernel on the m-point periodic FFT grid, over the brick lo..hi (inclusive, x fastest):
 * at index i the sum over the offsets d = i (mod m) inside the cutoff of the Gaussian at d*h,
 * normalised so that the kernel sums to 1 over the whole grid (a convolution keeps totals). */
void griddem_cg_kernel_brick(const int m[3], const int lo[3], const int hi[3], const double h[3],
                             double width, double *out);

/* out[i] = sum_j kernel[(i - j) mod m] field[j] over the whole m grid (x fastest): the circular
 * convolution an FFT computes, done point by point. Cost (m0 m1 m2)^2: small grids only. */
void griddem_cg_convolve_direct(const int m[3], const double *kernel, const double *field,
                                double *out);

#ifdef __cplusplus
}
#endif
#endif
