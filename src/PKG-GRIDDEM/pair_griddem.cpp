/* ----------------------------------------------------------------------
   GRIDDEM package: the part every griddem pair style shares (see pair_griddem.h).
   Ghosts receive no force (newton off across processes), so no reverse communication is needed.
   The contact history lives in a fix griddem, which the keeper (griddem_fix_keeper.h) makes,
   chooses and hands over as long as the pair style lives.
------------------------------------------------------------------------- */

#include "pair_griddem.h"

#include "griddem_search.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_griddem_face.h"
#include "force.h"
#include "group.h"
#include "math_const.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair_hybrid.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

PairGriddem::PairGriddem(LAMMPS *lmp) :
    Pair(lmp), model(), cutoff_global(-1.0), layout_set(0), single_hooke_layout(0), keeper(lmp), last_stats(),
    conducts_heat(false), grid_anchor{0.0, 0.0, 0.0}, coarsened_warned(0), cost_warned(0), cost_natoms(-1), auto_one_grid(0), rmin(0.0), rmax(0.0), radii_vary(false), ghost_reach_warned(0), image_axes(0), image_axes_found(0), images(nullptr), freeze_group_bit(0), exclusions(), fix_rigid(nullptr)
{
  no_virial_fdotr_compute = 1;    // ghosts get no force: the virial is tallied pair by pair
  comm_forward = 1;               // rigid bodies' masses (contact_masses())
  single_enable = 1;
  // what single() reports besides the force, as the stock styles: tangential force and its size,
  // then hooke: normal and tangential relative velocity; granular: rolling force and its size,
  // twisting torque (0: no twisting model), separation vector
  single_extra = 12;
  svector = new double[single_extra];
  type_contact = 0.0;
  griddem_engine_init(&engine);
}

PairGriddem::~PairGriddem()
{
  if (copymode) return;
  keeper.release();
  delete[] svector;
  griddem_engine_free(&engine);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairGriddem::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n, n, "pair:cutsq");
  specs.assign(n * n, griddem_pair_spec());
  params.assign(n * n, griddem_pair_params());
  create_default_fix();
}

/* the room per contact for a spec's history: as many values as the type pair that keeps the most
   (each pair lays out its own, griddem_pair_params.parity); the first spec of the style sets it */

void PairGriddem::adopt_layout(const griddem_pair_spec &s)
{
  const int size = griddem_spec_history(&s, nullptr);
  const int track = size > 0 || griddem_spec_beyond_contact(&s);
  model.history_size = layout_set ? MAX(model.history_size, size) : size;
  model.track_contacts = layout_set ? (model.track_contacts || track) : track;
  layout_set = 1;
}

/* pair_coeff: spec s for the type pairs of two LAMMPS type ranges */

void PairGriddem::set_specs(const char *irange, const char *jrange, const griddem_pair_spec &s)
{
  if (!allocated) allocate();
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, irange, 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, jrange, 1, atom->ntypes, jlo, jhi, error);
  make_params(s, ilo, jlo);    // refuse what cannot be evaluated now, naming the types
  adopt_layout(s);
  create_default_fix();

  const int n = atom->ntypes + 1;
  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      specs[i * n + j] = specs[j * n + i] = s;
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) error->all(FLERR, "Pair coeff for {}: no atom types in {} {}", force->pair_style, irange, jrange);
}

griddem_pair_params PairGriddem::make_params(const griddem_pair_spec &s, int i, int j)
{
  griddem_pair_params p;
  char why[256];
  if (griddem_spec_to_params(&s, &p, why, sizeof(why)) != 0)
    error->all(FLERR, "Pair style {}: types {} {}: {}", force->pair_style, i, j, why);
  return p;
}

/* unlike types without their own pair_coeff mix as in pair granular; cutoff = sum of the largest
   radii of the two types (including atoms fix pour/deposit will add), plus the pull-off distance
   of models that act beyond touching */

double PairGriddem::init_one(int i, int j)
{
  if (!allocated) allocate();
  const int n = atom->ntypes + 1;
  if (setflag[i][j] == 0) {
    griddem_pair_spec mixed;
    const int axis = griddem_spec_mix(&specs[i * n + i], &specs[j * n + j], &mixed);
    if (axis >= 0)
      error->all(FLERR, "Pair style {}: types {} and {} use different {} models ({} and {}); set pair_coeff {} {} explicitly",
                 force->pair_style, i, j, griddem_axis_name(axis), specs[i * n + i].sub[axis]->name,
                 specs[j * n + j].sub[axis]->name, i, j);
    specs[i * n + j] = specs[j * n + i] = mixed;
  }
  const griddem_pair_spec &s = specs[i * n + j];
  params[i * n + j] = params[j * n + i] = make_params(s, i, j);
  model.ntypes = atom->ntypes;
  model.pair = params.data();

  const double pulloff = griddem_pair_reach_extra(&params[i * n + j], type_radius[i], type_radius[j]);
  model.reach_extra = MAX(model.reach_extra, pulloff);
  type_contact = MAX(type_contact, type_radius[i] + type_radius[j] + pulloff);
  if (s.cutoff > 0.0) return s.cutoff;
  if (cutoff_global > 0.0) return cutoff_global;
  return type_radius[i] + type_radius[j] + pulloff;
}

