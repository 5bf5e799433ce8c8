/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem/rom, adaptive reduced-order DEM (see doc/fix_griddem_rom.md).
------------------------------------------------------------------------- */

#include "fix_griddem_rom.h"

#include "griddem_rom_model.h"

#include "atom.h"
#include "atom_vec.h"
#include "comm.h"
#include "compute.h"
#include "compute_griddem_cg.h"
#include "domain.h"
#include "dump.h"
#include "error.h"
#include "force.h"
#include "grid3d.h"
#include "group.h"
#include "input.h"
#include "irregular.h"
#include "memory.h"
#include "modify.h"
#include "output.h"
#include "region.h"
#include "pair.h"
#include "update.h"
#include "variable.h"

#include <cmath>
#include <algorithm>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;

namespace {
// atom-steps held out of LAMMPS, per atom of the scene, below which a store costs more than it
// saves (its two reneighborings against the held atoms' skipped per-step work; measured on
// examples/rom-pile and rom-hopper)
constexpr double STORE_PAYBACK = 8.0;

// Each process's lists for the others (send[q]: for process q) delivered: what this process gets,
// the parts of the processes one after the other (part q from start[q] to start[q + 1])
template <typename T>
std::vector<T> exchange_lists(const std::vector<std::vector<T>> &send, MPI_Datatype type, MPI_Comm world,
                              std::vector<int> &start)
{
  const int nprocs = (int) send.size();
  std::vector<int> nsend(nprocs), nrecv(nprocs), sstart(nprocs);
  for (int q = 0; q < nprocs; q++) nsend[q] = (int) send[q].size();
  MPI_Alltoall(nsend.data(), 1, MPI_INT, nrecv.data(), 1, MPI_INT, world);
  start.assign(nprocs + 1, 0);
  int stotal = 0;
  for (int q = 0; q < nprocs; q++) sstart[q] = stotal, stotal += nsend[q], start[q + 1] = start[q] + nrecv[q];
  std::vector<T> out(stotal), in(start[nprocs]);
  for (int q = 0; q < nprocs; q++) std::copy(send[q].begin(), send[q].end(), out.begin() + sstart[q]);
  MPI_Alltoallv(out.data(), nsend.data(), sstart.data(), type, in.data(), nrecv.data(), start.data(), type, world);
  return in;
}
}    // namespace

FixGriddemRom::FixGriddemRom(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), kinematic_bit(0), dynamic_bit(0), lagging_bit(0), grid(), frame_grid(), moving(false),
    origin_vars{-1, -1, -1}, origin{0.0, 0.0, 0.0}, ncontrol(0), eps(-1.0),
    v0(-1.0), force_predicted{0.0, 0.0, 0.0}, overlap_max(0.1), cfl(0.5), reach_user(-1.0), reach(0.0), cap(0.0),
    block_fraction(0.0), freeze(false), separate(true), drive(DRIVE_MATCH), dense_min(0.0), store_wanted(true), store_active(false),
    resolved(nullptr), period(1), model_step(1), last_model(0), next_model(-1), umax_far(0.0), nfar(0.0),
    fresh(false), force_each_step(false), track(nullptr), near_grid(), near_bins(), state(nullptr), fpair(nullptr),
    nmax(0), grid3d(nullptr), lo_in(), hi_in(), lo_out(), hi_out(), grid_values(), check_grid(), check_bins(),
    counts(), stored(), stored_used(0), nstored(0), nstored_all(0.0), store_at(-1), return_at(-1), reach_due(false),
    records_readable(false), near_return_at(-1), irregular(nullptr), jumped(false)
{
  std::string model_file;
  int every = 0;
  bool origin_given = false;
  int iarg = 3;
  while (iarg < narg) {
    const std::string word = arg[iarg];
    if (word == "control") {
      iarg++;
      while (iarg < narg && utils::strmatch(arg[iarg], "^v_")) control_names.emplace_back(arg[iarg++] + 2);
      if (control_names.empty()) error->all(FLERR, "Fix griddem/rom: keyword control needs v_name arguments");
      continue;
    }
    if (word == "origin") {
      if (iarg + 4 > narg) error->all(FLERR, "Fix griddem/rom: keyword origin needs 3 values (v_name or a number)");
      for (int d = 0; d < 3; d++) {
        if (utils::strmatch(arg[iarg + 1 + d], "^v_")) origin_names[d] = arg[iarg + 1 + d] + 2;
        else origin[d] = utils::numeric(FLERR, arg[iarg + 1 + d], false, lmp);
      }
      origin_given = true;
      iarg += 4;
      continue;
    }
    if (iarg + 2 > narg) error->all(FLERR, "Fix griddem/rom: keyword {} needs a value", word);
    if (word == "model") model_file = arg[iarg + 1];
    else if (word == "eps") eps = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "v0") v0 = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "every") every = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "overlap") overlap_max = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "resolved") resolved_id = arg[iarg + 1];
    else if (word == "cfl") cfl = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "reach") {
      reach_user = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (reach_user < 0.0) error->all(FLERR, "Fix griddem/rom: keyword reach must be >= 0");
    }
    else if (word == "block") block_fraction = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "freeze") freeze = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
    else if (word == "separate") separate = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
    else if (word == "drive") {
      const std::string how = arg[iarg + 1];
      if (how == "match") drive = DRIVE_MATCH;
      else if (how == "box") drive = DRIVE_BOX;
      else if (how == "dense") {
        if (iarg + 2 >= narg) utils::missing_cmd_args(FLERR, "fix griddem/rom drive dense", error);
        drive = DRIVE_DENSE;
        dense_min = utils::numeric(FLERR, arg[iarg + 2], false, lmp);
        if (dense_min <= 0.0)
          error->all(FLERR, "Fix griddem/rom: keyword drive dense needs a density > 0, not {}", arg[iarg + 2]);
        iarg++;
      } else error->all(FLERR, "Fix griddem/rom: keyword drive must be match, box or dense, not {}", how);
    }
    else if (word == "store") store_wanted = utils::logical(FLERR, arg[iarg + 1], false, lmp) == 1;
    else error->all(FLERR, "Fix griddem/rom: unknown keyword {}", word);
    iarg += 2;
  }
  if (model_file.empty()) error->all(FLERR, "Fix griddem/rom: keyword model is required");
  if (eps < 0.0) error->all(FLERR, "Fix griddem/rom: keyword eps is required and must be >= 0");
  if (v0 <= 0.0) error->all(FLERR, "Fix griddem/rom: keyword v0 is required and must be > 0");
  if (every <= 0) error->all(FLERR, "Fix griddem/rom: keyword every is required and must be > 0");
  if (overlap_max <= 0.0) error->all(FLERR, "Fix griddem/rom: keyword overlap must be > 0");
  if (cfl <= 0.0) error->all(FLERR, "Fix griddem/rom: keyword cfl must be > 0");
  if (block_fraction < 0.0 || block_fraction > 1.0)
    error->all(FLERR, "Fix griddem/rom: keyword block must be between 0 and 1");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "Fix griddem/rom requires atom_style sphere");
  period = model_step = every;
  restart_global = 1;    // the model steps' schedule, so that a run read back continues it

  read_model(model_file.c_str());
  if (moving && !origin_given)
    error->all(FLERR, "Fix griddem/rom: model {} has a moving frame (line 'frame moving'): keyword origin is "
               "required", model_file);
  if (origin_given && !moving)
    error->all(FLERR, "Fix griddem/rom: keyword origin needs a model with a moving frame (line 'frame moving'); "
               "model {} has its box in the simulation box", model_file);
  if ((int) control_names.size() != ncontrol)
    error->all(FLERR, "Fix griddem/rom: model {} has {} controls, the fix names {} (keyword control)",
               model_file, ncontrol, control_names.size());

  const int igroup_kin = group->find_or_create((std::string(id) + "_kinematic").c_str());
  kinematic_bit = group->bitmask[igroup_kin];
  const int igroup_dyn = group->find_or_create((std::string(id) + "_dynamic").c_str());
  dynamic_bit = group->bitmask[igroup_dyn];
  const int igroup_lag = group->find_or_create((std::string(id) + "_lagging").c_str());
  lagging_bit = group->bitmask[igroup_lag];

  peratom_flag = 1;
  size_peratom_cols = 0;
  peratom_freq = 1;
  vector_flag = 1;
  size_vector = NCOUNTER + 5;
  global_freq = 1;
  extvector = 0;
  comm_forward = 1;
  pergrid_flag = 1;
  pergrid_freq = every;

  create_attribute = 1;
  force_reneighbor = 1;    // the store's steps: its atoms leave and return before LAMMPS's exchange
  next_reneighbor = -1;

  FixGriddemRom::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);
  fill_state();
}

