/* Candidate search kernels; see griddem_search.h. Every kernel evaluates
 * ((dx dx + dy dy) + dz dz) < s s in double with separate multiplies and adds: this file is
 * compiled without contraction (-ffp-contract=off), so the plain-C kernel rounds as the vector
 * lanes do. Touching pairs are rare among the candidates, so a candidate costs its test and one
 * predictable branch; only a touching lane is written out. */
#include "griddem_search.h"

#include <stddef.h>
#include <string.h>

/* The cluster's spheres that candidate t may touch: the first lanes(t) (all ni, or in the own run
 * those before t) */
static inline int live_lanes(int own_run, int i0, int ni, int t)
{
  return own_run && t - i0 < ni ? t - i0 : ni;
}

static void touching_scalar(const griddem_spheres *sp, double reach, int i0, int ni, int own, const int *lo,
                            const int *hi, int nruns, int *const *slot, int *n)
{
  const double *X = sp->x, *Y = sp->y, *Z = sp->z, *R = sp->r;
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t++) {
      const int lanes = live_lanes(own && q == 0, i0, ni, t);
      for (int k = 0; k < lanes; k++) {
        const int i = i0 + k;
        const double dx = X[i] - X[t], dy = Y[i] - Y[t], dz = Z[i] - Z[t], s = (R[i] + reach) + R[t];
        if (dx * dx + dy * dy + dz * dz < s * s) slot[k][n[k]++] = t;
      }
    }
}

#if defined(__GNUC__) && defined(__x86_64__)
#define GRIDDEM_SEARCH_X86 1
#include <immintrin.h>

/* One run of candidates against the cluster (xi .. ri: its spheres' lanes), the own run's slots
 * at or before a sphere left out of its list; own_run is a constant of each inlined copy, so the
 * other runs' loop keeps no count for it */
__attribute__((target("avx2"), always_inline)) static inline void run_avx2(const griddem_spheres *sp, int i0, int ni,
                                                                          const int own_run, int lo, int hi, __m256d xi,
                                                                          __m256d yi, __m256d zi, __m256d ri,
                                                                          int *const *slot, int *n)
{
  const double *X = sp->x, *Y = sp->y, *Z = sp->z, *R = sp->r;
  for (int t = lo; t < hi; t++) {
    const __m256d dx = _mm256_sub_pd(xi, _mm256_set1_pd(X[t])), dy = _mm256_sub_pd(yi, _mm256_set1_pd(Y[t])),
                  dz = _mm256_sub_pd(zi, _mm256_set1_pd(Z[t])), s = _mm256_add_pd(ri, _mm256_set1_pd(R[t]));
    const __m256d d2 =
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
    unsigned bits = (unsigned) _mm256_movemask_pd(_mm256_cmp_pd(d2, _mm256_mul_pd(s, s), _CMP_LT_OQ));
    if (!bits) continue;
    bits &= (1u << live_lanes(own_run, i0, ni, t)) - 1u;
    for (; bits; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      slot[k][n[k]++] = t;
    }
  }
}

__attribute__((target("avx2"))) static void touching_avx2(const griddem_spheres *sp, double reach, int i0, int ni,
                                                          int own, const int *lo, const int *hi, int nruns,
                                                          int *const *slot, int *n)
{
  const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
  const __m256i cluster = _mm256_cmpgt_epi64(_mm256_set1_epi64x(ni), lane);
  const __m256d xi = _mm256_maskload_pd(sp->x + i0, cluster), yi = _mm256_maskload_pd(sp->y + i0, cluster),
                zi = _mm256_maskload_pd(sp->z + i0, cluster),
                ri = _mm256_add_pd(_mm256_maskload_pd(sp->r + i0, cluster), _mm256_set1_pd(reach));
  for (int q = 0; q < nruns; q++)
    if (own && q == 0) run_avx2(sp, i0, ni, 1, lo[q], hi[q], xi, yi, zi, ri, slot, n);
    else run_avx2(sp, i0, ni, 0, lo[q], hi[q], xi, yi, zi, ri, slot, n);
}

