/* Interleaved points (x, y, z of each, as LAMMPS holds positions and velocities) read four at a
 * time into AVX2 lanes: the three coordinates as three vectors of four points. For the streaming
 * passes of the scan and the binning (griddem_vector_reads chooses them at run time), each the
 * twin of a plain-C pass; on x86-64 with GCC or Clang. */
#ifndef GRIDDEM_POINTS_AVX2_H
#define GRIDDEM_POINTS_AVX2_H

#if defined(__GNUC__) && defined(__x86_64__)
#define GRIDDEM_POINTS_AVX2 1
#include <immintrin.h>

/* Points p[0..11] as x, y, z of points 0-3: loaded as the 128-bit halves (x0 y0 | x2 y2),
 * (z0 x1 | z2 x3) and (y1 z1 | y3 z3), then blended and shuffled within the halves */
__attribute__((target("avx2"), always_inline)) static inline void griddem_points4_avx2(const double *p, __m256d *x,
                                                                                      __m256d *y, __m256d *z)
{
  const __m256d r0 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_loadu_pd(p + 6), 1);
  const __m256d r1 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + 2)), _mm_loadu_pd(p + 8), 1);
  const __m256d r2 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p + 4)), _mm_loadu_pd(p + 10), 1);
  *x = _mm256_blend_pd(r0, r1, 0xa);
  *y = _mm256_shuffle_pd(r0, r2, 0x5);
  *z = _mm256_blend_pd(r1, r2, 0xa);
}

#endif

#endif
