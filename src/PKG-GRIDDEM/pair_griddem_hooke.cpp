/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke.
------------------------------------------------------------------------- */

#include "pair_griddem_hooke.h"

using namespace LAMMPS_NS;

PairGriddemHooke::PairGriddemHooke(LAMMPS *lmp) : PairGriddemHookeHistory(lmp)
{
  set_tangential(GRIDDEM_TANGENTIAL_DAMPED);
}
