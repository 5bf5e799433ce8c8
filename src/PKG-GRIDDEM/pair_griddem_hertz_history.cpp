/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/hertz/history.
------------------------------------------------------------------------- */

#include "pair_griddem_hertz_history.h"

using namespace LAMMPS_NS;

PairGriddemHertzHistory::PairGriddemHertzHistory(LAMMPS *lmp) : PairGriddemHookeHistory(lmp)
{
  hertz = 1;
}
