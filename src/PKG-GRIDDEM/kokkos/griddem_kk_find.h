/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: 3. the search, a thread per sorted particle: its touching candidates
   into its list.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_FIND_H
#define LMP_GRIDDEM_KK_FIND_H

#include "griddem_contact.h"
#include "griddem_exclusions.h"
#include "griddem_kk_sorted.h"
#include "griddem_search.h"

namespace LAMMPS_NS {

/* A team's copy of the `near` rows around its block (GriddemKKFindTeams): rows y0..y1, z0..z1
   of size class cls's grid, cells x0..x1 of each; slot u of row r is at data[4 * (u + shift[r])]
   (rows y fastest). valid 0: none, every row is read from `near`. */
struct GriddemKKWindow {
  int valid, cls, x0, x1, y0, y1, z0, z1;
  const int *shift;
  const float *data;
};

template <class DeviceType, typename Real>
struct GriddemKKFind : public GriddemKKSorted<DeviceType, Real> {
  typedef DeviceType device_type;

  double slack;          // added to every search distance: round-off of the positions
  double near_margin;    // added to the float test's distance: the rounding of `near` (0 where
                         // `near` is the law's own position)
  long capacity;         // entries of `list`
  Kokkos::View<const int *, DeviceType> start;                      // first slot of each cell
  griddem_exclusions excl;    // the CPU style's, its tables on the device
  Kokkos::View<const tagint *, DeviceType> molecule;    // by slot, where excl names molecules

  KOKKOS_INLINE_FUNCTION void operator()(const int s) const
  {
    const GriddemKKWindow none = {0, 0, 0, 0, 0, 0, 0, 0, nullptr, nullptr};
    list_candidates(s, none);
  }

  // slot s's list, in its room or, where that is short, in room at the end of the list
  KOKKOS_INLINE_FUNCTION void list_candidates(const int s, const GriddemKKWindow &w) const
  {
    const int i = this->order(s);
    if (i >= this->nlocal) return;
    int head = this->first(s);
    const int room = (int) Kokkos::min((long) this->count(s), Kokkos::max(0L, capacity - head));
    int n = search(s, i, head, room, w);
    if (n > room) {    // room at the end of the list, where the layout's ends
      const long end = Kokkos::atomic_fetch_add(&this->report().listed, (long) n);
      if (end + n <= capacity) {
        head = (int) end;
        this->first(s) = head;
        search(s, i, head, n, w);
      } else {
        Kokkos::atomic_fetch_or(&this->report().retry, (int) GRIDDEM_KK_RETRY_LISTS);
        n = -n;
      }
    }
    this->count(s) = n;
  }

  // lists slot s's (atom i's) touching candidates into list(head), up to room of them, reading
  // the rows w holds from it; returns how many there are
  KOKKOS_INLINE_FUNCTION int search(const int s, const int i, const int head, const int room,
                                    const GriddemKKWindow &w) const
  {
    const double pi[3] = {(double) this->near(s, 0), (double) this->near(s, 1),
                          (double) this->near(s, 2)};
    const double radi = this->radius_of(s);
    const int itype = this->tm(s, 0), imask = this->tm(s, 1);
    double corner[3], xi[3];
    this->grids.cell_corner(this->slot_cell(s), corner);
    for (int d = 0; d < 3; d++) xi[d] = corner[d] + pi[d];
    int n = 0;

    // every class's cells within reach of a partner as large as the class allows
    for (int cj = 0; cj < this->grids.ncls; cj++) {
      const GriddemKKGrid &g = this->grids.g[cj];
      const double d = radi + this->grids.upper[cj] + this->reach_extra + slack;
      int lo[3], hi[3];
      for (int k = 0; k < 3; k++) g.cells_within(k, xi[k], xi[k], d, lo[k], hi[k]);
      // x_i - x_j from the positions in their cells and the cells' corners; each shift is set
      // in the loop over its own axis, and a cell's first slot is its predecessor's end (the
      // cells of a row along x are consecutive)
      for (int z = lo[2]; z <= hi[2]; z++) {
        const double sz = corner[2] - g.corner(2, z);
        for (int y = lo[1]; y <= hi[1]; y++) {
          const double sy = corner[1] - g.corner(1, y);
          const int row = this->grids.offset[cj] + g.n[0] * (y + g.n[1] * z);
          const float *rows = this->near.data();    // candidate u's x, y, z, radius: rows[4 * (u + shift)]
          int shift = 0;
          if (w.valid && cj == w.cls && y >= w.y0 && y <= w.y1 && z >= w.z0 && z <= w.z1 &&
              lo[0] >= w.x0 && hi[0] <= w.x1) {
            rows = w.data;
            shift = w.shift[(y - w.y0) + (w.y1 - w.y0 + 1) * (z - w.z0)];
          }
          int u = start(row + lo[0]);
          for (int x = lo[0]; x <= hi[0]; x++) {
            const double sx = corner[0] - g.corner(0, x);
            for (const int end = start(row + x + 1); u < end; u++) {
              if (u == s) continue;
              const float *pu = rows + 4 * (size_t) (u + shift);
              const double dx = (pi[0] - (double) pu[0]) + sx;
              const double dy = (pi[1] - (double) pu[1]) + sy;
              const double dz = (pi[2] - (double) pu[2]) + sz;
              double sep[3] = {dx, dy, dz}, radj = (double) pu[3];
              if (!griddem_search_touches(sep, radi, this->reach_extra + near_margin, radj)) continue;
              double rsq = dx * dx + dy * dy + dz * dz;
              if constexpr (GriddemKKSorted<DeviceType, Real>::atom_positions) {
                rsq = this->separation(s, u, corner, sep, radj);
                if (!griddem_search_touches(sep, radi, this->reach_extra, radj)) continue;
              }
              if (rsq == 0.0) {
                Kokkos::atomic_min(&this->report().coincident,
                                   (long) i << 32 | (long) (unsigned) this->order(u));
                continue;
              }
              if (griddem_excluded(&excl, itype, imask, this->tm(u, 0), this->tm(u, 1)) ||
                  (excl.nmolecule && griddem_excluded_molecules(&excl, molecule(s), imask, molecule(u), this->tm(u, 1))))
                continue;
              if (n < room) this->list(head + n) = u;
              n++;
            }
          }
        }
      }
    }
    return n;
  }
};

}    // namespace LAMMPS_NS

#endif
