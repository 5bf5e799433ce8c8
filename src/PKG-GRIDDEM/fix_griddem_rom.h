/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: adaptive reduced-order DEM. A ridge-regression model predicts the voxel
   velocity field from the voxel density field and control variables; particles moving with the
   field become kinematic (carried by it, no contact forces, no contacts among themselves).
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem/rom,FixGriddemRom);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_ROM_H
#define LMP_FIX_GRIDDEM_ROM_H

#include "fix.h"
#include "griddem_rom.h"

#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

class FixGriddemRom : public Fix {
 public:
  FixGriddemRom(class LAMMPS *, int, char **);
  ~FixGriddemRom() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void setup_pre_reverse(int, int) override;
  void pre_reverse(int, int) override;
  void post_force(int) override;
  void end_of_step() override;
  void grow_arrays(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  double compute_vector(int) override;
  int get_grid_by_name(const std::string &, int &) override;
  void *get_grid_by_index(int) override;
  int get_griddata_by_name(int, const std::string &, int &) override;
  void *get_griddata_by_index(int) override;
  void reset_grid() override;
  void *extract(const char *, int &) override;
  double memory_usage() override;

  int kinematic_bit;    // group bit of the kinematic atoms (group ID_kinematic)

 private:
  griddem_rom_grid grid;
  int ncontrol;
  double lambda;
  std::vector<double> weights;    // [3 nvoxel][1 + nvoxel + ncontrol]
  std::vector<std::string> control_names;
  std::vector<int> control_vars;
  double eps, v0, overlap_max;
  std::string resolved_id;    // atoms in this region are never kinematic (keyword resolved)
  class Region *resolved;
  int period;    // classification every period steps
  std::vector<double> density, feature, field;
  double *state;    // per-atom output: 1 kinematic, 0 dynamic
  double **fpair;   // this step's contact forces on kinematic atoms (the pair's share of f)
  std::vector<std::pair<int, const double *>> gravities;    // group bit, acceleration of each fix gravity
  int nmax;
  // the voxel fields as LAMMPS grid data (dump grid, grid/vtk): this process's brick of them
  class Grid3d *grid3d;
  int lo_in[3], hi_in[3], lo_out[3], hi_out[3];
  double ***grid_values[4];    // vx vy vz density of the last classification
  griddem_grid check_grid;    // the contact checks' grid and bins (scratch kept between calls)
  griddem_bins check_bins;
  double counts[8];    // kinematic now, made kinematic, released by hits, overlaps, leaving, forces;
                       // classifications; released by field jumps

  void read_model(const char *file);
  void classify();
  void zero_kinematic_forces();
  void fill_state();
  void allocate_grid();
  void deallocate_grid();
  void fill_grid();
};

}    // namespace LAMMPS_NS

#endif
#endif