__attribute__((target("avx512f"), always_inline)) static inline void run_avx512(const griddem_spheres *sp, int i0,
                                                                               int ni, const int own_run, int lo,
                                                                               int hi, __m512d xi, __m512d yi,
                                                                               __m512d zi, __m512d ri,
                                                                               int *const *slot, int *n)
{
  const double *X = sp->x, *Y = sp->y, *Z = sp->z, *R = sp->r;
  for (int t = lo; t < hi; t++) {
    const __m512d dx = _mm512_sub_pd(xi, _mm512_set1_pd(X[t])), dy = _mm512_sub_pd(yi, _mm512_set1_pd(Y[t])),
                  dz = _mm512_sub_pd(zi, _mm512_set1_pd(Z[t])), s = _mm512_add_pd(ri, _mm512_set1_pd(R[t]));
    const __m512d d2 =
        _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
    unsigned bits = (unsigned) _mm512_cmp_pd_mask(d2, _mm512_mul_pd(s, s), _CMP_LT_OQ);
    if (!bits) continue;
    bits &= (1u << live_lanes(own_run, i0, ni, t)) - 1u;
    for (; bits; bits &= bits - 1) {
      const int k = __builtin_ctz(bits);
      slot[k][n[k]++] = t;
    }
  }
}

__attribute__((target("avx512f"))) static void touching_avx512(const griddem_spheres *sp, double reach, int i0,
                                                               int ni, int own, const int *lo, const int *hi,
                                                               int nruns, int *const *slot, int *n)
{
  const __mmask8 cluster = (__mmask8) ((1u << ni) - 1u);
  const __m512d xi = _mm512_maskz_loadu_pd(cluster, sp->x + i0), yi = _mm512_maskz_loadu_pd(cluster, sp->y + i0),
                zi = _mm512_maskz_loadu_pd(cluster, sp->z + i0),
                ri = _mm512_add_pd(_mm512_maskz_loadu_pd(cluster, sp->r + i0), _mm512_set1_pd(reach));
  for (int q = 0; q < nruns; q++)
    if (own && q == 0) run_avx512(sp, i0, ni, 1, lo[q], hi[q], xi, yi, zi, ri, slot, n);
    else run_avx512(sp, i0, ni, 0, lo[q], hi[q], xi, yi, zi, ri, slot, n);
}
#endif

static const struct {
  const char *name;
  int width;
} KERNELS[] = {{"avx512", 8}, {"avx2", 4}, {"scalar", 4}};
#define NKERNELS (sizeof(KERNELS) / sizeof(KERNELS[0]))

griddem_touching_fn griddem_touching_kernel(const char *name)
{
  if (strcmp(name, "scalar") == 0) return touching_scalar;
#ifdef GRIDDEM_SEARCH_X86
  __builtin_cpu_init();
  if (strcmp(name, "avx2") == 0) return __builtin_cpu_supports("avx2") ? touching_avx2 : NULL;
  if (strcmp(name, "avx512") == 0) return __builtin_cpu_supports("avx512f") ? touching_avx512 : NULL;
#endif
  return NULL;
}

int griddem_touching_kernel_width(const char *name)
{
  for (size_t k = 0; k < NKERNELS; k++)
    if (strcmp(name, KERNELS[k].name) == 0) return KERNELS[k].width;
  return 0;
}

static int chosen = -1; /* index into KERNELS */
static griddem_touching_fn chosen_fn;

/* The widest kernel this processor runs, once */
static void choose(void)
{
  for (size_t k = 0; chosen < 0 && k < NKERNELS; k++)
    if ((chosen_fn = griddem_touching_kernel(KERNELS[k].name))) chosen = (int) k;
}

griddem_touching_fn griddem_touching(void)
{
  if (chosen < 0) choose();
  return chosen_fn;
}

const char *griddem_touching_name(void)
{
  if (chosen < 0) choose();
  return KERNELS[chosen].name;
}

int griddem_touching_width(void)
{
  if (chosen < 0) choose();
  return KERNELS[chosen].width;
}

int griddem_touching_use(const char *name)
{
  for (size_t k = 0; k < NKERNELS; k++) {
    if (strcmp(name, KERNELS[k].name) != 0) continue;
    griddem_touching_fn fn = griddem_touching_kernel(name);
    if (!fn) return -1;
    chosen = (int) k, chosen_fn = fn;
    return 0;
  }
  return -1;
}

int griddem_touching_gathers(void)
{
#ifdef GRIDDEM_SEARCH_X86
  if (chosen < 0) choose();
  return strcmp(KERNELS[chosen].name, "scalar") != 0 && __builtin_cpu_supports("avx2");
#else
  return 0;
#endif
}
