/* Candidate search kernels; see griddem_search.h. Every kernel decides with
 * ((dx dx + dy dy) + dz dz) < s s in double with separate multiplies and adds: this file is
 * compiled without contraction (-ffp-contract=off), so the vector kernels' last test rounds as the
 * plain-C kernel does. A vector pass costs its float test and one branch; only a lane that passes
 * is tested again, in double. */
#include "griddem_search.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

double griddem_search_slack(double coordinate_max, double rmax, double reach)
{
  return ldexp(coordinate_max + 2.0 * rmax + reach, -20);
}

void griddem_spheres_one_radius(griddem_spheres *sp, double reach)
{
  /* as the vector kernels sum a sphere's distances (in double, rounded to float) and add a
     candidate's radius (in float) */
  const double r = sp->r[0];
  const float s = (float) ((r + reach) + (double) sp->slack) + (float) r;
  const float sure = fmaxf((float) ((r + reach) - (double) sp->slack) + (float) r, 0.0f);
  sp->same_radius = 1, sp->s2_same = s * s, sp->sure2_same = sure * sure;
}

/* The documented test of sphere i against candidate t */
static inline int touches(const griddem_spheres *sp, double reach, int i, int t)
{
  const double dx[3] = {sp->x[i] - sp->x[t], sp->y[i] - sp->y[t], sp->z[i] - sp->z[t]};
  return griddem_search_touches(dx, sp->r[i], reach, sp->r[t]);
}

/* A pair found: sphere k of the cluster and slot t */
static inline void hit(griddem_cluster_hits *hits, int k, int t)
{
  hits->sphere[hits->n] = k, hits->slot[hits->n] = t;
  hits->n++;
}

static void touching_scalar(const griddem_spheres *sp, double reach, int i0, int ni, int own, const int *lo,
                            const int *hi, int nruns, griddem_cluster_hits *hits)
{
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t++) {
      const int lanes = own && q == 0 && t - i0 < ni ? t - i0 : ni;    /* the own run: spheres before t */
      for (int k = 0; k < lanes; k++)
        if (touches(sp, reach, i0 + k, t)) hit(hits, k, t);
    }
}

#if defined(__GNUC__) && defined(__x86_64__)
#define GRIDDEM_SEARCH_X86 1
#include <immintrin.h>

/* A cluster's spheres (up to 8) as float lanes: centres, and where radii (a constant) radius +
 * reach + slack (s) and radius + reach - slack (sure), each summed in double first; past the
 * cluster, centres at +infinity and zero distances, where every test gives +infinity and fails
 * (never NaN: a candidate is finite). Reads the float copies up to slot i0 + 7 (within their
 * padding), the doubles only within the cluster. */
typedef struct cluster_lanes {
  __m256 x, y, z, s, sure;
} cluster_lanes;

__attribute__((target("avx2"), always_inline)) static inline cluster_lanes cluster_lanes_of(const griddem_spheres *sp,
                                                                                             double reach, int i0,
                                                                                             int ni, const int radii)
{
  const __m256i live = _mm256_cmpgt_epi32(_mm256_set1_epi32(ni), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
  const __m256 far = _mm256_set1_ps(INFINITY), on = _mm256_castsi256_ps(live);
  if (!radii) {    /* the centres alone */
    const cluster_lanes c = {_mm256_blendv_ps(far, _mm256_loadu_ps(sp->xf + i0), on),
                             _mm256_blendv_ps(far, _mm256_loadu_ps(sp->yf + i0), on),
                             _mm256_blendv_ps(far, _mm256_loadu_ps(sp->zf + i0), on), _mm256_setzero_ps(),
                             _mm256_setzero_ps()};
    return c;
  }
  const __m256d add = _mm256_set1_pd(reach), slack = _mm256_set1_pd((double) sp->slack);
  const __m256d r0 = _mm256_maskload_pd(sp->r + i0, _mm256_cvtepi32_epi64(_mm256_castsi256_si128(live))),
                r1 = _mm256_maskload_pd(sp->r + i0 + 4, _mm256_cvtepi32_epi64(_mm256_extracti128_si256(live, 1)));
  const __m256 s = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_add_pd(_mm256_add_pd(r1, add), slack)),
                                   _mm256_cvtpd_ps(_mm256_add_pd(_mm256_add_pd(r0, add), slack)));
  const __m256 sure = _mm256_set_m128(_mm256_cvtpd_ps(_mm256_sub_pd(_mm256_add_pd(r1, add), slack)),
                                      _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_add_pd(r0, add), slack)));
  const cluster_lanes c = {_mm256_blendv_ps(far, _mm256_loadu_ps(sp->xf + i0), on),
                           _mm256_blendv_ps(far, _mm256_loadu_ps(sp->yf + i0), on),
                           _mm256_blendv_ps(far, _mm256_loadu_ps(sp->zf + i0), on), _mm256_and_ps(s, on),
                           _mm256_and_ps(sure, on)};
  return c;
}