void PairGriddem::create_default_fix()
{
  keeper.make_default(history_fix_style(), history_fix_style() != "griddem", model.track_contacts);
}

bool PairGriddem::sweeps(const FixGriddem &fix) const
{
  return !fix.kokkosable;
}

double PairGriddem::memory_usage()
{
  return Pair::memory_usage() + griddem_engine_memory(&engine);
}

void *PairGriddem::extract(const char *name, int &dim)
{
  dim = 0;
  return strcmp(name, "griddem") == 0 ? static_cast<GriddemPairLink *>(this) : nullptr;
}

const griddem_engine_stats *PairGriddem::step_stats(const FixGriddem *of, int occupancy)
{
  if (!of || of != fix()) return nullptr;
  if (occupancy && last_stats.occupied_cells < 0) count_occupancy(last_stats);
  return &last_stats;
}

void PairGriddem::count_occupancy(griddem_engine_stats &stats)
{
  griddem_engine_count_occupancy(&engine);
  stats.occupied_cells = engine.stats.occupied_cells;
  stats.max_occupancy = engine.stats.max_occupancy;
}

void PairGriddem::init_style()
{
  const char *style = force->pair_style;
  // the sweep finds every pair on the grid: as a sub-style of pair hybrid (or hybrid/overlay, or
  // hybrid/scaled, which scales what it adds), only once and on every type pair
  if (force->pair != this) {
    char *keyword = force->pair_match_ptr(this);
    auto hybrid = dynamic_cast<PairHybrid *>(force->pair);
    const std::string kind = utils::strip_style_suffix(force->pair_style, lmp);
    bool alone = keyword && hybrid && (kind == "hybrid" || kind == "hybrid/overlay" || kind == "hybrid/scaled") &&
        force->pair_match(keyword, 1) == this;
    for (int i = 1; alone && i <= atom->ntypes; i++)
      for (int j = i; alone && j <= atom->ntypes; j++) alone = hybrid->check_ijtype(i, j, keyword);
    if (!alone)
      error->all(FLERR, "The griddem pair styles find all contacts on their own grid: as a sub-style of pair {} "
                 "a griddem style must be set on every type pair, and once (pair_style {} {} ... with "
                 "pair_coeff * * {})", force->pair_style, force->pair_style, keyword ? keyword : "griddem/...",
                 keyword ? keyword : "griddem/...");
    style = keyword;
  }
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "Pair style {} requires atom attributes radius, rmass, omega (atom_style sphere)", style);
  if (comm->ghost_velocity == 0)
    error->all(FLERR, "Pair style {} requires ghost atoms store velocity: use comm_modify vel yes", style);
  if (atom->molecular != Atom::ATOMIC)
    error->all(FLERR, "Pair style {} does not support molecular systems (special bonds)", style);
  // heat conduction, as pair granular: temperatures read, heat added to the atoms' heatflow
  const int n = atom->ntypes + 1;
  int conducting = 0, insulating = 0;
  for (int i = 1; i < n; i++)
    for (int j = i; allocated && j < n; j++)
      if (setflag[i][j]) (specs[i * n + j].sub[GRIDDEM_AXIS_HEAT]->model != GRIDDEM_HEAT_NONE ? conducting : insulating)++;
  conducts_heat = conducting > 0;
  if (conducting && insulating && comm->me == 0)
    error->warning(FLERR, "Pair style {}: {} type pairs given in pair_coeff have a heat model and {} do not; "
                   "those conduct no heat (pair granular asks for a heat model on every pair)", style,
                   conducting, insulating);
  if (conducts_heat) {
    if (!atom->temperature_flag)
      error->all(FLERR, "Heat conduction in pair style {} requires atom style with temperature property", style);
    if (!atom->heatflow_flag)
      error->all(FLERR, "Heat conduction in pair style {} requires atom style with heatflow property", style);
  }
  // pair granular's single() reports the heat model's heat after its 12 values
  const int extra = conducts_heat ? 13 : (single_hooke_layout ? 10 : 12);
  if (extra != single_extra) {
    delete[] svector;
    single_extra = extra;
    svector = new double[single_extra];
  }

  radii_vary = false;
  fix_rigid = nullptr;
  for (const auto &ifix : modify->get_fix_list()) {
    if (ifix->rigid_flag) {
      if (fix_rigid) error->all(FLERR, "Pair style {}: only one fix rigid at a time (fix {} and fix {})", style,
                                fix_rigid->id, ifix->id);
      fix_rigid = ifix;
    }
    radii_vary |= ifix->diam_flag != 0;
  }

  FixGriddem *fix = keeper.choose(history_fix_style(), history_fix_style() != "griddem", model.track_contacts);
  last_stats = griddem_engine_stats();    // the values of a step without atoms, which runs no sweep
  last_stats.energy_tallied = 1;          // (its energy, none, is known on every step)
  if (model.track_contacts && fix->options.contacts == 0)
    error->all(FLERR, "Pair style {} needs contact history: fix {} has contacts 0", style, fix->id);
  // the Kokkos kernels' options: they run with fix griddem/kk only
  if (fix->options.precision == GRIDDEM_PRECISION_SINGLE && !(kokkosable && fix->kokkosable))
    error->all(FLERR, "Pair style {}: fix {} precision single is implemented by the Kokkos styles only "
               "(griddem/.../kk, with fix griddem/kk); the CPU engine works in double", style, fix->id);
  if (fix->options.search != GRIDDEM_SEARCH_AUTO && !(kokkosable && fix->kokkosable))
    error->all(FLERR, "Pair style {}: fix {} search {} chooses among the Kokkos styles' searches "
               "(griddem/.../kk, with fix griddem/kk); the CPU engine has one", style, fix->id,
               fix->options.search == GRIDDEM_SEARCH_TEAM ? "team" : "thread");
  // the CPU engine's candidate kernel: every kernel finds the same pairs in the same order
  const char *kernel = GRIDDEM_KERNEL_NAMES[fix->options.kernel];
  if (fix->options.kernel != GRIDDEM_KERNEL_AUTO && kokkosable && fix->kokkosable)
    error->all(FLERR, "Pair style {}: fix {} kernel {} chooses among the CPU engine's candidate kernels; the "
               "Kokkos styles' kernels search with their own (fix griddem search)", style, fix->id, kernel);
  if (griddem_touching_use(kernel) != 0) {
    griddem_touching_use("auto");
    error->all(FLERR, "Pair style {}: fix {} kernel {}: this processor or build does not run it (the widest it "
               "runs: {})", style, fix->id, kernel, griddem_touching_name());
  }
  if (model.track_contacts && !sweeps(*fix))
    error->all(FLERR, "Pair style {} keeps its contact history in fix {}, but fix {} is fix {}: "
               "define the fix with the same Kokkos suffix as the pair style (or none)", style,
               history_fix_style(), fix->id, fix->kokkosable ? "griddem/kk" : "griddem");
  if (fix->igroup != 0) error->all(FLERR, "Fix griddem {} must be defined for group all", fix->id);
  fix->set_values(model.history_size);

  auto freezes = modify->get_fix_by_style("^freeze");
  if (freezes.size() > 1) error->all(FLERR, "Only one fix freeze command at a time allowed");
  freeze_group_bit = freezes.empty() ? 0 : freezes.front()->groupbit;

  setup_exclusions();
  model.reach_extra = 0.0;    // init_one() finds it per type pair
  find_radius_range();
  type_radius = max_radius_by_type();
  type_contact = 0.0;    // init_one() finds it per type pair

  // NN4DEM stability rule: dt <= pi/5 sqrt(m/k) for the lightest atom
  double mlocal = INFINITY, mmin;
  for (int i = 0; i < atom->nlocal; i++) mlocal = MIN(mlocal, atom->rmass[i]);
  MPI_Allreduce(&mlocal, &mmin, 1, MPI_DOUBLE, MPI_MIN, world);
  const double kn = linear_normal_stiffness();
  if (std::isfinite(mmin) && kn > 0.0) {
    const double limit = MathConst::MY_PI / 5.0 * sqrt(mmin / kn);
    if (update->dt > limit && comm->me == 0)
      error->warning(FLERR, "Pair style {}: timestep {} exceeds the stability limit pi/5*sqrt(m/Kn) = {} of the lightest atom (mass {})",
                     style, update->dt, limit, mmin);
  }
}

