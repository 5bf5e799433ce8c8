/* GRIDDEM candidate search: which spheres of some runs of sorted slots touch one sphere.
 *
 * The grid keeps a cell's spheres in consecutive slots, so the candidates of a sphere are a few
 * runs of slots (one per stencil row, or per row of a block of a coarser grid). The test of a run
 * reads the spheres as four separate arrays (x, y, z, radius by slot), which a SIMD kernel loads a
 * vector at a time. A plain-C kernel is the reference; AVX2 and AVX-512 kernels compute the same
 * expression in the same order, lane by lane (no fused multiply-add), so every kernel finds the
 * same slots in the same order. The best kernel the processor runs is chosen at load time. */
#ifndef GRIDDEM_SEARCH_H
#define GRIDDEM_SEARCH_H

#ifdef __cplusplus
extern "C" {
#endif

/* The spheres in slot order: centre and radius of each slot. */
typedef struct griddem_spheres {
  const double *x, *y, *z, *r;
} griddem_spheres;

/* Room a kernel may write past the slots it returns (a vector's store of its last hits). */
#define GRIDDEM_SEARCH_SLACK 16

/* Append to slot the slots t of the runs [lo[q], hi[q]), q < nruns, in run order, whose sphere
 * touches the sphere of centre c[0..2] and radius c[3] (the pull-off reach included): with
 * dx = c - centre of t and s = c[3] + radius of t, dx0 dx0 + dx1 dx1 + dx2 dx2 < s s, summed left
 * to right. slot needs room for every candidate plus GRIDDEM_SEARCH_SLACK. Returns the count. */
typedef int (*griddem_touching_fn)(const griddem_spheres *sp, const double *c, const int *lo, const int *hi,
                                   int nruns, int *slot);

/* The kernel by name ("scalar", "avx2", "avx512"), or NULL where this build or processor has none. */
griddem_touching_fn griddem_touching_kernel(const char *name);

/* The kernel the sweep uses: the widest this processor runs, unless griddem_touching_use chose one. */
griddem_touching_fn griddem_touching(void);
const char *griddem_touching_name(void);

/* Make the named kernel the sweep's (tests compare kernels through whole sweeps). 0, or -1 where
 * griddem_touching_kernel(name) is NULL. */
int griddem_touching_use(const char *name);

#ifdef __cplusplus
}
#endif

#endif
