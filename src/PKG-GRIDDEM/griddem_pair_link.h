/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: the one interface between fix griddem and the griddem pair styles.
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_PAIR_LINK_H
#define LMP_GRIDDEM_PAIR_LINK_H

#include "griddem_engine.h"

namespace LAMMPS_NS {

/* What fix griddem asks of the griddem pair style: every griddem style is one, and gives it by
   name, Pair::extract("griddem") (griddem_pair_link). */
class GriddemPairLink {
 public:
  // The contact history lives as long as the pair style (griddem_fix_keeper.h). A fix griddem
  // tells it when it is made (in_place: in the slot of the fix of its ID, which Modify has just
  // deleted) and when it goes.
  virtual void fix_made(class FixGriddem *made, int in_place) = 0;
  virtual void fix_leaving(class FixGriddem *leaving) = 0;
  // the statistics of the style's last step with fix `of` (before its first step: those of a
  // step without atoms), or nullptr where the style has not chosen that fix; occupancy: with the
  // occupied cells and the most centres in one (the Kokkos styles count them only when asked: a
  // pass over every cell that most steps do not need)
  virtual const griddem_engine_stats *step_stats(const class FixGriddem *of, int occupancy) = 0;

 protected:
  ~GriddemPairLink() = default;    // not deleted through this interface
};

// force->pair's link, or nullptr where it is not a griddem pair style
GriddemPairLink *griddem_pair_link(class Pair *pair);

}    // namespace LAMMPS_NS

#endif
