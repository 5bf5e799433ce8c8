/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke.
------------------------------------------------------------------------- */

#include "pair_griddem_hooke.h"

using namespace LAMMPS_NS;

PairGriddemHooke::PairGriddemHooke(LAMMPS *lmp) : PairGriddemHookeHistory(lmp)
{
  shear_history = 0;
}
