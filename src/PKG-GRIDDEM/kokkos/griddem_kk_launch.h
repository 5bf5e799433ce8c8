/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: how the griddem kk kernels are launched.

   A kernel's closure (its functor, or a lambda and what it captures) travels to a CUDA or HIP
   device as kernel arguments only below Kokkos's default threshold of 512 bytes; above it Kokkos
   copies the closure to constant memory, after waiting for the kernels still running: each
   launch would then wait for the last. The grids of a step alone take 760 bytes. Every griddem
   kernel is launched here instead, with Kokkos's light-weight hint, which passes a closure as
   kernel arguments up to the 4 KB those can hold (Kokkos's CudaTraits::KernelArgumentLimit), and
   a compile-time check keeps each closure below that limit with room for the launch's own policy
   and reducers. Host back ends ignore the hint.
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_LAUNCH_H
#define LMP_GRIDDEM_KK_LAUNCH_H

#include "Kokkos_Core.hpp"

#include <utility>

namespace LAMMPS_NS {

// the most bytes a griddem kernel's closure may take: 4 KB of kernel arguments, less 1 KB for
// the policy, reducers and Kokkos's own members of the launched driver
constexpr size_t griddem_kk_closure_max = 3072;

template <class Policy> auto griddem_kk_light(const Policy &policy)
{
  return Kokkos::Experimental::require(policy, Kokkos::Experimental::WorkItemProperty::HintLightWeight);
}

#define GRIDDEM_KK_CHECK_CLOSURE(Functor)                                       \
  static_assert(sizeof(Functor) <= griddem_kk_closure_max,                     \
                "a griddem kernel's closure outgrew a launch as kernel arguments " \
                "(griddem_kk_launch.h)")

template <class Policy, class Functor>
void griddem_kk_for(const char *name, const Policy &policy, const Functor &functor)
{
  GRIDDEM_KK_CHECK_CLOSURE(Functor);
  Kokkos::parallel_for(name, griddem_kk_light(policy), functor);
}

template <class Policy, class Functor, class... Results>
void griddem_kk_reduce(const char *name, const Policy &policy, const Functor &functor, Results &&...results)
{
  GRIDDEM_KK_CHECK_CLOSURE(Functor);
  Kokkos::parallel_reduce(name, griddem_kk_light(policy), functor, std::forward<Results>(results)...);
}

template <class Policy, class Functor, class... Results>
void griddem_kk_scan(const char *name, const Policy &policy, const Functor &functor, Results &&...results)
{
  GRIDDEM_KK_CHECK_CLOSURE(Functor);
  Kokkos::parallel_scan(name, griddem_kk_light(policy), functor, std::forward<Results>(results)...);
}

#undef GRIDDEM_KK_CHECK_CLOSURE

}    // namespace LAMMPS_NS

#endif
