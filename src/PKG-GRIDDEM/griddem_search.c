/* Candidate search kernels; see griddem_search.h. Every kernel evaluates
 * ((dx dx + dy dy) + dz dz) < s s in double with separate multiplies and adds: this file is
 * compiled without contraction (-ffp-contract=off), so the plain-C kernel rounds as the vector
 * lanes do. */
#include "griddem_search.h"

#include <stddef.h>
#include <string.h>

static int touching_scalar(const griddem_spheres *sp, const double *c, const int *lo, const int *hi, int nruns,
                           int *slot)
{
  const double xi = c[0], yi = c[1], zi = c[2], ri = c[3];
  int n = 0;
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t++) {
      const double dx = xi - sp->x[t], dy = yi - sp->y[t], dz = zi - sp->z[t], s = ri + sp->r[t];
      slot[n] = t;
      n += dx * dx + dy * dy + dz * dz < s * s;
    }
  return n;
}

#if defined(__GNUC__) && defined(__x86_64__)
#define GRIDDEM_SEARCH_X86 1
#include <immintrin.h>

/* The lanes set in a 4-bit mask, packed first: the slots an AVX2 pass stores */
static const int packed_lanes[16][4] = {
    {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0},
    {1, 2, 0, 0}, {0, 1, 2, 0}, {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0},
    {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};

__attribute__((target("avx2"))) static int touching_avx2(const griddem_spheres *sp, const double *c,
                                                         const int *lo, const int *hi, int nruns, int *slot)
{
  const __m256d xi = _mm256_set1_pd(c[0]), yi = _mm256_set1_pd(c[1]), zi = _mm256_set1_pd(c[2]),
                ri = _mm256_set1_pd(c[3]);
  const __m256i lane = _mm256_setr_epi64x(0, 1, 2, 3);
  int n = 0;
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t += 4) {
      /* lanes past the run are neither read nor counted */
      const __m256i live = _mm256_cmpgt_epi64(_mm256_set1_epi64x(hi[q] - t), lane);
      const __m256d dx = _mm256_sub_pd(xi, _mm256_maskload_pd(sp->x + t, live));
      const __m256d dy = _mm256_sub_pd(yi, _mm256_maskload_pd(sp->y + t, live));
      const __m256d dz = _mm256_sub_pd(zi, _mm256_maskload_pd(sp->z + t, live));
      const __m256d s = _mm256_add_pd(ri, _mm256_maskload_pd(sp->r + t, live));
      const __m256d d2 =
          _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
      const __m256d touch = _mm256_and_pd(_mm256_cmp_pd(d2, _mm256_mul_pd(s, s), _CMP_LT_OQ), _mm256_castsi256_pd(live));
      const int bits = _mm256_movemask_pd(touch);
      const __m128i packed = _mm_loadu_si128((const __m128i *) packed_lanes[bits]);
      _mm_storeu_si128((__m128i *) (slot + n), _mm_add_epi32(_mm_set1_epi32(t), packed));
      n += __builtin_popcount((unsigned) bits);
    }
  return n;
}

__attribute__((target("avx512f"))) static int touching_avx512(const griddem_spheres *sp, const double *c,
                                                              const int *lo, const int *hi, int nruns, int *slot)
{
  const __m512d xi = _mm512_set1_pd(c[0]), yi = _mm512_set1_pd(c[1]), zi = _mm512_set1_pd(c[2]),
                ri = _mm512_set1_pd(c[3]);
  const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  int n = 0;
  for (int q = 0; q < nruns; q++)
    for (int t = lo[q]; t < hi[q]; t += 8) {
      const int left = hi[q] - t;
      const __mmask8 live = left >= 8 ? 0xff : (__mmask8) ((1u << left) - 1u);
      const __m512d dx = _mm512_sub_pd(xi, _mm512_maskz_loadu_pd(live, sp->x + t));
      const __m512d dy = _mm512_sub_pd(yi, _mm512_maskz_loadu_pd(live, sp->y + t));
      const __m512d dz = _mm512_sub_pd(zi, _mm512_maskz_loadu_pd(live, sp->z + t));
      const __m512d s = _mm512_add_pd(ri, _mm512_maskz_loadu_pd(live, sp->r + t));
      const __m512d d2 =
          _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy)), _mm512_mul_pd(dz, dz));
      const __mmask8 touch = _mm512_mask_cmp_pd_mask(live, d2, _mm512_mul_pd(s, s), _CMP_LT_OQ);
      /* compressed in a register and stored whole: a compressing store to memory is slow on
         some processors */
      const __m512i slots = _mm512_add_epi32(_mm512_set1_epi32(t), lane);
      _mm512_storeu_si512((void *) (slot + n), _mm512_maskz_compress_epi32((__mmask16) touch, slots));
      n += __builtin_popcount((unsigned) touch);
    }
  return n;
}
#endif

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

static const char *const kernel_names[] = {"avx512", "avx2", "scalar"};
static const char *chosen_name;
static griddem_touching_fn chosen;

/* The widest kernel this processor runs, once */
static void choose(void)
{
  for (size_t k = 0; !chosen && k < sizeof(kernel_names) / sizeof(kernel_names[0]); k++)
    if ((chosen = griddem_touching_kernel(kernel_names[k]))) chosen_name = kernel_names[k];
}

griddem_touching_fn griddem_touching(void)
{
  if (!chosen) choose();
  return chosen;
}

const char *griddem_touching_name(void)
{
  if (!chosen) choose();
  return chosen_name;
}

int griddem_touching_use(const char *name)
{
  for (size_t k = 0; k < sizeof(kernel_names) / sizeof(kernel_names[0]); k++) {
    if (strcmp(name, kernel_names[k]) != 0) continue;
    griddem_touching_fn fn = griddem_touching_kernel(kernel_names[k]);
    if (!fn) return -1;
    chosen = fn, chosen_name = kernel_names[k];
    return 0;
  }
  return -1;
}
