/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: grid options, per-atom contact history and grid diagnostics.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem,FixGriddem);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_H
#define LMP_FIX_GRIDDEM_H

#include "fix.h"
#include "griddem_history.h"

namespace LAMMPS_NS {

class FixGriddem : public Fix {
 public:
  FixGriddem(class LAMMPS *, int, char **);
  ~FixGriddem() override;
  int setmask() override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;
  double compute_vector(int) override;

  // the pair style's history layout; rows already stored are converted
  void set_values(int values);
  // after a sweep: the history's row of sorted slot s is s; order maps slots to atoms
  void adopt_rows(int nslot, const int *order, int nlocal);

  // grid options (keywords cell and contacts)
  int cell_mode;        // enum griddem_cell_mode
  double cell_edge;     // for GRIDDEM_CELL_FIXED
  int slots;            // most contacts one atom may keep history for; 0: no history

  // Contact history in compressed rows (see griddem_history.h), in the order of the last
  // sweep's sorted slots; atoms point at their row. Atoms arriving from another process or a
  // restart file get rows appended.
  griddem_history hist;
  int *row_of;          // per atom: its row, or -1

  // this process's grid statistics of the last step, set by the pair style
  struct Stats {
    double occupied_cells, max_occupancy, max_cells_moved, cell_edge, contacts, max_contacts,
        elastic_energy;
  } stats;

 private:
  void add_row(int i, int count, const double *entries, int values);
};

}    // namespace LAMMPS_NS

#endif
#endif
