/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: what the griddem/.../kk pair styles share. One class template,
   PairGriddemKokkos<DeviceType, Base>, derives from the CPU style Base (PairGriddemHooke,
   PairGriddemGranular), which parses the arguments, mixes and checks the coefficients and fills
   `model`/`params`; this class only replaces compute() with device kernels:

   1. scan: bounding box of owned + ghost centres (and of each size class's), non-finite
      positions and velocities, fastest owned atom, radius range (one parallel_reduce);
   2. binning: a counting sort of the centres into the grids of fix griddem's cell mode (a grid
      per size class, or one grid of `multi`'s, `exact`'s or a given edge), anchored at
      domain->boxlo; within a cell the slots are ordered by tag (then position, for periodic
      images of one atom), so sums do not depend on storage order;
      the sorted positions (float, relative to the cell: `near`), radii, velocities, masses,
      types and masks are the "channels";
   3. search: each sorted owned particle visits the cells of every size class within reach of it
      and lists the candidates that touch (GriddemKKFind): the compact float positions reject
      the far candidates (a conservative margin: a pair they reject cannot touch), the touch
      test of the rest is the law's own, in its precision. A thread per particle
      (GriddemKKFind), or a team per block of cells with the candidates of its neighbourhood in
      its class staged in scratch memory (GriddemKKFindTeams), per fix griddem's `search`;
   4. sweep: one thread per sorted owned particle evaluates the law over its list from its own
      side (griddem_contact_eval). The law is exactly odd under i <-> j, so each particle sums its
      own force and torque: no atomics, no colouring, no reverse communication. The global virial
      (half of del*f per owned side) and fix griddem's statistics come back from its
      parallel_reduce; the occupancy of the cells is counted only when fix griddem is asked.

   One blocking synchronisation a step: the kernels leave what the host needs in one report
   (GriddemKKStepReport), copied back once after the sweep. Between reneighborings the grids are
   planned from the last step's boxes, widened by what an atom can move in a step, and the scan
   runs alongside the other kernels (its errors are raised from the report); a reneighboring step
   reads its scan before binning, as every process must agree on the radius range there. What
   the plan could not know is found on the device and makes the sweep do nothing, and the step
   is computed again: an atom binned more than a cell outside the grid (planned anew from a
   scan), a list or the history rows outgrowing the room laid out (grown to what they needed).

   Laws with contact history keep it in fix griddem/kk (a row per atom, written anew each step by
   the atom's own thread with room for its list: GriddemKKSweep). Views grow, never shrink, and are
   not reallocated in a step unless a size grew.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_GRIDDEM_KOKKOS_H
#define LMP_PAIR_GRIDDEM_KOKKOS_H

#include "fix_griddem_kokkos.h"
#include "griddem_contact.h"
#include "griddem_engine.h"
#include "kokkos_type.h"
#include "pair_kokkos.h"

#include <climits>
#include <type_traits>

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

/* the grid of one step, as griddem_grid: cell (ix,iy,iz) covers anchor + (k0 + i) * h */
struct GriddemKKGrid {
  double anchor[3], h, hinv;
  long k0[3];
  int n[3];
  KOKKOS_INLINE_FUNCTION int axis_cell(int d, double x) const
  {
    return griddem_axis_cell(x, anchor[d], hinv, k0[d], n[d]);
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

/* what the law's kernel sums: global virial and fix griddem's statistics */
struct GriddemKKSweepValue {
  double v[6];
  double energy;     // elastic energy in the springs (a pair counts half on each side)
  long contacts;     // contacts of owned atoms (an owned pair counts twice)
  int most;          // most contacts of one owned atom
};

/* why a step is computed again (GriddemKKStepReport::retry) */
enum {
  GRIDDEM_KK_RETRY_GRID = 1,     // an atom binned more than a cell outside the planned grid
  GRIDDEM_KK_RETRY_LISTS = 2,    // the contact lists outgrew their room
  GRIDDEM_KK_RETRY_ROWS = 4      // the history rows outgrew the other pool
};

/* What one step's kernels leave for the host, read in one copy after the sweep. */
struct GriddemKKStepReport {
  GriddemKKScanValue scan;
  double class_boxes[griddem_kk_class_values * GRIDDEM_MAX_CLASSES];    // GriddemKKClassScan's
  long coincident;    // the first pair of coincident centres (local indices i << 32 | j), or
                      // LONG_MAX: none
  GriddemKKSweepValue sums;
  long listed;    // list entries taken: the layout's, then those of lists that outgrew it
  long rows;      // history entries of the step's rows
  int retry;      // GRIDDEM_KK_RETRY_* bits: the sweep did nothing
};

/* the boxes of a report's scan: the whole box for one class, else the class scan's */
inline GriddemKKClassBoxes griddem_kk_boxes(const GriddemKKStepReport &report, int ncls, int nall)
{
  GriddemKKClassBoxes boxes;
  if (ncls == 1) {
    boxes.count[0] = nall;
    for (int d = 0; d < 3; d++) boxes.lo[0][d] = report.scan.lo[d], boxes.hi[0][d] = report.scan.hi[d];
    return boxes;
  }
  for (int c = 0; c < ncls; c++) {
    const double *box = report.class_boxes + griddem_kk_class_values * c;
    boxes.count[c] = (int) box[0];
    for (int d = 0; d < 3; d++) boxes.lo[c][d] = box[1 + d], boxes.hi[c][d] = box[4 + d];
  }
  return boxes;
}

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
      for (int k = 0; k < 3; k++)
        lo[k] = g.axis_cell(k, xi[k] - d), hi[k] = g.axis_cell(k, xi[k] + d);
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
              double rsq = dx * dx + dy * dy + dz * dz;
              const double reach = radi + this->reach_extra + (double) pu[3] + near_margin;
              if (!(rsq < reach * reach)) continue;
              if constexpr (GriddemKKSorted<DeviceType, Real>::atom_positions) {
                double sep[3], radj;
                rsq = this->separation(s, u, corner, sep, radj);
                const double rs = radi + this->reach_extra + radj;
                if (!(rsq < rs * rs)) continue;
              }
              if (rsq == 0.0) {
                Kokkos::atomic_min(&this->report().coincident,
                                   (long) i << 32 | (long) (unsigned) this->order(u));
                continue;
              }
              if (griddem_excluded(&excl, itype, imask, this->tm(u, 0), this->tm(u, 1))) continue;
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

/* The contact law over each owned particle's list: the thread sums its particle's force and
   torque (the law is exactly odd under i <-> j, so each side is evaluated on its own: no atomics)
   and, for laws with history, writes the atom's new row into fix griddem/kk's other pool, at the
   place laid out from its list's length (the contacts of this step, with their values found in
   the last step's row and advanced).
   Classic: every type pair uses the gran/hooke laws (griddem_classic.h), so the kernel is compiled
   without the composed sub-models; on a GPU that halves the registers a thread holds. */
template <class DeviceType, typename Real, bool Classic>
struct GriddemKKSweep : public GriddemKKSorted<DeviceType, Real> {
  typedef DeviceType device_type;
  typedef GriddemKKSweepValue value_type;
  typedef ArrayTypes<DeviceType> AT;

  int frozen_bit, vflag_global, vflag_atom;
  double dt;
  int history_update;    // 0 in setup: stored values are read, not advanced
  int track;             // model.track_contacts: rows are kept
  int nv;                // values per contact
  Kokkos::View<const Real *[7], Kokkos::LayoutRight, DeviceType> state;    // v, omega, mass
  typename AT::t_tagint_1d_randomread tag;                                // by atom index
  int keyed_by_image;    // the box has image axes: contacts keyed by partner and periodic image
  Kokkos::View<const int *, DeviceType> image;    // by atom index: image codes (keyed_by_image)
  Kokkos::View<const griddem_pair_params *, DeviceType> params;
  typename FixGriddemKokkos<DeviceType>::Rows rows;    // fix griddem/kk's rows
  Kokkos::View<int *, DeviceType> last;    // by atom index: its list's length, for the next layout
  typename AT::t_f_array f, torque;
  typename AT::t_virial_array vatom;

  KOKKOS_INLINE_FUNCTION void init(value_type &s) const
  {
    for (int k = 0; k < 6; k++) s.v[k] = 0.0;
    s.energy = 0.0;
    s.contacts = 0;
    s.most = 0;
  }
  KOKKOS_INLINE_FUNCTION void join(value_type &s, const value_type &o) const
  {
    for (int k = 0; k < 6; k++) s.v[k] += o.v[k];
    s.energy += o.energy;
    s.contacts += o.contacts;
    if (o.most > s.most) s.most = o.most;
  }

  // the entry of partner p in atom i's last row, or -1
  KOKKOS_INLINE_FUNCTION long find(int i, int64_t p) const
  {
    return griddem_history_entry(rows.partner.data(), rows.first(i), rows.count(i), p);
  }

  // history values per contact the kernel holds: loops over nhist with constant bounds let a
  // GPU keep them in registers
  static constexpr int nhist = Classic ? 3 : GRIDDEM_MAX_HISTORY;

  KOKKOS_INLINE_FUNCTION void operator()(const int s, value_type &sum) const
  {
    const int i = this->order(s);
    if (i >= this->nlocal || this->report().retry) return;
    const double radi = this->radius_of(s), mi = state(s, 6);
    const int itype = this->tm(s, 0), imask = this->tm(s, 1);
    double corner[3] = {0.0, 0.0, 0.0};    // separation() reads it in single precision only
    if constexpr (!GriddemKKSorted<DeviceType, Real>::atom_positions)
      this->grids.cell_corner(this->slot_cell(s), corner);
    double fsum[3] = {0.0, 0.0, 0.0}, tsum[3] = {0.0, 0.0, 0.0};
    double w[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, energy = 0.0;
    const int head = this->first(s), n = this->count(s);
    const int out = track ? rows.first_out(i) : 0;
    int stored = 0, ncontact = 0;

    for (int e = head; e < head + n; e++) {
      const int u = this->list(e);
      double sep[3], radj;
      const double rsq = this->separation(s, u, corner, sep, radj);
      const double dx = sep[0], dy = sep[1], dz = sep[2];
      const int jtype = this->tm(u, 0), jmask = this->tm(u, 1);
      const griddem_pair_params *law = &params(itype * (this->ntypes + 1) + jtype);
      const int j = this->order(u);
      const int64_t partner = !track ? 0 : keyed_by_image ? griddem_image_key(tag(j), image(i), image(j)) : tag(j);
      const long found = track ? find(i, partner) : -1;
      if (this->reach_extra > 0.0 && !griddem_contact_touch(law, rsq, radi, radj, found >= 0)) continue;

      griddem_contact c;
      const double vi[3] = {state(s, 0), state(s, 1), state(s, 2)}, wi[3] = {state(s, 3), state(s, 4), state(s, 5)};
      const double vj[3] = {state(u, 0), state(u, 1), state(u, 2)}, wj[3] = {state(u, 3), state(u, 4), state(u, 5)};
      griddem_contact_setup(&c, sep, rsq, radi, radj, vi, vj, wi, wj, mi, state(u, 6), (imask & frozen_bit) != 0,
                            (jmask & frozen_bit) != 0, dt, history_update);
      double hist[nhist];
      for (int h = 0; h < nhist; h++)
        hist[h] = (found >= 0 && h < nv) ? rows.value(found * nv + h) : 0.0;
      double fc[3], ti[3], tj[3];
      const double uel = Classic ? griddem_classic_eval(law, &c, hist, fc, ti, tj)
                                 : griddem_contact_eval(law, &c, hist, fc, ti, tj);
      if (track) {    // griddem_history_put's layout, its loop bound constant (hist stays in registers)
        const long o = out + stored++;
        rows.partner_out(o) = partner;
        for (int h = 0; h < nhist; h++)
          if (h < nv) rows.value_out(o * nv + h) = hist[h];
      }
      for (int d = 0; d < 3; d++) fsum[d] += fc[d], tsum[d] += ti[d];
      energy += 0.5 * uel;
      ncontact++;
      if (vflag_global || vflag_atom) {
        w[0] += 0.5 * dx * fc[0], w[1] += 0.5 * dy * fc[1], w[2] += 0.5 * dz * fc[2];
        w[3] += 0.5 * dx * fc[1], w[4] += 0.5 * dx * fc[2], w[5] += 0.5 * dy * fc[2];
      }
    }

    last(i) = n;
    if (track) rows.count_out(i) = stored;
    sum.contacts += ncontact;
    if (ncontact > sum.most) sum.most = ncontact;
    for (int d = 0; d < 3; d++) f(i, d) += fsum[d], torque(i, d) += tsum[d];
    sum.energy += energy;
    if (vflag_global)
      for (int k = 0; k < 6; k++) sum.v[k] += w[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom(i, k) += w[k];
  }
};

template <class DeviceType, class Base>
class PairGriddemKokkos : public Base {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;

  PairGriddemKokkos(class LAMMPS *);
  ~PairGriddemKokkos() override;
  void init_style() override;
  void compute(int, int) override;
  double memory_usage() override;
  void count_occupancy(griddem_engine_stats &stats) override;
  // public only because CUDA's extended lambdas may not live in a protected member function
  void scan(const GriddemKKGrids &grids, bool atoms, bool class_boxes);
  template <typename Real> void bin_and_sweep(const GriddemKKGrids &grids, double slack);
  template <typename Real> void bin(const GriddemKKGrids &grids);
  template <typename Real, bool Classic>
  void sweep(const GriddemKKGrids &grids, double slack, double near_margin);
  template <typename Real> void search(const GriddemKKFind<DeviceType, Real> &find);

 protected:
  // sizes the Views below were allocated for
  int nmax_atoms, nmax_cells;
  int ncell_counted;    // cells of the last step's grids
  Kokkos::View<int *, DeviceType> d_cell;        // [nall] cell of each atom
  Kokkos::View<int *, DeviceType> d_count;       // [ncell+1] atoms per cell, then fill cursor;
                                                 // zero between steps
  Kokkos::View<int *, DeviceType> d_start;       // [ncell+1] first slot of each cell
  Kokkos::View<int *, DeviceType> d_order;       // [nall] atom index of each sorted slot
  Kokkos::View<int *, DeviceType> d_slot_cell;   // [nall] cell of each sorted slot
  // contact lists (GriddemKKSorted): candidates, [nall+1] first entry and [nall] count per slot;
  // [nmax] each atom's list length of the last step (by atom index: it guides the next layout
  // only, so atoms that moved in LAMMPS's arrays cost at most a repair)
  Kokkos::View<int *, DeviceType> d_list, d_list_first, d_list_count, d_last;
  Kokkos::View<GriddemKKNear *, Kokkos::LayoutRight, DeviceType> d_near;    // [nall]
  GriddemKKChannels<DeviceType, double> channels_double;
  GriddemKKChannels<DeviceType, float> channels_single;
  GriddemKKChannels<DeviceType, double> &channels(double) { return channels_double; }
  GriddemKKChannels<DeviceType, float> &channels(float) { return channels_single; }
  Kokkos::View<int *[2], Kokkos::LayoutRight, DeviceType> d_tm;
  Kokkos::View<GriddemKKStepReport, DeviceType> d_report;
  typename Kokkos::View<GriddemKKStepReport, DeviceType>::HostMirror h_report;
  // the boxes of the last step's scan and its fastest atom, to plan the next step's grids
  GriddemKKClassBoxes last_boxes;
  double last_speed;
  int boxes_known;    // 0 until a step has been computed
  // room the last step's lists and history rows needed
  long list_needed, rows_needed;
  // attempts at one step before giving up: each retry grows what it found short
  static constexpr int max_attempts = 8;
  Kokkos::View<griddem_pair_params *, DeviceType> d_params;
  Kokkos::View<unsigned char *, DeviceType> d_excl_type;
  Kokkos::View<int *, DeviceType> d_excl_group;
  // [nall] the history keys' image codes, where the box has image axes (upload_images)
  Kokkos::View<int *, DeviceType> d_image;
  typename Kokkos::View<int *, DeviceType>::HostMirror h_image;
  // candidates an atom may gain in a step without a repair of its list: in LAMMPS's chute
  // (32,000 atoms) more than one came to some atom in 967 of 1,000 steps, more than two in 13.
  // The history rows are laid out from the lists' true lengths, so the margin costs 4 bytes an
  // atom, not a history entry in each of fix griddem/kk's two pools.
  static constexpr int list_margin = 2;
  int params_stale;
  int all_classic;    // every type pair's law is classic: the sweep without the composed law
  int coarsened_warned_kk;
  FixGriddemKokkos<DeviceType> *history;    // fix griddem/kk, when the law keeps history

  DAT::tdual_virial_array k_vatom;

  std::string history_fix_style() const override;
  void upload_tables();
  void upload_images();
  void check_scan(const GriddemKKScanValue &sc);
  // fix griddem's cell mode takes a grid per size class (auto, classes), not one grid
  bool class_grids() const
  {
    return this->fix->cell_mode == GRIDDEM_CELL_AUTO || this->fix->cell_mode == GRIDDEM_CELL_CLASSES;
  }
  void plan_classes(GriddemKKGrids &grids);
  void fit_grids(GriddemKKGrids &grids, const GriddemKKClassBoxes &boxes, double margin);
  void close_step(const GriddemKKGrids &grids, const GriddemKKStepReport &report);
  void report_coincident(int i, int j);
};

}    // namespace LAMMPS_NS

#endif
