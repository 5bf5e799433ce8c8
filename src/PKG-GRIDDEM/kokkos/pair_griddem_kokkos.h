/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: what the griddem/.../kk pair styles share. One class template,
   PairGriddemKokkos<DeviceType, Base>, derives from the CPU style Base (PairGriddemHooke,
   PairGriddemGranular), which parses the arguments, mixes and checks the coefficients and fills
   `model`/`params`; this class only replaces compute() with device kernels:

   1. scan (griddem_kk_scan.h): bounding box of owned + ghost centres (and of each size class's),
      non-finite positions and velocities, fastest owned atom, radius range (one parallel_reduce);
   2. binning (bin() in pair_griddem_kokkos_impl.h, on the grids of griddem_kk_grid.h): a
      counting sort of the centres into the grids of fix griddem's cell mode (a grid per size class, or one grid of `multi`'s, `exact`'s or a given edge), anchored at
      domain->boxlo; within a cell the slots are ordered by tag (then position, for periodic
      images of one atom), so sums do not depend on storage order;
      the sorted positions (float, relative to the cell: `near`), radii, velocities, masses,
      types and masks are the "channels" (griddem_kk_sorted.h);
   3. search (griddem_kk_find.h, griddem_kk_find_teams.h): each sorted owned particle visits the cells of every size class within reach of it
      and lists the candidates that touch (GriddemKKFind): the compact float positions reject
      the far candidates (a conservative margin: a pair they reject cannot touch), the touch
      test of the rest is the law's own, in its precision. A thread per particle
      (GriddemKKFind), or a team per block of cells with the candidates of its neighbourhood in
      its class staged in scratch memory (GriddemKKFindTeams), per fix griddem's `search`;
   4. sweep (griddem_kk_sweep.h): one thread per sorted owned particle evaluates the law over its list from its own
      side (griddem_contact_eval). The law is exactly odd under i <-> j, so each particle sums its
      own force and torque: no atomics, no colouring, no reverse communication. The global virial
      (half of del*f per owned side) and the step's statistics (which fix griddem's vector reports)
      come back from its parallel_reduce; the occupancy of the cells is counted only when asked.

   One blocking synchronisation a step: the kernels leave what the host needs in one report
   (GriddemKKStepReport, griddem_kk_report.h), copied back once after the sweep. Between reneighborings the grids are
   planned from the last step's boxes, widened by what an atom can move in a step, and the scan
   runs alongside the other kernels (its errors are raised from the report); a reneighboring step
   reads its scan before binning, as every process must agree on the radius range there. What
   the plan could not know is found on the device and makes the sweep do nothing, and the step
   is computed again: an atom binned more than a cell outside the grid (planned anew from a
   scan), a list or the history rows outgrowing the room laid out (grown to what they needed).

   On a host back end (Kokkos OpenMP or Serial) the style runs the CPU styles' engine instead
   (PairGriddem::engine_step: the same grid, search and contacts, threaded by OpenMP) over fix
   griddem's store, unless the script's fix griddem is fix griddem/kk (fix griddem under -sf kk),
   whose pools only the kernels sweep.

   Laws with contact history keep it in fix griddem/kk (a row per atom, written anew each step by
   the atom's own thread with room for its list: GriddemKKSweep). Views grow, never shrink, and are
   not reallocated in a step unless a size grew.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_GRIDDEM_KOKKOS_H
#define LMP_PAIR_GRIDDEM_KOKKOS_H

#include "fix_griddem_kokkos.h"
#include "griddem_contact.h"
#include "griddem_engine.h"
#include "griddem_kk_find.h"
#include "griddem_kk_find_teams.h"
#include "griddem_kk_report.h"
#include "griddem_kk_scan.h"
#include "griddem_kk_sorted.h"
#include "griddem_kk_sweep.h"
#include "kokkos_type.h"
#include "pair_kokkos.h"

#include <type_traits>

namespace LAMMPS_NS {

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
  Kokkos::View<tagint *, DeviceType> d_molecule;    // by slot, where the exclusions name molecules
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
  // molecule exclusions: their group bits, then their intra flags (griddem_exclusions)
  Kokkos::View<int *, DeviceType> d_excl_molecule;
  // [nall] each atom's contact mass, with rigid bodies (PairGriddem::contact_masses)
  Kokkos::View<double *, DeviceType> d_contact_mass;
  void upload_contact_masses();
  // heat conduction: the atoms' temperatures (host arrays of fix property/atom) copied to the
  // device each step, and each owned atom's heat from its contacts added to its heatflow on the host
  Kokkos::View<double *, DeviceType> d_temperature, d_heat;
  void upload_temperatures();
  void add_heat();
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

  // a host back end (OpenMP, Serial, or the host of a GPU build): the kk style may run the CPU
  // engine, with its threads, over fix griddem's store, which it does where the fix is fix
  // griddem (engine) rather than fix griddem/kk
  static constexpr bool on_host = std::is_same<DeviceType, LMPHostType>::value;
  bool engine;
  std::string history_fix_style() const override;
  bool sweeps(const FixGriddem &fix) const override;
  void upload_tables();
  void upload_images();
  void check_scan(const GriddemKKScanValue &sc);
  void plan_classes(GriddemKKGrids &grids);
  void fit_grids(GriddemKKGrids &grids, const GriddemKKClassBoxes &boxes, double margin);
  void close_step(const GriddemKKGrids &grids, const GriddemKKStepReport &report);
  void report_coincident(int i, int j);
};

}    // namespace LAMMPS_NS

#endif
