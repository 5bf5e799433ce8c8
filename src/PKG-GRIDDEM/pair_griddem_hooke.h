/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke, the grid-based twin of gran/hooke.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hooke,PairGriddemHooke);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HOOKE_H
#define LMP_PAIR_GRIDDEM_HOOKE_H

#include "pair_griddem_hooke_history.h"

namespace LAMMPS_NS {

// Same engine without shear memory: tangential force is velocity damping capped by Coulomb.
class PairGriddemHooke : public PairGriddemHookeHistory {
 public:
  PairGriddemHooke(class LAMMPS *);
};

}    // namespace LAMMPS_NS

#endif
#endif
