/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/hertz/history/kk (and /kk/device, /kk/host), the Kokkos
   twin of griddem/hertz/history (itself the grid-based twin of gran/hertz/history); see pair_griddem_kokkos.h.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hertz/history/kk,PairGriddemHertzHistoryKokkos<LMPDeviceType>);
PairStyle(griddem/hertz/history/kk/device,PairGriddemHertzHistoryKokkos<LMPDeviceType>);
PairStyle(griddem/hertz/history/kk/host,PairGriddemHertzHistoryKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HERTZ_HISTORY_KOKKOS_H
#define LMP_PAIR_GRIDDEM_HERTZ_HISTORY_KOKKOS_H

#include "pair_griddem_hertz_history.h"
#include "pair_griddem_kokkos.h"

namespace LAMMPS_NS {

template <class DeviceType> using PairGriddemHertzHistoryKokkos = PairGriddemKokkos<DeviceType, PairGriddemHertzHistory>;

}    // namespace LAMMPS_NS

#endif
#endif
