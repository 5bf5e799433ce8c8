/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/hooke/history/kk (and /kk/device, /kk/host), the Kokkos
   twin of griddem/hooke/history (itself the grid-based twin of gran/hooke/history); see pair_griddem_kokkos.h.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hooke/history/kk,PairGriddemHookeHistoryKokkos<LMPDeviceType>);
PairStyle(griddem/hooke/history/kk/device,PairGriddemHookeHistoryKokkos<LMPDeviceType>);
PairStyle(griddem/hooke/history/kk/host,PairGriddemHookeHistoryKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HOOKE_HISTORY_KOKKOS_H
#define LMP_PAIR_GRIDDEM_HOOKE_HISTORY_KOKKOS_H

#include "pair_griddem_hooke_history.h"
#include "pair_griddem_kokkos.h"

namespace LAMMPS_NS {

template <class DeviceType> using PairGriddemHookeHistoryKokkos = PairGriddemKokkos<DeviceType, PairGriddemHookeHistory>;

}    // namespace LAMMPS_NS

#endif
#endif
