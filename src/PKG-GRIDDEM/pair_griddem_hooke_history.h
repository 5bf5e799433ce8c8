/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke/history, the grid-based twin of gran/hooke/history.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hooke/history,PairGriddemHookeHistory);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HOOKE_HISTORY_H
#define LMP_PAIR_GRIDDEM_HOOKE_HISTORY_H

#include "pair_griddem.h"

namespace LAMMPS_NS {

class PairGriddemHookeHistory : public PairGriddem {
 public:
  PairGriddemHookeHistory(class LAMMPS *);
  void settings(int, char **) override;
  void coeff(int, char **) override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;

 protected:
  int dampflag;
  int style_tangential;    // the style's tangential model, before select_tangential()
  void select_tangential();
  double linear_normal_stiffness() override;
};

}    // namespace LAMMPS_NS

#endif
#endif
