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

#include <math.h>

#endif