FixGriddemRom::~FixGriddemRom()
{
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(state);
  memory->destroy(fpair);
  memory->destroy(track);
  griddem_bins_free(&check_bins);
  griddem_bins_free(&near_bins);
  deallocate_grid();
  delete irregular;
}

int FixGriddemRom::setmask()
{
  return INITIAL_INTEGRATE | PRE_EXCHANGE | POST_NEIGHBOR | PRE_REVERSE | END_OF_STEP | POST_RUN;
}

/* The model file (griddem_rom_model.h), read and checked on rank 0 and sent to all. */
void FixGriddemRom::read_model(const char *file)
{
  griddem_rom_model model = {};
  std::string msg;
  if (comm->me == 0) {
    std::vector<char> message(GRIDDEM_ROM_MODEL_MESSAGE + strlen(file));
    if (griddem_rom_model_read(file, &model, message.data(), message.size()) != 0) msg = message.data();
  }
  int len = msg.size();
  MPI_Bcast(&len, 1, MPI_INT, 0, world);
  msg.resize(len);
  MPI_Bcast(&msg[0], len, MPI_CHAR, 0, world);
  if (len) error->all(FLERR, "Fix griddem/rom: {}", msg);
  frame_grid = model.box;
  int flags[4] = {model.moving, model.ncontrol, model.force != nullptr, model.form};
  MPI_Bcast(frame_grid.n, 3, MPI_INT, 0, world);
  MPI_Bcast(frame_grid.lo, 3, MPI_DOUBLE, 0, world);
  MPI_Bcast(frame_grid.hi, 3, MPI_DOUBLE, 0, world);
  MPI_Bcast(flags, 4, MPI_INT, 0, world);
  grid = frame_grid;
  moving = flags[0] != 0;
  ncontrol = flags[1];
  form = flags[3];
  const int nvox = griddem_rom_nvoxel(&grid);
  const size_t ncol = form == GRIDDEM_ROM_OCCUPANCY ? 1 + ncontrol : 1 + nvox + ncontrol;
  weights.resize(3 * nvox * ncol);
  force_weights.resize(flags[2] ? 3 * ncol : 0);
  if (comm->me == 0) {
    std::copy(model.weights, model.weights + weights.size(), weights.begin());
    if (model.force) std::copy(model.force, model.force + force_weights.size(), force_weights.begin());
  }
  griddem_rom_model_free(&model);
  MPI_Bcast(weights.data(), weights.size(), MPI_DOUBLE, 0, world);
  MPI_Bcast(force_weights.data(), force_weights.size(), MPI_DOUBLE, 0, world);
  density.assign(nvox, 0.0);
  feature.assign(ncol, 0.0);
  field.assign(3 * nvox, 0.0);
}

/* The voxels in the simulation box: the model's box, shifted by the frame's origin where it moves. */
void FixGriddemRom::place_grid()
{
  if (!moving) return;
  for (int d = 0; d < 3; d++)
    if (origin_vars[d] >= 0) {
      origin[d] = input->variable->compute_equal(origin_vars[d]);
      if (!std::isfinite(origin[d]))
        error->all(FLERR, "Fix griddem/rom: origin variable {} is {} at step {}", origin_names[d], origin[d],
                   update->ntimestep);
    }
  griddem_rom_place(&frame_grid, origin, &grid);    // frame_grid has the box's periodicity (init)
}

void FixGriddemRom::init()
{
  if (!force->pair || !utils::strmatch(force->pair_style, "^griddem/"))
    error->all(FLERR, "Fix griddem/rom needs a griddem pair style (it skips kinematic-kinematic "
               "pairs through the pair's exclusions); pair style is {}",
               force->pair ? force->pair_style : "none");
  if (domain->dimension != 3) error->all(FLERR, "Fix griddem/rom requires a 3d simulation (its voxels are 3d)");
  if (domain->triclinic) error->all(FLERR, "Fix griddem/rom does not support triclinic boxes (its voxels are orthogonal)");
  for (int d = 0; d < 3; d++) {
    frame_grid.periodic[d] = grid.periodic[d] = domain->periodicity[d];
    if (moving && domain->periodicity[d] && (!origin_names[d].empty() || origin[d] != 0.0))
      error->all(FLERR, "Fix griddem/rom: keyword origin moves the frame along the periodic axis {}; "
                 "give 0 there", "xyz"[d]);
  }
  check_box();
  for (int d = 0; d < 3; d++) {
    origin_vars[d] = -1;
    if (origin_names[d].empty()) continue;
    origin_vars[d] = input->variable->find(origin_names[d].c_str());
    if (origin_vars[d] < 0)
      error->all(FLERR, "Fix griddem/rom: origin variable {} does not exist", origin_names[d]);
    if (!input->variable->equalstyle(origin_vars[d]))
      error->all(FLERR, "Fix griddem/rom: origin variable {} is not equal-style", origin_names[d]);
  }
  place_grid();
  resolved = nullptr;
  if (!resolved_id.empty()) {
    resolved = domain->get_region_by_id(resolved_id);
    if (!resolved) error->all(FLERR, "Fix griddem/rom: region {} (keyword resolved) does not exist", resolved_id);
  }
  if (!comm->ghost_velocity)
    error->all(FLERR, "Fix griddem/rom needs comm_modify vel yes (its hit test reads ghost velocities)");
  if (!grid3d) allocate_grid();
  control_vars.clear();
  for (const auto &name : control_names) {
    const int ivar = input->variable->find(name.c_str());
    if (ivar < 0) error->all(FLERR, "Fix griddem/rom: control variable {} does not exist", name);
    if (!input->variable->equalstyle(ivar))
      error->all(FLERR, "Fix griddem/rom: control variable {} is not equal-style", name);
    control_vars.push_back(ivar);
  }
  // kinematic atoms are moved by this fix alone: an integrator of atoms of the fix's group must
  // integrate ID_dynamic
  const int *mask = atom->mask;
  for (auto &ifix : modify->get_fix_list()) {
    if (ifix == this || !ifix->time_integrate || ifix->groupbit == dynamic_bit) continue;
    int mine = 0, all = 0;
    for (int i = 0; i < atom->nlocal; i++) mine += (mask[i] & ifix->groupbit) && (mask[i] & groupbit);
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_SUM, world);
    if (all)
      error->all(FLERR, "Fix griddem/rom: fix {} ({}) integrates group {}, which holds atoms of the fix's "
                 "group; integrate group {}_dynamic instead", ifix->id, ifix->style, group->names[ifix->igroup], id);
  }
  // a fix that adds forces to kinematic atoms (its group is not ID_dynamic), gravity aside, is
  // answered by the force rule each step; otherwise kinematic atoms cost nothing between model steps
  force_each_step = false;
  for (auto &ifix : modify->get_fix_list())
    if (ifix != this && (ifix->setmask() & POST_FORCE) && ifix->groupbit != dynamic_bit &&
        !utils::strmatch(ifix->style, "^gravity"))
      force_each_step = true;
  // the store leaves the force rule of other fixes nothing to watch, and holds lagging atoms
  // where they were, on the process that took them out: not with fixes that act on kinematic atoms,
  // nor where sub-domains or the box move under them
  store_active = store_wanted && !force_each_step;
  std::string unstorable;
  if (!modify->get_fix_by_style("^balance").empty()) unstorable = "fix balance moves sub-domains";
  else if (!modify->get_fix_by_style("^deform").empty()) unstorable = "fix deform changes the box";
  else if (domain->nonperiodic == 2) unstorable = "a shrink-wrapped boundary moves the box";
  if (store_active && !unstorable.empty()) {
    store_active = false;
    if (comm->me == 0)
      error->warning(FLERR, "Fix griddem/rom: {} while lagging atoms would be held out of LAMMPS on the process "
                     "that took them out; they stay in LAMMPS's arrays (keyword store ignored)", unstorable);
  }
  grid_computes = modify->get_compute_by_style("^griddem/cg$");
  for (auto *compute : modify->get_compute_by_style("^griddem/grid$")) grid_computes.push_back(compute);
  grid_averages = modify->get_fix_by_style("^ave/grid");
  grid_dumps_in_place = true;
  for (const auto &compute : modify->get_compute_list()) {
    auto cg = dynamic_cast<ComputeGriddemCg *>(compute);
    if (compute->pergrid_flag && !(cg && cg->reads_store())) grid_dumps_in_place = false;
  }
  for (const auto &ifix : modify->get_fix_list())
    if (ifix->pergrid_flag && ifix != this && !utils::strmatch(ifix->style, "^ave/grid")) grid_dumps_in_place = false;
  gravities.clear();
  for (auto &ifix : modify->get_fix_by_style("^gravity")) {
    int dim = 0;
    auto gvec = (const double *) ifix->extract("gvec", dim);
    if (gvec) gravities.emplace_back(ifix->groupbit, gvec);
  }
  // no atom lags until the reach test of this run's setup: the pair's setup step sees every
  // kinematic atom, wherever the script has moved atoms since the last run
  for (int i = 0; i < atom->nlocal; i++) atom->mask[i] &= ~lagging_bit;
}