/* stiffness of a linear (hooke) normal spring, for the dt <= pi/5 sqrt(m/k) warning; 0: not linear */

double PairGriddem::linear_normal_stiffness()
{
  double kn = 0.0;
  const int n = atom->ntypes + 1;
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) {
      if (!setflag[i][j]) continue;
      const griddem_pair_spec &s = specs[i * n + j];
      if (s.sub[GRIDDEM_AXIS_NORMAL]->model != GRIDDEM_NORMAL_HOOKE) return 0.0;
      kn = MAX(kn, s.coeffs[GRIDDEM_AXIS_NORMAL][0]);
    }
  return kn;
}

/* neigh_modify exclude type and group, as a neighbor list would honour them */

void PairGriddem::setup_exclusions()
{
  const int n = atom->ntypes + 1;
  excluded_types.assign(neighbor->nex_type ? n * n : 0, 0);
  for (int k = 0; k < neighbor->nex_type; k++) {
    const int a = neighbor->ex1_type[k], b = neighbor->ex2_type[k];
    excluded_types[a * n + b] = excluded_types[b * n + a] = 1;
  }
  excluded_groups.clear();
  // group bits from the group indices: neighbor sets its own bits only after pair styles init;
  // a group's pairs with itself in one mask of bits, tested at once
  exclusions.group_both_bits = 0;
  for (int k = 0; k < neighbor->nex_group; k++) {
    const int b1 = group->bitmask[neighbor->ex1_group[k]], b2 = group->bitmask[neighbor->ex2_group[k]];
    if (b1 == b2) {
      exclusions.group_both_bits |= b1;
    } else {
      excluded_groups.push_back(b1);
      excluded_groups.push_back(b2);
    }
  }
  excluded_molecule_bits.clear();
  excluded_molecule_intra.clear();
  for (int k = 0; k < neighbor->nex_mol; k++) {
    excluded_molecule_bits.push_back(group->bitmask[neighbor->ex_mol_group[k]]);
    excluded_molecule_intra.push_back(neighbor->ex_mol_intra[k]);
  }
  exclusions.nmolecule = neighbor->nex_mol;
  exclusions.molecule_bits = excluded_molecule_bits.data();
  exclusions.molecule_intra = excluded_molecule_intra.data();
  exclusions.type_pair = excluded_types.empty() ? nullptr : excluded_types.data();
  exclusions.ntypes = atom->ntypes;
  exclusions.ngroup_pairs = (int) excluded_groups.size() / 2;
  exclusions.group_bits = excluded_groups.data();
  // fix griddem/rom: pairs of two kinematic atoms (both in the fix's kinematic group) are skipped,
  // and lagging atoms (its reach test keeps every other atom out of their contact distance) are in
  // no pair: they leave the grid
  exclusions.both_bit = exclusions.apart_bit = 0;
  auto roms = modify->get_fix_by_style("^griddem/rom$");
  if (roms.size() > 1) error->all(FLERR, "Only one fix griddem/rom may be defined");
  if (!roms.empty()) {
    int nbit = 0;
    auto kinematic = (int *) roms.front()->extract("kinematic_bit", nbit);
    auto lagging = (int *) roms.front()->extract("lagging_bit", nbit);
    if (kinematic) exclusions.both_bit = *kinematic;
    if (lagging) exclusions.apart_bit = *lagging;
  }
}

