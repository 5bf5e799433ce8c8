/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: 1. the scan: bounding boxes, non-finite values, the fastest atom, the
   radius range; and each size class's box.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_SCAN_H
#define LMP_GRIDDEM_KK_SCAN_H

#include "griddem_kk_grid.h"
#include "kokkos_type.h"

#include <climits>

namespace LAMMPS_NS {

/* what the scan finds */
struct GriddemKKScanValue {
  double lo[3], hi[3];    // bounding box of finite centres (owned and ghosts)
  double rmin, rmax;      // radius range of owned atoms
  double vmax2;           // largest squared speed of an owned atom
  int ivmax;              // its index
  int badx,
      badv;    // smallest index of a non-finite position (all) / velocity (owned); INT_MAX: none
};

template <class DeviceType> struct GriddemKKScan {
  typedef DeviceType device_type;
  typedef GriddemKKScanValue value_type;
  typedef ArrayTypes<DeviceType> AT;
  typename AT::t_x_array_randomread x;
  typename AT::t_v_array_randomread v;
  typename AT::t_float_1d_randomread radius;
  int nlocal;

  KOKKOS_INLINE_FUNCTION void init(value_type &s) const
  {
    for (int d = 0; d < 3; d++) s.lo[d] = 1e308, s.hi[d] = -1e308;
    s.rmin = 1e308, s.rmax = 0.0, s.vmax2 = -1.0;
    s.ivmax = -1, s.badx = s.badv = INT_MAX;
  }
  KOKKOS_INLINE_FUNCTION void join(value_type &s, const value_type &o) const
  {
    for (int d = 0; d < 3; d++) {
      if (o.lo[d] < s.lo[d]) s.lo[d] = o.lo[d];
      if (o.hi[d] > s.hi[d]) s.hi[d] = o.hi[d];
    }
    if (o.rmin < s.rmin) s.rmin = o.rmin;
    if (o.rmax > s.rmax) s.rmax = o.rmax;
    if (o.vmax2 > s.vmax2 || (o.vmax2 == s.vmax2 && o.ivmax < s.ivmax))
      s.vmax2 = o.vmax2, s.ivmax = o.ivmax;
    if (o.badx < s.badx) s.badx = o.badx;
    if (o.badv < s.badv) s.badv = o.badv;
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type &s) const
  {
    const double xi = x(i, 0), yi = x(i, 1), zi = x(i, 2);
    if (!(Kokkos::isfinite(xi) && Kokkos::isfinite(yi) && Kokkos::isfinite(zi))) {
      if (i < s.badx) s.badx = i;
      return;
    }
    const double p[3] = {xi, yi, zi};
    for (int d = 0; d < 3; d++) {
      if (p[d] < s.lo[d]) s.lo[d] = p[d];
      if (p[d] > s.hi[d]) s.hi[d] = p[d];
    }
    if (i >= nlocal) return;
    const double r = radius(i);
    if (r < s.rmin) s.rmin = r;
    if (r > s.rmax) s.rmax = r;
    const double v2 = v(i, 0) * v(i, 0) + v(i, 1) * v(i, 1) + v(i, 2) * v(i, 2);
    if (!Kokkos::isfinite(v2)) {
      if (i < s.badv) s.badv = i;
    } else if (v2 > s.vmax2 || (v2 == s.vmax2 && i < s.ivmax)) {
      s.vmax2 = v2, s.ivmax = i;
    }
  }
};


// values a class takes in GriddemKKClassScan's reduction: count, lo[3], hi[3]
constexpr int griddem_kk_class_values = 7;

/* The boxes as an array reduction of 7 values a class present (count, lo[3], hi[3]): Kokkos keeps
   such a value in memory, where a struct for GRIDDEM_MAX_CLASSES classes filled the registers of
   a GPU thread and spilled (255 registers, 368 bytes of spill stores on sm_90). */
template <class DeviceType> struct GriddemKKClassScan {
  typedef DeviceType device_type;
  typedef double value_type[];
  typedef ArrayTypes<DeviceType> AT;
  static constexpr int per_class = griddem_kk_class_values;
  size_t value_count;    // per_class * grids.ncls
  typename AT::t_x_array_randomread x;
  typename AT::t_float_1d_randomread radius;
  GriddemKKGrids grids;

  KOKKOS_INLINE_FUNCTION void init(value_type s) const
  {
    for (size_t c = 0; c < value_count; c += per_class) {
      s[c] = 0.0;
      for (int d = 0; d < 3; d++) s[c + 1 + d] = 1e308, s[c + 4 + d] = -1e308;
    }
  }
  KOKKOS_INLINE_FUNCTION void join(value_type s, const value_type o) const
  {
    for (size_t c = 0; c < value_count; c += per_class) {
      s[c] += o[c];
      for (int d = 0; d < 3; d++) {
        if (o[c + 1 + d] < s[c + 1 + d]) s[c + 1 + d] = o[c + 1 + d];
        if (o[c + 4 + d] > s[c + 4 + d]) s[c + 4 + d] = o[c + 4 + d];
      }
    }
  }
  KOKKOS_INLINE_FUNCTION void operator()(const int i, value_type s) const
  {
    double *box = s + per_class * grids.class_of(radius(i));
    box[0] += 1.0;
    for (int d = 0; d < 3; d++) {
      if (x(i, d) < box[1 + d]) box[1 + d] = x(i, d);
      if (x(i, d) > box[4 + d]) box[4 + d] = x(i, d);
    }
  }
};

}    // namespace LAMMPS_NS

#endif