/* The lanes of the own run's candidates t, t + 1 (lane 2 k + j: sphere k, candidate t + j) that
 * are candidates of their sphere, t + j > i0 + k, by o = t - i0 < 8: k < o + j (none for o < 0) */
static const unsigned OWN_LANES[8] = {0x2u, 0xbu, 0x2fu, 0xbfu, 0x2ffu, 0xbffu, 0x2fffu, 0xbfffu};
static inline unsigned own_lanes(int o)
{
  return o < 0 ? 0u : OWN_LANES[o];
}

/* The lanes of candidate u that passed the float test (lanes: lane 2 k + j, sphere k), in lane
 * order: those that passed it against the contact distance narrowed by the slack (sure; the test
 * widens it by the slack) touch in double too (the float test's roundings move a distance by at
 * most half the slack), the others are tested again in double */
static inline void passed_lanes(const griddem_spheres *sp, double reach, int i0, int u, unsigned lanes,
                                unsigned sure, griddem_cluster_hits *hits)
{
  for (; lanes; lanes &= lanes - 1) {
    const int l = __builtin_ctz(lanes), k = l / 2;
    if (((sure >> l) & 1u) || touches(sp, reach, i0 + k, u)) hit(hits, k, u);
  }
}

/* The lanes that passed the float test (bits; lane 2 k + j: sphere k, candidate t + j), candidate
 * t's (the even lanes) before t + 1's; candidate t + 1 past the run's end is left out */
static inline void passed(const griddem_spheres *sp, double reach, int i0, int t, int hi, unsigned bits,
                          unsigned sure, griddem_cluster_hits *hits)
{
  passed_lanes(sp, reach, i0, t, bits & 0x5555u, sure, hits);
  if (t + 1 < hi) passed_lanes(sp, reach, i0, t + 1, bits & 0xaaaau, sure, hits);
}

/* run_ISA: one run against 8 spheres in 16 lanes (AVX2: two vectors; AVX-512: one), candidates t
 * and t + 1 at once: each candidate pair's floats loaded as one 64-bit value and broadcast (V: the
 * float vector, B: the double broadcast that carries the pair, FMA(a, b, c): a b + c and
 * FNMA(a, b, c): c - a b, each in one rounding, which the slack covers as it covers two; SIGNS:
 * the lanes whose sign bit is set as bits; ANY_SIGN: whether there is one). d2 - s s in one
 * rounding is negative exactly where d2 < s s, and never -0. The narrowed distance is negative
 * where the slack exceeds the contact distance (coordinates far from the origin): none is then
 * sure (MAX with ZERO). In the own run (own_run, a constant of each inlined copy), the candidates
 * within the cluster (t < i0 + NS, NS spheres a vector) are masked to those after their sphere
 * (mask) before any is looked at again. Where every sphere has one radius (same_radius, a
 * constant of each copy), no candidate's radius is read: the test subtracts the contact distance
 * to that radius squared (s2_same) in its first multiply (FMS(a, b, c): a b - c, in one rounding),
 * and the narrowed test adds to that difference the gap of the two squares (gap_same: s2_same -
 * sure2_same), each a rounding more, which the slack covers as it covers the others. Where no pair
 * is sure (sure2_same 0), the sum is never negative: every rounding of the test keeps its result at
 * or above -s2_same. */