std::vector<double> PairGriddem::max_radius_by_type()
{
  std::vector<double> onerad(atom->ntypes + 1, 0.0), maxrad(atom->ntypes + 1, 0.0);
  for (const auto &ifix : modify->get_fix_list()) {
    if (!utils::strmatch(ifix->style, "^pour") && !utils::strmatch(ifix->style, "^deposit")) continue;
    for (int t = 1; t <= atom->ntypes; t++) {
      int itype = t;
      auto r = (double *) ifix->extract("radius", itype);
      if (r && *r > 0.0) onerad[t] = MAX(onerad[t], *r);
    }
  }
  for (int k = 0; k < atom->nlocal; k++)
    onerad[atom->type[k]] = MAX(onerad[atom->type[k]], atom->radius[k]);
  MPI_Allreduce(&onerad[1], &maxrad[1], atom->ntypes, MPI_DOUBLE, MPI_MAX, world);
  return maxrad;
}

void PairGriddem::find_radius_range()
{
  double local[2] = {INFINITY, 0.0};
  for (int i = 0; i < atom->nlocal; i++) {
    local[0] = MIN(local[0], atom->radius[i]);
    local[1] = MAX(local[1], atom->radius[i]);
  }
  set_radius_range(local[0], local[1]);
}

bool PairGriddem::radius_range_due() const
{
  return neighbor->ago == 0 || radii_vary;
}

/* rmin, rmax over all processes from this process's (INFINITY, 0 without atoms) */

void PairGriddem::set_radius_range(double local_min, double local_max)
{
  double local[2] = {local_min, -local_max}, global[2];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, world);
  rmin = global[0];
  rmax = -global[1];
  if (rmax > 0.0 && !(rmin > 0.0)) {    // the lowest ID of an atom whose radius is not positive
    tagint mine = MAXTAGINT, first;
    for (int i = 0; i < atom->nlocal; i++)
      if (!(atom->radius[i] > 0.0)) mine = MIN(mine, atom->tag[i]);
    MPI_Allreduce(&mine, &first, 1, MPI_LMP_TAGINT, MPI_MIN, world);
    error->all(FLERR, "Pair style {} requires positive radii: atom {} has a radius that is not positive (smallest radius {})",
               force->pair_style, first, rmin);
  }
  find_image_axes();
}

/* A contact with a ghost atom is found only where LAMMPS keeps that ghost: it keeps atoms within
   its ghost cutoff (from the pair cutoffs, made from the radii at the run's start, plus the
   neighbor skin) and rebuilds the ghosts when an atom has moved half the skin, so every pair
   closer than the cutoff less the skin is present. Radii that grow during a run (fix adapt) can
   outgrow either bound; stock's neighbor lists have the same two. */

