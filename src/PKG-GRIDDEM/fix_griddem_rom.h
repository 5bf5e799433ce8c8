/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: adaptive reduced-order DEM. A ridge-regression model predicts the voxel
   velocity field from the voxel density field and control variables; particles moving with the
   field become kinematic (carried by it at the model's step, no contact forces, no contacts
   among themselves); the others form the group ID_dynamic that the user's integrator moves.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem/rom,FixGriddemRom);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_ROM_H
#define LMP_FIX_GRIDDEM_ROM_H

#include "fix.h"
#include "griddem_rom.h"

#include <string>
#include <utility>
#include <vector>

namespace LAMMPS_NS {

class FixGriddemRom : public Fix {
 public:
  FixGriddemRom(class LAMMPS *, int, char **);
  ~FixGriddemRom() override;
  int setmask() override;
  void init() override;
  void setup(int) override;
  void initial_integrate(int) override;
  void pre_exchange() override;
  void post_neighbor() override;
  void setup_pre_reverse(int, int) override;
  void pre_reverse(int, int) override;
  void end_of_step() override;
  void post_run() override;
  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  double compute_vector(int) override;
  void write_restart(FILE *) override;
  void restart(char *) override;
  int get_grid_by_name(const std::string &, int &) override;
  void *get_grid_by_index(int) override;
  int get_griddata_by_name(int, const std::string &, int &) override;
  void *get_griddata_by_index(int) override;
  void reset_grid() override;
  void *extract(const char *, int &) override;
  double memory_usage() override;

  // compute griddem/cg's fields from the stored atoms where they are (no return for them): on one
  // process, with records laid out as AtomVec::pack_exchange lays them
  bool fields_in_place() const;
  // the stored atoms of the group bits groupbit appended to out, FIELD_VALUES values each: x
  // wrapped into the periodic box, v, mass, radius
  enum { FIELD_VALUES = 8 };
  void stored_for_fields(int groupbit, std::vector<double> &out) const;

  int kinematic_bit;    // group bit of the kinematic atoms (group ID_kinematic)
  int dynamic_bit;      // group bit of all other atoms (group ID_dynamic), for the integrator
  int lagging_bit;      // group bit of the kinematic atoms no dynamic atom can reach (ID_lagging)

 private:
  void check_box();    // the model box against the simulation box (init, model steps)
  griddem_rom_grid grid;          // the voxels in the simulation box (frame_grid placed at the origin)
  griddem_rom_grid frame_grid;    // the model file's box (relative to the origin where moving)
  bool moving;                    // model line 'frame moving': its box is relative to keyword origin
  std::string origin_names[3];    // keyword origin: equal-style variable names ("" where constant)
  int origin_vars[3];
  double origin[3];               // the frame's origin now (constants from keyword origin)
  int ncontrol;
  int form;    // the model's form, enum griddem_rom_form
  std::vector<double> weights;    // [3 nvoxel][1 + nvoxel + ncontrol] (occupancy: [1 + ncontrol])
  std::vector<double> force_weights;    // model block 'force': [3][columns of weights], or empty
  double force_predicted[3];            // the force block's prediction at the last classification
  std::vector<std::string> control_names;
  std::vector<int> control_vars;
  double eps, v0, overlap_max;
  double cfl;               // model step: at most cfl h / max |u| (keyword cfl)
  double reach_user;        // keyword reach, or -1: the most the ghost cutoff allows
  double reach, cap;        // near: gap to a dynamic atom below reach; cap: the ghost cutoff's bound
  double block_fraction;    // keyword block: share of a voxel's atoms that must qualify (0: per atom)
  bool freeze;              // keyword freeze: kinematic atoms get velocity 0, not the field
  bool separate;            // keyword separate: released atoms are moved out of their overlaps
  enum Drive { DRIVE_MATCH, DRIVE_BOX, DRIVE_DENSE };
  Drive drive;              // keyword drive: which atoms the model drives (doc/fix_griddem_rom.md)
  double dense_min;         // drive dense: the density from which the model drives an atom
  bool store_wanted;        // keyword store: lagging atoms leave LAMMPS's arrays between reach tests
  bool store_active;        // this run stores them (init, setup)
  std::vector<class Compute *> grid_computes;    // computes griddem/cg and griddem/grid, whose steps need every atom
  std::vector<class Fix *> grid_averages;      // fixes ave/grid, which invoke them unannounced
  bool grid_dumps_in_place;    // every per-grid compute is a compute griddem/cg that reads_store(),
                               // every per-grid fix this one or a fix ave/grid: a grid dump needs
                               // no stored atom back where fields_in_place()
  std::string resolved_id;    // atoms in this region are never kinematic (keyword resolved)
  class Region *resolved;
  int period;    // keyword every: the longest model step, in DEM steps
  int model_step;              // the current model step (CFL rule), in DEM steps
  bigint last_model;           // the step the lagging kinematic atoms were last brought up to date
  bigint next_model;           // the step of the next classification
  double umax_far;             // largest speed of a lagging kinematic atom (all processes)
  double nfar;                 // number of lagging kinematic atoms (all processes)
  bool fresh;                  // atoms were created on this process since its last reach test
  bool force_each_step;        // a fix other than gravity acts on kinematic atoms: test forces each step
  // per atom: x at last_model (3), the budget, near (1: moves each step); moves with the atom
  enum Track { TRACK_X, TRACK_BUDGET = TRACK_X + 3, TRACK_NEAR, NTRACK };
  double **track;              // [nmax][NTRACK]
  std::vector<int> nearlist;   // owned kinematic atoms that move each step (rebuilt at reneighboring)
  griddem_grid near_grid;      // the reach test's grid and bins (scratch kept between calls)
  griddem_bins near_bins;
  std::vector<double> density, feature, field;
  double *state;    // per-atom output: 1 kinematic, 0 dynamic
  double **fpair;   // this step's contact forces on kinematic atoms (the pair's share of f)
  std::vector<std::pair<int, const double *>> gravities;    // group bit, acceleration of each fix gravity
  int nmax;
  // the voxel fields as LAMMPS grid data (dump grid, grid/vtk): this process's brick of them
  class Grid3d *grid3d;
  int lo_in[3], hi_in[3], lo_out[3], hi_out[3];
  double ***grid_values[4];    // vx vy vz density of the last classification
  griddem_grid check_grid;    // the contact checks' grid and bins (scratch kept between calls)
  griddem_bins check_bins;
  // the global vector's entries 1-13 in its order (doc/fix_griddem_rom.md; 14-16: force_predicted):
  // kinematic atoms now; made kinematic; released by a hit, an overlap, leaving the model box or
  // entering the resolved region, a force; classifications; released by a jump of the field;
  // kinematic atoms near a dynamic one at the last reach test; the model step in DEM steps; reach
  // tests between model steps; atoms held dynamic by their voxel; seconds spent at the end of steps.
  // KINEMATIC, NEAR and MODEL_STEP are values now, the others sums over the run.
  enum Counter {
    KINEMATIC, MADE_KINEMATIC, RELEASED_HIT, RELEASED_OVERLAP, RELEASED_LEFT, RELEASED_FORCE,
    CLASSIFICATIONS, RELEASED_JUMP, NEAR, MODEL_STEP, REACH_TESTS, HELD_BY_VOXEL, SECONDS, HELD_BY_BOX, SEPARATED,
    NCOUNTER
  };
  double counts[NCOUNTER];

