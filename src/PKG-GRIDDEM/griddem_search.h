/* GRIDDEM candidate search: which spheres of some runs of sorted slots touch the spheres of a
 * cluster of consecutive slots.
 *
 * The grid keeps a cell's spheres in consecutive slots, so the candidates of a sphere are a few
 * runs of slots (one per stencil row, or per row of a block of a coarser grid), and consecutive
 * spheres of one cell row share them. A kernel tests a cluster of up to GRIDDEM_CLUSTER_MAX such
 * spheres against some candidates at once, a pair of sphere and candidate per vector lane (as
 * GROMACS's cluster-pair kernels do), reading the spheres as four arrays (x, y, z, radius by
 * slot). A plain-C kernel is the reference, in double. The AVX2 (with FMA: 8 spheres by 2
 * candidates in 16 float lanes, two vectors of 8) and AVX-512 (8 by 2 in 16) kernels first test
 * single-precision copies against a contact distance widened by a slack that covers their
 * rounding, so that no touching pair fails it; a pair that also passes against the distance
 * narrowed by the slack (where that is positive) touches in double too, and every other pair that
 * passes is tested again with the reference's expression in double, in the same order (no fused
 * multiply-add): every kernel finds the same pairs in the same order, in clusters of the same
 * width. The widest kernel the processor runs is chosen at first use. */
#ifndef GRIDDEM_SEARCH_H
#define GRIDDEM_SEARCH_H

#include "griddem_portable.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The search's test of a sphere of radius ri against a candidate of radius rj whose centres lie dx
 * apart: closer than (ri + reach) + rj, the squares summed left to right. Every search calls it
 * on its exact separations (the CPU kernels' double test, the Kokkos search on the device), so
 * that they find the same pairs from the same separations. */
GRIDDEM_INLINE int griddem_search_touches(const double *dx, double ri, double reach, double rj)
{
  const double s = (ri + reach) + rj;
  return dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2] < s * s;
}

/* The spheres in slot order: centre and radius of each slot; the same rounded to float (each
 * array readable GRIDDEM_SEARCH_PAD slots past the last), and the slack of the float test, at
 * least griddem_search_slack's for these spheres; same_radius: nonzero only where every slot has
 * one radius (griddem_spheres_one_radius; the vector kernels then read no radius but s2_same and
 * sure2_same, the float test's contact distances widened and narrowed by the slack, squared). */
typedef struct griddem_spheres {
  const double *x, *y, *z, *r;
  const float *xf, *yf, *zf, *rf;
  float slack;
  int same_radius;
  float s2_same, sure2_same;
} griddem_spheres;

/* Mark spheres of one radius so, for a search within reach (their slack set) */
void griddem_spheres_one_radius(griddem_spheres *sp, double reach);

/* Slots past the last that the vector kernels read (and never use) */
#define GRIDDEM_SEARCH_PAD 8

/* The slack that makes the float test pass every pair whose double test does, for spheres whose
 * |coordinates| are at most coordinate_max and radii at most rmax, tested within reach: their
 * extent, coordinate_max plus the largest contact distance (rmax + reach + rmax), bounds every
 * coordinate and distance the test rounds. Rounding a coordinate to float moves it by at most
 * 2^-24 of its size, and the float test's own roundings add a few units of 2^-24 of the contact
 * distance: 2^-20 of the extent covers both twice over. */
double griddem_search_slack(double coordinate_max, double rmax, double reach);

/* The most spheres in a cluster (the widest kernel's). */
#define GRIDDEM_CLUSTER_MAX 8

/* The touching pairs of a cluster, in the order a kernel found them: for each, the cluster's
 * sphere (0 .. ni - 1) and the candidate's slot; n of them. */
typedef struct griddem_cluster_hits {
  int *sphere, *slot;
  int n;
} griddem_cluster_hits;

/* Append to hits the pairs of the spheres k < ni of the cluster of slots i0 + k with the slots t
 * of the runs [lo[q], hi[q]), q < nruns, that touch: with dx = centre of i0 + k - centre of t and
 * s = (radius of i0 + k + reach) + radius of t, dx0 dx0 + dx1 dx1 + dx2 dx2 < s s, summed left to
 * right; run by run, candidate by candidate in run order, and a candidate's spheres in order of k
 * (so each sphere's candidates come in run order, and each candidate's spheres in slot order). If
 * own, run 0 is the cluster's own run and only its slots t > i0 + k are candidates of sphere k.
 * ni is at most the kernel's width (griddem_touching_width); hits needs room for ni pairs a
 * candidate. */
typedef void (*griddem_touching_fn)(const griddem_spheres *sp, double reach, int i0, int ni, int own, const int *lo,
                                    const int *hi, int nruns, griddem_cluster_hits *hits);

/* The kernel by name ("scalar", "avx2", "avx512"), or NULL where this build or processor has none;
 * and its width (the cluster it tests at once; 0 for an unknown name). */
griddem_touching_fn griddem_touching_kernel(const char *name);
int griddem_touching_kernel_width(const char *name);

/* The kernel the sweep uses, its name and width: the widest this processor runs, unless
 * griddem_touching_use chose one. */
griddem_touching_fn griddem_touching(void);
const char *griddem_touching_name(void);
int griddem_touching_width(void);

/* Make the named kernel the sweep's (fix griddem kernel; tests compare kernels through whole
 * sweeps), or with "auto" the widest again. 0, or -1 where griddem_touching_kernel(name) is NULL. */
int griddem_touching_use(const char *name);

/* Whether the CPU engine reads particles into AVX2 lanes (with FMA) in its passes written for them
 * (the scan's boxes and speeds, the binning's cells, the channels, a batch's inputs), each the twin
 * of a plain-C pass that gives the same values: where the processor has them, except with the
 * plain-C kernel, so that the tests that run each kernel run the plain passes too. */
int griddem_vector_reads(void);

#ifdef __cplusplus
}
#endif

#endif
