/* How GRIDDEM's contact-law functions are declared: plain static inline functions for C and C++,
 * and host-device functions when a CUDA or HIP compiler reads them (the Kokkos styles), so one
 * header serves the CPU sweep and the GPU kernels. Keyed on the compiler, not on which header
 * happened to be included first. */
#ifndef GRIDDEM_PORTABLE_H
#define GRIDDEM_PORTABLE_H

#if defined(__CUDACC__) || defined(__HIPCC__)
#define GRIDDEM_INLINE static inline __host__ __device__
#else
#define GRIDDEM_INLINE static inline
#endif

/* A condition that almost never holds (a fault, an exclusion, a full store): the compiler lays
 * its branch out of the way of the loop around it */
#if defined(__GNUC__)
#define GRIDDEM_RARELY(c) __builtin_expect(!!(c), 0)
#else
#define GRIDDEM_RARELY(c) (c)
#endif

#include <math.h> /* and with it the C library's name (__GLIBC__) */

/* A loop's function in a copy for AVX2 processors and one for any x86-64, chosen at load time (by
 * the C library's indirect functions: GCC on glibc), where the build targets no particular
 * processor; elsewhere one copy. The vectorizer takes one loop a function: give each its own. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__GLIBC__)
#define GRIDDEM_VECTOR_COPIES __attribute__((target_clones("arch=x86-64-v3", "default"), noinline))
#else
#define GRIDDEM_VECTOR_COPIES
#endif

#endif