#define GRIDDEM_RUN_KERNEL(ISA, TARGET, V, B, SUB, ADD, MUL, FMA, FNMA, FMS, MAX, ZERO, SIGNS, ANY_SIGN, NS,  \
                           LANES, BCAST)                                                                      \
  /* the float test of candidates t and t + 1: d2 - s s by lane (d2 the squared distances) */                  \
  __attribute__((target(TARGET), always_inline)) static inline V test_##ISA(                                 \
      const griddem_spheres *sp, int t, const cluster_##ISA *c, const int same_radius, V *d2)                 \
  {                                                                                                           \
    double px, py, pz, pr = 0.0;                                                                              \
    memcpy(&px, sp->xf + t, 8), memcpy(&py, sp->yf + t, 8), memcpy(&pz, sp->zf + t, 8);                      \
    if (!same_radius) memcpy(&pr, sp->rf + t, 8);                                                             \
    const V dx = SUB(c->x, B(px)), dy = SUB(c->y, B(py)), dz = SUB(c->z, B(pz));                             \
    if (same_radius) return *d2 = FMA(dz, dz, FMA(dy, dy, FMS(dx, dx, c->s2_same)));    /* d2 - s2_same */    \
    const V s = ADD(c->s, B(pr));                                                                             \
    *d2 = FMA(dz, dz, FMA(dy, dy, MUL(dx, dx)));                                                              \
    return FNMA(s, s, *d2);                                                                                   \
  }                                                                                                           \
  /* the pairs of a test that some lanes of mask passed (diff, d2: test_ISA's; one radius: both diff) */     \
  __attribute__((target(TARGET), always_inline)) static inline void hits_of_##ISA(                           \
      const griddem_spheres *sp, double reach, int i0, int t, int hi, unsigned mask, V diff, V d2,            \
      const cluster_##ISA *c, const int same_radius, griddem_cluster_hits *hits)                              \
  {                                                                                                           \
    const unsigned bits = (unsigned) SIGNS(diff) & mask;                                                      \
    if (!bits) return;                                                                                        \
    V narrow;                                                                                                 \
    if (same_radius)                                                                                          \
      narrow = ADD(diff, c->gap_same);                                                                        \
    else {                                                                                                    \
      double pr;                                                                                              \
      memcpy(&pr, sp->rf + t, 8);                                                                             \
      const V sure = MAX(ADD(c->sure, B(pr)), ZERO);                                                          \
      narrow = FNMA(sure, sure, d2);                                                                          \
    }                                                                                                         \
    passed(sp, reach, i0, t, hi, bits, (unsigned) SIGNS(narrow), hits);                                       \
  }                                                                                                           \
  /* the own run's head (own_run, a constant) with its lanes masked, then the tests of the rest, the hit     \
     path out of the way of those that pass no lane (most) */                                                 \
  __attribute__((target(TARGET), always_inline)) static inline void run_##ISA(                               \
      const griddem_spheres *sp, double reach, int i0, const int own_run, int lo, int hi,                     \
      const cluster_##ISA *c, const int same_radius, griddem_cluster_hits *hits)                              \
  {                                                                                                           \
    int t = lo;                                                                                               \
    V d2, diff;                                                                                               \
    if (own_run)                                                                                              \
      for (const int head = hi < i0 + NS ? hi : i0 + NS; t < head; t += 2) {                                  \
        diff = test_##ISA(sp, t, c, same_radius, &d2);                                                        \
        hits_of_##ISA(sp, reach, i0, t, hi, own_lanes(t - i0), diff, d2, c, same_radius, hits);               \
      }                                                                                                       \
    /* one radius: the tests that pass no lane in a loop of their own, which leaves the loop its       \
       registers; with the candidates' radii read too, one loop, whose values then stay in registers */      \
    for (; t < hi; t += 2) {                                                                                  \
      for (; same_radius; t += 2) {                                                                           \
        if (t >= hi) return;                                                                                  \
        diff = test_##ISA(sp, t, c, same_radius, &d2);                                                        \
        if (ANY_SIGN(diff)) break;                                                                            \
      }                                                                                                       \
      if (!same_radius && !ANY_SIGN(diff = test_##ISA(sp, t, c, same_radius, &d2))) continue;                \
      hits_of_##ISA(sp, reach, i0, t, hi, ~0u, diff, d2, c, same_radius, hits);                               \
    }                                                                                                         \
  }                                                                                                           \
  /* the runs [lo[q], hi[q]), the own one first (own: run 0), one inlined copy of run_ISA each */             \
  __attribute__((target(TARGET), always_inline)) static inline void runs_##ISA(                              \
      const griddem_spheres *sp, double reach, int i0, int own, const int *lo, const int *hi, int nruns,      \
      const cluster_##ISA *c, const int same_radius, griddem_cluster_hits *hits)                              \
  {                                                                                                           \
    const int first = own && nruns > 0;                                                                       \
    if (first) run_##ISA(sp, reach, i0, 1, lo[0], hi[0], c, same_radius, hits);                               \
    for (int q = first; q < nruns; q++) run_##ISA(sp, reach, i0, 0, lo[q], hi[q], c, same_radius, hits);      \
  }                                                                                                           \
  /* the cluster's lanes (LANES: a float lane per sphere as the kernel holds them; BCAST: one float
     in every lane) and its runs; where every sphere has one radius, the contact distance squared
     that the spheres marked hold and its gap to the narrowed one */                                          \
  __attribute__((target(TARGET))) static void touching_##ISA(const griddem_spheres *sp, double reach, int i0,  \
                                                           int ni, int own, const int *lo, const int *hi,     \
                                                           int nruns, griddem_cluster_hits *hits)             \
  {                                                                                                           \
    if (sp->same_radius) {                                                                                    \
      const cluster_lanes l = cluster_lanes_of(sp, reach, i0, ni, 0);                                         \
      const cluster_##ISA c = {LANES(l.x), LANES(l.y), LANES(l.z), ZERO, ZERO, BCAST(sp->s2_same),            \
                               BCAST(sp->s2_same - sp->sure2_same)};                                          \
      runs_##ISA(sp, reach, i0, own, lo, hi, nruns, &c, 1, hits);                                             \
    } else {                                                                                                  \
      const cluster_lanes l = cluster_lanes_of(sp, reach, i0, ni, 1);                                         \
      const cluster_##ISA c = {LANES(l.x), LANES(l.y), LANES(l.z), LANES(l.s), LANES(l.sure), ZERO, ZERO};   \
      runs_##ISA(sp, reach, i0, own, lo, hi, nruns, &c, 0, hits);                                             \
    }                                                                                                         \
  }

