/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: what every griddem pair style shares. Each step it bins owned and ghost atoms
   into a uniform grid (no neighbor list) and runs the C core's stencil sweep; per-atom contact
   history lives in fix griddem. Derived styles parse their arguments into a griddem_model.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_GRIDDEM_H
#define LMP_PAIR_GRIDDEM_H

#include "griddem_grid.h"
#include "griddem_sweep.h"
#include "pair.h"

#include <vector>

namespace LAMMPS_NS {

class PairGriddem : public Pair {
 public:
  PairGriddem(class LAMMPS *);
  ~PairGriddem() override;
  void compute(int, int) override;
  void init_style() override;
  double single(int, int, int, int, double, double, double, double &) override;
  double memory_usage() override;

 protected:
  griddem_model model;          // the contact law and its parameters, set by the derived style
  class FixGriddem *fix;
  int coarsened_warned;
  double rmin, rmax;            // smallest and largest radius of all atoms, refreshed on reneighbor

  griddem_grid grid;
  griddem_bins bins;
  griddem_channels channels;
  int freeze_group_bit;
  std::vector<unsigned char> excluded_types;
  std::vector<int> excluded_groups;
  griddem_exclusions exclusions;

  void allocate();
  void create_default_fix();
  // largest radius per type of the atoms present and those fix pour/deposit will add, found
  // once per init_style() for init_one()
  std::vector<double> type_radius;
  // linear normal stiffness for the dt <= pi/5 sqrt(m/k) warning; 0: not a linear spring
  virtual double linear_normal_stiffness() = 0;

 private:
  void setup_exclusions();
  std::vector<double> max_radius_by_type();
  void find_radius_range();
  void check_motion(double h_nn4dem);
  void report_fault(const griddem_sweep_result &);
};

}    // namespace LAMMPS_NS

#endif
