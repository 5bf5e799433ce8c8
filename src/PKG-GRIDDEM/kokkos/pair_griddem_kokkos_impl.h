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
#include "fix_griddem_face.h"
#include "force.h"
#include "griddem_grid.h"
#include "griddem_kk_launch.h"
#include "memory_kokkos.h"
#include "neighbor_kokkos.h"
#include "update.h"

#include <cmath>
#include <string>
#include <type_traits>

namespace LAMMPS_NS {

template <class DeviceType, class Base>
PairGriddemKokkos<DeviceType, Base>::PairGriddemKokkos(LAMMPS *lmp) :
    Base(lmp), nmax_atoms(0), nmax_cells(0), ncell_counted(0), last_speed(0.0), boxes_known(0),
    list_needed(0), rows_needed(0), params_stale(1), coarsened_warned_kk(0), history(nullptr),
    engine(false)
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

/* On a host back end the default store is fix griddem's, swept by the CPU engine; fix griddem/kk
   (the script's fix griddem under -sf kk) keeps the kernels */

template <class DeviceType, class Base>
std::string PairGriddemKokkos<DeviceType, Base>::history_fix_style() const
{
  return on_host ? "griddem" : "griddem/kk";
}

template <class DeviceType, class Base>
bool PairGriddemKokkos<DeviceType, Base>::sweeps(const FixGriddem &fix) const
{
  return fix.kokkosable || on_host;
}

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::init_style()
{
  Base::init_style();
  engine = on_host && !this->fix()->kokkosable;
  this->execution_space = engine ? Host : ExecutionSpaceFromDevice<DeviceType>::space;
  history = dynamic_cast<FixGriddemKokkos<DeviceType> *>(this->fix());
  if (this->model.track_contacts && !engine && !history)
    this->error->all(FLERR, "Pair style {} needs fix griddem/kk{} for its contact history, not fix {} {}",
                     this->force->pair_style, std::is_same<DeviceType, LMPDeviceType>::value ? "" : "/host",
                     this->fix()->id, this->fix()->style);
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
  add(d_cell), add(d_count), add(d_start), add(d_order), add(d_tm);
  add(d_slot_cell), add(d_list), add(d_list_first), add(d_list_count), add(d_last);
  add(d_near), add(channels_double.state), add(channels_single.state);
  add(d_params), add(d_excl_type), add(d_excl_group), add(d_image);
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

  const int nmolecule = this->exclusions.nmolecule;
  d_excl_molecule = Kokkos::View<int *, DeviceType>("griddem/kk:excl_molecule", 2 * nmolecule);
  auto h_excl_molecule = Kokkos::create_mirror_view(d_excl_molecule);
  for (int k = 0; k < nmolecule; k++)
    h_excl_molecule(k) = this->excluded_molecule_bits[k],
    h_excl_molecule(nmolecule + k) = this->excluded_molecule_intra[k];
  Kokkos::deep_copy(d_excl_molecule, h_excl_molecule);
  params_stale = 0;
}

/* a per-atom host array of the first n atoms and ghosts copied into view, which grows to nmax
   where it is shorter */
template <class DeviceType>
static void griddem_kk_upload(Kokkos::View<double *, DeviceType> &view, const std::string &label,
                              const double *host, int n, int nmax)
{
  if ((int) view.extent(0) < n) view = Kokkos::View<double *, DeviceType>(label, nmax);
  Kokkos::View<const double *, LMPHostType, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h_view(host, n);
  Kokkos::deep_copy(Kokkos::subview(view, std::make_pair(0, n)), h_view);
}

/* the contact masses of rigid bodies' atoms, found on the host (a non-Kokkos fix rigid's bodies,
   the pair's forward communication) and copied to the device each step */

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::upload_contact_masses()
{
  this->atomKK->sync(Host, RMASS_MASK);
  griddem_kk_upload(d_contact_mass, "griddem/kk:contact_mass", this->contact_masses(),
                    this->atom->nlocal + this->atom->nghost, this->atom->nmax);
}

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::upload_temperatures()
{
  griddem_kk_upload(d_temperature, "griddem/kk:temperature", this->atom->temperature,
                    this->atom->nlocal + this->atom->nghost, this->atom->nmax);
  if ((int) d_heat.extent(0) < this->atom->nlocal)
    d_heat = Kokkos::View<double *, DeviceType>("griddem/kk:heat", this->atom->nmax);
}

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::add_heat()
{
  const int nlocal = this->atom->nlocal;
  auto h_heat = Kokkos::create_mirror_view_and_copy(LMPHostType(), Kokkos::subview(d_heat, std::make_pair(0, nlocal)));
  double *heatflow = this->atom->heatflow;
  for (int i = 0; i < nlocal; i++) heatflow[i] += h_heat(i);
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
  // a Kokkos Tools region per step, for profilers (and the tests, which count the blocking
  // synchronisations in it)
  struct ProfilingRegion {
    ProfilingRegion() { Kokkos::Profiling::pushRegion("griddem/kk:compute"); }
    ~ProfilingRegion() { Kokkos::Profiling::popRegion(); }
  } region;
  this->ev_init(eflag, vflag, 0);
  if (this->vflag_atom) {    // grown when atom->nmax grew, else cleared where it is written
    if ((int) k_vatom.extent(0) < this->maxvatom) {
      this->memoryKK->destroy_kokkos(k_vatom, this->vatom);
      this->memoryKK->create_kokkos(k_vatom, this->vatom, this->maxvatom, "pair:vatom");
    } else if (engine) {
      Kokkos::deep_copy(k_vatom.h_view, 0.0);
    } else {
      Kokkos::deep_copy(k_vatom.template view<DeviceType>(), 0.0);
    }
  }
  if (engine) {
    this->atomKK->sync(Host, this->datamask_read | (this->exclusions.nmolecule ? MOLECULE_MASK : 0));
    this->atomKK->modified(Host, this->datamask_modify);
    this->engine_step();
    if (this->vflag_atom) k_vatom.modify_host();
    return;
  }
  this->find_image_axes();    // the box may have changed since the radius range was found
  if (params_stale) upload_tables();
  if (!d_report.data()) {
    d_report = Kokkos::View<GriddemKKStepReport, DeviceType>("griddem/kk:report");
    h_report = Kokkos::create_mirror_view(d_report);
  }

  AtomKokkos *atomKK = this->atomKK;
  atomKK->sync(this->execution_space, this->datamask_read | (this->exclusions.nmolecule ? MOLECULE_MASK : 0));
  atomKK->modified(this->execution_space, this->datamask_modify);
  const int nall = this->atom->nlocal + this->atom->nghost;

  // the grids planned from the last step's boxes, between reneighborings
  bool planned = !this->radius_range_due() && boxes_known;
  for (int attempt = 0;; attempt++) {
    if (attempt == max_attempts)
      this->error->one(FLERR, "Pair style {}: a step still found its room short after {} "
                       "attempts", this->force->pair_style, max_attempts);
    GriddemKKGrids grids;
    GriddemKKClassBoxes boxes;
    double margin = 0.0;
    if (planned) {
      plan_classes(grids);
      scan(grids, true, grids.ncls > 1);    // read with the rest, below
      boxes = last_boxes;
      // an atom moves less than an exact-mode cell in a step (the NN4DEM rule); twice that and
      // the last step's fastest atom's move, for the atoms that speed up
      const double h_nn4dem = griddem_cell_edge(GRIDDEM_CELL_EXACT, this->rmin, this->rmax, 0.0);
      margin = 2.0 * (h_nn4dem + last_speed * this->update->dt);
    } else {
      // 1. scan: read before binning, as a reneighboring step sets the radius range from it
      scan(grids, true, false);
      Kokkos::deep_copy(h_report, d_report);
      const GriddemKKScanValue &sc = h_report().scan;
      check_scan(sc);
      // the radius range, refreshed as the CPU style does: once, as every process takes part
      // (a step computed again is this process's alone)
      if (this->radius_range_due() && attempt == 0) {
        this->set_radius_range(this->atom->nlocal ? sc.rmin : INFINITY, sc.rmax);
        this->check_ghost_reach();
      }
      if (this->rmax == 0.0) return;    // no atoms yet
      if (attempt == 0 && this->grid_cost_due()) {
        atomKK->sync(Host, X_MASK | V_MASK | RADIUS_MASK | TAG_MASK | MASK_MASK);
        this->check_grid_cost();
      }
      plan_classes(grids);
      if (grids.ncls > 1) {
        scan(grids, false, true);
        Kokkos::deep_copy(h_report, d_report);
      }
      boxes = griddem_kk_boxes(h_report(), grids.ncls, nall);
    }

    // the history keys' images, once a step (every process takes part; a step computed again
    // is this process's alone)
    if (attempt == 0) upload_images();
    if (attempt == 0 && this->fix_rigid) upload_contact_masses();
    if (attempt == 0 && this->conducts_heat) upload_temperatures();

    // 2. grids
    fit_grids(grids, boxes, margin);
    // the search distance's margin for round-off of positions relative to their cells
    double extent = 0.0;
    for (int c = 0; c < grids.ncls; c++)
      for (int d = 0; d < 3; d++)
        extent = MAX(extent, MAX(fabs(grids.g[c].corner(d, 0) - this->domain->boxlo[d]),
                                 fabs(grids.g[c].corner(d, grids.g[c].n[d]) -
                                      this->domain->boxlo[d])));
    const double slack = 1e-10 * (2.0 * this->rmax + this->model.reach_extra) + 1e-14 * extent;
    // one grid of a given edge: refused where the CPU style's stencil would be (the largest
    // pair's search distance over more than GRIDDEM_MAX_REACH edges), rather than searched over
    // (2 x reach + 1)^3 cells per atom
    if (!this->grid_per_class() &&
        griddem_stencil_reach(grids.g[0].h, 2.0 * this->rmax + this->model.reach_extra + slack) >
            GRIDDEM_MAX_REACH)
      this->error_stencil_reach(grids.g[0].h);

    // 3.-6. binning, lists, search, law: launched, then the step's one blocking copy
    if (this->fix()->options.precision == GRIDDEM_PRECISION_SINGLE)
      bin_and_sweep<float>(grids, slack);
    else
      bin_and_sweep<double>(grids, slack);
    Kokkos::deep_copy(h_report, d_report);
    const GriddemKKStepReport &report = h_report();
    if (planned) check_scan(report.scan);
    if (report.retry & GRIDDEM_KK_RETRY_GRID) planned = false;
    if (report.retry & GRIDDEM_KK_RETRY_LISTS) list_needed = report.listed;
    if (report.retry & GRIDDEM_KK_RETRY_ROWS) rows_needed = report.rows;
    if (report.retry) continue;

    last_boxes = griddem_kk_boxes(report, grids.ncls, nall);
    last_speed = report.scan.ivmax >= 0 ? sqrt(report.scan.vmax2) : 0.0;
    boxes_known = 1;
    close_step(grids, report);
    if (this->conducts_heat) add_heat();
    return;
  }
}

/* the history keys' image codes of the owned and ghost atoms on the device, where the box has
   image axes (found on the host, as the CPU style does) */

template <class DeviceType, class Base> void PairGriddemKokkos<DeviceType, Base>::upload_images()
{
  this->images = nullptr;
  if (!this->image_axes) return;
  this->atomKK->sync(Host, IMAGE_MASK | TAG_MASK);
  this->images = this->fix()->periodic_images(this->image_axes);
  const int nall = this->atom->nlocal + this->atom->nghost;
  if (nall > (int) d_image.extent(0)) {
    d_image = Kokkos::View<int *, DeviceType>("griddem/kk:image", MAX(nall, (int) (1.2 * d_image.extent(0))));
    h_image = Kokkos::create_mirror_view(d_image);
  }
  for (int i = 0; i < nall; i++) h_image(i) = this->images[i];
  Kokkos::deep_copy(d_image, h_image);
}

/* non-finite positions and velocities, and the NN4DEM rule (as the CPU style): no atom crosses
   more than one exact-mode cell per step */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::check_scan(const GriddemKKScanValue &sc)
{
  AtomKokkos *atomKK = this->atomKK;
  if (sc.badx != INT_MAX) {
    atomKK->sync(Host, X_MASK | TAG_MASK);
    this->error_nonfinite("position", sc.badx, this->atom->x[sc.badx]);
  }
  if (sc.badv != INT_MAX) {
    atomKK->sync(Host, V_MASK | TAG_MASK);
    this->error_nonfinite("velocity", sc.badv, this->atom->v[sc.badv]);
  }
  if (this->rmax == 0.0) return;
  const double h_nn4dem = griddem_cell_edge(GRIDDEM_CELL_EXACT, this->rmin, this->rmax, 0.0);
  if (sc.ivmax >= 0 && sqrt(sc.vmax2) * this->update->dt > h_nn4dem) {
    atomKK->sync(Host, TAG_MASK);
    this->error_too_fast(sc.ivmax, sqrt(sc.vmax2), h_nn4dem);
  }
}

/* 1. the scan into the report (atoms), the boxes of grids' size classes (class_boxes) */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::scan(const GriddemKKGrids &grids, bool atoms,
                                               bool class_boxes)
{
  AtomKokkos *atomKK = this->atomKK;
  const int nall = this->atom->nlocal + this->atom->nghost;
  GriddemKKStepReport *report = d_report.data();    // addresses on the device, not dereferenced
  auto x = atomKK->k_x.template view<DeviceType>();
  auto radius = atomKK->k_radius.template view<DeviceType>();
  if (atoms) {
    GriddemKKScan<DeviceType> scan;
    scan.x = x;
    scan.v = atomKK->k_v.template view<DeviceType>();
    scan.radius = radius;
    scan.nlocal = this->atom->nlocal;
    griddem_kk_reduce(
        "griddem/kk:scan", Kokkos::RangePolicy<DeviceType>(0, nall), scan,
        Kokkos::View<GriddemKKScanValue, DeviceType, Kokkos::MemoryUnmanaged>(&report->scan));
  }
  if (!class_boxes) return;
  GriddemKKClassScan<DeviceType> class_scan;
  class_scan.value_count = GriddemKKClassScan<DeviceType>::per_class * grids.ncls;
  class_scan.x = x;
  class_scan.radius = radius;
  class_scan.grids = grids;
  griddem_kk_reduce(
      "griddem/kk:class_scan", Kokkos::RangePolicy<DeviceType>(0, nall), class_scan,
      Kokkos::View<double *, DeviceType, Kokkos::MemoryUnmanaged>(report->class_boxes,
                                                                   class_scan.value_count));
}

/* the size classes of fix griddem's cell mode for the radius range: a grid per class (classes,
   auto where its measure says so), else one */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::plan_classes(GriddemKKGrids &grids)
{
  grids.ncls = this->grid_per_class() ? griddem_class_count(this->rmin, this->rmax) : 1;
  griddem_class_bounds(this->rmax, grids.ncls, grids.upper);
}

/* 2. each class's grid over its box widened by margin: of the mode's edge (multi, exact, a
   number: as the CPU style) or multi's for the class, anchored at boxlo, given larger cells where
   it would need too many */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::fit_grids(GriddemKKGrids &grids,
                                                    const GriddemKKClassBoxes &boxes,
                                                    double margin)
{
  const int mode = this->fix()->options.cell_mode;
  const bool classes = this->grid_per_class();
  const double *boxlo = this->domain->boxlo;
  long total = 0;
  for (int c = 0; c < grids.ncls; c++) {
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
      lo[d] = boxes.count[c] ? boxes.lo[c][d] - margin : boxlo[d];
      hi[d] = boxes.count[c] ? boxes.hi[c][d] + margin : boxlo[d];
    }
    const long max_cells = grids.ncls == 1 ? GRIDDEM_ONE_GRID_MAX_CELLS(boxes.count[0])
                                           : GRIDDEM_CLASS_MAX_CELLS(boxes.count[c]);
    griddem_grid fitted;
    const double edge = classes ? griddem_cell_edge(GRIDDEM_CELL_MULTI, 0.0, grids.upper[c], 0.0)
                                : griddem_cell_edge(mode, this->rmin, this->rmax, this->fix()->options.cell_edge);
    const int coarsened = griddem_grid_fit(&fitted, boxlo, lo, hi, edge, max_cells);
    if (coarsened && !coarsened_warned_kk) {
      coarsened_warned_kk = 1;
      // worded as the CPU style's, naming the class when there are several
      this->error->warning(FLERR,
                           "Pair style {}: cell edge {}enlarged from {} to {} so that the grid over "
                           "this process's atoms stays within {} cells",
                           this->force->pair_style,
                           grids.ncls > 1 ? fmt::format("of size class {} ", c) : "", edge,
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
      this->error->one(FLERR, "Pair style {}: the grids would need {} cells, more than an int "
                       "counts", this->force->pair_style, total);
  }
  grids.offset[grids.ncls] = (int) total;
}

template <class DeviceType, class Base>
template <typename Real>
void PairGriddemKokkos<DeviceType, Base>::bin_and_sweep(const GriddemKKGrids &grids, double slack)
{
  bin<Real>(grids);
  // the float positions' rounding: 2^-24 of a position in its cell (under two edges: the
  // binning retries a step with an atom further out) and of a radius, for each side of a pair,
  // well inside this margin; none where they are the law's
  double near_margin = 0.0;
  if (GriddemKKSorted<DeviceType, Real>::atom_positions) {
    double hmax = 0.0;
    for (int c = 0; c < grids.ncls; c++) hmax = MAX(hmax, grids.g[c].h);
    near_margin = 1e-6 * (hmax + 2.0 * this->rmax + this->model.reach_extra) + slack;
  }
  if (all_classic)
    sweep<Real, true>(grids, slack, near_margin);
  else
    sweep<Real, false>(grids, slack, near_margin);
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

  // Views grow only; made once even for a process without atoms
  if (nall > nmax_atoms || !nmax_atoms) {
    nmax_atoms = MAX(MAX(nall, 1), (int) (1.2 * nmax_atoms));
    d_cell = Kokkos::View<int *, DeviceType>("griddem/kk:cell", nmax_atoms);
    d_order = Kokkos::View<int *, DeviceType>("griddem/kk:order", nmax_atoms);
    d_slot_cell = Kokkos::View<int *, DeviceType>("griddem/kk:slot_cell", nmax_atoms);
    d_list_first = Kokkos::View<int *, DeviceType>("griddem/kk:list_first", nmax_atoms);
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
  auto order = d_order;
  auto slot_cell = d_slot_cell;
  auto near = d_near;
  auto state = chan.state;
  auto tm = d_tm;
  auto report = d_report;
  // with rigid bodies the contact masses (bodies' masses), else the atoms'
  const bool rigid = this->fix_rigid != nullptr;
  auto contact_mass = d_contact_mass;
  // the molecules by slot, where the exclusions name molecules
  const bool molecules = this->exclusions.nmolecule > 0;
  if (molecules && (int) d_molecule.extent(0) < nall)
    d_molecule = Kokkos::View<tagint *, DeviceType>("griddem/kk:molecule", nmax_atoms);
  auto molecule = d_molecule;
  auto atom_molecule = atomKK->k_molecule.template view<DeviceType>();    // read only where molecules
  griddem_kk_for(
      "griddem/kk:report_reset", Kokkos::RangePolicy<DeviceType>(0, 1), KOKKOS_LAMBDA(const int) {
        report().retry = 0;
        report().listed = report().rows = 0;
        report().coincident = LONG_MAX;
      });
  // count is zero here: zero-filled when made, and each binning zeroes what it counted
  griddem_kk_for(
      "griddem/kk:bin", Kokkos::RangePolicy<DeviceType>(0, nall), KOKKOS_LAMBDA(const int i) {
        const int k = grids.class_of(radius(i));
        const int c = grids.offset[k] + grids.g[k].cell_of(x(i, 0), x(i, 1), x(i, 2));
        cell(i) = c;
        Kokkos::atomic_inc(&count(c));
      });
  griddem_kk_scan(
      "griddem/kk:scan_cells", Kokkos::RangePolicy<DeviceType>(0, ncell + 1),
      KOKKOS_LAMBDA(const int c, int &partial, const bool final) {
        const int k = count(c);
        if (final) {
          start(c) = partial;
          count(c) = 0;    // from here on: the cell's fill cursor
        }
        partial += k;
      });
  griddem_kk_for(
      "griddem/kk:fill", Kokkos::RangePolicy<DeviceType>(0, nall), KOKKOS_LAMBDA(const int i) {
        const int c = cell(i);
        order(start(c) + Kokkos::atomic_fetch_add(&count(c), 1)) = i;
      });
  // within a cell, slots by (tag, x, y, z): the same order whatever order atoms are stored in
  const tagint *tags = tag.data();
  const double *xs = x.data();    // LayoutRight: 3 interleaved coordinates an atom
  griddem_kk_for(
      "griddem/kk:sort_cells", Kokkos::RangePolicy<DeviceType>(0, ncell),
      KOKKOS_LAMBDA(const int c) {
        count(c) = 0;    // the fill cursor's work is done: zero again for the next binning
        // an empty cell past the last slot has no element of order to point at
        const int n = start(c + 1) - start(c);
        if (n > 1) griddem_sort_cell(&order(start(c)), n, tags, sizeof(tagint), xs);
      });
  griddem_kk_for(
      "griddem/kk:place", Kokkos::RangePolicy<DeviceType>(0, nall), KOKKOS_LAMBDA(const int slot) {
        const int i = order(slot);
        const int c = cell(i);
        slot_cell(slot) = c;
        const double p[3] = {x(i, 0), x(i, 1), x(i, 2)};
        double corner[3];
        grids.cell_corner(c, corner);
        const double h = grids.g[grids.class_of_cell(c)].h;
        bool inside = true;
        for (int d = 0; d < 3; d++) {
          const double rel = p[d] - corner[d];
          inside = inside && rel >= -h && rel < 2.0 * h;
          near(slot, d) = (float) rel;
        }
        if (!inside) Kokkos::atomic_fetch_or(&report().retry, (int) GRIDDEM_KK_RETRY_GRID);
        near(slot, 3) = (float) radius(i);
        for (int d = 0; d < 3; d++) state(slot, d) = v(i, d), state(slot, 3 + d) = omega(i, d);
        state(slot, 6) = rigid ? contact_mass(i) : rmass(i);
        tm(slot, 0) = type(i), tm(slot, 1) = mask(i);
        if (molecules) molecule(slot) = atom_molecule(i);
      });
}

/* the contact lists and the law over them, their sums into the report */

template <class DeviceType, class Base>
template <typename Real, bool Classic>
void PairGriddemKokkos<DeviceType, Base>::sweep(const GriddemKKGrids &grids, double slack,
                                                double near_margin)
{
  AtomKokkos *atomKK = this->atomKK;
  const int nlocal = this->atom->nlocal;
  const int nall = nlocal + this->atom->nghost;
  auto &chan = channels(Real());
  const int track = this->model.track_contacts;
  GriddemKKStepReport *report_at = d_report.data();    // addresses on the device
  auto report = d_report;

  // fix griddem/kk's rows, with room in the other pool for as many as the last step's
  typename FixGriddemKokkos<DeviceType>::Rows rows;
  long row_room = 0;
  if (track) {
    history->reserve_out(rows_needed);
    rows = history->rows_on_device();
    row_room = history->out_room();
  }

  // 4. lists laid out slot by slot: each owned atom's last list length (or its history row's,
  // which moved with it) plus the margin, in room the last step's lists needed
  auto first = d_list_first;
  auto count = d_list_count;
  auto order = d_order;
  auto last = d_last;
  auto row_count = rows.count;
  griddem_kk_scan(
      "griddem/kk:list_layout", Kokkos::RangePolicy<DeviceType>(0, nall + 1),
      KOKKOS_LAMBDA(const int s, long &offset, const bool final) {
        if (s == nall) {
          if (final) report().listed = offset;
          return;
        }
        const int i = order(s);
        const int room =
            i < nlocal ? list_margin + (track ? Kokkos::max(last(i), row_count(i)) : last(i)) : 0;
        if (final) first(s) = (int) offset, count(s) = room;
        offset += room;
      });
  if (list_needed > INT_MAX)
    this->error->one(FLERR, "Pair style {}: {} contact candidates on one process, more than an "
                     "int counts", this->force->pair_style, list_needed);
  if (list_needed > (long) d_list.extent(0))
    d_list = Kokkos::View<int *, DeviceType>(
        "griddem/kk:list", MIN((long) INT_MAX, MAX(list_needed, (long) (1.25 * d_list.extent(0)))));

  // 5. the search
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
  sorted.report = d_report;
  find.slack = slack;
  find.near_margin = near_margin;
  find.capacity = (long) d_list.extent(0);
  find.start = d_start;
  find.excl = this->exclusions;
  find.excl.type_pair = d_excl_type.extent(0) ? d_excl_type.data() : nullptr;
  find.excl.group_bits = d_excl_group.data();
  find.excl.molecule_bits = d_excl_molecule.data();
  find.excl.molecule_intra = d_excl_molecule.data() + this->exclusions.nmolecule;
  find.molecule = d_molecule;
  search<Real>(find);

  // the new history rows: room for each owned atom's list, slot by slot, in the other pool
  if (track) {
    griddem_kk_scan(
        "griddem/kk:row_layout", Kokkos::RangePolicy<DeviceType>(0, nall + 1),
        KOKKOS_LAMBDA(const int s, long &offset, const bool final) {
          if (s == nall) {
            if (final) {
              report().rows = offset;
              if (offset > row_room)
                Kokkos::atomic_fetch_or(&report().retry, (int) GRIDDEM_KK_RETRY_ROWS);
            }
            return;
          }
          const int i = order(s);
          if (i >= nlocal) return;
          if (final) rows.first_out(i) = (int) offset;
          offset += Kokkos::max(count(s), 0);
        });
  }

  // 6. the law over the lists
  GriddemKKSweep<DeviceType, Real, Classic> sweep;
  static_cast<GriddemKKSorted<DeviceType, Real> &>(sweep) = sorted;
  sweep.frozen_bit = this->freeze_group_bit;
  sweep.eflag_global = this->eflag_global;
  sweep.vflag_global = this->vflag_global;
  sweep.vflag_atom = this->vflag_atom;
  sweep.dt = this->update->dt;
  sweep.history_update = this->update->setupflag ? 0 : 1;
  sweep.track = track;
  sweep.nv = track ? history->history_values() : 0;
  sweep.state = chan.state;
  sweep.tag = atomKK->k_tag.template view<DeviceType>();
  sweep.keyed_by_image = this->image_axes != 0;
  sweep.image = d_image;
  sweep.params = d_params;
  sweep.last = d_last;
  sweep.f = atomKK->k_f.template view<DeviceType>();
  sweep.torque = atomKK->k_torque.template view<DeviceType>();
  if (this->vflag_atom) sweep.vatom = k_vatom.template view<DeviceType>();
  sweep.rows = rows;
  sweep.heat = this->conducts_heat;
  sweep.temperature = d_temperature;
  sweep.heatflow = d_heat;
  griddem_kk_reduce(
      "griddem/kk:sweep", Kokkos::RangePolicy<DeviceType>(0, nall), sweep,
      Kokkos::View<GriddemKKSweepValue, DeviceType, Kokkos::MemoryUnmanaged>(&report_at->sums));
}

/* 5. the search: a thread per slot, or a team per block of cells (fix griddem's search) */

template <class DeviceType, class Base>
template <typename Real>
void PairGriddemKokkos<DeviceType, Base>::search(const GriddemKKFind<DeviceType, Real> &find)
{
  const int nall = this->atom->nlocal + this->atom->nghost;
  constexpr bool on_host =
      std::is_same<typename DeviceType::execution_space, Kokkos::DefaultHostExecutionSpace>::value;
  // auto is the thread search, the faster on the GPU measured (bench/results/README.md)
  if (this->fix()->options.search != GRIDDEM_SEARCH_TEAM) {
    griddem_kk_for("griddem/kk:find", Kokkos::RangePolicy<DeviceType>(0, nall), find);
    return;
  }
  GriddemKKFindTeams<DeviceType, Real> teams;
  teams.find = find;
  const GriddemKKGrids &grids = find.grids;
  int blocks = 0, most_reach = 0;
  for (int c = 0; c < grids.ncls; c++) {
    const GriddemKKGrid &g = grids.g[c];
    teams.first_block[c] = blocks;
    blocks += GriddemKKFindTeams<DeviceType, Real>::blocks_along_x(g.n[0]) * g.n[1] * g.n[2];
    teams.reach[c] = griddem_stencil_reach(g.h, 2.0 * grids.upper[c] + find.reach_extra + find.slack);
    most_reach = MAX(most_reach, teams.reach[c]);
  }
  teams.first_block[grids.ncls] = blocks;
  teams.most_rows = (2 * most_reach + 1) * (2 * most_reach + 1);
  // a stencil too wide for the device's team scratch takes the thread search (same lists)
  if (teams.team_shmem_size(0) > (size_t) Kokkos::TeamPolicy<DeviceType>::scratch_size_max(0)) {
    griddem_kk_for("griddem/kk:find", Kokkos::RangePolicy<DeviceType>(0, nall), find);
    return;
  }
  // a warp a team on a GPU (a block holds ~8-30 particles); one thread on the host
  Kokkos::TeamPolicy<DeviceType> policy(blocks, on_host ? 1 : 32);
  griddem_kk_for("griddem/kk:find_teams", policy, teams);
}

/* a computed step's report: faults, the history rows made current, virial and diagnostics */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::close_step(const GriddemKKGrids &grids,
                                                     const GriddemKKStepReport &report)
{
  if (report.coincident != LONG_MAX)
    report_coincident((int) (report.coincident >> 32), (int) (report.coincident & 0xffffffffL));
  const GriddemKKSweepValue &sums = report.sums;
  if (this->model.track_contacts) {
    rows_needed = report.rows;
    history->commit(report.rows, sums.most);
  }
  list_needed = report.listed;

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
  stats.energy_tallied = this->eflag_global != 0;
  stats.max_speed = last_speed;
  stats.max_cells_moved = stats.max_speed * this->update->dt / grids.g[grids.ncls - 1].h;
  stats.nonfinite_velocity = 0;
  this->last_stats = stats;
  ncell_counted = grids.offset[grids.ncls];
}

/* the occupied cells and the most centres in one, of the last step's grids */

template <class DeviceType, class Base>
void PairGriddemKokkos<DeviceType, Base>::count_occupancy(griddem_engine_stats &stats)
{
  if (engine) {
    Base::count_occupancy(stats);    // of the CPU engine's grids
    return;
  }
  auto start = d_start;
  int occupied = 0, occupancy = 0;
  griddem_kk_reduce(
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