  // The store: this process's lagging atoms taken out of LAMMPS's arrays (each as LAMMPS's own
  // exchange record, so every fix's per-atom data goes with it) from the step after a reach test
  // until they are needed again: the next model step, a reach test in a triclinic box, dump,
  // restart file, the run's last step or a step where another fix creates or deletes atoms
  // (return_at). They wait where the last model step or in-place reach test left them, as lagging
  // atoms do.
  std::vector<double> stored;    // the records, one after the other
  size_t stored_used;            // doubles of stored in use
  int nstored;                   // records held here
  double nstored_all;            // records held on all processes
  bigint store_at;               // the step whose pre_exchange takes the lagging atoms out (-1: none)
  bigint return_at;              // the step whose pre_exchange brings them back
  bool reach_due;                // the skin rule fired while atoms were stored: the reach test runs
                                 // after they are back (post_neighbor)
  // The reach test on the store in place (an orthogonal box, records laid out as
  // AtomVec::pack_exchange lays them: x, v at 1-6, mask at 9, then atom style sphere's radius and
  // rmass): the stored atoms are brought up to date in their records and take part where they are;
  // those it finds near come back at the next step's exchange (near_return_at), the others stay out.
  enum RecordOffset { RECORD_X = 1, RECORD_V = 4, RECORD_MASK = 9, RECORD_RADIUS = 11, RECORD_RMASS = 12 };
  std::vector<size_t> record_at;       // where each record starts in stored
  std::vector<double> stored_budget;   // the in-place reach test's budget of each record's atom
  std::vector<char> stored_near;       // records that reach test found near
  bool records_readable;               // records hold x, v, mask, radius and mass where RecordOffset
                                       // says, on every process (check_records, at each run's set-up)
  bigint near_return_at;               // the step whose pre_exchange brings back the records found near
  class Irregular *irregular;          // migrate_far()
  bool jumped;                         // atoms came back or caught up since the last exchange (the same
                                       // on every process: set where all act alike)

  void read_model(const char *file);
  void place_grid();
  void classify();
  void separate_released(const std::vector<int> &was_kinematic);
  void release_by_force();
  void catch_up();
  void migrate_far();
  size_t record_room() const;
  void check_records();
  void held_within_reach(std::vector<double> &held, std::vector<double> &images,
                         std::vector<std::pair<int, int>> &from) const;
  void near_elsewhere(const std::vector<std::pair<int, int>> &from, const int *near);
  void mark_near();
  void fill_nearlist();
  void fill_state();
  bigint next_other_exchange(bigint from) const;
  bigint next_grid_step(bigint from) const;
  bigint next_dump_of_atoms() const;
  void plan_store();
  void plan_return();
  void store_lagging();
  void reset_local_map();
  void return_stored(bool exchange_follows);
  bool reach_test_in_place() const;
  void catch_up_store();
  void return_near();
  void arm_reneighbor();
  void allocate_grid();
  void deallocate_grid();
  void fill_grid();
};

}    // namespace LAMMPS_NS

#endif
#endif
