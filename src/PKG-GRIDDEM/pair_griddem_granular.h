/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: pair style griddem/granular, the grid-based twin of pair granular for the
   sub-models the C core evaluates (see griddem_contact.h).
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/granular,PairGriddemGranular);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_GRANULAR_H
#define LMP_PAIR_GRIDDEM_GRANULAR_H

#include "pair_griddem.h"

#include <vector>

namespace LAMMPS_NS {

class PairGriddemGranular : public PairGriddem {
 public:
  PairGriddemGranular(class LAMMPS *);
  void settings(int, char **) override;
  void coeff(int, char **) override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;

  enum Normal { HOOKE, HERTZ, HERTZ_MATERIAL };

  // one pair_coeff line as given (or mixed): sub-model choices and their raw coefficients
  struct Spec {
    int normal, damping, tangential, rolling, limit_damping;
    double normal_coeffs[3], tangential_coeffs[3], rolling_coeffs[3];
    double cutoff;    // < 0: from the radii
    int mixed;        // coefficients mixed from two like-type lines (hertz/material's E is then E_eff)
  };

 protected:
  double cutoff_global;
  std::vector<Spec> specs;                         // [i*(ntypes+1)+j]
  std::vector<griddem_granular_params> params;     // [i*(ntypes+1)+j], both orders
  int layout_set;                                  // history layout fixed by a first pair_coeff

  double linear_normal_stiffness() override;
  Spec mix(const Spec &a, const Spec &b, int i, int j);
  griddem_granular_params to_params(const Spec &s);
};

}    // namespace LAMMPS_NS

#endif
#endif
