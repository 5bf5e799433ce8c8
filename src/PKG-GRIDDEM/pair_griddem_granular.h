/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: pair style griddem/granular, the grid-based twin of pair granular for the
   sub-models of griddem_submodels.c.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/granular,PairGriddemGranular);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_GRANULAR_H
#define LMP_PAIR_GRIDDEM_GRANULAR_H

#include "pair_griddem.h"

namespace LAMMPS_NS {

class PairGriddemGranular : public PairGriddem {
 public:
  PairGriddemGranular(class LAMMPS *);
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;

 private:
  const griddem_submodel *find_submodel(int axis, const char *name);
  void write_spec(FILE *, const griddem_pair_spec &);
  griddem_pair_spec read_spec(FILE *);
};

}    // namespace LAMMPS_NS

#endif
#endif
