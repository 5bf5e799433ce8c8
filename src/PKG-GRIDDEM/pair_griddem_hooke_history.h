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
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;

 protected:
  double kn, kt, gamman, gammat, xmu;
  int dampflag, limit_damping;
  int shear_history;    // 1: gran/hooke/history's shear spring, 0: gran/hooke's damping only
  int hertz;            // 1: gran/hertz/history's Hertzian normal force and friction
  griddem_pair_spec style_spec() const;
  void adopt_style_spec();
};

}    // namespace LAMMPS_NS

#endif
#endif
