/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: a step's grids, one per size class, and the boxes they are fitted to.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_GRID_H
#define LMP_GRIDDEM_KK_GRID_H

#include "griddem_engine.h"
#include "griddem_grid.h"
#include "kokkos_type.h"

namespace LAMMPS_NS {

/* the grid of one step, as griddem_grid: cell (ix,iy,iz) covers anchor + (k0 + i) * h */
struct GriddemKKGrid {
  double anchor[3], h, hinv;
  long k0[3];
  int n[3];
  KOKKOS_INLINE_FUNCTION int axis_cell(int d, double x) const
  {
    return griddem_axis_cell(x, anchor[d], hinv, k0[d], n[d]);
  }
  // the cells along d within dist of xlo..xhi
  KOKKOS_INLINE_FUNCTION void cells_within(int d, double xlo, double xhi, double dist, int &lo, int &hi) const
  {
    griddem_axis_cells_within(xlo, xhi, dist, anchor[d], hinv, k0[d], n[d], &lo, &hi);
  }
  KOKKOS_INLINE_FUNCTION int cell_of(double x, double y, double z) const
  {
    return axis_cell(0, x) + n[0] * (axis_cell(1, y) + n[1] * axis_cell(2, z));
  }
  // lower face along d of cell c
  KOKKOS_INLINE_FUNCTION double corner(int d, int c) const
  {
    return griddem_cell_face(anchor[d], h, k0[d] + c);
  }
};

/* One grid per size class (one class unless fix griddem's cell mode is auto or classes and the
   radii span a factor 4), as the CPU engine: class c holds radii in (upper[c+1], upper[c]] on a
   grid of edge 2 upper[c] (larger for a sparse class); the classes' cells are numbered one
   after the other, so a single counting sort bins them all. */
struct GriddemKKGrids {
  int ncls;
  GriddemKKGrid g[GRIDDEM_MAX_CLASSES];
  int offset[GRIDDEM_MAX_CLASSES + 1];      // first cell of each class; offset[ncls]: all cells
  double upper[GRIDDEM_MAX_CLASSES + 1];    // upper[ncls] = 0
  KOKKOS_INLINE_FUNCTION int class_of(double r) const { return griddem_class_of(r, upper, ncls); }
  // the class whose grid holds cell c (numbered over all classes)
  KOKKOS_INLINE_FUNCTION int class_of_cell(int c) const
  {
    int k = 0;
    while (offset[k + 1] <= c) k++;
    return k;
  }
  // the lower corner of cell c
  KOKKOS_INLINE_FUNCTION void cell_corner(int c, double corner[3]) const
  {
    const int k = class_of_cell(c);
    const GriddemKKGrid &gk = g[k];
    const int local = c - offset[k];
    corner[0] = gk.corner(0, local % gk.n[0]);
    corner[1] = gk.corner(1, (local / gk.n[0]) % gk.n[1]);
    corner[2] = gk.corner(2, local / (gk.n[0] * gk.n[1]));
  }
};

/* per size class: atoms, and the bounding box of their centres */
struct GriddemKKClassBoxes {
  int count[GRIDDEM_MAX_CLASSES];
  double lo[GRIDDEM_MAX_CLASSES][3], hi[GRIDDEM_MAX_CLASSES][3];
};

}    // namespace LAMMPS_NS

#endif