/* a model box in the simulation box equals it; a moving frame may be any box, but along a
   periodic axis it is the box's period, and it does not move there. Checked at every model step
   too, since fix deform may change the box during a run. */

void FixGriddemRom::check_box()
{
  for (int d = 0; d < 3; d++) {
    const double len = domain->boxhi[d] - domain->boxlo[d];
    if (moving && !domain->periodicity[d]) continue;
    if (fabs(frame_grid.lo[d] - domain->boxlo[d]) > 1e-9 * len ||
        fabs(frame_grid.hi[d] - domain->boxhi[d]) > 1e-9 * len)
      error->all(FLERR, "Fix griddem/rom: model box {} {} along axis {} differs from the simulation box {} {}{}{}",
                 frame_grid.lo[d], frame_grid.hi[d], "xyz"[d], domain->boxlo[d], domain->boxhi[d],
                 moving ? " (a moving frame spans the box along a periodic axis)" : "",
                 update->ntimestep > update->firststep ? fmt::format(" at step {}", update->ntimestep) : "");
  }
}

void FixGriddemRom::setup(int)
{
  // the reach test looks for dynamic atoms among the owned and ghost atoms: a gap up to the ghost
  // cutoff less the longest contact distance is seen on every process
  double rmax = 0.0, rall = 0.0;
  for (int i = 0; i < atom->nlocal; i++) rmax = MAX(rmax, atom->radius[i]);
  MPI_Allreduce(&rmax, &rall, 1, MPI_DOUBLE, MPI_MAX, world);
  cap = comm->get_comm_cutoff() - 2.0 * rall;
  if (cap <= 0.0 && rall > 0.0 && comm->me == 0)
    error->warning(FLERR, "Fix griddem/rom: the ghost cutoff {} leaves no reach beyond the largest contact "
                   "distance {}: all kinematic atoms move at DEM's step (raise comm_modify cutoff)",
                   comm->get_comm_cutoff(), 2.0 * rall);
  reach = reach_user < 0.0 ? MAX(cap, 0.0) : reach_user;
  if (reach > MAX(cap, 0.0) && reach > 0.0)
    error->all(FLERR, "Fix griddem/rom: keyword reach {} exceeds the ghost cutoff's bound {} (the ghost cutoff "
               "less the largest contact distance); raise comm_modify cutoff", reach, cap);
  int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    mask[i] = (mask[i] & kinematic_bit) ? (mask[i] & ~dynamic_bit) : (mask[i] | dynamic_bit);
  const bool never_classified = next_model < 0;
  last_model = update->ntimestep;
  if (next_model <= update->ntimestep) next_model = update->ntimestep + model_step;
  comm->forward_comm(this);
  // drive box and dense drive atoms whatever their motion: from the first step on (drive match
  // first classifies after N steps)
  if (drive != DRIVE_MATCH && never_classified) classify();
  mark_near();
  store_active = store_active && cap > 0.0;    // without reach no atom lags
  check_records();
  plan_store();
  fill_state();
}

void FixGriddemRom::setup_pre_reverse(int eflag, int vflag)
{
  pre_reverse(eflag, vflag);
}

/* Kinematic atoms within reach of a dynamic atom move at DEM's step; the others wait for the
   next model step (catch_up). */
void FixGriddemRom::initial_integrate(int)
{
  double **x = atom->x, **v = atom->v;
  const int *mask = atom->mask;
  const double dt = update->dt;
  for (const int i : nearlist)
    if (mask[i] & kinematic_bit)
      for (int d = 0; d < 3; d++) x[i][d] += dt * v[i][d];
}

/* Atoms appear only at reneighboring (fix pour, create_atoms): a new atom could land within reach
   of a lagging one, so the reach test runs before the pair sees it. */
void FixGriddemRom::post_neighbor()
{
  if (reach_due) {    // the skin rule fired (counted then): the stored atoms are back and up to date
    reach_due = false;
    mark_near();
    plan_store();
    return;
  }
  int mine = fresh ? 1 : 0, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, world);
  if (any && nstored_all > 0.0) {
    // atoms held while others appeared (stored atoms are back at the steps where other fixes
    // create atoms, so only a fix that creates them unannounced gets here): the reach test needs
    // them, at the next step
    reach_due = true;
    counts[REACH_TESTS] += 1;
    return_at = next_reneighbor = update->ntimestep + 1;
    fill_nearlist();
  } else if (any) {
    mark_near();
    counts[REACH_TESTS] += 1;
    plan_store();
  } else
    fill_nearlist();
}

void FixGriddemRom::fill_nearlist()
{
  nearlist.clear();
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if ((mask[i] & kinematic_bit) && track[i][TRACK_NEAR] != 0.0) nearlist.push_back(i);
}

/* The pair has run and no fix has added forces yet (griddem styles give ghosts nothing, so the
   owned atoms' forces are final): f is the contact forces, kept for the force rule. */
void FixGriddemRom::pre_reverse(int, int)
{
  if (!force_each_step && update->ntimestep != next_model) return;
  double **f = atom->f;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & kinematic_bit)
      for (int d = 0; d < 3; d++) fpair[i][d] = f[i][d];
}

/* A kinematic atom is released (made dynamic) when the force on it other than its contacts with
   atoms and gravity would change its velocity by more than eps v0 within a model step:
   |f - f_pair - m g| M dt / m > eps v0: a wall it is driven into, or another fix's force. Its
   contacts with dynamic atoms do not count: in a resting pile a kinematic atom carries the weight
   of dynamic ones above it, which is no reason to release it; a dynamic atom that hits it is
   judged by the hit test at the next classification. Gravity is the field's business. A lagging
   atom is brought up to date first; a released atom gets budget 0, so the reach test runs again
   at this step's end. */
void FixGriddemRom::release_by_force()
{
  int *mask = atom->mask;
  double **f = atom->f, **x = atom->x, **v = atom->v;
  const double *rmass = atom->rmass;
  const double scale = model_step * update->dt, threshold = eps * v0;
  const double lag = (update->ntimestep - last_model) * update->dt;
  int released = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & kinematic_bit)) continue;
    double fo[3] = {f[i][0] - fpair[i][0], f[i][1] - fpair[i][1], f[i][2] - fpair[i][2]};
    for (const auto &g : gravities)
      if (mask[i] & g.first)
        for (int d = 0; d < 3; d++) fo[d] -= rmass[i] * g.second[d];
    const double fm2 = fo[0] * fo[0] + fo[1] * fo[1] + fo[2] * fo[2];
    if (sqrt(fm2) * scale > threshold * rmass[i]) {
      if (track[i][TRACK_NEAR] == 0.0)
        for (int d = 0; d < 3; d++) x[i][d] += lag * v[i][d];
      mask[i] = (mask[i] & ~(kinematic_bit | lagging_bit)) | dynamic_bit;
      for (int d = 0; d < 3; d++) track[i][TRACK_X + d] = x[i][d];
      track[i][TRACK_BUDGET] = track[i][TRACK_NEAR] = 0.0;
      released++;
    }
  }
  int all = 0;
  MPI_Allreduce(&released, &all, 1, MPI_INT, MPI_SUM, world);
  if (all && lag > 0.0) jumped = true;    // a lagging atom released has caught up (on every process alike)
  if (all) {
    comm->forward_comm(this);    // the ghosts of released atoms too
    counts[RELEASED_FORCE] += all;
    counts[KINEMATIC] -= all;
  }
}

/* The lagging kinematic atoms to the present: x += v (steps since last_model) dt. */
void FixGriddemRom::catch_up()
{
  const double lag = (update->ntimestep - last_model) * update->dt;
  if (lag > 0.0) {
    double **x = atom->x, **v = atom->v;
    const int *mask = atom->mask;
    for (int i = 0; i < atom->nlocal; i++)
      if ((mask[i] & kinematic_bit) && track[i][TRACK_NEAR] == 0.0)
        for (int d = 0; d < 3; d++) x[i][d] += lag * v[i][d];
    jumped = true;
  }
  last_model = update->ntimestep;
}

