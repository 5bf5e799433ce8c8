/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: compute griddem/cg, continuum fields (solid fraction, density, velocity, stress,
   granular temperature, coordination) by cloud-in-cell assignment and FFT Gaussian smoothing.
------------------------------------------------------------------------- */

#ifdef COMPUTE_CLASS
// clang-format off
ComputeStyle(griddem/cg,ComputeGriddemCg);
// clang-format on
#else

#ifndef LMP_COMPUTE_GRIDDEM_CG_H
#define LMP_COMPUTE_GRIDDEM_CG_H

#include "compute.h"
#include "griddem_grid.h"

#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

class ComputeGriddemCg : public Compute {
 public:
  ComputeGriddemCg(class LAMMPS *, int, char **);
  ~ComputeGriddemCg() override;
  void init() override;
  void compute_pergrid() override;
  void reset_grid() override;
  int get_grid_by_name(const std::string &, int &) override;
  void *get_grid_by_index(int) override;
  int get_griddata_by_name(int, const std::string &, int &) override;
  void *get_griddata_by_index(int) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;
  // whether its values come from the atoms' own quantities alone (no per-atom virial, no contact
  // count), so that fix griddem/rom's stored atoms can be read where they are held
  bool reads_store() const;

 private:
  int ngrid[3];
  double width;
  std::vector<int> values;       // what each output is (enum in the .cpp)
  std::vector<int> slot;         // per channel: its place in the channel brick, or -1
  std::vector<int> carried;      // per place in the brick: its channel
  int nslot;

  class Grid3d *grid3d;
  class Fix *ghost_sum;          // Grid3d's reverse communication goes through a Fix
  int lo_in[3], hi_in[3], lo_out[3], hi_out[3];
  double ****channels;           // assigned particle quantities, owned + ghost points
  std::vector<double ***> fields;    // one output per value, owned + ghost extent
  double *gc_buf1, *gc_buf2;

  int fftsize[3], fft_lo[3], fft_hi[3];
  class FFT3d *fft;
  class Remap *to_fft, *from_fft;
  std::vector<double> kernel_hat, work, fft_real, owned, smoothed;
  double kernel_h[3];            // the grid spacings kernel_hat was transformed for

  int nmax;
  std::vector<class Fix *> averages;    // the fixes ave/grid, whose samples need the per-atom virial
  double **virial;               // per-atom virial (pair + fixes), ghosts summed back when newton
  std::vector<double> contacts;  // touching neighbours per owned atom
  griddem_grid contact_grid;     // the grid they are found on, kept between steps
  griddem_bins contact_bins;

  void allocate_grid();
  void deallocate_grid();
  void make_fft(const int size[3]);
  void destroy_fft();
  void transform_kernel(const double h[3]);
  void smooth(int s, bool by_kernel);
  void convolve();
  void ask_for_virial();
  void gather_virial();
  void count_contacts();
};

}    // namespace LAMMPS_NS

#endif
#endif
