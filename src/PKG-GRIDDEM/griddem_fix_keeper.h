/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: which fix griddem holds a griddem pair style's contact history, kept as long
   as the pair style, as stock keeps its history fix. The keeper makes fix GRIDDEM when the
   style is defined (or read from a restart file) unless the script has a fix griddem, and deletes
   it with the style; a fix griddem of the script's then keeps its options and loses its rows. A
   fix griddem defined after a run takes the history of the one that ran: one of another ID at
   the next init, one of the same ID (which Modify deletes before making the new one) from the
   rows the old one left here, by atom ID.
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_FIX_KEEPER_H
#define LMP_GRIDDEM_FIX_KEEPER_H

#include "pointers.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixGriddem;

class GriddemFixKeeper : protected Pointers {
 public:
  explicit GriddemFixKeeper(class LAMMPS *);
  // the pair style goes: its own fix with it, a script's fix loses its rows
  void release();

  // style: the fix style made to hold the pair style's history ("griddem", or "griddem/kk" for
  // a kk style whose history lives on its device: kokkosable). make_default() makes fix GRIDDEM
  // unless a fix griddem exists (or where the pair style's own was made for a model without
  // history, or for the other kind of store, and track_contacts needs one), so that thermo_style
  // can name f_GRIDDEM before the first run; remake: its own made again even if it suits
  void make_default(const std::string &style, int kokkosable, int track_contacts, int remake = 0);
  // the fix griddem of this init: the script's, else the pair style's own; one defined beside
  // the one that ran replaces it and takes its history
  FixGriddem *choose(const std::string &style, int kokkosable, int track_contacts);
  // the fix of the last choose(), or nullptr once it went
  FixGriddem *fix() const { return chosen; }

  // told by each fix griddem as it is made (in_place: in the slot of the fix of its ID, which
  // Modify has just deleted) and as it goes, while its rows can still be read
  void fix_made(FixGriddem *made, int in_place);
  void fix_leaving(FixGriddem *leaving);

 private:
  FixGriddem *chosen;
  // the rows of a fix that went, by atom ID, for the fix that replaced it in place
  std::vector<double> parked;    // per atom: its ID, then its restart record
  std::string parked_id;         // the ID of the fix they came from
  FixGriddem *heir;              // the fix that takes them at the next choose()
  void forget_parked();
  void park(FixGriddem &from);
  void unpark(FixGriddem &to);
};

}    // namespace LAMMPS_NS

#endif