/* The held atoms a reach test on this process takes part with, each as (x, y, z, radius): this
   process's (nstored, where they are) and, on several processes, the others' that lie, as
   themselves or as a periodic image, within the ghost cutoff of this sub-domain (no process holds
   ghosts of held atoms, and a held atom may have drifted from its process's sub-domain), with the
   process and record each came from (from); in images, the periodic images of this process's that
   lie within that reach. */
void FixGriddemRom::held_within_reach(std::vector<double> &held, std::vector<double> &images,
                                      std::vector<std::pair<int, int>> &from) const
{
  const int nprocs = comm->nprocs, me = comm->me;
  const double cut = comm->get_comm_cutoff();
  const double *prd = domain->prd;
  // on several processes, each one's sub-domain widened by the cutoff (orthogonal:
  // reach_test_in_place)
  std::vector<double> reach_of(nprocs > 1 ? 6 * (size_t) nprocs : 0);
  if (nprocs > 1) {
    double mine[6];
    for (int d = 0; d < 3; d++) mine[d] = domain->sublo[d] - cut, mine[3 + d] = domain->subhi[d] + cut;
    MPI_Allgather(mine, 6, MPI_DOUBLE, reach_of.data(), 6, MPI_DOUBLE, world);
  }
  auto within = [&](const double *p, int q) {
    const double *b = &reach_of[6 * (size_t) q];
    return p[0] >= b[0] && p[0] <= b[3] && p[1] >= b[1] && p[1] <= b[4] && p[2] >= b[2] && p[2] <= b[5];
  };
  held.resize(4 * (size_t) nstored);
  images.clear(), from.clear();
  const double *lo = domain->boxlo, *hi = domain->boxhi;
  const int *periodic = domain->periodicity;
  std::vector<std::vector<double>> send(nprocs);    // (x, y, z, radius, record) for each process
  for (int k = 0; k < nstored; k++) {
    const double *p = &stored[record_at[k] + RECORD_X], radius = stored[record_at[k] + RECORD_RADIUS];
    double *h = &held[4 * (size_t) k];
    h[0] = p[0], h[1] = p[1], h[2] = p[2], h[3] = radius;
    // per axis the shifts by the box's length that keep the point within the cutoff of the box
    int nshift[3], shift[3][3];
    for (int d = 0; d < 3; d++) {
      nshift[d] = 0;
      shift[d][nshift[d]++] = 0;
      if (periodic[d]) {
        if (p[d] + prd[d] <= hi[d] + cut) shift[d][nshift[d]++] = 1;
        if (p[d] - prd[d] >= lo[d] - cut) shift[d][nshift[d]++] = -1;
      }
    }
    for (int a = 0; a < nshift[0]; a++)
      for (int b = 0; b < nshift[1]; b++)
        for (int c = 0; c < nshift[2]; c++) {
          const bool itself = a == 0 && b == 0 && c == 0;
          if (itself && nprocs == 1) continue;
          const double image[4] = {p[0] + shift[0][a] * prd[0], p[1] + shift[1][b] * prd[1],
                                   p[2] + shift[2][c] * prd[2], radius};
          if (nprocs == 1) {    // (the sub-domain is the box: the shifts keep it within the cutoff)
            images.insert(images.end(), image, image + 4);
            continue;
          }
          for (int q = 0; q < nprocs; q++) {
            if (!within(image, q)) continue;
            if (q != me) {
              send[q].insert(send[q].end(), image, image + 4);
              send[q].push_back(k);
            } else if (!itself)
              images.insert(images.end(), image, image + 4);
          }
        }
  }
  if (nprocs == 1) return;
  std::vector<int> start;
  const std::vector<double> in = exchange_lists(send, MPI_DOUBLE, world, start);
  for (int q = 0; q < nprocs; q++)
    for (int m = start[q]; m < start[q + 1]; m += 5) {
      held.insert(held.end(), &in[m], &in[m] + 4);
      from.emplace_back(q, (int) in[m + 4]);
    }
}

/* The near flags this process found for other processes' held atoms (near, one per entry of from)
   sent to those processes, which mark their records near (stored_near). */
void FixGriddemRom::near_elsewhere(const std::vector<std::pair<int, int>> &from, const int *near)
{
  const int nprocs = comm->nprocs;
  std::vector<std::vector<int>> send(nprocs);
  for (size_t j = 0; j < from.size(); j++)
    if (near[j]) send[from[j].first].push_back(from[j].second);
  std::vector<int> start;
  for (const int k : exchange_lists(send, MPI_INT, world, start)) stored_near[k] = 1;
}

/* Which kinematic atoms move at DEM's step (near: a dynamic atom within reach), and how far each
   dynamic atom may move before a lagging one could meet it (its budget); griddem_rom_mark_near.
   Positions and masks of the ghosts must be current. Atoms held in the store (only where
   reach_test_in_place) take part where they are (held_within_reach): those found near are marked
   to come back, where their own process or another found them near. */
void FixGriddemRom::mark_near()
{
  const int nlocal = atom->nlocal, nghost = atom->nghost;
  double **x = atom->x, **v = atom->v;
  int *mask = atom->mask;
  const int ns = nstored;
  std::vector<double> held, images;
  std::vector<std::pair<int, int>> from;
  if (nstored_all > 0.0) held_within_reach(held, images, from);
  // the held atoms take part as owned atoms after LAMMPS's (so that each gets its near flag), the
  // images of this process's after LAMMPS's ghosts
  const int nheld = (int) held.size() / 4, nimage = (int) images.size() / 4, nown = nlocal + nheld;
  std::vector<int> kinematic(nown + nghost + nimage), near(nown);
  std::vector<double> budget(nown), points, radii;
  const double *xs = nlocal + nghost ? x[0] : nullptr, *rs = atom->radius;
  for (int j = 0; j < nlocal + nghost; j++) kinematic[j < nlocal ? j : j + nheld] = (mask[j] & kinematic_bit) ? 1 : 0;
  if (nheld > 0) {
    const size_t nall = kinematic.size();
    points.resize(3 * nall);
    radii.resize(nall);
    if (nlocal + nghost) {
      std::copy(xs, xs + 3 * (size_t) nlocal, points.begin());
      std::copy(xs + 3 * (size_t) nlocal, xs + 3 * (size_t) (nlocal + nghost), points.begin() + 3 * (size_t) nown);
      std::copy(rs, rs + nlocal, radii.begin());
      std::copy(rs + nlocal, rs + nlocal + nghost, radii.begin() + nown);
    }
    for (int k = 0; k < nheld + nimage; k++) {
      const size_t at = k < nheld ? nlocal + k : nown + nghost + (k - nheld);
      const double *p = k < nheld ? &held[4 * (size_t) k] : &images[4 * (size_t) (k - nheld)];
      std::copy(p, p + 3, points.begin() + 3 * at);
      radii[at] = p[3];
      kinematic[at] = 1;
    }
    xs = points.data(), rs = radii.data();
  }
  const int nall = (int) kinematic.size();
  if (cap <= 0.0) {
    std::fill(near.begin(), near.end(), 1);
    std::fill(budget.begin(), budget.end(), INFINITY);
  } else if (nall && griddem_rom_mark_near(nown, nall, xs, rs, kinematic.data(), reach, cap, near.data(), budget.data(),
                                           &near_grid, &near_bins) != 0)
    error->one(FLERR, "Fix griddem/rom: out of memory for the reach test of {} atoms", nall);
  double umax = 0.0, nnear = 0.0, nkin = 0.0;
  for (int i = 0; i < nlocal; i++) {
    nkin += kinematic[i];
    for (int d = 0; d < 3; d++) track[i][TRACK_X + d] = x[i][d];
    track[i][TRACK_BUDGET] = budget[i];
    track[i][TRACK_NEAR] = near[i] && kinematic[i];
    nnear += track[i][TRACK_NEAR];
    const bool lagging = kinematic[i] && !near[i];
    mask[i] = lagging ? (mask[i] | lagging_bit) : (mask[i] & ~lagging_bit);
    if (lagging) umax = MAX(umax, sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]));
  }
  stored_near.assign(ns, 0);
  stored_budget.assign(ns, 0.0);
  for (int k = 0; k < ns; k++) stored_near[k] = near[nlocal + k] ? 1 : 0;
  if (comm->nprocs > 1 && nstored_all > 0.0) near_elsewhere(from, &near[nlocal + ns]);
  for (int k = 0; k < ns; k++) {    // near: back at the next step; lagging: out, as they were
    nkin += 1.0;
    stored_budget[k] = budget[nlocal + k];
    nnear += stored_near[k];
    const double *vk = &stored[record_at[k] + RECORD_V];
    if (!stored_near[k]) umax = MAX(umax, sqrt(vk[0] * vk[0] + vk[1] * vk[1] + vk[2] * vk[2]));
  }
  comm->forward_comm(this);    // the ghosts' lagging bits: the pair leaves lagging atoms out
  fresh = false;
  MPI_Allreduce(&umax, &umax_far, 1, MPI_DOUBLE, MPI_MAX, world);
  double mine[2] = {nnear, nkin}, all[2];
  MPI_Allreduce(mine, all, 2, MPI_DOUBLE, MPI_SUM, world);
  counts[NEAR] = all[0];
  counts[KINEMATIC] = all[1];
  nfar = all[1] - all[0];
  fill_nearlist();
}

