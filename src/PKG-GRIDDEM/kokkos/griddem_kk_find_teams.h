/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: 3. the search as a team per block of cells, its neighbourhood staged
   in scratch memory.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_FIND_TEAMS_H
#define LMP_GRIDDEM_KK_FIND_TEAMS_H

#include "griddem_kk_find.h"

namespace LAMMPS_NS {

/* The search as a team per block of `width` cells along x of one size class's grid (after Chrono
   GPU's and DEM-Engine's kernels): the team copies the `near` rows of its class within `reach`
   cells of the block into scratch memory once, then its threads search the block's particles as
   GriddemKKFind does, reading those rows from the copy (other classes' rows from `near`). A block
   whose neighbourhood holds more than `budget` candidates reads them all from `near`. Lists,
   their order and every number are GriddemKKFind's. */
template <class DeviceType, typename Real> struct GriddemKKFindTeams {
  typedef DeviceType device_type;
  typedef typename Kokkos::TeamPolicy<DeviceType>::member_type member_type;
  typedef Kokkos::View<int *, typename DeviceType::scratch_memory_space,
                       Kokkos::MemoryTraits<Kokkos::Unmanaged>>
      scratch_ints;
  typedef Kokkos::View<float *, typename DeviceType::scratch_memory_space,
                       Kokkos::MemoryTraits<Kokkos::Unmanaged>>
      scratch_floats;
  static constexpr int width = 8;        // cells of a block along x
  static constexpr int budget = 1024;    // candidates a team's scratch holds

  GriddemKKFind<DeviceType, Real> find;
  int reach[GRIDDEM_MAX_CLASSES];              // cells around a block its class's search visits
  int first_block[GRIDDEM_MAX_CLASSES + 1];    // blocks of the classes before
  int most_rows;                               // of a window: (2 reach + 1)^2 at most

  KOKKOS_INLINE_FUNCTION static int blocks_along_x(int nx) { return (nx + width - 1) / width; }
  size_t team_shmem_size(int) const
  {
    return scratch_ints::shmem_size(most_rows) + scratch_floats::shmem_size(4 * budget);
  }

  KOKKOS_INLINE_FUNCTION void operator()(const member_type &team) const
  {
    const int b = team.league_rank();
    int ci = 0;
    while (first_block[ci + 1] <= b) ci++;
    const GriddemKKGrid &g = find.grids.g[ci];
    const int nbx = blocks_along_x(g.n[0]), local = b - first_block[ci];
    const int bx = local % nbx, y = (local / nbx) % g.n[1], z = local / (nbx * g.n[1]);
    const int x0 = bx * width, x1 = Kokkos::min(x0 + width, g.n[0]) - 1, r = reach[ci];
    GriddemKKWindow w;
    w.cls = ci;
    w.x0 = Kokkos::max(x0 - r, 0), w.x1 = Kokkos::min(x1 + r, g.n[0] - 1);
    w.y0 = Kokkos::max(y - r, 0), w.y1 = Kokkos::min(y + r, g.n[1] - 1);
    w.z0 = Kokkos::max(z - r, 0), w.z1 = Kokkos::min(z + r, g.n[2] - 1);
    const int ny = w.y1 - w.y0 + 1, nrows = ny * (w.z1 - w.z0 + 1);
    scratch_ints shift(team.team_scratch(0), most_rows);
    scratch_floats data(team.team_scratch(0), 4 * budget);
    auto row_start = [&](int row) {    // first slot of the window's row `row`
      const int yy = w.y0 + row % ny, zz = w.z0 + row / ny;
      return find.grids.offset[ci] + g.n[0] * (yy + g.n[1] * zz);
    };
    // the window's rows, each a range of slots, laid out one after the other
    int staged = 0;
    for (int row = 0; row < nrows; row++) {
      const int cells = row_start(row);
      const int u0 = find.start(cells + w.x0), u1 = find.start(cells + w.x1 + 1);
      if (staged + (u1 - u0) <= budget) {
        Kokkos::single(Kokkos::PerTeam(team), [&]() { shift(row) = staged - u0; });
        Kokkos::parallel_for(Kokkos::TeamThreadRange(team, u1 - u0), [&](const int k) {
          for (int d = 0; d < 4; d++) data(4 * (staged + k) + d) = find.near(u0 + k, d);
        });
      }
      staged += u1 - u0;
    }
    team.team_barrier();
    w.valid = staged <= budget;
    w.shift = shift.data();
    w.data = data.data();
    const int cells = find.grids.offset[ci] + g.n[0] * (y + g.n[1] * z);
    const int s0 = find.start(cells + x0), s1 = find.start(cells + x1 + 1);
    Kokkos::parallel_for(Kokkos::TeamThreadRange(team, s0, s1),
                         [&](const int s) { find.list_candidates(s, w); });
  }
};

}    // namespace LAMMPS_NS

#endif
