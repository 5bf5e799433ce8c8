/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/granular/kk (and /kk/device, /kk/host), the Kokkos
   twin of griddem/granular (itself the grid-based twin of pair granular); see pair_griddem_kokkos.h.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/granular/kk,PairGriddemGranularKokkos<LMPDeviceType>);
PairStyle(griddem/granular/kk/device,PairGriddemGranularKokkos<LMPDeviceType>);
PairStyle(griddem/granular/kk/host,PairGriddemGranularKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_GRANULAR_KOKKOS_H
#define LMP_PAIR_GRIDDEM_GRANULAR_KOKKOS_H

#include "pair_griddem_granular.h"
#include "pair_griddem_kokkos.h"

namespace LAMMPS_NS {

template <class DeviceType> using PairGriddemGranularKokkos = PairGriddemKokkos<DeviceType, PairGriddemGranular>;

}    // namespace LAMMPS_NS

#endif
#endif