/* At a model step: the lagging atoms to the present, the force rule, the classification, the
   reach test. Between: the force rule where needed, and the skin rule of the lagging atoms: a
   dynamic atom that has moved, plus the lagging atoms' possible travel, as far as its budget
   brings all kinematic atoms up to date and runs the reach test again. */
void FixGriddemRom::end_of_step()
{
  const double t0 = MPI_Wtime();
  if (update->ntimestep == next_model) {
    check_box();
    catch_up();
    comm->forward_comm();
    release_by_force();
    classify();
    mark_near();
    plan_store();
  } else {
    if (force_each_step) release_by_force();
    double **x = atom->x;
    const int *mask = atom->mask;
    const double travel = umax_far * (update->ntimestep - last_model) * update->dt;
    int mine = 0, any = 0;
    for (int i = 0; i < atom->nlocal && !mine && nfar > 0.0; i++) {
      if (mask[i] & kinematic_bit) continue;
      const double *x0 = &track[i][TRACK_X];
      double dx[3] = {x[i][0] - x0[0], x[i][1] - x0[1], x[i][2] - x0[2]};
      domain->minimum_image(dx);
      mine = sqrt(dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2]) + travel >= track[i][TRACK_BUDGET];
    }
    MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, world);
    if (any) counts[REACH_TESTS] += 1;
    if (any && nstored_all > 0.0 && !reach_test_in_place()) {    // the stored atoms come back first: next step
      reach_due = true;
      return_at = next_reneighbor = update->ntimestep + 1;
    } else if (any) {
      catch_up_store();
      catch_up();
      comm->forward_comm();
      mark_near();
      plan_store();
      int near_here = std::find(stored_near.begin(), stored_near.end(), 1) != stored_near.end(), near_any = 0;
      MPI_Allreduce(&near_here, &near_any, 1, MPI_INT, MPI_MAX, world);
      if (near_any) near_return_at = update->ntimestep + 1;    // every process returns its own then
    }
    if (nstored_all > 0.0) plan_return();
    arm_reneighbor();
  }
  counts[SECONDS] += MPI_Wtime() - t0;
  fill_state();
}

void FixGriddemRom::post_run()
{
  if (nstored_all > 0.0) return_stored(false);    // a run stopped early (fix halt, timer)
  catch_up();
  if (jumped) migrate_far();    // (LAMMPS's next exchange, a command's or a run's set-up, reaches neighbours only)
  store_at = return_at = near_return_at = next_reneighbor = -1;
  reach_due = false;
}

/* ----------------------------------------------------------------------
   the store (doc/fix_griddem_rom.md, keyword store)
------------------------------------------------------------------------- */

/* The first step from `from` on at which another fix acts at its pre_exchange (fix pour, fix
   deposit, fix evaporate: they create or delete atoms among LAMMPS's, and a new atom must not
   land on a stored one), or MAXBIGINT. */
bigint FixGriddemRom::next_other_exchange(bigint from) const
{
  bigint next = MAXBIGINT;
  for (const auto &ifix : modify->get_fix_list())
    if (ifix != this && ifix->force_reneighbor && ifix->next_reneighbor >= from)
      next = MIN(next, ifix->next_reneighbor);
  return next;
}

/* The first step from `from` on that a compute griddem/cg or griddem/grid may be invoked on, or
   MAXBIGINT, so that its fields see every atom: a step announced to it (dumps, thermo: LAMMPS's
   list of the steps a compute is invoked on), or a step of a fix ave/grid, which invokes per-grid
   computes unannounced (or bins atoms itself), on multiples of its Nevery. */
bigint FixGriddemRom::next_grid_step(bigint from) const
{
  bigint next = MAXBIGINT;
  for (const auto &compute : grid_computes) {
    auto cg = dynamic_cast<ComputeGriddemCg *>(compute);
    if (cg && cg->reads_store() && fields_in_place()) continue;    // it reads them where they are
    for (int k = compute->ntime - 1; k >= 0; k--)    // the list is in decreasing order
      if (compute->tlist[k] >= from) {
        next = MIN(next, compute->tlist[k]);
        break;
      }
  }
  for (const auto &ave : grid_averages)
    if (ave->nevery > 0) next = MIN(next, (from + ave->nevery - 1) / ave->nevery * ave->nevery);
  return next;
}

/* The next dump step that needs the stored atoms back (as output->next_dump_any, this step's
   included): every dump's, but a grid dump's where grid_dumps_in_place and fields_in_place() (the
   computes it can dump read them where they are held). */
bigint FixGriddemRom::next_dump_of_atoms() const
{
  const bool grids_read_store = grid_dumps_in_place && fields_in_place();
  bigint next = MAXBIGINT;
  for (int k = 0; k < output->ndump; k++)
    if (!(grids_read_store && utils::strmatch(output->dump[k]->style, "^grid"))) next = MIN(next, output->next_dump[k]);
  return next;
}

/* After a reach test: the lagging atoms leave at the next step's exchange, or the one after if
   another fix acts then (its pre_exchange may come before this fix's). */
void FixGriddemRom::plan_store()
{
  bigint at = update->ntimestep + 1;
  if (next_other_exchange(at) == at) at++;
  if (!store_active || at >= update->laststep) return;
  store_at = next_reneighbor = at;
}

/* The first step that needs the stored atoms back in LAMMPS: the next model step, a dump, a
   restart file, a compute griddem/cg, the run's last step (each at its pre_exchange, before the
   step's end of step and output), the step before another fix acts at its pre_exchange, or an
   earlier return already planned. */
void FixGriddemRom::plan_return()
{
  bigint due = MIN(next_model, update->laststep);
  due = MIN(due, next_dump_of_atoms());
  due = MIN(due, output->next_restart);
  const bigint other = next_other_exchange(update->ntimestep + 1);
  if (other < MAXBIGINT) due = MIN(due, other - 1);
  due = MIN(due, next_grid_step(update->ntimestep + 1));
  due = MAX(due, update->ntimestep + 1);    // this step's exchange is past
  if (return_at < 0 || due < return_at) return_at = next_reneighbor = due;
}

/* LAMMPS's exchange (and its decision to make one) comes after pre_exchange: atoms that leave or
   come back here are in the step's migration, borders and ghosts. A planned step is also met
   late, at the next reneighboring, should another fix have forced one past it. */
void FixGriddemRom::pre_exchange()
{
  const bigint now = update->ntimestep;
  if (now >= next_reneighbor) next_reneighbor = -1;
  // the atoms the in-place reach test found near first, as near atoms, also where all come back
  if (near_return_at >= 0 && now >= near_return_at) return_near();
  near_return_at = -1;
  if (nstored_all > 0.0 && now >= return_at) {
    return_stored(true);
    return_at = -1;
    if (reach_due) catch_up();    // the reach test follows at post_neighbor
    else if (now != next_model) plan_store();    // a dump, restart or the last step: out again after it
  }
  if (store_at >= 0 && now >= store_at) {
    store_at = -1;
    store_lagging();
  }
  if (jumped) migrate_far();
  arm_reneighbor();
}

/* LAMMPS's exchange passes an atom to a neighbouring process only: atoms that came back from the
   store or caught up with the field since the last exchange (jumped) may have gone further, and
   go by irregular communication, as fix balance moves atoms (wrapped into the box first). */
void FixGriddemRom::migrate_far()
{
  jumped = false;
  if (comm->nprocs == 1) return;
  if (!irregular) irregular = new Irregular(lmp);
  if (domain->triclinic) domain->x2lamda(atom->nlocal);
  domain->pbc();
  if (comm->layout == Comm::LAYOUT_TILED || irregular->migrate_check()) irregular->migrate_atoms();
  if (domain->triclinic) domain->lamda2x(atom->nlocal);
}

/* The next step whose pre_exchange takes atoms out or brings them back, as the step LAMMPS is asked
   to reneighbor at (-1: none). */
