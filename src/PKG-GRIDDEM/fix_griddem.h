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
  // the sweep's input: row index of each atom in rows (-1: no contacts), and the output buffer
  // with one row per sorted slot, of which slots_next rows are needed
  double *rows_next(int slots_next);
  // after a sweep: the output becomes the history; order maps sorted slots to atoms
  void adopt_next(int nslot, const int *order, int nlocal);

  // grid options (keywords cell and contacts)
  int cell_mode;        // enum griddem_cell_mode
  double cell_edge;     // for GRIDDEM_CELL_FIXED
  int slots;            // contact history entries per atom; 0: no history stored
  int values;           // history values per contact (3: tangential; 6: tangential and rolling)
  int stride;           // doubles per row: 1 + (1 + values) * slots

  // Rows live in the order of the last sweep's sorted slots, so the sweep reads and writes them
  // nearly sequentially; atoms only point at their row. Atoms arriving from another process or
  // a restart file get rows appended after those.
  double *rows;         // [rows_cap][stride]: count, then (partner tag, values) per contact
  int *row_of;          // per atom: its row in rows, or -1
  int rows_used, rows_cap;

  // this process's grid statistics of the last step, set by the pair style
  struct Stats {
    double occupied_cells, max_occupancy, max_cells_moved, cell_edge, contacts, max_contacts,
        elastic_energy;
  } stats;

 private:
  double *next;
  int next_cap;
  int used_length(const double *row) const;
  const double *row(int i) const;
  double *append_row();
};

}    // namespace LAMMPS_NS

#endif
#endif
