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
  void init() override;

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
  void commit_step() override;

 private:
  griddem_history rows;
  int *row_of;          // per atom: its history row, or -1
  int reserved;         // history storage reserved for `contacts` per atom
  void update_maxexchange();
};

}    // namespace LAMMPS_NS

#endif
#endif