void FixGriddemRom::arm_reneighbor()
{
  next_reneighbor = -1;
  for (const bigint at : {store_at, return_at, near_return_at})
    if (at >= 0 && (next_reneighbor < 0 || at < next_reneighbor)) next_reneighbor = at;
}

/* Take this process's lagging atoms out of LAMMPS's arrays, each packed by LAMMPS's exchange
   packing (the atom and every fix's data of it), as fix evaporate deletes atoms. */
void FixGriddemRom::store_lagging()
{
  const int *mask = atom->mask;
  double lagging = 0.0, lagging_all = 0.0;
  for (int i = 0; i < atom->nlocal; i++) lagging += (mask[i] & lagging_bit) ? 1.0 : 0.0;
  if (nstored_all == 0.0) return_at = -1;
  plan_return();
  MPI_Allreduce(&lagging, &lagging_all, 1, MPI_DOUBLE, MPI_SUM, world);
  // a store and its return cost about two reneighborings of every atom, and each held atom saves
  // its share of a step's per-atom loops while it is out: only so many atom-steps out pay for it
  if ((double) (return_at - update->ntimestep) * lagging_all < STORE_PAYBACK * (double) atom->natoms) {
    if (nstored_all == 0.0) return_at = next_reneighbor = -1;
    return;
  }
  const size_t record = record_room();
  AtomVec *avec = atom->avec;
  int taken = 0, kept = 0;
  // the atoms that stay close ranks in order: most of a bed lags at once, so moving the few that
  // stay costs less than filling each hole with the last atom
  for (int i = 0; i < atom->nlocal; i++) {
    if (mask[i] & lagging_bit) {
      if (stored.size() < stored_used + record) stored.resize(2 * (stored_used + record));
      const size_t at = stored_used;
      stored_used += avec->pack_exchange(i, &stored[at]);
      record_at.push_back(at);
      taken++;
    } else {
      if (kept != i) avec->copy(i, kept, 1);
      kept++;
    }
  }
  atom->nlocal = kept;
  nstored += taken;
  double counts_mine[2] = {(double) taken, (double) nstored}, counts_all[2];
  MPI_Allreduce(counts_mine, counts_all, 2, MPI_DOUBLE, MPI_SUM, world);
  nstored_all = counts_all[1];
  atom->natoms -= (bigint) counts_all[0];
  if (nstored_all == 0.0) return_at = next_reneighbor = -1;
  reset_local_map();
}

/* Room for one atom's record: what LAMMPS's exchange leaves for one (CommBrick: the atom style's
   and the fixes' maxexchange plus its BUFEXTRA of 1024). */
size_t FixGriddemRom::record_room() const
{
  size_t record = atom->avec->maxexchange + 1024;
  for (const auto &ifix : modify->get_fix_list()) record += ifix->maxexchange;
  return record;
}

/* Whether AtomVec::pack_exchange's records hold x, v, mask, radius and mass where RecordOffset
   says: the atom style lays them out, so once a run, on the first atom of every process that has
   one (a process without atoms keeps no other's from reading theirs). */
void FixGriddemRom::check_records()
{
  int readable = 1, readable_all = 0;
  if (atom->nlocal > 0) {
    std::vector<double> scratch(record_room());
    atom->avec->pack_exchange(0, scratch.data());
    const double *r = scratch.data();
    readable = ubuf(r[RECORD_MASK]).i == atom->mask[0] && atom->rmass && r[RECORD_RADIUS] == atom->radius[0] &&
        r[RECORD_RMASS] == atom->rmass[0];
    for (int d = 0; d < 3; d++) readable = readable && r[RECORD_X + d] == atom->x[0][d] && r[RECORD_V + d] == atom->v[0][d];
  }
  MPI_Allreduce(&readable, &readable_all, 1, MPI_INT, MPI_MIN, world);
  records_readable = readable_all != 0;
}

/* After atoms left or came back: the ghosts are rebuilt by this step's borders (or the next run's
   set-up), and the map must not point at moved atoms until then. */
void FixGriddemRom::reset_local_map()
{
  atom->nghost = 0;
  if (atom->map_style != Atom::MAP_NONE) {
    atom->map_init();
    atom->map_set();
  }
}

/* Whether the skin rule's reach test can read the stored atoms where they are instead of bringing
   them back: in an orthogonal box (their periodic images are shifts by the box's lengths), with
   records that hold x, v and the mask where AtomVec::pack_exchange puts them (check_records),
   atoms being held. */
bool FixGriddemRom::reach_test_in_place() const
{
  return !domain->triclinic && records_readable && nstored_all > 0.0;
}

/* Whether compute griddem/cg can deposit the stored atoms where they are: on one process (whose
   grid holds the ghost points of the whole periodic box), with readable records (as the reach test
   in place). */
bool FixGriddemRom::fields_in_place() const
{
  return comm->nprocs == 1 && records_readable;
}

/* The stored atoms of the group bits groupbit as compute griddem/cg deposits them: where they are
   held, as the lagging atoms LAMMPS holds would be (where the last model step or reach test left
   them), wrapped into the box along periodic axes (a held atom is not remapped by reneighboring). */
void FixGriddemRom::stored_for_fields(int groupbit, std::vector<double> &out) const
{
  for (const size_t at : record_at) {
    if (!(ubuf(stored[at + RECORD_MASK]).i & groupbit)) continue;
    double x[3] = {stored[at + RECORD_X], stored[at + RECORD_X + 1], stored[at + RECORD_X + 2]};
    domain->remap(x);
    out.insert(out.end(), x, x + 3);
    for (int d = 0; d < 3; d++) out.push_back(stored[at + RECORD_V + d]);
    out.push_back(stored[at + RECORD_RMASS]);
    out.push_back(stored[at + RECORD_RADIUS]);
  }
}

/* The stored atoms to the present in their records, as catch_up() moves LAMMPS's lagging atoms
   (before it: it sets last_model). */
void FixGriddemRom::catch_up_store()
{
  const double lag = (update->ntimestep - last_model) * update->dt;
  if (lag > 0.0)
    for (const size_t at : record_at)
      for (int d = 0; d < 3; d++) stored[at + RECORD_X + d] += lag * stored[at + RECORD_V + d];
}

/* Bring back the records the in-place reach test found near (LAMMPS's exchange unpacking), as near
   kinematic atoms moved to this step (x += v dt since that test, as initial_integrate moved the near
   atoms LAMMPS held), and close the store over the holes they leave. */
void FixGriddemRom::return_near()
{
  AtomVec *avec = atom->avec;
  const double lag = (update->ntimestep - last_model) * update->dt;
  std::vector<size_t> kept_at;
  size_t write = 0;
  int back = 0;
  for (size_t k = 0; k < record_at.size(); k++) {
    const size_t at = record_at[k], end = k + 1 < record_at.size() ? record_at[k + 1] : stored_used;
    if (stored_near[k]) {
      const int i = atom->nlocal;
      avec->unpack_exchange(&stored[at]);
      for (int d = 0; d < 3; d++) track[i][TRACK_X + d] = atom->x[i][d];
      track[i][TRACK_BUDGET] = stored_budget[k];
      track[i][TRACK_NEAR] = 1.0;
      atom->mask[i] &= ~lagging_bit;
      for (int d = 0; d < 3; d++) atom->x[i][d] += lag * atom->v[i][d];
      back++;
    } else {
      if (write != at) std::memmove(&stored[write], &stored[at], (end - at) * sizeof(double));
      kept_at.push_back(write);
      write += end - at;
    }
  }
  record_at.swap(kept_at);
  stored_near.clear();
  stored_budget.clear();
  stored_used = write;
  nstored -= back;
  int back_all = 0;
  MPI_Allreduce(&back, &back_all, 1, MPI_INT, MPI_SUM, world);
  nstored_all -= back_all;
  atom->natoms += back_all;
  jumped = true;
  reset_local_map();
}

/* Bring every stored atom back into LAMMPS's arrays (LAMMPS's exchange unpacking), as they were
   taken out: lagging, where the last model step or in-place reach test left them. Without an exchange to follow (the
   end of a run) the next run's set-up migrates them. */
void FixGriddemRom::return_stored(bool exchange_follows)
{
  AtomVec *avec = atom->avec;
  for (size_t m = 0; m < stored_used;) m += avec->unpack_exchange(&stored[m]);
  atom->natoms += (bigint) nstored_all;
  nstored = 0;
  stored_used = 0;
  nstored_all = 0.0;
  record_at.clear();
  stored_budget.clear();
  stored_near.clear();
  jumped = true;
  reset_local_map();
  if (!exchange_follows) fill_nearlist();
}