/* AVX2's 16 lanes as two vectors (lo: lanes 0-7, spheres 0-3; hi: lanes 8-15, spheres 4-7), so
 * that its clusters are the AVX-512 kernel's 8 spheres: a cluster's set-up, and its runs' cells at
 * either end, are paid once for 8 spheres */
typedef struct avx2x2 {
  __m256 lo, hi;
} avx2x2;
#define AVX2X2_OP(name, op)                                                                                   \
  __attribute__((target("avx2,fma"), always_inline)) static inline avx2x2 name(avx2x2 a, avx2x2 b)            \
  {                                                                                                           \
    const avx2x2 r = {op(a.lo, b.lo), op(a.hi, b.hi)};                                                        \
    return r;                                                                                                 \
  }
#define AVX2X2_OP3(name, op)                                                                                  \
  __attribute__((target("avx2,fma"), always_inline)) static inline avx2x2 name(avx2x2 a, avx2x2 b, avx2x2 c)  \
  {                                                                                                           \
    const avx2x2 r = {op(a.lo, b.lo, c.lo), op(a.hi, b.hi, c.hi)};                                            \
    return r;                                                                                                 \
  }
AVX2X2_OP(avx2x2_sub, _mm256_sub_ps)
AVX2X2_OP(avx2x2_add, _mm256_add_ps)
AVX2X2_OP(avx2x2_mul, _mm256_mul_ps)
AVX2X2_OP(avx2x2_max, _mm256_max_ps)
AVX2X2_OP3(avx2x2_fma, _mm256_fmadd_ps)
AVX2X2_OP3(avx2x2_fnma, _mm256_fnmadd_ps)
AVX2X2_OP3(avx2x2_fms, _mm256_fmsub_ps)
__attribute__((target("avx2,fma"), always_inline)) static inline avx2x2 avx2x2_pair(double p)
{
  const __m256 v = _mm256_castpd_ps(_mm256_set1_pd(p));
  const avx2x2 r = {v, v};
  return r;
}
__attribute__((target("avx2,fma"), always_inline)) static inline avx2x2 avx2x2_zero(void)
{
  const avx2x2 r = {_mm256_setzero_ps(), _mm256_setzero_ps()};
  return r;
}
__attribute__((target("avx2,fma"), always_inline)) static inline unsigned avx2x2_signs(avx2x2 a)
{
  return (unsigned) _mm256_movemask_ps(a.lo) | (unsigned) _mm256_movemask_ps(a.hi) << 8;
}
__attribute__((target("avx2,fma"), always_inline)) static inline int avx2x2_any_sign(avx2x2 a)
{
  const __m256 either = _mm256_or_ps(a.lo, a.hi);
  return !_mm256_testz_ps(either, either);
}

