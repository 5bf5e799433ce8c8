/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: pair style griddem/hertz/history, the grid-based twin of gran/hertz/history.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hertz/history,PairGriddemHertzHistory);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HERTZ_HISTORY_H
#define LMP_PAIR_GRIDDEM_HERTZ_HISTORY_H

#include "pair_griddem_hooke_history.h"

namespace LAMMPS_NS {

// gran/hooke/history's arguments and shear spring, with the normal force and the friction scaled
// by sqrt(delta R_eff) (griddem_classic.h)
class PairGriddemHertzHistory : public PairGriddemHookeHistory {
 public:
  PairGriddemHertzHistory(class LAMMPS *);
};

}    // namespace LAMMPS_NS

#endif
#endif
