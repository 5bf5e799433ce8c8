/* ----------------------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/granular/kk (pair_griddem_kokkos.h).
------------------------------------------------------------------------- */

#include "pair_griddem_granular_kokkos.h"

#include "pair_griddem_kokkos_impl.h"

namespace LAMMPS_NS {
template class PairGriddemKokkos<LMPDeviceType, PairGriddemGranular>;
#ifdef LMP_KOKKOS_GPU
template class PairGriddemKokkos<LMPHostType, PairGriddemGranular>;
#endif
}    // namespace LAMMPS_NS