void PairGriddem::check_ghost_reach()
{
  // one process in a box without periodic images (in 2d none along z) has no ghosts to lose
  const bool ghosts = comm->nprocs > 1 || domain->xperiodic || domain->yperiodic ||
      (domain->dimension == 3 && domain->zperiodic);
  if (rmax == 0.0 || !ghosts) return;
  // the type pairs' own distances while no radius outgrew its type's (radii that grew during the
  // run: bounded by the largest radius twice and the largest pull-off distance)
  const double typed = *std::max_element(type_radius.begin(), type_radius.end());
  const double contact = rmax <= typed ? type_contact : 2.0 * rmax + model.reach_extra;
  const double cutghost = comm->get_comm_cutoff();
  const double tolerance = 1e-10 * contact;
  if (contact > cutghost + tolerance)
    error->all(FLERR, "Pair style {}: the largest contact distance {} (radius {}) exceeds the ghost cutoff {}: "
               "contacts with atoms of other processes and periodic images would be lost (radii grew during "
               "the run, or a pair cutoff is below the contact distance): set comm_modify cutoff to at least {} "
               "plus the neighbor skin {}", force->pair_style, contact, rmax, cutghost, contact, neighbor->skin);
  if (contact > cutghost - neighbor->skin + tolerance && !ghost_reach_warned) {
    ghost_reach_warned = 1;
    if (comm->me == 0)
      error->warning(FLERR, "Pair style {}: at step {} the largest contact distance {} (radius {}) exceeds the ghost "
                     "cutoff {} less the neighbor skin {}: contacts with ghost atoms are certain only while atoms "
                     "move less than {} between reneighborings (stock's neighbor lists have the same limit); "
                     "comm_modify cutoff {} makes them certain",
                     force->pair_style, update->ntimestep, contact, rmax, cutghost, neighbor->skin,
                     0.5 * (cutghost - contact), contact + neighbor->skin);
  }
}

/* Where a periodic box is narrower than twice the largest contact distance, a sphere can touch
   two images of one partner, or its own image: contacts are then keyed by partner ID and periodic
   image along those axes (griddem_history.h), which costs a forward communication a step; wider
   boxes key by ID alone. The width is the distance between opposite faces (a triclinic box's
   too). */

void PairGriddem::find_image_axes()
{
  const int before = image_axes;
  image_axes = 0;
  if (model.track_contacts && rmax > 0.0) image_axes_of_box();
  // contacts across a boundary that turns thin or wide are keyed anew: their history restarts
  const int changed = image_axes_found ? before ^ image_axes : 0;
  image_axes_found = 1;
  if (changed && comm->me == 0)
    for (int d = 0; d < 3; d++)
      if (changed >> d & 1)
        error->warning(FLERR, "Pair style {}: at step {} the periodic box became {} than twice the largest contact "
                       "distance along {}: contacts with a partner's periodic image along {} restart their "
                       "history (the contact history is kept per periodic image only in boxes that thin)",
                       force->pair_style, update->ntimestep, image_axes >> d & 1 ? "narrower" : "wider",
                       "xyz"[d], "xyz"[d]);
}

void PairGriddem::image_axes_of_box()
{
  const double contact = 2.0 * rmax + model.reach_extra;
  const double *hi = domain->h_inv;
  const double width[3] = {1.0 / sqrt(hi[0] * hi[0] + hi[5] * hi[5] + hi[4] * hi[4]),
                           1.0 / sqrt(hi[1] * hi[1] + hi[3] * hi[3]), 1.0 / hi[2]};
  // in 2d LAMMPS makes no images along z
  for (int d = 0; d < domain->dimension; d++) {
    if (!domain->periodicity[d] || width[d] >= 2.0 * contact) continue;
    image_axes |= 1 << d;
    if (width[d] < GRIDDEM_IMAGE_MIN_WIDTH(contact))
      error->all(FLERR, "Pair style {}: the periodic box is {} wide along {}, less than {} (1/8 of the largest contact "
                 "distance {}, radius {}): a sphere would touch more images of one partner than the contact "
                 "history (kept per partner ID and periodic image) tells apart; make the box at least {} wide "
                 "along {} (replicate it) or make that boundary non-periodic",
                 force->pair_style, width[d], "xyz"[d], GRIDDEM_IMAGE_MIN_WIDTH(contact), contact, rmax,
                 GRIDDEM_IMAGE_MIN_WIDTH(contact), "xyz"[d]);
  }
}

void PairGriddem::error_nonfinite(const char *what, int i, const double *value)
{
  error->one(FLERR, "Pair style {}: atom {} has a non-finite {} ({} {} {})", force->pair_style, atom->tag[i], what,
             value[0], value[1], value[2]);
}

void PairGriddem::error_coincident(int i, int j)
{
  double **x = atom->x;
  error->one(FLERR, "Pair style {}: atoms {} and {} are at the same position ({} {} {}): the contact normal is undefined",
             force->pair_style, atom->tag[i], atom->tag[j], x[i][0], x[i][1], x[i][2]);
}

