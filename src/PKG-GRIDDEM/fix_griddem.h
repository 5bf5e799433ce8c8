/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: grid options, the engine (grid, bins, channels, contact history) and its
   per-atom row index, grid diagnostics.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem,FixGriddem);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_H
#define LMP_FIX_GRIDDEM_H

#include "fix.h"
#include "griddem_engine.h"
#include "griddem_pair_link.h"

namespace LAMMPS_NS {

enum { GRIDDEM_PRECISION_DOUBLE, GRIDDEM_PRECISION_SINGLE };
// the Kokkos styles' search: a thread per atom reading its candidates from device memory, or a
// team per block of cells with their neighbourhood staged in scratch memory; auto: teams on a GPU
enum { GRIDDEM_SEARCH_AUTO, GRIDDEM_SEARCH_THREAD, GRIDDEM_SEARCH_TEAM };


class FixGriddem : public Fix {
 public:
  FixGriddem(class LAMMPS *, int, char **);
  ~FixGriddem() override;
  int setmask() override;
  void init() override;

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
  virtual void set_values(int values);
  // one engine step; the step's row_of is this fix's
  int run_step(griddem_step &step, griddem_sweep_result &result, int &coarsened);
  const griddem_engine_stats &stats() const { return engine.stats; }
  // a step that ran outside the engine (the Kokkos styles) reports its statistics here, the
  // occupancy as -1 where the pair style counts it when asked (GriddemPairLink)
  void set_stats(const griddem_engine_stats &s)
  {
    engine.stats = s;
    stats_current = 1;
  }
  // atom i takes the row of a record laid out as pack_restart writes it
  void put_history(int i, const double *record);
  // every atom's row emptied; the grid values are refused until a griddem pair style's next step
  void drop_history();
  // stored history values of atom i's contact with the atom tagged partner, or nullptr
  virtual const double *find_history(int i, double partner) const;
  // 1: the rows live in fix griddem/kk's Kokkos arrays, not in the engine
  int kokkos_history;

  // grid options (keywords cell and contacts)
  int cell_mode;        // enum griddem_cell_mode
  double cell_edge;     // for GRIDDEM_CELL_FIXED
  int contacts;         // expected contacts per atom (initial history storage); 0: no history
  int precision;        // of the sorted particle data (the Kokkos styles); GRIDDEM_PRECISION_*
  int search;           // the Kokkos styles' search; GRIDDEM_SEARCH_*

  int made_by_pair;     // 1: the pair style's own fix, deleted with the pair style

 protected:
  // tells the pair style this fix goes, while its rows can still be read: called by the
  // destructor of the most derived class
  void leave();

 private:
  int stats_current;    // engine.stats are of a griddem pair style's step with this fix
  griddem_engine engine;
  int *row_of;          // per atom: its history row, or -1
  int reserved;         // history storage reserved for `contacts` per atom
  void add_row(int i, const double *message, int values);
};

}    // namespace LAMMPS_NS

#endif
#endif
