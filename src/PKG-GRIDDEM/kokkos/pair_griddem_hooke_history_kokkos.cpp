/* ----------------------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/hooke/history/kk (pair_griddem_kokkos.h).
------------------------------------------------------------------------- */

#include "pair_griddem_hooke_history_kokkos.h"

#include "pair_griddem_kokkos_impl.h"

namespace LAMMPS_NS {
template class PairGriddemKokkos<LMPDeviceType, PairGriddemHookeHistory>;
#ifdef LMP_KOKKOS_GPU
template class PairGriddemKokkos<LMPHostType, PairGriddemHookeHistory>;
#endif
}    // namespace LAMMPS_NS
