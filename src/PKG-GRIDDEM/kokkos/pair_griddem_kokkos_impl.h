/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: the member functions of PairGriddemKokkos (pair_griddem_kokkos.h),
   included by the .cpp file of each style, which instantiates the template for its base class.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_GRIDDEM_KOKKOS_IMPL_H
#define LMP_PAIR_GRIDDEM_KOKKOS_IMPL_H

#include "pair_griddem_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "domain.h"
#include "error.h"
#include "fix_griddem.h"
#include "force.h"
#include "griddem_grid.h"
#include "memory_kokkos.h"
#include "neighbor_kokkos.h"
#include "update.h"

#include <cmath>
#include <string>
#include <type_traits>

namespace LAMMPS_NS {

template <class DeviceType, class Base>
PairGriddemKokkos<DeviceType, Base>::PairGriddemKokkos(LAMMPS *lmp) :
    Base(lmp), nmax_atoms(0), nmax_cells(0), ncell_counted(0), params_stale(1),
    coarsened_warned_kk(0), history(nullptr)
{
  this->kokkosable = 1;
  this->atomKK = (AtomKokkos *) this->atom;
  this->execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  this->datamask_read = X_MASK | V_MASK | OMEGA_MASK | F_MASK | TORQUE_MASK | TYPE_MASK |
      MASK_MASK | TAG_MASK | RMASS_MASK | RADIUS_MASK;
  this->datamask_modify = F_MASK | TORQUE_MASK;
}

template <class DeviceType, class Base> PairGriddemKokkos<DeviceType, Base>::~PairGriddemKokkos()
{
  if (this->copymode) return;
  this->memoryKK->destroy_kokkos(k_vatom, this->vatom);
  this->vatom = nullptr;
}

template <class DeviceType, class Base>
std::string PairGriddemKokkos<DeviceType, Base>::history_fix_style() const
{
  return std::is_same<DeviceType, LMPDeviceType>::value ? "griddem/kk" : "griddem/kk/host";
}

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::init_style()
{
  Base::init_style();
  history = dynamic_cast<FixGriddemKokkos<DeviceType> *>(this->fix);
  if (this->model.track_contacts && !history)
    this->error->all(FLERR, "Pair style {} needs fix {} for its contact history, not fix {} {}",
                     this->force->pair_style, history_fix_style(), this->fix->id, this->fix->style);
  params_stale = 1;    // init_one() fills params after init_style()

  // NeighborKokkos checks displacements and keeps the reneighbouring reference positions on the
  // device only if some neighbor list lives there; this style requests none, so without this
  // every step would copy the positions to the host and check them there (measured on an H100:
  // 90% of a 2M-atom chute step)
  if (std::is_same<DeviceType, LMPDeviceType>::value)
    ((NeighborKokkos *) this->neighbor)->device_flag = 1;
}

/* the grid's arrays on the device (LAMMPS's memory summary); the history is fix griddem/kk's */

template <class DeviceType, class Base> double PairGriddemKokkos<DeviceType, Base>::memory_usage()
{
  double bytes = Base::memory_usage();
  auto add = [&bytes](const auto &view) {
    bytes += (double) view.span() * sizeof(typename std::decay_t<decltype(view)>::value_type);
  };
  add(d_cell), add(d_count), add(d_start), add(d_unsorted), add(d_order), add(d_tm);
  add(d_slot_cell), add(d_list), add(d_list_first), add(d_list_count), add(d_last);
  add(d_near), add(channels_double.state), add(channels_single.state);
  add(d_params), add(d_excl_type), add(d_excl_group);
  return bytes;
}

/* the law table and the exclusions, copied to the device after each init */

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::upload_tables()
{
  const int n = this->atom->ntypes + 1;
  d_params = Kokkos::View<griddem_pair_params *, DeviceType>("griddem/kk:params", n * n);
  auto h_params = Kokkos::create_mirror_view(d_params);
  all_classic = 1;
  for (int k = 0; k < n * n; k++) {
    h_params(k) = this->params[k];
    // type 0 and unset pairs have no law; only pairs of real types choose the sweep
    if (k / n && k % n && !this->params[k].classic) all_classic = 0;
  }
  Kokkos::deep_copy(d_params, h_params);

  const int ntype_pairs = this->excluded_types.empty() ? 0 : n * n;
  d_excl_type = Kokkos::View<unsigned char *, DeviceType>("griddem/kk:excl_type", ntype_pairs);
  auto h_excl_type = Kokkos::create_mirror_view(d_excl_type);
  for (int k = 0; k < ntype_pairs; k++) h_excl_type(k) = this->excluded_types[k];
  Kokkos::deep_copy(d_excl_type, h_excl_type);

  const int ngroup = (int) this->excluded_groups.size();
  d_excl_group = Kokkos::View<int *, DeviceType>("griddem/kk:excl_group", ngroup);
  auto h_excl_group = Kokkos::create_mirror_view(d_excl_group);
  for (int k = 0; k < ngroup; k++) h_excl_group(k) = this->excluded_groups[k];
  Kokkos::deep_copy(d_excl_group, h_excl_group);
  params_stale = 0;
}

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::report_coincident(int i, int j)
{
  this->atomKK->sync(Host, X_MASK | TAG_MASK);
  this->error_coincident(i, j);
}

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::compute(int eflag, int vflag)
{
  Error *error = this->error;
  const char *style = this->force->pair_style;

  this->ev_init(eflag, vflag, 0);
  if (this->vflag_atom) {    // grown when atom->nmax grew, else cleared
    if ((int) k_vatom.extent(0) < this->maxvatom) {
      this->memoryKK->destroy_kokkos(k_vatom, this->vatom);
      this->memoryKK->create_kokkos(k_vatom, this->vatom, this->maxvatom, "pair:vatom");
    } else {
      Kokkos::deep_copy(k_vatom.template view<DeviceType>(), 0.0);
    }
  }
  if (params_stale) upload_tables();

  AtomKokkos *atomKK = this->atomKK;
  atomKK->sync(this->execution_space, this->datamask_read);
  atomKK->modified(this->execution_space, this->datamask_modify);

  auto x = atomKK->k_x.template view<DeviceType>();
  auto v = atomKK->k_v.template view<DeviceType>();
  auto radius = atomKK->k_radius.template view<DeviceType>();
  const int nlocal = this->atom->nlocal;
  const int nall = nlocal + this->atom->nghost;

  // 1. scan
  GriddemKKScan<DeviceType> scan;
  scan.x = x;
  scan.v = v;
  scan.radius = radius;
  scan.nlocal = nlocal;
  GriddemKKScanValue sc;
  Kokkos::parallel_reduce("griddem/kk:scan", Kokkos::RangePolicy<DeviceType>(0, nall), scan, sc);
  if (sc.badx != INT_MAX) {
    atomKK->sync(Host, X_MASK | TAG_MASK);
    this->error_nonfinite("position", sc.badx, this->atom->x[sc.badx]);
  }
  if (sc.badv != INT_MAX) {
    atomKK->sync(Host, V_MASK | TAG_MASK);
    this->error_nonfinite("velocity", sc.badv, this->atom->v[sc.badv]);
  }
  if (this->neighbor->ago == 0)    // radius range, refreshed as the CPU style does
    this->set_radius_range(nlocal ? sc.rmin : INFINITY, sc.rmax);
  const double rmax = this->rmax;
  if (rmax == 0.0) return;    // no atoms yet

  // NN4DEM rule, as the CPU style: no atom crosses more than one exact-mode cell per step
  const double h_nn4dem = griddem_cell_edge(GRIDDEM_CELL_EXACT, this->rmin, rmax, 0.0);
  if (sc.ivmax >= 0 && sqrt(sc.vmax2) * this->update->dt > h_nn4dem) {
    atomKK->sync(Host, TAG_MASK);
    this->error_too_fast(sc.ivmax, sqrt(sc.vmax2), h_nn4dem);
  }

  // 2. grids: one per size class (fix griddem's auto and classes), else one grid of the mode's
  // edge (multi, exact, a number: as the CPU style), anchored at boxlo, a grid given larger cells
  // where it would need too many
  GriddemKKGrids grids;
  const int mode = this->fix->cell_mode;
  const int classes = mode == GRIDDEM_CELL_AUTO || mode == GRIDDEM_CELL_CLASSES;
  grids.ncls = classes ? griddem_class_count(this->rmin, rmax) : 1;
  griddem_class_bounds(rmax, grids.ncls, grids.upper);
  GriddemKKClassBoxes boxes;
  if (grids.ncls == 1) {
    boxes.count[0] = nall;
    for (int d = 0; d < 3; d++) boxes.lo[0][d] = sc.lo[d], boxes.hi[0][d] = sc.hi[d];
  } else {
    GriddemKKClassScan<DeviceType> class_scan;
    class_scan.value_count = GriddemKKClassScan<DeviceType>::per_class * grids.ncls;
    class_scan.x = x;
    class_scan.radius = radius;
    class_scan.grids = grids;
    double found[GriddemKKClassScan<DeviceType>::per_class * GRIDDEM_MAX_CLASSES];
    Kokkos::parallel_reduce("griddem/kk:class_scan", Kokkos::RangePolicy<DeviceType>(0, nall),
                            class_scan, found);
    for (int c = 0; c < grids.ncls; c++) {
      const double *box = found + GriddemKKClassScan<DeviceType>::per_class * c;
      boxes.count[c] = (int) box[0];
      for (int d = 0; d < 3; d++) boxes.lo[c][d] = box[1 + d], boxes.hi[c][d] = box[4 + d];
    }
  }
  double extent = 0.0;
  long total = 0;
  for (int c = 0; c < grids.ncls; c++) {
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
      lo[d] = boxes.count[c] ? boxes.lo[c][d] : this->domain->boxlo[d];
      hi[d] = boxes.count[c] ? boxes.hi[c][d] : this->domain->boxlo[d];
      extent = MAX(extent,
                   MAX(fabs(lo[d] - this->domain->boxlo[d]), fabs(hi[d] - this->domain->boxlo[d])));
    }
    const long max_cells = grids.ncls == 1 ? GRIDDEM_ONE_GRID_MAX_CELLS(nall)
                                           : GRIDDEM_CLASS_MAX_CELLS(boxes.count[c]);
    griddem_grid fitted;
    const double edge = classes ? griddem_cell_edge(GRIDDEM_CELL_MULTI, 0.0, grids.upper[c], 0.0)
                                : griddem_cell_edge(mode, this->rmin, rmax, this->fix->cell_edge);
    const int coarsened = griddem_grid_fit(&fitted, this->domain->boxlo, lo, hi, edge, max_cells);
    if (coarsened && !coarsened_warned_kk) {
      coarsened_warned_kk = 1;
      // worded as the CPU style's, naming the class when there are several
      error->warning(FLERR,
                     "Pair style {}: cell edge {}enlarged from {} to {} so that the grid over "
                     "this process's atoms stays within {} cells",
                     style, grids.ncls > 1 ? fmt::format("of size class {} ", c) : "", edge,
                     fitted.h, max_cells);
    }
    GriddemKKGrid &g = grids.g[c];
    for (int d = 0; d < 3; d++)
      g.anchor[d] = fitted.anchor[d], g.k0[d] = fitted.k0[d], g.n[d] = fitted.n[d];
    g.h = fitted.h;
    g.hinv = fitted.hinv;
    grids.offset[c] = (int) total;
    total += fitted.ncell;
    if (total >= INT_MAX)
      error->one(FLERR, "Pair style {}: the grids would need {} cells, more than an int counts",
                 style, total);
  }
  grids.offset[grids.ncls] = (int) total;
  // the search distance's margin for round-off of positions relative to their cells
  const double slack = 1e-10 * (2.0 * rmax + this->model.reach_extra) + 1e-14 * extent;
  // one grid of a given edge: refused where the CPU style's stencil would be (the largest pair's
  // search distance over more than GRIDDEM_MAX_REACH edges), rather than searched over
  // (2 x reach + 1)^3 cells per atom
  if (!classes &&
      griddem_stencil_reach(grids.g[0].h, 2.0 * rmax + this->model.reach_extra + slack) >
          GRIDDEM_MAX_REACH)
    this->error_stencil_reach(grids.g[0].h);