void PairGriddem::error_too_fast(int i, double speed, double h_nn4dem)
{
  error->one(FLERR, "Pair style {}: atom {} moves {} per step (speed {}), more than the {} one grid cell allows (dt <= dx/v_max); reduce the timestep",
             force->pair_style, atom->tag[i], speed * update->dt, speed, h_nn4dem);
}

/* NN4DEM rule: no atom may cross more than one exact-mode cell (d_min/sqrt(3)) per step */

void PairGriddem::check_motion(double h_nn4dem)
{
  const griddem_engine_stats &st = last_stats;
  const double moved = st.max_speed * update->dt;
  if (!st.nonfinite_velocity && !(moved > h_nn4dem)) return;
  // the engine found a fault; name the atom (the first non-finite one, else the fastest)
  double **v = atom->v;
  int worst = -1;
  double vmax2 = -1.0;
  for (int i = 0; i < atom->nlocal; i++) {
    const double v2 = v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2];
    if (!std::isfinite(v2)) error_nonfinite("velocity", i, v[i]);
    if (v2 > vmax2) vmax2 = v2, worst = i;
  }
  error_too_fast(worst, st.max_speed, h_nn4dem);
}

void PairGriddem::error_stencil_reach(double edge)
{
  error->one(FLERR, "Pair style {}: contact distance {} spans more than {} cells of edge {} (radius ratio {}); use fix griddem cell auto (the default: a grid per size class) or a larger edge",
             force->pair_style, 2.0 * rmax + model.reach_extra, GRIDDEM_MAX_REACH, edge, rmax / rmin);
}

void PairGriddem::report_fault(const griddem_sweep_result &r)
{
  if (r.fault == GRIDDEM_FAULT_COINCIDENT) error_coincident(r.fault_i, r.fault_j);
  if (r.fault == GRIDDEM_FAULT_STENCIL) error_stencil_reach(last_stats.cell_edge);
  if (r.fault == GRIDDEM_FAULT_MEMORY)
    error->one(FLERR, "Pair style {}: out of memory for the grid or the contact history of {} atoms", force->pair_style,
               atom->nlocal + atom->nghost);
}

/* LAMMPS's owned and ghost atoms as the engine reads them */

griddem_particles PairGriddem::host_particles()
{
  griddem_particles part;
  part.nlocal = atom->nlocal;
  part.nall = atom->nlocal + atom->nghost;
  part.x = atom->x[0];
  part.v = atom->v[0];
  part.omega = atom->omega[0];
  part.radius = atom->radius;
  part.rmass = atom->rmass;
  part.tag = atom->tag;
  part.tag_bytes = sizeof(tagint);
  part.type = atom->type;
  part.mask = atom->mask;
  part.frozen_bit = freeze_group_bit;
  part.image = nullptr;
  part.molecule = exclusions.nmolecule ? atom->molecule : nullptr;
  part.temperature = conducts_heat ? atom->temperature : nullptr;
  part.heatflow = conducts_heat ? atom->heatflow : nullptr;
  return part;
}

/* Each atom's mass in a contact, as stock's: its rigid body's total where it belongs to one (the
   bodies' atoms change only where LAMMPS reneighbors; sent to the ghosts then), else its own. */

const double *PairGriddem::contact_masses()
{
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  if (neighbor->ago == 0) {
    int dim;
    auto body = (int *) fix_rigid->extract("body", dim);
    auto mass_body = (double *) fix_rigid->extract("masstotal", dim);
    if (nlocal && (!body || !mass_body))
      error->all(FLERR, "Pair style {}: fix {} gives no body masses at step {}", force->pair_style, fix_rigid->id,
                 update->ntimestep);
    body_mass.assign(atom->nmax, 0.0);
    for (int i = 0; i < nlocal; i++) body_mass[i] = body[i] >= 0 ? mass_body[body[i]] : 0.0;
    comm->forward_comm(this);
  }
  contact_mass.resize(nall);
  for (int i = 0; i < nall; i++) contact_mass[i] = body_mass[i] > 0.0 ? body_mass[i] : atom->rmass[i];
  return contact_mass.data();
}

int PairGriddem::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  for (int k = 0; k < n; k++) buf[k] = body_mass[list[k]];
  return n;
}

void PairGriddem::unpack_forward_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) body_mass[first + k] = buf[k];
}

/* A cell mode with one grid (multi, exact, a given edge) can cost far more than the default's
   grid per size class: at a large size ratio, multi's cells sized for the largest sphere hold
   many small ones. Measured on the host's atoms at the start of each run and when the atom count
   changes (grid_cost_due(), the same on every process): the candidate pairs the sweep tests on
   each layout, and the most centres in one cell; warned once. Cell auto takes the measure to
   choose: one grid (multi's) where the grids per class would not test fewer candidates by more
   than GRIDDEM_AUTO_ONE_GRID, else a grid per class. */

bool PairGriddem::grid_cost_due() const
{
  const int mode = fix()->options.cell_mode;
  if (mode == GRIDDEM_CELL_CLASSES || rmax == 0.0) return false;
  // auto has a choice only where the radii span several classes
  if (mode == GRIDDEM_CELL_AUTO ? griddem_class_count(rmin, rmax) == 1 : cost_warned) return false;
  return update->setupflag || atom->natoms != cost_natoms;
}

