/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: compute griddem/grid, granular fields on a LAMMPS distributed grid
   (for dump grid and dump grid/vtk, which ParaView reads).
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(griddem/grid,ComputeGriddemGrid);
// clang-format on
#else

#ifndef LMP_COMPUTE_GRIDDEM_GRID_H
#define LMP_COMPUTE_GRIDDEM_GRID_H

#include "compute.h"

#include <vector>

namespace LAMMPS_NS {

class ComputeGriddemGrid : public Compute {
 public:
  ComputeGriddemGrid(class LAMMPS *, int, char **);
  ~ComputeGriddemGrid() override;
  void init() override;
  void compute_pergrid() override;
  void reset_grid() override;
  int get_grid_by_name(const std::string &, int &) override;
  void *get_grid_by_index(int) override;
  int get_griddata_by_name(int, const std::string &, int &) override;
  void *get_griddata_by_index(int) override;
  double memory_usage() override;

  enum Field { COUNT, BINNED_SOLID, VX, VY, VZ, NFIELDS };

 private:
  int ncell[3];
  std::vector<int> fields;
  class Grid3d *grid3d;
  int lo_in[3], hi_in[3], lo_out[3], hi_out[3];
  std::vector<double ***> columns;    // each value alone, grid data named by the value
  double ****array3d;                 // all values, grid data "data" (with two or more values)
  std::vector<double> global;    // per cell: count, solid volume, momentum xyz, mass

  void allocate_grid();
  void deallocate_grid();
};

}    // namespace LAMMPS_NS

#endif
#endif
