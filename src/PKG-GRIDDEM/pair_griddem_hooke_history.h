/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke/history, the grid-based twin of gran/hooke/history.
------------------------------------------------------------------------- */

#ifdef PAIR_CLASS
// clang-format off
PairStyle(griddem/hooke/history,PairGriddemHookeHistory);
// clang-format on
#else

#ifndef LMP_PAIR_GRIDDEM_HOOKE_HISTORY_H
#define LMP_PAIR_GRIDDEM_HOOKE_HISTORY_H

#include "griddem_grid.h"
#include "griddem_sweep.h"
#include "pair.h"

namespace LAMMPS_NS {

class PairGriddemHookeHistory : public Pair {
 public:
  PairGriddemHookeHistory(class LAMMPS *);
  ~PairGriddemHookeHistory() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  double memory_usage() override;

 protected:
  griddem_hooke_params params;  // kn kt gamman gammat xmu limit_damping, tangential model
  int dampflag;
  int history;                  // 1: tangential spring needs per-contact shear history
  class FixGriddem *fix;
  int freeze_group_bit;
  double rmin, rmax;            // smallest and largest radius of all atoms, refreshed on reneighbor
  int coarsened_warned;

  griddem_grid grid;
  griddem_bins bins;
  griddem_channels channels;

  void allocate();
  void create_default_fix();
  void find_radius_range();
  void check_motion(double h_nn4dem);
  void report_fault(const griddem_sweep_result &);
};

}    // namespace LAMMPS_NS

#endif
#endif