/* The voxel density, the predicted velocity field, and the new state of each atom of the group. */
void FixGriddemRom::classify()
{
  const int nlocal = atom->nlocal, nvox = griddem_rom_nvoxel(&grid);
  double **x = atom->x, **v = atom->v, **omega = atom->omega, **f = atom->f, **torque = atom->torque;
  const double *radius = atom->radius, *rmass = atom->rmass;
  int *mask = atom->mask;

  place_grid();
  std::vector<int> use(nlocal);
  for (int i = 0; i < nlocal; i++) use[i] = (mask[i] & groupbit) ? 1 : 0;
  std::vector<double> local(nvox, 0.0);
  if (nlocal) griddem_rom_deposit(&grid, nlocal, x[0], 3, rmass, use.data(), local.data());
  MPI_Allreduce(local.data(), density.data(), nvox, MPI_DOUBLE, MPI_SUM, world);
  std::vector<double> control(ncontrol);
  for (int c = 0; c < ncontrol; c++) control[c] = input->variable->compute_equal(control_vars[c]);
  if (form == GRIDDEM_ROM_OCCUPANCY) {
    griddem_rom_predict_occupancy(nvox, ncontrol, weights.data(), control.data(), density.data(), feature.data(),
                                  field.data());
  } else {
    feature[0] = 1.0;
    for (int m = 0; m < nvox; m++) feature[1 + m] = density[m];
    for (int c = 0; c < ncontrol; c++) feature[1 + nvox + c] = control[c];
    griddem_rom_predict(3 * nvox, 1 + nvox + ncontrol, weights.data(), feature.data(), field.data());
  }
  if (!force_weights.empty())    // the features of a row of weights: the occupancy form's [1, controls]
    griddem_rom_predict(3, (int) feature.size(), force_weights.data(), feature.data(), force_predicted);
  fill_grid();

  const double threshold = eps * v0;
  if (resolved) resolved->prematch();
  std::vector<int> next(nlocal, 0);
  std::vector<double> u(3 * (size_t) nlocal, 0.0);
  double made = 0, left = 0, jumps = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!use[i]) continue;
    const int was = (mask[i] & kinematic_bit) ? 1 : 0;
    if (resolved && resolved->match(x[i][0], x[i][1], x[i][2])) {
      left += was;
      continue;
    }
    if (!griddem_rom_inside(&grid, x[i])) {
      // drive box: the field is zero outside the box, so an atom at rest there is kinematic (held
      // at rest) and one that moves (one that left the box with the field's velocity) is dynamic
      if (drive == DRIVE_BOX)
        next[i] = eps > 0.0 && sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]) <= threshold;
      left += was && !next[i];
      continue;
    }
    griddem_rom_interpolate(&grid, field.data(), 3, x[i], &u[3 * i]);
    // the model drives every atom in its box (drive box), or where the material is dense (drive
    // dense), whatever it did before (eps 0: none)
    double rho = 0.0;
    if (drive == DRIVE_DENSE) griddem_rom_interpolate(&grid, density.data(), 1, x[i], &rho);
    if (drive == DRIVE_BOX || (drive == DRIVE_DENSE && rho >= dense_min)) {
      next[i] = eps > 0.0;
      continue;
    }
    const double dx = v[i][0] - u[3 * i], dy = v[i][1] - u[3 * i + 1], dz = v[i][2] - u[3 * i + 2];
    // a kinematic atom follows the field only while it changes by at most eps v0 between
    // classifications: a larger jump (a control switched, a mass distribution the model
    // extrapolates badly) releases it with its velocity instead of kicking it
    next[i] = eps > 0.0 && sqrt(dx * dx + dy * dy + dz * dz) <= threshold;
    jumps += was && !next[i];
  }

  // contacts of the (would-be) kinematic atoms: an overlap beyond overlap_max min(ri, rj), or a
  // touching partner that is not kinematic and moves at more than eps v0 relative to the atom,
  // makes (or keeps) it dynamic. Partners' states are those before this classification.
  const int nall = nlocal + atom->nghost;
  std::vector<int> kinematic(nall);
  for (int j = 0; j < nall; j++) kinematic[j] = (mask[j] & kinematic_bit) ? 1 : 0;
  int hits = 0, overlaps = 0;
  // drive box or dense: only the overlap bound releases an atom (a hit does not)
  const double hit_threshold = drive == DRIVE_MATCH ? threshold : INFINITY;
  if (nall && griddem_rom_check_contacts(nlocal, nall, x[0], v[0], radius, kinematic.data(), u.data(), hit_threshold,
                                         overlap_max, next.data(), &hits, &overlaps, &check_grid, &check_bins) != 0)
    error->one(FLERR, "Fix griddem/rom: out of memory for the contact check of {} atoms", nall);

  // voxel blocks: a voxel's atoms are kinematic only where a share block_fraction of the atoms of
  // the group in it qualify, so that kinematic atoms come in whole cells
  double held = 0;
  if (block_fraction > 0.0) {
    std::vector<int> votes(2 * (size_t) nvox, 0), sums(2 * (size_t) nvox);
    std::vector<int> voxel(nlocal, -1);
    for (int i = 0; i < nlocal; i++) {
      if (!use[i] || (voxel[i] = griddem_rom_voxel(&grid, x[i])) < 0) continue;
      votes[2 * voxel[i]] += 1;
      votes[2 * voxel[i] + 1] += next[i];
    }
    MPI_Allreduce(votes.data(), sums.data(), 2 * nvox, MPI_INT, MPI_SUM, world);
    for (int i = 0; i < nlocal; i++)
      if (next[i] && sums[2 * voxel[i] + 1] < block_fraction * sums[2 * voxel[i]]) {
        next[i] = 0;
        held += 1;
      }
  }

  // the box: a kinematic atom moves with the field until the next classification, at most `period`
  // steps; one the field would carry out through a face that is not periodic (its centre on or past
  // it) stays dynamic, which LAMMPS would otherwise lose (walls there act on dynamic atoms only)
  double held_box = 0;
  if (!freeze) {
    const double ahead = period * update->dt;
    for (int i = 0; i < nlocal; i++)
      for (int d = 0; d < 3 && next[i]; d++) {
        const double to = x[i][d] + ahead * u[3 * i + d];
        if ((domain->boundary[d][0] == 1 && to <= domain->boxlo[d]) ||
            (domain->boundary[d][1] == 1 && to >= domain->boxhi[d])) {
          next[i] = 0;
          held_box += 1;
        }
      }
  }

  double nkin = 0, umax = 0;
  for (int i = 0; i < nlocal; i++) {
    const int was = (mask[i] & kinematic_bit) ? 1 : 0;
    if (next[i]) {
      made += !was;
      nkin += 1;
      mask[i] = (mask[i] | kinematic_bit) & ~dynamic_bit;
      // freeze: the do-nothing baseline, the atoms the model would drive held at rest
      for (int d = 0; d < 3; d++) {
        v[i][d] = freeze ? 0.0 : u[3 * i + d];
        omega[i][d] = f[i][d] = torque[i][d] = 0.0;
      }
      umax = MAX(umax, sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]));
    } else
      mask[i] = (mask[i] & ~(kinematic_bit | lagging_bit)) | dynamic_bit;
  }
  comm->forward_comm(this);
  if (separate) separate_released(kinematic);

  double mine[NCOUNTER] = {}, all[NCOUNTER];
  mine[KINEMATIC] = nkin;
  mine[MADE_KINEMATIC] = made;
  mine[RELEASED_HIT] = hits;
  mine[RELEASED_OVERLAP] = overlaps;
  mine[RELEASED_LEFT] = left;
  mine[RELEASED_JUMP] = jumps;
  mine[HELD_BY_VOXEL] = held;
  mine[HELD_BY_BOX] = held_box;
  MPI_Allreduce(mine, all, NCOUNTER, MPI_DOUBLE, MPI_SUM, world);
  counts[KINEMATIC] = all[KINEMATIC];
  for (const int k : {MADE_KINEMATIC, RELEASED_HIT, RELEASED_OVERLAP, RELEASED_LEFT, RELEASED_JUMP, HELD_BY_VOXEL,
                      HELD_BY_BOX})
    counts[k] += all[k];
  counts[CLASSIFICATIONS] += 1;

  // the model step: the fastest kinematic atom crosses at most cfl of the smallest voxel edge
  double umax_all = 0.0, hmin = grid.hi[0] - grid.lo[0];
  MPI_Allreduce(&umax, &umax_all, 1, MPI_DOUBLE, MPI_MAX, world);
  for (int d = 0; d < 3; d++) hmin = MIN(hmin, (grid.hi[d] - grid.lo[d]) / grid.n[d]);
  const double steps = umax_all > 0.0 ? cfl * hmin / (umax_all * update->dt) : period;
  model_step = steps >= period ? period : MAX(1, (int) steps);
  counts[MODEL_STEP] = model_step;
  next_model = update->ntimestep + model_step;
}

