/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/hooke/kk (and /kk/device, /kk/host), the Kokkos
   twin of griddem/hooke (itself the grid-based twin of gran/hooke); see pair_griddem_kokkos.h.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hooke/kk,PairGriddemHookeKokkos<LMPDeviceType>);
PairStyle(griddem/hooke/kk/device,PairGriddemHookeKokkos<LMPDeviceType>);
PairStyle(griddem/hooke/kk/host,PairGriddemHookeKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HOOKE_KOKKOS_H
#define LMP_PAIR_GRIDDEM_HOOKE_KOKKOS_H

#include "pair_griddem_hooke.h"
#include "pair_griddem_kokkos.h"

namespace LAMMPS_NS {

template <class DeviceType> using PairGriddemHookeKokkos = PairGriddemKokkos<DeviceType, PairGriddemHooke>;

}    // namespace LAMMPS_NS

#endif
#endif
