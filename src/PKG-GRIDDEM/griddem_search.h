/* GRIDDEM candidate search: which spheres of some runs of sorted slots touch the spheres of a
 * cluster of consecutive slots.
 *
 * The grid keeps a cell's spheres in consecutive slots, so the candidates of a sphere are a few
 * runs of slots (one per stencil row, or per row of a block of a coarser grid), and consecutive
 * spheres of one cell row share them. A kernel tests a cluster of up to GRIDDEM_CLUSTER_MAX such
 * spheres against each candidate at once, one sphere per vector lane (as GROMACS's cluster-pair
 * kernels do), reading the spheres as four arrays (x, y, z, radius by slot). A plain-C kernel is
 * the reference; the AVX-512 kernel (8 lanes) computes the same expression in the same order lane
 * by lane (no fused multiply-add); the AVX2 kernel tests two candidates against 4 spheres in the
 * float shadow and the pairs that pass it in the reference's arithmetic. So every kernel finds the
 * same slots in the same order. The widest kernel the processor runs is chosen at first use. */
#ifndef GRIDDEM_SEARCH_H
#define GRIDDEM_SEARCH_H

#ifdef __cplusplus
extern "C" {
#endif

/* How the spheres' float shadow is made (griddem_spheres below): a coordinate relative to a
 * corner of the spheres' box, a radius scaled up by 2^-18 and padded by pad (four times the most a
 * shadow coordinate strays from its exact value, through the box's extent). The pad is at least
 * 1e-18, so that a shadow's squared contact distance is a normal float. Where floats cannot bound
 * the exact test (a box of 1e15 or more across, or not finite) every shadow is the same point and
 * radius, so that every candidate takes the exact test. */
typedef struct griddem_shadow_frame {
  double corner[3];
  double pad;
  int exact_only;
} griddem_shadow_frame;

/* The frame for spheres whose centres lie in the box lo..hi */
griddem_shadow_frame griddem_shadow_frame_of(const double lo[3], const double hi[3]);

/* The spheres in slot order: centre and radius of each slot; and their shadow in float in frame,
 * x y z r of a slot side by side (GRIDDEM_SHADOW_PAD slots of zeros past the last), which a kernel
 * may test first so that a vector holds twice the lanes and two slots come in one load. A pair
 * the exact test finds always passes the shadow's test, and a pair well inside it (by more than
 * the shadow can err) always passes the exact one: the shadow spares the exact test of the pairs
 * clearly apart and clearly touching, and every kernel finds the same slots. */
typedef struct griddem_spheres {
  const double *x, *y, *z, *r;
  const float *shadow;
  int n;    /* slots */
  griddem_shadow_frame frame;
} griddem_spheres;

/* The shadow's slots of zeros past its last: a kernel reads a cluster's four slots, or a pair of
 * candidates, past the last */
#define GRIDDEM_SHADOW_PAD 4

/* The shadow of n spheres (centres x, y, z and radii r by slot) in frame into shadow (4 floats a
 * slot), and its pad */
void griddem_shadow_fill(const griddem_shadow_frame *frame, int n, const double *x, const double *y, const double *z,
                         const double *r, float *shadow);

/* The most spheres in a cluster (the widest kernel's lanes). */
#define GRIDDEM_CLUSTER_MAX 8

/* For each sphere k < ni of the cluster of slots i0 + k, append to slot[k] (count n[k]) the slots
 * t of the runs [lo[q], hi[q]), q < nruns, in run order, whose sphere touches it: with
 * dx = centre of i0 + k - centre of t and s = (radius of i0 + k + reach) + radius of t,
 * dx0 dx0 + dx1 dx1 + dx2 dx2 < s s, summed left to right. If own, run 0 is the cluster's own
 * run and only its slots t > i0 + k are candidates of sphere k. ni is at most the kernel's
 * width (griddem_touching_width); slot[k] needs room for every candidate. */
typedef void (*griddem_touching_fn)(const griddem_spheres *sp, double reach, int i0, int ni, int own, const int *lo,
                                    const int *hi, int nruns, int *const *slot, int *n);

/* The kernel by name ("scalar", "avx2", "avx512"), or NULL where this build or processor has none;
 * and its width (the cluster it tests at once; 0 for an unknown name). */
griddem_touching_fn griddem_touching_kernel(const char *name);
int griddem_touching_kernel_width(const char *name);

/* The kernel the sweep uses, its name and width: the widest this processor runs, unless
 * griddem_touching_use chose one. */
griddem_touching_fn griddem_touching(void);
const char *griddem_touching_name(void);
int griddem_touching_width(void);
/* Whether it reads the spheres' shadow (which a sweep then fills) */
int griddem_touching_reads_shadow(void);

/* Make the named kernel the sweep's (tests compare kernels through whole sweeps). 0, or -1 where
 * griddem_touching_kernel(name) is NULL. */
int griddem_touching_use(const char *name);

#ifdef __cplusplus
}
#endif

#endif