/* The atoms this classification released (kinematic before it, owned or ghost: was_kinematic) start
   DEM without the overlaps the model made: the field carries kinematic atoms into each other and
   into dynamic ones, and a soft contact would return such an overlap as a speed of about
   overlap sqrt(k / m), throwing the atom out of the material (measured on examples/rom-hopper).
   One pass of griddem_rom_separate on the contact check's binning (the positions have not moved
   since), the ghosts brought up to date after it. */
void FixGriddemRom::separate_released(const std::vector<int> &was_kinematic)
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  const int *mask = atom->mask;
  std::vector<int> released(nall);
  for (int j = 0; j < nall; j++) released[j] = was_kinematic[j] && !(mask[j] & kinematic_bit);
  std::vector<double> shift(3 * (size_t) nlocal);
  const int moved = nall ? griddem_rom_separate(nlocal, nall, atom->x[0], atom->radius, released.data(), shift.data(),
                                                &check_grid, &check_bins)
                         : 0;
  if (moved < 0) error->one(FLERR, "Fix griddem/rom: out of memory for the separation of {} atoms", nall);
  int all = 0;
  MPI_Allreduce(&moved, &all, 1, MPI_INT, MPI_SUM, world);
  counts[SEPARATED] += all;
  if (all) comm->forward_comm();
}

/* ----------------------------------------------------------------------
   per-atom arrays: the state (output), the pair's forces of this step, and the reach test's
   record (moves with the atom)
------------------------------------------------------------------------- */

void FixGriddemRom::fill_state()
{
  for (int i = 0; i < atom->nlocal; i++) state[i] = (atom->mask[i] & kinematic_bit) ? 1.0 : 0.0;
}

void FixGriddemRom::grow_arrays(int n)
{
  memory->grow(state, n, "griddem/rom:state");
  memory->grow(fpair, n, 3, "griddem/rom:fpair");
  memory->grow(track, n, NTRACK, "griddem/rom:track");
  vector_atom = state;
  nmax = n;
}

void FixGriddemRom::copy_arrays(int i, int j, int)
{
  for (int k = 0; k < NTRACK; k++) track[j][k] = track[i][k];
}

/* A new atom (fix pour, create_atoms) is dynamic, with budget 0; it is not lagging, and the reach
   test runs again before the pair's next call (post_neighbor). */
void FixGriddemRom::set_arrays(int i)
{
  int *mask = atom->mask;
  mask[i] &= ~lagging_bit;
  mask[i] = (mask[i] & kinematic_bit) ? (mask[i] & ~dynamic_bit) : (mask[i] | dynamic_bit);
  fresh = true;
  for (int d = 0; d < 3; d++) track[i][TRACK_X + d] = atom->x[i][d];
  track[i][TRACK_BUDGET] = track[i][TRACK_NEAR] = 0.0;
  state[i] = 0.0;
}

int FixGriddemRom::pack_exchange(int i, double *buf)
{
  for (int k = 0; k < NTRACK; k++) buf[k] = track[i][k];
  return NTRACK;
}

int FixGriddemRom::unpack_exchange(int i, double *buf)
{
  for (int k = 0; k < NTRACK; k++) track[i][k] = buf[k];
  return NTRACK;
}

/* a ghost's kinematic and lagging bits, as one number */
namespace {
constexpr int COMM_KINEMATIC = 1, COMM_LAGGING = 2;
}

int FixGriddemRom::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  const int *mask = atom->mask;
  for (int i = 0; i < n; i++)
    buf[i] = ((mask[list_[i]] & kinematic_bit) ? COMM_KINEMATIC : 0) + ((mask[list_[i]] & lagging_bit) ? COMM_LAGGING : 0);
  return n;
}

void FixGriddemRom::unpack_forward_comm(int n, int first, double *buf)
{
  int *mask = atom->mask;
  for (int i = 0; i < n; i++) {
    const int j = first + i;
    const int bits = (int) buf[i];
    mask[j] = (bits & COMM_KINEMATIC) ? (mask[j] | kinematic_bit) & ~dynamic_bit : (mask[j] & ~kinematic_bit) | dynamic_bit;
    mask[j] = (bits & COMM_LAGGING) ? (mask[j] | lagging_bit) : (mask[j] & ~lagging_bit);
  }
}

/* the counters up to SECONDS, the force the model's block 'force' predicts, the atoms stored, the
   scene's atoms (LAMMPS's and stored), and the counters after SECONDS */
double FixGriddemRom::compute_vector(int n)
{
  const int first = SECONDS + 1, after = first + 5;    // the five values between the counters
  if (n < first) return counts[n];
  if (n < first + 3) return force_predicted[n - first];
  if (n == first + 3) return nstored_all;
  if (n == first + 4) return (double) atom->natoms + nstored_all;
  return counts[first + n - after];
}

/* the next model step and the step length the CFL rule chose (from `every`, which a script
   defining the fix again may change: then the schedule starts afresh) */

void FixGriddemRom::write_restart(FILE *fp)
{
  const double list[3] = {(double) next_model, (double) model_step, (double) period};
  const int size = sizeof(list);
  if (comm->me == 0) {
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 3, fp);
  }
}

void FixGriddemRom::restart(char *buf)
{
  const auto *list = (const double *) buf;
  if ((int) list[2] != period) return;
  next_model = (bigint) list[0];
  model_step = (int) list[1];
}

void *FixGriddemRom::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "kinematic_bit") == 0) return &kinematic_bit;
  if (strcmp(name, "lagging_bit") == 0) return &lagging_bit;
  if (strcmp(name, "stored_atoms") == 0) return &nstored_all;    // held out of LAMMPS, all processes
  return nullptr;
}

/* The voxels as a distributed LAMMPS grid, the model's grid over the box (voxel centres as grid
   points), so that dump grid and dump grid/vtk write the field. Every process holds all of it;
   each copies its own brick. */
void FixGriddemRom::allocate_grid()
{
  grid3d = new Grid3d(lmp, world, grid.n[0], grid.n[1], grid.n[2]);
  grid3d->setup_grid(lo_in[0], hi_in[0], lo_in[1], hi_in[1], lo_in[2], hi_in[2], lo_out[0], hi_out[0],
                     lo_out[1], hi_out[1], lo_out[2], hi_out[2]);
  for (auto &values : grid_values)
    memory->create3d_offset(values, lo_out[2], hi_out[2], lo_out[1], hi_out[1], lo_out[0], hi_out[0],
                            "griddem/rom:grid");
  fill_grid();
}

void FixGriddemRom::deallocate_grid()
{
  for (auto &values : grid_values) memory->destroy3d_offset(values, lo_out[2], lo_out[1], lo_out[0]);
  delete grid3d;
  grid3d = nullptr;
}

void FixGriddemRom::reset_grid()
{
  deallocate_grid();
  allocate_grid();
}

void FixGriddemRom::fill_grid()
{
  if (!grid3d) return;
  for (int iz = lo_in[2]; iz <= hi_in[2]; iz++)
    for (int iy = lo_in[1]; iy <= hi_in[1]; iy++)
      for (int ix = lo_in[0]; ix <= hi_in[0]; ix++) {
        const int m = ix + grid.n[0] * (iy + grid.n[1] * iz);
        for (int d = 0; d < 3; d++) grid_values[d][iz][iy][ix] = field[3 * m + d];
        grid_values[3][iz][iy][ix] = density[m];
      }
}

int FixGriddemRom::get_grid_by_name(const std::string &name, int &dim)
{
  if (name != "field") return -1;
  dim = 3;
  return 0;
}

void *FixGriddemRom::get_grid_by_index(int index)
{
  return index == 0 ? grid3d : nullptr;
}

int FixGriddemRom::get_griddata_by_name(int igrid, const std::string &name, int &ncol)
{
  static const char *const names[4] = {"vx", "vy", "vz", "density"};
  if (igrid != 0) return -1;
  for (int k = 0; k < 4; k++)
    if (name == names[k]) {
      ncol = 0;
      return k;
    }
  return -1;
}

void *FixGriddemRom::get_griddata_by_index(int index)
{
  return index >= 0 && index < 4 ? grid_values[index] : nullptr;
}

double FixGriddemRom::memory_usage()
{
  return (double) nmax * (1 + 3 + NTRACK) * sizeof(double) +
      (weights.size() + 4 * density.size() + stored.capacity()) * sizeof(double);
}
