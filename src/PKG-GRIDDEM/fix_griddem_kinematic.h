/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: a kinematic region. The atoms of the fix's group inside a region move at a
   prescribed velocity (constants or equal-style variables) without rotating, whatever the forces
   on them; membership is tested every step, so atoms join and leave as they move (a kinematic
   outlet: the discharge of a silo at a controlled speed).
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem/kinematic,FixGriddemKinematic);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_KINEMATIC_H
#define LMP_FIX_GRIDDEM_KINEMATIC_H

#include "fix.h"

#include <string>

namespace LAMMPS_NS {

class FixGriddemKinematic : public Fix {
 public:
  FixGriddemKinematic(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_force(int) override;
  double compute_scalar() override;

 private:
  // a velocity component: a constant, or an equal-style variable evaluated every step
  struct Component {
    double value;
    std::string variable;    // empty: constant
    int index;
  };
  Component velocity[3];
  std::string region_id;
  class Region *region;
  bigint held;    // atoms of this process held at the last step (the scalar sums them)
};

}    // namespace LAMMPS_NS

#endif
#endif