/* A cluster's lanes as each kernel holds them: lane 2 k + j for sphere k and candidate t + j */
typedef struct cluster_avx2 {
  avx2x2 x, y, z, s, sure, s2_same, gap_same;
} cluster_avx2;
typedef struct cluster_avx512 {
  __m512 x, y, z, s, sure, s2_same, gap_same;
} cluster_avx512;

/* Sphere k's lanes 2 k and 2 k + 1 of a cluster's 8 floats v, as the two AVX2 vectors hold them;
 * one float in every lane */
__attribute__((target("avx2,fma"), always_inline)) static inline avx2x2 avx2x2_lanes(__m256 v)
{
  const avx2x2 r = {_mm256_permutevar8x32_ps(v, _mm256_setr_epi32(0, 0, 1, 1, 2, 2, 3, 3)),
                    _mm256_permutevar8x32_ps(v, _mm256_setr_epi32(4, 4, 5, 5, 6, 6, 7, 7))};
  return r;
}
__attribute__((target("avx2,fma"), always_inline)) static inline avx2x2 avx2x2_one(float f)
{
  const avx2x2 r = {_mm256_set1_ps(f), _mm256_set1_ps(f)};
  return r;
}

GRIDDEM_RUN_KERNEL(avx2, "avx2,fma", avx2x2, avx2x2_pair, avx2x2_sub, avx2x2_add, avx2x2_mul, avx2x2_fma, avx2x2_fnma,
                   avx2x2_fms, avx2x2_max, avx2x2_zero(), avx2x2_signs, avx2x2_any_sign, 8, avx2x2_lanes, avx2x2_one)
#define AVX512_PAIR(p) _mm512_castpd_ps(_mm512_set1_pd(p))
#define AVX512_NEGATIVE(v) _mm512_cmp_ps_mask(v, _mm512_setzero_ps(), _CMP_LT_OQ)
#define AVX512_LANES(v) \
  _mm512_permutexvar_ps(_mm512_setr_epi32(0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7), _mm512_castps256_ps512(v))
GRIDDEM_RUN_KERNEL(avx512, "avx512f", __m512, AVX512_PAIR, _mm512_sub_ps, _mm512_add_ps, _mm512_mul_ps,
                   _mm512_fmadd_ps, _mm512_fnmadd_ps, _mm512_fmsub_ps, _mm512_max_ps, _mm512_setzero_ps(),
                   AVX512_NEGATIVE, AVX512_NEGATIVE, 8, AVX512_LANES, _mm512_set1_ps)
#endif

static const struct {
  const char *name;
  int width;
} KERNELS[] = {{"avx512", 8}, {"avx2", 8}, {"scalar", 8}};    /* one width: the same clusters, so the same order */
#define NKERNELS (sizeof(KERNELS) / sizeof(KERNELS[0]))

griddem_touching_fn griddem_touching_kernel(const char *name)
{
  if (strcmp(name, "scalar") == 0) return touching_scalar;
#ifdef GRIDDEM_SEARCH_X86
  __builtin_cpu_init();
  if (strcmp(name, "avx2") == 0)
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? touching_avx2 : NULL;
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
  if (strcmp(name, "auto") == 0) {
    chosen = -1;
    return 0;
  }
  for (size_t k = 0; k < NKERNELS; k++) {
    if (strcmp(name, KERNELS[k].name) != 0) continue;
    griddem_touching_fn fn = griddem_touching_kernel(name);
    if (!fn) return -1;
    chosen = (int) k, chosen_fn = fn;
    return 0;
  }
  return -1;
}

int griddem_vector_reads(void)
{
#ifdef GRIDDEM_SEARCH_X86
  if (chosen < 0) choose();
  return strcmp(KERNELS[chosen].name, "scalar") != 0 && __builtin_cpu_supports("avx2") &&
         __builtin_cpu_supports("fma");
#else
  return 0;
#endif
}