bool PairGriddem::grid_per_class() const
{
  const int mode = fix()->options.cell_mode;
  return mode == GRIDDEM_CELL_CLASSES ||
      (mode == GRIDDEM_CELL_AUTO && !(auto_one_grid && griddem_class_count(rmin, rmax) > 1));
}

void PairGriddem::check_grid_cost()
{
  const int mode = fix()->options.cell_mode;
  cost_natoms = atom->natoms;

  griddem_step step;
  memset(&step, 0, sizeof(step));
  step.particles = host_particles();
  for (int d = 0; d < 3; d++) step.anchor[d] = domain->boxlo[d];
  step.rmin = rmin;
  step.rmax = rmax;
  step.max_cells = GRIDDEM_ONE_GRID_MAX_CELLS(step.particles.nall);
  step.model = &model;
  step.excl = &exclusions;
  griddem_engine probe;
  griddem_engine_init(&probe);
  step.cell_edge = griddem_cell_edge(mode, rmin, rmax, fix()->options.cell_edge);
  double local[2], total[2];
  local[0] = griddem_engine_candidates(&probe, &step);
  int most_local = probe.stats.max_occupancy, most;
  step.cell_edge = griddem_cell_edge(GRIDDEM_CELL_AUTO, rmin, rmax, 0.0);
  step.size_classes = 1;
  local[1] = griddem_engine_candidates(&probe, &step);
  griddem_engine_free(&probe);
  if (local[0] < 0.0 || local[1] < 0.0) local[0] = local[1] = 0.0;    // no memory to measure: no verdict
  MPI_Allreduce(local, total, 2, MPI_DOUBLE, MPI_SUM, world);
  MPI_Allreduce(&most_local, &most, 1, MPI_INT, MPI_MAX, world);
  const double natoms = MAX((double) atom->natoms, 1.0), here = total[0] / natoms, defaults = total[1] / natoms;
  if (mode == GRIDDEM_CELL_AUTO) {
    auto_one_grid = total[0] <= GRIDDEM_AUTO_ONE_GRID * total[1];
    return;
  }
  if (here <= GRIDDEM_COST_RATIO_WARN * defaults && most <= GRIDDEM_OCCUPANCY_WARN) return;
  cost_warned = 1;
  const std::string name = mode == GRIDDEM_CELL_EXACT ? "exact" : mode == GRIDDEM_CELL_MULTI ? "multi"
                                                                  : fmt::format("{}", fix()->options.cell_edge);
  if (comm->me == 0)
    error->warning(FLERR, "Pair style {}: fix {} cell {} tests {:.6g} candidate pairs per atom, {:.6g} times the {:.6g} "
                   "of cell auto, and holds up to {} centres in one cell (warned above {} times or {} centres); "
                   "use cell auto (the default), which gives each size class a grid of its own",
                   force->pair_style, fix()->id, name, here, here / MAX(defaults, 1e-300), defaults,
                   most, GRIDDEM_COST_RATIO_WARN, GRIDDEM_OCCUPANCY_WARN);
}

void PairGriddem::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  engine_step();
}