  if (this->fix->precision == GRIDDEM_PRECISION_SINGLE)
    bin_and_sweep<float>(grids, slack, sc);
  else
    bin_and_sweep<double>(grids, slack, sc);
}

template <class DeviceType, class Base>
template <typename Real>
void PairGriddemKokkos<DeviceType, Base>::bin_and_sweep(const GriddemKKGrids &grids, double slack,
                                                        const GriddemKKScanValue &sc)
{
  bin<Real>(grids);
  // the float positions' rounding: 2^-24 of a position in its cell (under an edge) and of a
  // radius, for each side of a pair, well inside this margin; none where they are the law's
  double near_margin = 0.0;
  if (GriddemKKSorted<DeviceType, Real>::atom_positions) {
    double hmax = 0.0;
    for (int c = 0; c < grids.ncls; c++) hmax = MAX(hmax, grids.g[c].h);
    near_margin = 1e-6 * (hmax + 2.0 * this->rmax + this->model.reach_extra) + slack;
  }
  if (all_classic)
    sweep<Real, true>(grids, slack, near_margin, sc);
  else
    sweep<Real, false>(grids, slack, near_margin, sc);
}

/* counting sort into the channels (positions relative to their cell and radius in float; of
   Real: velocities, angular velocities, mass) */

template <class DeviceType, class Base>
template <typename Real>
void PairGriddemKokkos<DeviceType, Base>::bin(const GriddemKKGrids &grids)
{
  AtomKokkos *atomKK = this->atomKK;
  auto x = atomKK->k_x.template view<DeviceType>();
  auto v = atomKK->k_v.template view<DeviceType>();
  auto omega = atomKK->k_omega.template view<DeviceType>();
  auto radius = atomKK->k_radius.template view<DeviceType>();
  auto rmass = atomKK->k_rmass.template view<DeviceType>();
  auto type = atomKK->k_type.template view<DeviceType>();
  auto mask = atomKK->k_mask.template view<DeviceType>();
  auto tag = atomKK->k_tag.template view<DeviceType>();
  const int nlocal = this->atom->nlocal;
  const int nall = nlocal + this->atom->nghost;
  auto &chan = channels(Real());

  // Views grow only; made once even for a process without atoms (the list layout writes
  // the end of its last list, entry nall)
  if (nall > nmax_atoms || !nmax_atoms) {
    nmax_atoms = MAX(MAX(nall, 1), (int) (1.2 * nmax_atoms));
    d_cell = Kokkos::View<int *, DeviceType>("griddem/kk:cell", nmax_atoms);
    d_unsorted = Kokkos::View<int *, DeviceType>("griddem/kk:unsorted", nmax_atoms);
    d_order = Kokkos::View<int *, DeviceType>("griddem/kk:order", nmax_atoms);
    d_slot_cell = Kokkos::View<int *, DeviceType>("griddem/kk:slot_cell", nmax_atoms);
    d_list_first = Kokkos::View<int *, DeviceType>("griddem/kk:list_first", nmax_atoms + 1);
    d_list_count = Kokkos::View<int *, DeviceType>("griddem/kk:list_count", nmax_atoms);
    Kokkos::resize(d_last, nmax_atoms);    // kept: the next layout's guide
    d_tm = Kokkos::View<int *[2], Kokkos::LayoutRight, DeviceType>("griddem/kk:tm", nmax_atoms);
  }
  if (nall > (int) d_near.extent(0))
    d_near = Kokkos::View<GriddemKKNear *, Kokkos::LayoutRight, DeviceType>("griddem/kk:near", nmax_atoms);
  if (nall > (int) chan.state.extent(0)) {
    chan.state =
        typename GriddemKKChannels<DeviceType, Real>::t_state("griddem/kk:state", nmax_atoms);
  }
  const int ncell = grids.offset[grids.ncls];
  if (ncell + 1 > nmax_cells) {
    nmax_cells = MAX(ncell + 1, (int) MIN(1.2 * nmax_cells, (double) INT_MAX));
    d_count = Kokkos::View<int *, DeviceType>("griddem/kk:count", nmax_cells);
    d_start = Kokkos::View<int *, DeviceType>("griddem/kk:start", nmax_cells);
  }

  // 3. counting sort by cell
  auto cell = d_cell;
  auto count = d_count;
  auto start = d_start;
  auto unsorted = d_unsorted;
  auto order = d_order;
  auto slot_cell = d_slot_cell;
  auto near = d_near;
  auto state = chan.state;
  auto tm = d_tm;
  // count is zero here: zero-filled when made, and each binning zeroes what it counted
  Kokkos::parallel_for(
      "griddem/kk:bin", Kokkos::RangePolicy<DeviceType>(0, nall), KOKKOS_LAMBDA(const int i) {
        const int k = grids.class_of(radius(i));
        const int c = grids.offset[k] + grids.g[k].cell_of(x(i, 0), x(i, 1), x(i, 2));
        cell(i) = c;
        Kokkos::atomic_inc(&count(c));
      });
  Kokkos::parallel_scan(
      "griddem/kk:scan_cells", Kokkos::RangePolicy<DeviceType>(0, ncell + 1),
      KOKKOS_LAMBDA(const int c, int &partial, const bool final) {
        const int k = count(c);
        if (final) {
          start(c) = partial;
          count(c) = 0;    // from here on: the cell's fill cursor
        }
        partial += k;
      });
  Kokkos::parallel_for(
      "griddem/kk:fill", Kokkos::RangePolicy<DeviceType>(0, nall), KOKKOS_LAMBDA(const int i) {
        const int c = cell(i);
        unsorted(start(c) + Kokkos::atomic_fetch_add(&count(c), 1)) = i;
      });
  // within a cell, slot = rank by (tag, x, y, z): the same order whatever order atoms are stored in
  Kokkos::parallel_for(
      "griddem/kk:place", Kokkos::RangePolicy<DeviceType>(0, nall), KOKKOS_LAMBDA(const int s) {
        const int i = unsorted(s);
        const int c = cell(i);
        const tagint ti = tag(i);
        const double xi = x(i, 0), yi = x(i, 1), zi = x(i, 2);
        int rank = 0;
        for (int u = start(c); u < start(c + 1); u++) {
          const int j = unsorted(u);
          const tagint tj = tag(j);
          const double xj = x(j, 0), yj = x(j, 1), zj = x(j, 2);
          rank += tj < ti ||
              (tj == ti && (xj < xi || (xj == xi && (yj < yi || (yj == yi && zj < zi)))));
        }
        const int slot = start(c) + rank;
        count(c) = 0;    // the fill cursor's work is done: zero again for the next binning
        order(slot) = i;
        slot_cell(slot) = c;
        const double p[3] = {xi, yi, zi};
        double corner[3];
        grids.cell_corner(c, corner);
        for (int d = 0; d < 3; d++) near(slot, d) = (float) (p[d] - corner[d]);
        near(slot, 3) = (float) radius(i);
        for (int d = 0; d < 3; d++) state(slot, d) = v(i, d), state(slot, 3 + d) = omega(i, d);
        state(slot, 6) = rmass(i);
        tm(slot, 0) = type(i), tm(slot, 1) = mask(i);
      });
}

