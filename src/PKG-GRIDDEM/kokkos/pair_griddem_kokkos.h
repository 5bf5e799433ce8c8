/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: what the griddem/.../kk pair styles share. One class template,
   PairGriddemKokkos<DeviceType, Base>, derives from the CPU style Base (PairGriddemHooke,
   PairGriddemGranular), which parses the arguments, mixes and checks the coefficients and fills
   `model`/`params`; this class only replaces compute() with device kernels:

   1. scan: bounding box of owned + ghost centres, non-finite positions and velocities, fastest
      owned atom, radius range (one parallel_reduce);
   2. binning: a counting sort of the centres into cells of edge 2*rmax*(1+1e-9) anchored at
      domain->boxlo (fix griddem's `cell multi` grid); within a cell the slots are ordered by tag
      (then position, for periodic images of one atom), so sums do not depend on storage order;
      the sorted positions, radii, velocities, masses, types and masks are the "channels";
   3. sweep: one thread per sorted owned particle visits the (2R+1)^3 cells around its own
      (R = 1 unless a pull-off distance reaches further) and evaluates every touching pair from
      its own side with griddem_contact_eval. The law is exactly odd under i <-> j, so each
      particle sums its own force and torque: no atomics, no colouring, no reverse communication.
      The global virial (half of del*f per owned side) and the first coincident-centres fault come
      back from the same parallel_reduce.

   Laws with contact history keep it in fix griddem/kk (one row per atom, rewritten in place by
   the atom's own thread: GriddemKKSweep). Views grow, never shrink, and are not reallocated in a
   step unless a size grew.
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
    const long c = (long) floor((x - anchor[d]) * hinv) - k0[d];
    return c < 0 ? 0 : (c >= n[d] ? n[d] - 1 : (int) c);
  }
  KOKKOS_INLINE_FUNCTION int cell_of(double x, double y, double z) const
  {
    return axis_cell(0, x) + n[0] * (axis_cell(1, y) + n[1] * axis_cell(2, z));
  }
  // lower face along d of cell c, and of the cell holding coordinate x
  KOKKOS_INLINE_FUNCTION double corner(int d, int c) const
  {
    return anchor[d] + (double) (k0[d] + c) * h;
  }
  KOKKOS_INLINE_FUNCTION double cell_origin(int d, double x) const
  {
    return corner(d, axis_cell(d, x));
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
  KOKKOS_INLINE_FUNCTION int class_of(double r) const
  {
    int c = 0;
    while (c < ncls - 1 && r <= upper[c + 1]) c++;
    return c;
  }
};

/* per size class: atoms, and the bounding box of their centres */
struct GriddemKKClassBoxes {
  int count[GRIDDEM_MAX_CLASSES];
  double lo[GRIDDEM_MAX_CLASSES][3], hi[GRIDDEM_MAX_CLASSES][3];
};

/* The boxes as an array reduction of 7 values a class present (count, lo[3], hi[3]): Kokkos keeps
   such a value in memory, where a struct for GRIDDEM_MAX_CLASSES classes filled the registers of
   a GPU thread and spilled (255 registers, 368 bytes of spill stores on sm_90). */
template <class DeviceType> struct GriddemKKClassScan {
  typedef DeviceType device_type;
  typedef double value_type[];
  typedef ArrayTypes<DeviceType> AT;
  static constexpr int per_class = 7;
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

/* The sorted particles' data the sweep reads, in the precision of fix griddem's `precision`:
   positions relative to their cell's lower corner (so single precision keeps ~1e-7 of a cell,
   not of the box), radius, velocity, angular velocity, mass. Rows (LayoutRight) on every device:
   the sweep gathers a candidate's four values together (one 32-byte sector on a GPU, where the
   default layout would spread them over four arrays). */
template <class DeviceType, typename Real> struct GriddemKKChannels {
  typedef Kokkos::View<Real *[4], Kokkos::LayoutRight, DeviceType> t_pos;      // x y z in the cell, radius
  typedef Kokkos::View<Real *[7], Kokkos::LayoutRight, DeviceType> t_state;    // v, omega, mass
  t_pos pos;
  t_state state;
};

/* what the sweep sums: global virial, statistics, and the coincident pair with the smallest
   owned index */
struct GriddemKKSweepValue {
  double v[6];
  double energy;           // elastic energy in the springs (a pair counts half on each side)
  long contacts;           // contacts of owned atoms (an owned pair counts twice)
  int most;                // most contacts of one owned atom
  int incomplete;          // owned atoms with new contacts their row had no room for
  long overflow;           // the contacts of those atoms
  int fault_i, fault_j;    // local indices; fault_i == INT_MAX: none
};

/* One thread per sorted owned particle sums the force and torque of its contacts (griddem_contact_eval)
   and, for laws with history, writes its atom's new row into fix griddem/kk's other pool (the
   contacts of this step, with their values found in the last step's row and advanced) at the
   place the fix laid out. A contact beyond that room is not stored and the atom's count of
   contacts is recorded (negated): the pass `repair` then evaluates only those atoms' contacts
   again, from the same last rows, into rows of that length appended to the pool (`top`), adding
   no force.
   Classic: every type pair uses the gran/hooke laws (griddem_classic.h), so the kernel is compiled
   without the composed sub-models; on a GPU that halves the registers a thread holds. */
template <class DeviceType, typename Real, bool Classic> struct GriddemKKSweep {
  typedef DeviceType device_type;
  typedef GriddemKKSweepValue value_type;
  typedef ArrayTypes<DeviceType> AT;

  GriddemKKGrids grids;
  double slack;          // added to every search distance: round-off of the positions
  double reach_extra;    // model.reach_extra
  int nlocal, ntypes, frozen_bit, vflag_global, vflag_atom;
  double dt;
  int history_update;    // 0 in setup: stored values are read, not advanced
  int track;             // model.track_contacts: rows are kept
  int nv;                // values per contact
  int repair;            // 1: rewrite the rows of incomplete atoms only, adding no force
  Kokkos::View<const int *, DeviceType> start, order, cell, cls;    // cell, class: of each atom
  Kokkos::View<const Real *[4], Kokkos::LayoutRight, DeviceType> pos;    // GriddemKKChannels, sorted
  Kokkos::View<const Real *[7], Kokkos::LayoutRight, DeviceType> state;
  Kokkos::View<const int *[2], Kokkos::LayoutRight, DeviceType> tm;    // type, mask, sorted
  typename AT::t_tagint_1d_randomread tag;        // by atom index
  Kokkos::View<const griddem_pair_params *, DeviceType> params;
  Kokkos::View<const unsigned char *, DeviceType> excl_type;        // empty: no type exclusions
  Kokkos::View<const int *, DeviceType> excl_group;                 // pairs of group bits
  int excl_both;    // pairs whose two masks both have this bit (fix griddem/rom's kinematic atoms)
  typename FixGriddemKokkos<DeviceType>::Rows rows;    // fix griddem/kk's rows
  Kokkos::View<long, DeviceType> top;                   // repair: the next free entry
  typename AT::t_f_array f, torque;
  typename AT::t_virial_array vatom;

  KOKKOS_INLINE_FUNCTION void init(value_type &s) const
  {
    for (int k = 0; k < 6; k++) s.v[k] = 0.0;
    s.energy = 0.0;
    s.contacts = 0;
    s.most = s.incomplete = 0;
    s.overflow = 0;
    s.fault_i = s.fault_j = INT_MAX;
  }
  KOKKOS_INLINE_FUNCTION void join(value_type &s, const value_type &o) const
  {
    for (int k = 0; k < 6; k++) s.v[k] += o.v[k];
    s.energy += o.energy;
    s.contacts += o.contacts;
    if (o.most > s.most) s.most = o.most;
    s.incomplete += o.incomplete;
    s.overflow += o.overflow;
    if (o.fault_i < s.fault_i) s.fault_i = o.fault_i, s.fault_j = o.fault_j;
  }

  KOKKOS_INLINE_FUNCTION int excluded(int ta, int ma, int tb, int mb) const
  {
    if (ma & mb & excl_both) return 1;
    if (excl_type.extent(0) && excl_type(ta * (ntypes + 1) + tb)) return 1;
    for (int k = 0; k + 1 < (int) excl_group.extent(0); k += 2) {
      const int b1 = excl_group(k), b2 = excl_group(k + 1);
      if (((ma & b1) && (mb & b2)) || ((ma & b2) && (mb & b1))) return 1;
    }
    return 0;
  }

  // the entry of partner p in atom i's last row, or -1
  KOKKOS_INLINE_FUNCTION int find(int i, tagint p) const
  {
    const int first = rows.first(i), last = first + rows.count(i);
    for (int e = first; e < last; e++)
      if (rows.partner(e) == p) return e;
    return -1;
  }

  // history values per contact the kernel holds: loops over nhist with constant bounds let a
  // GPU keep them in registers
  static constexpr int nhist = Classic ? 3 : GRIDDEM_MAX_HISTORY;

  // what one thread accumulates over its atom's contacts
  struct Atom {
    int s, i, itype, imask;
    double pi[3], radi, mi;
    int out, room, n, lost, ncontact;    // new row: first entry, room, entries, not stored; contacts
    double fsum[3], tsum[3], w[6], energy;
  };

  // the contact law for the gathered candidates t[0..nb) at separations del[k] (x, y, z, rsq)
  KOKKOS_INLINE_FUNCTION void evaluate(Atom &a, const int *t, const double (*del)[4], int nb) const
  {
    const int i = a.i;
    for (int k = 0; k < nb; k++) {
      const int tk = t[k];
      const double dx = del[k][0], dy = del[k][1], dz = del[k][2], rsq = del[k][3];
      const double radj = pos(tk, 3);
      const int jtype = tm(tk, 0), jmask = tm(tk, 1);
      if (excluded(a.itype, a.imask, jtype, jmask)) continue;
      const griddem_pair_params *law = &params(a.itype * (ntypes + 1) + jtype);
      const tagint partner = track ? tag(order(tk)) : 0;
      const int e = track ? find(i, partner) : -1;
      if (reach_extra > 0.0 && !griddem_contact_touch(law, rsq, a.radi, radj, e >= 0)) continue;

      griddem_contact c;
      c.dx[0] = dx, c.dx[1] = dy, c.dx[2] = dz;
      c.rsq = rsq;
      c.radi = a.radi, c.radj = radj;
      for (int d = 0; d < 3; d++) {
        c.vr[d] = state(a.s, d) - state(tk, d);
        c.wi[d] = state(a.s, 3 + d), c.wj[d] = state(tk, 3 + d);
      }
      c.meff = griddem_effective_mass(a.mi, state(tk, 6), (a.imask & frozen_bit) != 0,
                                      (jmask & frozen_bit) != 0);
      c.dt = dt;
      c.history_update = history_update;
      c.fr[0] = c.fr[1] = c.fr[2] = 0.0;
      double hist[nhist];
      for (int h = 0; h < nhist; h++) hist[h] = (e >= 0 && h < nv) ? rows.value((long) e * nv + h) : 0.0;
      double fc[3], ti[3], tj[3];
      const double u = Classic ? griddem_classic_eval(law, &c, hist, fc, ti, tj)
                               : griddem_contact_eval(law, &c, hist, fc, ti, tj);
      if (track) {
        if (a.n < a.room) {
          const int o = a.out + a.n++;
          rows.partner_out(o) = partner;
          for (int h = 0; h < nhist; h++)
            if (h < nv) rows.value_out((long) o * nv + h) = hist[h];
        } else {
          a.lost++;
        }
      }
      if (repair) continue;
      for (int d = 0; d < 3; d++) a.fsum[d] += fc[d], a.tsum[d] += ti[d];
      a.energy += 0.5 * u;
      a.ncontact++;
      if (vflag_global || vflag_atom) {
        a.w[0] += 0.5 * dx * fc[0], a.w[1] += 0.5 * dy * fc[1], a.w[2] += 0.5 * dz * fc[2];
        a.w[3] += 0.5 * dx * fc[1], a.w[4] += 0.5 * dx * fc[2], a.w[5] += 0.5 * dy * fc[2];
      }
    }
  }

  // Candidates within reach are gathered first and the law is evaluated for them in batches:
  // on a GPU the threads of a warp then run the law together over their few contacts instead of
  // each branching into it at a different one of the ~30 candidates of a stencil. On a CPU a
  // thread has no such partners and the buffer only costs (13% of the chute's loop time on 2
  // OpenMP threads): there a batch is one candidate. The order of evaluation (cells z, y, x;
  // slots ascending) is that of a single pass either way.
  static constexpr int batch =
      std::is_same<typename DeviceType::memory_space, Kokkos::HostSpace>::value ? 1 : 8;

  KOKKOS_INLINE_FUNCTION void operator()(const int s, value_type &sum) const
  {
    Atom a;
    a.s = s;
    a.i = order(s);
    const int i = a.i;
    if (i >= nlocal) return;
    for (int d = 0; d < 3; d++) a.pi[d] = pos(s, d);
    a.radi = pos(s, 3);
    a.itype = tm(s, 0), a.imask = tm(s, 1);
    a.mi = state(s, 6);
    // own cell, its lower corner, and the absolute centre
    const GriddemKKGrid &gi = grids.g[cls(i)];
    const int ci = cell(i) - grids.offset[cls(i)];
    const int ic[3] = {ci % gi.n[0], (ci / gi.n[0]) % gi.n[1], ci / (gi.n[0] * gi.n[1])};
    double corner[3], xi[3];
    for (int d = 0; d < 3; d++) corner[d] = gi.corner(d, ic[d]), xi[d] = corner[d] + a.pi[d];
    for (int d = 0; d < 3; d++) a.fsum[d] = a.tsum[d] = 0.0;
    for (int k = 0; k < 6; k++) a.w[k] = 0.0;
    a.energy = 0.0;
    if (repair) {
      a.room = -rows.count_out(i);
      if (a.room <= 0) return;    // its row was complete
      a.out = (int) Kokkos::atomic_fetch_add(&top(), (long) a.room);
      rows.first_out(i) = a.out;
    } else {
      a.out = track ? rows.first_out(i) : 0;
      a.room = track ? rows.count(i) + FixGriddemKokkos<DeviceType>::margin : 0;
    }
    a.n = a.lost = a.ncontact = 0;
    int t[batch], nb = 0;
    double del[batch][4];

    // every class's cells within reach of a partner as large as the class allows
    for (int cj = 0; cj < grids.ncls; cj++) {
      const GriddemKKGrid &g = grids.g[cj];
      const double d = a.radi + grids.upper[cj] + reach_extra + slack;
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
          const int row = grids.offset[cj] + g.n[0] * (y + g.n[1] * z);
          int u = start(row + lo[0]);
          for (int x = lo[0]; x <= hi[0]; x++) {
            const double sx = corner[0] - g.corner(0, x);
            for (const int end = start(row + x + 1); u < end; u++) {
              if (u == s) continue;
              const Real *pu = &pos(u, 0);    // x, y, z, radius: one row (LayoutRight)
              const double dx = (a.pi[0] - (double) pu[0]) + sx;
              const double dy = (a.pi[1] - (double) pu[1]) + sy;
              const double dz = (a.pi[2] - (double) pu[2]) + sz;
              const double rsq = dx * dx + dy * dy + dz * dz;
              const double rs = a.radi + reach_extra + (double) pu[3];
              if (!(rsq < rs * rs)) continue;
              if (rsq == 0.0) {
                if (i < sum.fault_i) sum.fault_i = i, sum.fault_j = order(u);
                continue;
              }
              t[nb] = u;
              del[nb][0] = dx, del[nb][1] = dy, del[nb][2] = dz, del[nb][3] = rsq;
              if (++nb == batch) evaluate(a, t, del, nb), nb = 0;
            }
          }
        }
      }
    }
    evaluate(a, t, del, nb);

    if (track) {
      rows.count_out(i) = a.lost ? -(a.n + a.lost) : a.n;
      if (a.lost) sum.incomplete++, sum.overflow += a.n + a.lost;
    }
    if (repair) return;
    sum.contacts += a.ncontact;
    if (a.ncontact > sum.most) sum.most = a.ncontact;
    for (int d = 0; d < 3; d++) f(i, d) += a.fsum[d], torque(i, d) += a.tsum[d];
    sum.energy += a.energy;
    if (vflag_global)
      for (int k = 0; k < 6; k++) sum.v[k] += a.w[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom(i, k) += a.w[k];
  }
};

template <class DeviceType, class Base> class PairGriddemKokkos : public Base {
 public:
  typedef DeviceType device_type;
  typedef ArrayTypes<DeviceType> AT;

  PairGriddemKokkos(class LAMMPS *);
  ~PairGriddemKokkos() override;
  void init_style() override;
  void compute(int, int) override;
  double memory_usage() override;
  // public only because CUDA's extended lambdas may not live in a protected member function
  template <typename Real>
  void bin_and_sweep(const GriddemKKGrids &grids, double slack, const GriddemKKScanValue &sc);
  template <typename Real> void bin(const GriddemKKGrids &grids);
  template <typename Real, bool Classic>
  void sweep(const GriddemKKGrids &grids, double slack, const GriddemKKScanValue &sc);

 protected:
  // sizes the Views below were allocated for
  int nmax_atoms, nmax_cells;
  Kokkos::View<int *, DeviceType> d_cell;        // [nall] cell of each atom
  Kokkos::View<int *, DeviceType> d_cls;         // [nall] size class of each atom
  Kokkos::View<int *, DeviceType> d_count;       // [ncell+1] atoms per cell, then fill cursor
  Kokkos::View<int *, DeviceType> d_start;       // [ncell+1] first slot of each cell
  Kokkos::View<int *, DeviceType> d_unsorted;    // [nall] slots filled in arrival order
  Kokkos::View<int *, DeviceType> d_order;       // [nall] atom index of each sorted slot
  GriddemKKChannels<DeviceType, double> channels_double;
  GriddemKKChannels<DeviceType, float> channels_single;
  GriddemKKChannels<DeviceType, double> &channels(double) { return channels_double; }
  GriddemKKChannels<DeviceType, float> &channels(float) { return channels_single; }
  Kokkos::View<int *[2], Kokkos::LayoutRight, DeviceType> d_tm;
  Kokkos::View<long, DeviceType> d_top;    // the repair pass's next free history entry
  Kokkos::View<griddem_pair_params *, DeviceType> d_params;
  Kokkos::View<unsigned char *, DeviceType> d_excl_type;
  Kokkos::View<int *, DeviceType> d_excl_group;
  int params_stale;
  int all_classic;    // every type pair's law is classic: the sweep without the composed law
  int coarsened_warned_kk;
  FixGriddemKokkos<DeviceType> *history;    // fix griddem/kk, when the law keeps history

  DAT::tdual_virial_array k_vatom;

  std::string history_fix_style() const override;
  void upload_tables();
  void report_coincident(int i, int j);
};

}    // namespace LAMMPS_NS

#endif