void PairGriddem::engine_step()
{
  find_image_axes();    // the box may have changed since the radius range was found

  double **x = atom->x;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;

  griddem_step step;
  griddem_particles &part = step.particles;
  part = host_particles();
  if (fix_rigid) part.rmass = contact_masses();

  // one pass: non-finite positions, the box, the fastest atom (the radius range where it can change)
  griddem_scan scan;
  const int radii = radius_range_due();
  griddem_engine_scan(&part, radii, &scan);
  if (scan.first_nonfinite >= 0) error_nonfinite("position", scan.first_nonfinite, x[scan.first_nonfinite]);
  if (radii) {
    set_radius_range(scan.rmin, scan.rmax);
    check_ghost_reach();
  }
  if (rmax == 0.0) return;    // no atoms yet
  if (grid_cost_due()) check_grid_cost();
  FixGriddem *fix = this->fix();
  part.image = images = image_axes ? fix->periodic_images(image_axes) : nullptr;

  const GriddemFixOptions &options = fix->options;
  step.scan = &scan;
  // LAMMPS re-sorts, exchanges and re-ghosts atoms only on steps it reneighbors (ago 0)
  step.same_particles = neighbor->ago > 0;
  step.fixed_radii = !radii_vary;
  step.ghost_margin = neighbor->skin;
  // the cells stay where they were while the atoms are the same ones, though the box deforms
  if (!step.same_particles)
    for (int d = 0; d < 3; d++) grid_anchor[d] = domain->boxlo[d];
  for (int d = 0; d < 3; d++) step.anchor[d] = grid_anchor[d];
  step.cell_edge = griddem_cell_edge(options.cell_mode, rmin, rmax, options.cell_edge);
  step.size_classes = grid_per_class();
  step.rmin = rmin;
  step.max_cells = GRIDDEM_ONE_GRID_MAX_CELLS(nall);
  step.rmax = rmax;
  step.model = &model;
  step.excl = &exclusions;
  step.dt = update->dt;
  step.history_update = update->setupflag ? 0 : 1;
  const griddem_history_rows rows = model.track_contacts ? fix->begin_step() : griddem_history_rows{nullptr, nullptr};
  step.hist = rows.hist;
  step.row_of = rows.row_of;
  step.f = atom->f[0];
  step.torque = atom->torque[0];
  step.vatom = vflag_atom ? vatom[0] : nullptr;
  step.tally = (vflag_global ? GRIDDEM_TALLY_VIRIAL : 0) | (eflag_global ? GRIDDEM_TALLY_ENERGY : 0);

  griddem_sweep_result result;
  int coarsened = 0;
  griddem_engine_step(&engine, &step, &result, &coarsened);
  last_stats = engine.stats;
  if (model.track_contacts) fix->commit_step(model, last_stats.max_contacts);
  if (coarsened && !coarsened_warned) {
    coarsened_warned = 1;
    error->warning(FLERR, "Pair style {}: cell edge enlarged from {} to {} so that the grid over this process's atoms stays within {} cells",
                   force->pair_style, step.cell_edge, last_stats.cell_edge, step.max_cells);
  }
  if (result.fault != GRIDDEM_FAULT_NONE) report_fault(result);
  if (vflag_global)
    for (int k = 0; k < 6; k++) virial[k] += result.virial[k];
  check_motion(griddem_cell_edge(GRIDDEM_CELL_EXACT, rmin, rmax, 0.0));
}

/* One pair's contact for compute pair/local: the force over the distance in fforce, the parts
   in svector (layout above, as gran/hooke/history and pair granular); its history is read, not
   advanced. */

double PairGriddem::single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/,
                           double /*factor_lj*/, double &fforce)
{
  fforce = 0.0;
  for (int m = 0; m < single_extra; m++) svector[m] = 0.0;
  if (rsq == 0.0) return 0.0;

  // the pair's history, from whichever of the two atoms this process owns
  double hv[GRIDDEM_MAX_HISTORY] = {0.0};
  const int nv = model.history_size;
  const double *stored = nullptr;
  const griddem_pair_params *law = griddem_model_pair(&model, itype, jtype);
  int owner_is_i = 1;
  if (model.track_contacts && (i < atom->nlocal || j < atom->nlocal)) {
    owner_is_i = i < atom->nlocal;
    const int owner = owner_is_i ? i : j, other = owner_is_i ? j : i;
    const int64_t tag = atom->tag[other];
    stored = fix()->find_history(owner, image_axes && images ? griddem_image_key(tag, images[owner], images[other]) : tag);
    for (int m = 0; stored && m < nv; m++) hv[m] = owner_is_i ? stored[m] : law->parity[m] * stored[m];
  }
  const double *radius = atom->radius;
  if (!griddem_contact_touch(law, rsq, radius[i], radius[j], stored != nullptr)) return 0.0;

  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  const double dx[3] = {x[i][0] - x[j][0], x[i][1] - x[j][1], x[i][2] - x[j][2]};
  const int *mask = atom->mask;
  griddem_contact c;
  // the contact masses of the last step (with rigid bodies: their bodies')
  const double *mass = fix_rigid && (int) contact_mass.size() > MAX(i, j) ? contact_mass.data() : atom->rmass;
  griddem_contact_setup(&c, dx, rsq, radius[i], radius[j], v[i], v[j], omega[i], omega[j], mass[i], mass[j],
                        (mask[i] & freeze_group_bit) != 0, (mask[j] & freeze_group_bit) != 0, update->dt, 0);
  c.fr[0] = c.fr[1] = c.fr[2] = 0.0;    // set by a rolling model only, reported by all
  c.temp_i = conducts_heat ? atom->temperature[i] : 0.0;
  c.temp_j = conducts_heat ? atom->temperature[j] : 0.0;

  double f[3], ti[3], tj[3];
  griddem_contact_eval(law, &c, hv, f, ti, tj);
  fforce = c.fntot * c.rinv;
  for (int k = 0; k < 3; k++) svector[k] = c.fs[k];
  svector[3] = griddem_len3(c.fs);
  if (single_hooke_layout) {
    for (int k = 0; k < 3; k++) svector[4 + k] = c.vnnr * c.n[k], svector[7 + k] = c.vt[k];
  } else {
    for (int k = 0; k < 3; k++) svector[4 + k] = c.fr[k];
    svector[7] = griddem_len3(c.fr);
    svector[8] = law->twisting.model != GRIDDEM_TWISTING_NONE ? c.magtortwist : 0.0;
    for (int k = 0; k < 3; k++) svector[9 + k] = c.dx[k];
    if (conducts_heat) svector[12] = c.heat;
  }
  return 0.0;
}