/* the contact lists, the law over them, and fix griddem's statistics */

template <class DeviceType, class Base>
template <typename Real, bool Classic>
void PairGriddemKokkos<DeviceType, Base>::sweep(const GriddemKKGrids &grids, double slack,
                                                double near_margin, const GriddemKKScanValue &sc)
{
  AtomKokkos *atomKK = this->atomKK;
  const int nlocal = this->atom->nlocal;
  const int nall = nlocal + this->atom->nghost;
  auto &chan = channels(Real());
  const int track = this->model.track_contacts;

  // 4. lists laid out slot by slot: each owned atom's last list length (or its history row's,
  // which moved with it) plus the margin
  typename FixGriddemKokkos<DeviceType>::Rows rows;    // fix griddem/kk's, with history
  if (track) rows = history->rows_on_device();
  auto first = d_list_first;
  auto order = d_order;
  auto last = d_last;
  auto row_count = rows.count;
  long laid_out = 0;
  Kokkos::parallel_scan(
      "griddem/kk:list_layout", Kokkos::RangePolicy<DeviceType>(0, nall + 1),
      KOKKOS_LAMBDA(const int s, long &offset, const bool final) {
        if (final) first(s) = (int) offset;
        if (s == nall) return;
        const int i = order(s);
        if (i < nlocal)
          offset += list_margin + (track ? Kokkos::max(last(i), row_count(i)) : last(i));
      },
      laid_out);
  auto reserve_list = [&](long entries, bool keep) {
    if (entries > INT_MAX)
      this->error->one(FLERR, "Pair style {}: {} contact candidates on one process, more than an "
                       "int counts", this->force->pair_style, entries);
    if (entries <= (long) d_list.extent(0)) return;
    const long room = MAX(entries, (long) (1.25 * d_list.extent(0)));
    if (keep)
      Kokkos::resize(d_list, room);
    else
      d_list = Kokkos::View<int *, DeviceType>("griddem/kk:list", room);
  };
  reserve_list(laid_out, false);

  // 5. the search, and again for the atoms whose room was short
  GriddemKKFind<DeviceType, Real> find;
  GriddemKKSorted<DeviceType, Real> &sorted = find;
  sorted.grids = grids;
  sorted.nlocal = nlocal;
  sorted.ntypes = this->atom->ntypes;
  sorted.reach_extra = this->model.reach_extra;
  sorted.order = d_order;
  sorted.slot_cell = d_slot_cell;
  sorted.near = d_near;
  sorted.x = atomKK->k_x.template view<DeviceType>();
  sorted.radius = atomKK->k_radius.template view<DeviceType>();
  sorted.tm = d_tm;
  sorted.list = d_list;
  sorted.first = d_list_first;
  sorted.count = d_list_count;
  find.slack = slack;
  find.near_margin = near_margin;
  find.repair = 0;
  find.start = d_start;
  find.excl = this->exclusions;
  find.excl.type_pair = d_excl_type.extent(0) ? d_excl_type.data() : nullptr;
  find.excl.group_bits = d_excl_group.data();
  GriddemKKFindValue found;
  Kokkos::parallel_reduce("griddem/kk:find", Kokkos::RangePolicy<DeviceType>(0, nall), find,
                          found);
  if (found.fault_i != INT_MAX) report_coincident(found.fault_i, found.fault_j);
  if (found.incomplete) {
    reserve_list(laid_out + found.needed, true);
    if (!d_top.data()) d_top = Kokkos::View<long, DeviceType>("griddem/kk:top");
    Kokkos::deep_copy(d_top, laid_out);
    sorted.list = d_list;
    find.top = d_top;
    find.repair = 1;
    GriddemKKFindValue repaired;
    Kokkos::parallel_reduce("griddem/kk:find_repair", Kokkos::RangePolicy<DeviceType>(0, nall),
                            find, repaired);
    if (repaired.incomplete)
      this->error->one(FLERR, "Pair style {}: contact lists laid out too short",
                       this->force->pair_style);
  }

  // the new history rows: room for each owned atom's list, slot by slot
  if (track) {
    history->reserve_out(found.listed);
    rows = history->rows_on_device();
    auto count = d_list_count;
    Kokkos::parallel_scan(
        "griddem/kk:row_layout", Kokkos::RangePolicy<DeviceType>(0, nall),
        KOKKOS_LAMBDA(const int s, long &offset, const bool final) {
          const int i = order(s);
          if (i >= nlocal) return;
          if (final) rows.first_out(i) = (int) offset;
          offset += count(s);
        });
  }

  // 6. the law over the lists
  GriddemKKSweep<DeviceType, Real, Classic> sweep;
  static_cast<GriddemKKSorted<DeviceType, Real> &>(sweep) = sorted;
  sweep.frozen_bit = this->freeze_group_bit;
  sweep.vflag_global = this->vflag_global;
  sweep.vflag_atom = this->vflag_atom;
  sweep.dt = this->update->dt;
  sweep.history_update = this->update->setupflag ? 0 : 1;
  sweep.track = track;
  sweep.nv = track ? history->values_per_contact() : 0;
  sweep.state = chan.state;
  sweep.tag = atomKK->k_tag.template view<DeviceType>();
  sweep.params = d_params;
  sweep.last = d_last;
  sweep.f = atomKK->k_f.template view<DeviceType>();
  sweep.torque = atomKK->k_torque.template view<DeviceType>();
  if (this->vflag_atom) sweep.vatom = k_vatom.template view<DeviceType>();
  sweep.rows = rows;
  GriddemKKSweepValue sums;
  Kokkos::parallel_reduce("griddem/kk:sweep", Kokkos::RangePolicy<DeviceType>(0, nall), sweep,
                          sums);
  if (track) history->commit(sums.most);

  if (this->vflag_global)
    for (int k = 0; k < 6; k++) this->virial[k] += sums.v[k];
  if (this->vflag_atom) {
    k_vatom.template modify<DeviceType>();
    k_vatom.template sync<LMPHostType>();
  }

  // fix griddem's diagnostics, as the CPU engine reports them; the occupancy only when asked
  griddem_engine_stats stats;
  stats.occupied_cells = -1;
  stats.max_occupancy = -1;
  stats.cell_edge = grids.g[0].h;
  stats.contacts = sums.contacts;
  stats.max_contacts = sums.most;
  stats.elastic_energy = sums.energy;
  stats.max_speed = sc.ivmax >= 0 ? sqrt(sc.vmax2) : 0.0;
  stats.max_cells_moved = stats.max_speed * this->update->dt / grids.g[grids.ncls - 1].h;
  stats.nonfinite_velocity = 0;
  this->fix->set_stats(stats);
  ncell_counted = grids.offset[grids.ncls];
}

/* the occupied cells and the most centres in one, of the last step's grids */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::count_occupancy(griddem_engine_stats &stats)
{
  auto start = d_start;
  int occupied = 0, occupancy = 0;
  Kokkos::parallel_reduce(
      "griddem/kk:occupancy", Kokkos::RangePolicy<DeviceType>(0, ncell_counted),
      KOKKOS_LAMBDA(const int c, int &cells, int &most) {
        const int k = start(c + 1) - start(c);
        cells += k > 0;
        if (k > most) most = k;
      },
      occupied, Kokkos::Max<int>(occupancy));
  stats.occupied_cells = occupied;
  stats.max_occupancy = occupancy;
}

}    // namespace LAMMPS_NS

#endif
