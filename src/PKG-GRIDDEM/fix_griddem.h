/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: fix griddem, the contact history of the CPU pair styles: a griddem_history
   (griddem_history.h) in host memory and each atom's row in it, which the styles' engine sweeps.
   History rows grow with the contacts: no atom has a fixed limit.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem,FixGriddemCPU);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_H
#define LMP_FIX_GRIDDEM_H

#include "fix_griddem_face.h"

namespace LAMMPS_NS {

class FixGriddemCPU : public FixGriddem {
 public:
  FixGriddemCPU(class LAMMPS *, int, char **);
  ~FixGriddemCPU() override;
  int setmask() override;
  void init() override;
  void setup_pre_exchange() override { complete(); }
  void pre_exchange() override { complete(); }
  void min_pre_exchange() override { complete(); }
  void post_run() override
  {
    complete();
    FixGriddem::post_run();
  }

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  double memory_usage() override;

  int history_values() const override { return rows.values; }
  void set_values(int values) override;
  const double *find_history(int i, int64_t partner) override;
  int get_message(int i, double *message) override;
  int message_length(int i) override;
  int longest_message() override;
  void put_message(int i, const double *message) override;

  griddem_history_rows begin_step() override { return griddem_history_rows{&rows, row_of}; }
  void commit_step(const griddem_model &law, int most_contacts) override;

 private:
  griddem_history rows;
  int *row_of;          // per atom: its history row, or -1
  int reserved;         // history storage reserved for `contacts` per atom
  // the last step's law: per type pair, the sign of each history value seen from the partner
  std::vector<double> parity;
  int parity_types;
  int most_contacts;    // of one atom, in the last step
  // the contacts of owned pairs that the last step kept in one row mirrored into the other: before
  // atoms migrate, and before anything else reads the rows
  void complete();
  void update_maxexchange();
};

}    // namespace LAMMPS_NS

#endif
#endif
