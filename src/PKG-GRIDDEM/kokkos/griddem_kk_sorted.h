/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: the sorted particles (the channels) that the search and the sweep
   read.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_SORTED_H
#define LMP_GRIDDEM_KK_SORTED_H

#include "griddem_kk_report.h"
#include "kokkos_type.h"

#include <type_traits>

namespace LAMMPS_NS {

/* The sorted particles' positions for the search: float, relative to their cell's lower corner
   (~1e-7 of a cell, not of the box), and radius. Rows (LayoutRight) on every device: the search
   gathers a candidate's four values together, 16 bytes (half a 32-byte sector on a GPU, where the
   default layout would spread them over four arrays, and half of what doubles took). In single
   precision they are also the law's positions. */
typedef float GriddemKKNear[4];

/* The sorted particles' velocity, angular velocity and mass, in the precision of fix griddem's
   `precision`; rows, as the positions. */
template <class DeviceType, typename Real> struct GriddemKKChannels {
  typedef Kokkos::View<Real *[7], Kokkos::LayoutRight, DeviceType> t_state;    // v, omega, mass
  t_state state;
};

/* The sweep is two kernels, one thread per sorted particle in each. The first (GriddemKKFind)
   visits the cells within reach and lists the candidates that touch (a list per particle,
   sorted slot by slot); the second (GriddemKKSweep) evaluates the contact law over each list.
   A stencil holds ~30 candidates of which a few touch: searching them wants many threads in
   flight to hide the gathers, which a kernel that also holds the law cannot have (one kernel:
   180 registers on sm_90, ~11 warps an SM; the search alone: 64), while the law runs once per
   contact, the threads of a warp together. The lists are laid out before the search from each
   atom's last count plus a margin; an atom with more candidates than its room takes room at the
   end of the list and is searched again there (a repair of the search, not of the law).
   Evaluation order: cells z, y, x, slots ascending, as one pass over the stencil. What both
   kernels read: */
template <class DeviceType, typename Real> struct GriddemKKSorted {
  // double: the law's positions and radii are LAMMPS's own (x_i - x_j as the CPU engine takes
  // them); float: the channels' (positions in their cells, plus the cells' corners)
  static constexpr bool atom_positions = std::is_same<Real, double>::value;
  GriddemKKGrids grids;
  int nlocal, ntypes;
  double reach_extra;    // model.reach_extra
  Kokkos::View<const int *, DeviceType> order;        // atom index of each slot
  Kokkos::View<const int *, DeviceType> slot_cell;    // cell of each slot (over all classes)
  Kokkos::View<const GriddemKKNear *, Kokkos::LayoutRight, DeviceType> near;
  typename ArrayTypes<DeviceType>::t_x_array_randomread x;            // by atom index
  typename ArrayTypes<DeviceType>::t_float_1d_randomread radius;      // by atom index
  Kokkos::View<const int *[2], Kokkos::LayoutRight, DeviceType> tm;     // type, mask
  Kokkos::View<int *, DeviceType> list;     // candidate slots, each slot's from first(s)
  Kokkos::View<int *, DeviceType> first;    // [nall] laid out; a repaired slot's moves
  Kokkos::View<int *, DeviceType> count;    // room laid out, then candidates listed (-needed:
                                            // the list had no room left; the step is retried)
  Kokkos::View<GriddemKKStepReport, DeviceType> report;

  // slot s's radius, in the law's precision
  KOKKOS_INLINE_FUNCTION double radius_of(int s) const
  {
    if constexpr (atom_positions) return radius(order(s));
    else return near(s, 3);
  }
  // x_s - x_u into dx and its square, and u's radius, in the law's precision; cs: s's cell corner
  KOKKOS_INLINE_FUNCTION double separation(int s, int u, const double cs[3], double dx[3],
                                           double &radj) const
  {
    if constexpr (atom_positions) {
      const int i = order(s), j = order(u);
      for (int d = 0; d < 3; d++) dx[d] = x(i, d) - x(j, d);
      radj = radius(j);
    } else {
      double cu[3];
      grids.cell_corner(slot_cell(u), cu);
      for (int d = 0; d < 3; d++)
        dx[d] = ((double) near(s, d) - (double) near(u, d)) + (cs[d] - cu[d]);
      radj = near(u, 3);
    }
    return dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
  }
};

}    // namespace LAMMPS_NS

#endif
