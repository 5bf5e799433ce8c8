/* Candidate search kernels; see griddem_search.h. Every kernel decides by
 * ((dx dx + dy dy) + dz dz) < s s in double with separate multiplies and adds: this file is
 * compiled without contraction (-ffp-contract=off), so the plain-C kernel rounds as the vector
 * lanes do. Touching pairs are rare among the candidates, so a candidate costs its test and one
 * predictable branch; only a touching lane is written out.
 *
 * The shadow's bounds (griddem_shadow_frame_of): a shadow coordinate strays from x - corner by at
 * most E = 2^-23 L (L the box's extent: the double difference and its float each round by half a
 * unit of L's last place); a difference of two, and the float sums and products, add at most a
 * few units of 2^-24 relative, so a pair's shadow distance lies within (1 +- 2^-21)
 * (|dx| +- 2 sqrt(3) E). A pair the exact test finds has |dx| < s (1 + 2^-50), and the shadow's
 * contact distance S ((r_i + reach) + r_j scaled by 1 + 2^-18, plus pad >= 4 E) is above its
 * shadow distance after its own rounding: the shadow test passes every pair the exact test
 * finds. A pair whose shadow distance is below S (1 - 2^-16) - 2 pad (1 + 2^-10) has
 * |dx| < s (1 - 2^-17): the exact test finds it, and the AVX2 kernel takes it without. */
#include "griddem_search.h"
#include "griddem_portable.h"

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

/* Whether the exact test finds sphere i and candidate t: the reference's arithmetic */
static inline int touches(const griddem_spheres *sp, double reach, int i, int t)
{
  const double dx = sp->x[i] - sp->x[t], dy = sp->y[i] - sp->y[t], dz = sp->z[i] - sp->z[t];
  const double s = (sp->r[i] + reach) + sp->r[t];
  return dx * dx + dy * dy + dz * dz < s * s;
}

/* Append candidate t to the lists of the cluster's spheres whose shadow lanes (bits) it passed,
 * in lane order: where the shadow puts it well inside (sure), or the exact test finds it */
static inline void confirm(const griddem_spheres *sp, double reach, int i0, int t, unsigned bits, unsigned sure,
                           int *const *slot, int *n)
{
  for (; bits; bits &= bits - 1) {
    const int k = __builtin_ctz(bits);
    if ((sure >> k & 1u) || touches(sp, reach, i0 + k, t)) slot[k][n[k]++] = t;
  }
}

/* The cluster's 4 spheres' shadow lanes, each value twice (lanes 0-3 and 4-7), and the shadow's
 * inner margin: a pair whose shadow distance is below (its shadow contact distance) scale - less
 * touches (zero scale and less where the frame is exact only) */
typedef struct cluster_shadow {
  __m256 x, y, z, r, scale, less;
} cluster_shadow;

/* The lanes of the cluster that pass the shadow test against the shadows two (slot ta's in lanes
 * 0-3, tb's in lanes 4-7, each value spread over its half); *sure: those well inside */
__attribute__((target("avx2"), always_inline)) static inline unsigned shadow_lanes(const cluster_shadow *c,
                                                                                  __m256 two, unsigned *sure)
{
  const __m256 dx = _mm256_sub_ps(c->x, _mm256_permute_ps(two, 0x00)),
               dy = _mm256_sub_ps(c->y, _mm256_permute_ps(two, 0x55)),
               dz = _mm256_sub_ps(c->z, _mm256_permute_ps(two, 0xaa)),
               s = _mm256_add_ps(c->r, _mm256_permute_ps(two, 0xff));
  const __m256 d2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
  const unsigned bits = (unsigned) _mm256_movemask_ps(_mm256_cmp_ps(d2, _mm256_mul_ps(s, s), _CMP_LT_OQ));
  if (bits) {
    const __m256 inner = _mm256_max_ps(_mm256_sub_ps(_mm256_mul_ps(s, c->scale), c->less), _mm256_setzero_ps());
    *sure = (unsigned) _mm256_movemask_ps(_mm256_cmp_ps(d2, _mm256_mul_ps(inner, inner), _CMP_LT_OQ));
  }
  return bits;
}

/* Slots ta and tb's shadows side by side */
__attribute__((target("avx2"), always_inline)) static inline __m256 shadow_two(const float *shadow, int ta, int tb)
{
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(shadow + 4 * (size_t) ta)),
                              _mm_loadu_ps(shadow + 4 * (size_t) tb), 1);
}

/* The lists of the candidates ta and tb (whose lanes are bits, sure those well inside, the
 * cluster's live ones for each in first and second) */
static inline void confirm_two(const griddem_spheres *sp, double reach, int i0, int ta, int tb, unsigned bits,
                               unsigned sure, unsigned first, unsigned second, int *const *slot, int *n)
{
  confirm(sp, reach, i0, ta, bits & first, sure, slot, n);
  confirm(sp, reach, i0, tb, (bits >> 4) & second, sure >> 4, slot, n);
}

/* The shadow tests two candidates a pass, slots t and t + 1 of a run in one load; a run's odd last
 * slot waits for the next run's first (pending), and the last one left pairs with the slot after
 * it, whose lanes are dropped. The own run (run 0 where own) pairs within itself, each slot for
 * the spheres before it. */
