/* ----------------------------------------------------------------------
   GRIDDEM package, Kokkos: pair style griddem/hooke/kk (pair_griddem_kokkos.h).
------------------------------------------------------------------------- */

#include "pair_griddem_hooke_kokkos.h"

#include "pair_griddem_kokkos_impl.h"

namespace LAMMPS_NS {
template class PairGriddemKokkos<LMPDeviceType, PairGriddemHooke>;
#ifdef LMP_KOKKOS_GPU
template class PairGriddemKokkos<LMPHostType, PairGriddemHooke>;
#endif
}    // namespace LAMMPS_NS
