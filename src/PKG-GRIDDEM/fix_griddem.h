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
  // after a sweep has written history_next: make it the current history
  void swap_history();

  // grid options (keywords cell and contacts)
  int cell_mode;        // enum griddem_cell_mode
  double cell_edge;     // for GRIDDEM_CELL_FIXED
  int slots;            // contact history entries per atom; 0: no history stored
  int values;           // history values per contact (3: tangential; 6: tangential and rolling)
  int stride;           // doubles per atom row: 1 + (1 + values) * slots
  double **history;     // [nmax][stride]: count, then (partner tag, values) per contact
  double **history_next;// the sweep's output buffer, same layout

  // this process's grid statistics of the last step, set by the pair style
  struct Stats {
    double occupied_cells, max_occupancy, max_cells_moved, cell_edge, contacts, max_contacts,
        elastic_energy;
  } stats;

 private:
  int used_length(const double *row) const;
};

}    // namespace LAMMPS_NS

#endif
#endif
