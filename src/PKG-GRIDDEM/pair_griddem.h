/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: what every griddem pair style shares. Each step the CPU styles hand owned
   and ghost atoms to their grid engine (no neighbor list), which sweeps the contact history
   that fix griddem keeps. A derived style turns its
   arguments into one sub-model spec per type pair (griddem_submodels.h); this class mixes,
   checks and converts them into the law the engine evaluates.
------------------------------------------------------------------------- */

#ifndef LMP_PAIR_GRIDDEM_H
#define LMP_PAIR_GRIDDEM_H

#include "griddem_engine.h"
#include "griddem_fix_keeper.h"
#include "griddem_pair_link.h"
#include "griddem_submodels.h"
#include "pair.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

// check_grid_cost(): a mode warns above this many times cell auto's candidates per atom, or above
// this many centres in one cell
#define GRIDDEM_COST_RATIO_WARN 8
#define GRIDDEM_OCCUPANCY_WARN 64
// cell auto takes one grid where it tests at most this many times the candidates per atom of a
// grid per size class (whose every further grid and pairs across classes cost their own passes)
#define GRIDDEM_AUTO_ONE_GRID 1.5

class PairGriddem : public Pair, public GriddemPairLink {
 public:
  PairGriddem(class LAMMPS *);
  ~PairGriddem() override;
  void compute(int, int) override;
  void init_style() override;
  double init_one(int, int) override;
  double single(int, int, int, int, double, double, double, double &) override;
  // "griddem": this style's GriddemPairLink, for fix griddem
  void *extract(const char *, int &) override;
  double memory_usage() override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

  void fix_made(class FixGriddem *made, int in_place) override { keeper.fix_made(made, in_place); }
  void fix_leaving(class FixGriddem *leaving) override { keeper.fix_leaving(leaving); }
  const griddem_engine_stats *step_stats(const class FixGriddem *of, int occupancy) override;

 protected:
  griddem_model model;                         // what the engine evaluates
  std::vector<griddem_pair_spec> specs;        // [i*(ntypes+1)+j], as given or mixed
  std::vector<griddem_pair_params> params;     // [i*(ntypes+1)+j], both orders
  double cutoff_global;                        // < 0: cutoffs from the radii
  int layout_set;                              // history layout fixed by a first spec
  int single_hooke_layout;                     // single() reports as gran/hooke/history
  bool conducts_heat;                          // some type pair has a heat model
  GriddemFixKeeper keeper;    // which fix griddem holds the history
  // the fix of the last init_style: the history and the grid options
  class FixGriddem *fix() const { return keeper.fix(); }
  griddem_engine engine;    // the CPU styles' grids, bins and channels
  griddem_engine_stats last_stats;    // of the last step (init_style: of a step without atoms)
  // the occupancy of last_stats, which a step leaves -1: counted when asked
  virtual void count_occupancy(griddem_engine_stats &);
  // a step of the CPU engine after ev_init(): grids, search and contacts over the host arrays
  void engine_step();
  double grid_anchor[3];    // the cells' corner: the box's where LAMMPS last reneighbored
  int coarsened_warned;
  int cost_warned;        // check_grid_cost() warned
  bigint cost_natoms;     // the atom count check_grid_cost() last measured
  int auto_one_grid;      // cell auto's choice at the last check_grid_cost(): one grid, not one per class
  // the cell mode's grids: one per size class (classes; auto where its measure says so), or one
  bool grid_per_class() const;
  double rmin, rmax;            // smallest and largest radius of all atoms (radius_range_due())
  // where rmin and rmax are found anew: at reneighborings (atoms come and go), and every step
  // where a fix may change radii (diam_flag: fix adapt's diameter)
  bool radius_range_due() const;
  bool radii_vary;
  int ghost_reach_warned;

  int freeze_group_bit;
  std::vector<unsigned char> excluded_types;
  std::vector<int> excluded_groups;
  std::vector<int> excluded_molecule_bits, excluded_molecule_intra;
  griddem_exclusions exclusions;

  // rigid bodies (fix rigid, rigid/small): a contact takes an atom's body's mass, as stock's
  class Fix *fix_rigid;
  std::vector<double> body_mass;       // per atom and ghost: its body's mass, 0 outside bodies
  std::vector<double> contact_mass;    // per atom and ghost: the mass its contacts take
  const double *contact_masses();

  // makes fix GRIDDEM (when no fix griddem exists), so that it exists from the pair style's
  // settings, pair_coeff or restart on
  void allocate();
  void create_default_fix();
  // the fix style made to hold this style's contact history where the script defines none:
  // "griddem" (the CPU store), or a Kokkos variant (fix griddem/kk, whose pools live on the
  // device of a kk style)
  virtual std::string history_fix_style() const { return "griddem"; }
  // whether this style sweeps the store of `fix`: a CPU style fix griddem's, a kk style fix
  // griddem/kk's (and, on a host back end, fix griddem's through the CPU engine)
  virtual bool sweeps(const class FixGriddem &fix) const;
  // give the type pairs of two LAMMPS type ranges spec s
  void set_specs(const char *irange, const char *jrange, const griddem_pair_spec &s);
  // make room for the history of s (the first spec of the style sets it, later ones widen it;
  // each type pair lays its values out as its sub-models say)
  void adopt_layout(const griddem_pair_spec &s);
  // largest radius per type of the atoms present and those fix pour/deposit will add, found
  // once per init_style() for init_one()
  std::vector<double> type_radius;
  // the largest contact distance of the type pairs at their largest radii (with a pull-off
  // distance where the pair's model has one), found by init_one
  double type_contact;

  // shared by the CPU and Kokkos styles, so both name the same faults in the same words
  void set_radius_range(double local_min, double local_max);
  // in a step: refuses (warns of) a contact distance the ghost atoms do not (may not) cover
  void check_ghost_reach();
  void error_nonfinite(const char *what, int i, const double *value);
  void error_too_fast(int i, double speed, double h_nn4dem);
  void error_coincident(int i, int j);
  void error_stencil_reach(double edge);
  // warns once where the fix's cell mode tests far more candidates than cell auto would
  bool grid_cost_due() const;
  void check_grid_cost();    // on the host's atoms
  griddem_particles host_particles();
  // image_axes from the box and the radius range; refuses an axis too thin for the history keys
  // to tell a partner's images apart
  void find_image_axes();
  void image_axes_of_box();
  int image_axes;    // bit d: periodic axis d narrower than twice the largest contact distance
  int image_axes_found;    // image_axes was found once (a change after that is warned of)
                     // (history styles): contacts keyed by partner and periodic image
  const int *images;    // the keys' image codes of the last step's atoms (nullptr: no image axes)

 private:
  griddem_pair_params make_params(const griddem_pair_spec &s, int i, int j);
  double linear_normal_stiffness();
  void setup_exclusions();
  std::vector<double> max_radius_by_type();
  void find_radius_range();
  void check_motion(double h_nn4dem);
  void report_fault(const griddem_sweep_result &);
};

}    // namespace LAMMPS_NS

#endif
