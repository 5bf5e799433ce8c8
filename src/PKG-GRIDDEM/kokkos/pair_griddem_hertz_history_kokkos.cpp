/* ----------------------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/hertz/history/kk (pair_griddem_kokkos.h).
------------------------------------------------------------------------- */

#include "pair_griddem_hertz_history_kokkos.h"

#include "pair_griddem_kokkos_impl.h"

namespace LAMMPS_NS {
template class PairGriddemKokkos<LMPDeviceType, PairGriddemHertzHistory>;
#ifdef LMP_KOKKOS_GPU
template class PairGriddemKokkos<LMPHostType, PairGriddemHertzHistory>;
#endif
}    // namespace LAMMPS_NS