__attribute__((target("avx2"))) static void touching_avx2(const griddem_spheres *sp, double reach, int i0, int ni,
                                                          int own, const int *lo, const int *hi, int nruns,
                                                          int *const *slot, int *n)
{
  const float *shadow = sp->shadow;
  /* the cluster's shadows transposed into lanes (lanes past it: pad or later slots, dropped) */
  __m128 c0 = _mm_loadu_ps(shadow + 4 * (size_t) i0), c1 = _mm_loadu_ps(shadow + 4 * (size_t) i0 + 4),
         c2 = _mm_loadu_ps(shadow + 4 * (size_t) i0 + 8), c3 = _mm_loadu_ps(shadow + 4 * (size_t) i0 + 12);
  _MM_TRANSPOSE4_PS(c0, c1, c2, c3);
  const int exact_only = sp->frame.exact_only;
  const cluster_shadow c = {_mm256_set_m128(c0, c0), _mm256_set_m128(c1, c1), _mm256_set_m128(c2, c2),
                            _mm256_add_ps(_mm256_set_m128(c3, c3), _mm256_set1_ps((float) (reach * (1.0 + 0x1p-18)))),
                            _mm256_set1_ps(exact_only ? 0.0f : 1.0f - 0x1p-16f),
                            _mm256_set1_ps(exact_only ? 0.0f : (float) (2.0 * sp->frame.pad * (1.0 + 0x1p-10)))};
  const unsigned cluster = (1u << ni) - 1u;
  unsigned sure = 0;
  int q = 0, pending = -1;
  if (own && nruns > 0) {
    for (int t = lo[0]; t < hi[0]; t += 2) {
      const unsigned bits = shadow_lanes(&c, _mm256_loadu_ps(shadow + 4 * (size_t) t), &sure);
      if (bits)
        confirm_two(sp, reach, i0, t, t + 1, bits, sure, (1u << live_lanes(1, i0, ni, t)) - 1u,
                    t + 1 < hi[0] ? (1u << live_lanes(1, i0, ni, t + 1)) - 1u : 0u, slot, n);
    }
    q = 1;
  }
  for (; q < nruns; q++) {
    int t = lo[q];
    const int end = hi[q];
    if (pending >= 0 && t < end) {
      const unsigned bits = shadow_lanes(&c, shadow_two(shadow, pending, t), &sure);
      if (bits) confirm_two(sp, reach, i0, pending, t, bits, sure, cluster, cluster, slot, n);
      pending = -1, t++;
    }
    for (; t + 1 < end; t += 2) {
      const unsigned bits = shadow_lanes(&c, _mm256_loadu_ps(shadow + 4 * (size_t) t), &sure);
      if (bits) confirm_two(sp, reach, i0, t, t + 1, bits, sure, cluster, cluster, slot, n);
    }
    if (t < end) pending = t;
  }
  if (pending >= 0) {
    const unsigned bits = shadow_lanes(&c, _mm256_loadu_ps(shadow + 4 * (size_t) pending), &sure);
    if (bits) confirm(sp, reach, i0, pending, bits & cluster, sure, slot, n);
  }
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

griddem_shadow_frame griddem_shadow_frame_of(const double lo[3], const double hi[3])
{
  griddem_shadow_frame frame;
  double extent = 0.0;
  for (int d = 0; d < 3; d++) {
    frame.corner[d] = lo[d];
    extent = hi[d] - lo[d] > extent ? hi[d] - lo[d] : extent;
  }
  frame.pad = extent * 0x1p-21 > 1e-18 ? extent * 0x1p-21 : 1e-18;
  frame.exact_only = !(extent < 1e15);
  return frame;
}

GRIDDEM_VECTOR_COPIES void griddem_shadow_fill(const griddem_shadow_frame *frame, int n, const double *restrict x,
                                               const double *restrict y, const double *restrict z,
                                               const double *restrict r, float *restrict shadow)
{
  /* every shadow the same point and radius where floats cannot bound the exact test */
  const double keep = frame->exact_only ? 0.0 : 1.0, grow = frame->exact_only ? 0.0 : 1.0 + 0x1p-18,
               pad = frame->exact_only ? 1.0 : 0.5 * frame->pad;
  const double c0 = frame->corner[0], c1 = frame->corner[1], c2 = frame->corner[2];
  for (int s = 0; s < n; s++) {
    shadow[4 * s] = (float) ((x[s] - c0) * keep);
    shadow[4 * s + 1] = (float) ((y[s] - c1) * keep);
    shadow[4 * s + 2] = (float) ((z[s] - c2) * keep);
    shadow[4 * s + 3] = (float) (r[s] * grow + pad);
  }
  for (int k = 4 * n; k < 4 * (n + GRIDDEM_SHADOW_PAD); k++) shadow[k] = 0.0f;
}

static const struct {
  const char *name;
  int width;
  int reads_shadow;
} KERNELS[] = {{"avx512", 8, 0}, {"avx2", 4, 1}, {"scalar", 4, 0}};
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

int griddem_touching_reads_shadow(void)
{
  if (chosen < 0) choose();
  return KERNELS[chosen].reads_shadow;
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
