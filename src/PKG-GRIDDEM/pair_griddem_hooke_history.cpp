/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke/history.
   Takes the arguments of gran/hooke/history. Each step bins owned and ghost atoms into a uniform
   grid (no neighbor list) and runs the C core's stencil sweep in gather form (newton off: ghosts
   receive no force, so no reverse communication). Per-atom history lives in fix griddem.
------------------------------------------------------------------------- */

#include "pair_griddem_hooke_history.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_griddem.h"
#include "force.h"
#include "math_const.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static const char AUTO_FIX_ID[] = "GRIDDEM";

PairGriddemHookeHistory::PairGriddemHookeHistory(LAMMPS *lmp) :
    Pair(lmp), params(), dampflag(1), history(1), fix(nullptr), freeze_group_bit(0), rmin(0.0),
    rmax(0.0), coarsened_warned(0), grid(), bins(), channels()
{
  single_enable = 0;
  no_virial_fdotr_compute = 1;    // ghosts get no force in gather form: tally pair by pair
  params.tangential = GRIDDEM_TANGENTIAL_HISTORY;
}

PairGriddemHookeHistory::~PairGriddemHookeHistory()
{
  griddem_bins_free(&bins);
  griddem_channels_free(&channels);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairGriddemHookeHistory::allocate()
{
  allocated = 1;
  const int n = atom->ntypes + 1;
  memory->create(setflag, n, n, "pair:setflag");
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n, n, "pair:cutsq");
}

/* Kn Kt gamma_n gamma_t xmu dampflag [limit_damping], as gran/hooke/history */

void PairGriddemHookeHistory::settings(int narg, char **arg)
{
  if (narg != 6 && narg != 7)
    error->all(FLERR, "Pair style {} expects Kn Kt gamma_n gamma_t xmu dampflag [limit_damping], got {} arguments",
               force->pair_style, narg);

  params.kn = utils::numeric(FLERR, arg[0], false, lmp);
  params.kt = strcmp(arg[1], "NULL") == 0 ? params.kn * 2.0 / 7.0
                                          : utils::numeric(FLERR, arg[1], false, lmp);
  params.gamman = utils::numeric(FLERR, arg[2], false, lmp);
  params.gammat = strcmp(arg[3], "NULL") == 0 ? 0.5 * params.gamman
                                              : utils::numeric(FLERR, arg[3], false, lmp);
  params.xmu = utils::numeric(FLERR, arg[4], false, lmp);
  dampflag = utils::inumeric(FLERR, arg[5], false, lmp);
  if (dampflag == 0) params.gammat = 0.0;
  params.limit_damping = 0;
  if (narg == 7) {
    if (strcmp(arg[6], "limit_damping") != 0)
      error->all(FLERR, "Pair style {}: unknown keyword {} (only limit_damping)", force->pair_style,
                 arg[6]);
    params.limit_damping = 1;
  }

  if (params.kn < 0.0) error->all(FLERR, "Pair style {}: Kn must be >= 0, not {}", force->pair_style, arg[0]);
  if (params.kt < 0.0) error->all(FLERR, "Pair style {}: Kt must be >= 0, not {}", force->pair_style, arg[1]);
  if (params.gamman < 0.0)
    error->all(FLERR, "Pair style {}: gamma_n must be >= 0, not {}", force->pair_style, arg[2]);
  if (params.gammat < 0.0)
    error->all(FLERR, "Pair style {}: gamma_t must be >= 0, not {}", force->pair_style, arg[3]);
  if (params.xmu < 0.0 || params.xmu > 10000.0)
    error->all(FLERR, "Pair style {}: xmu must be in [0,10000], not {}", force->pair_style, arg[4]);
  if (dampflag < 0 || dampflag > 1)
    error->all(FLERR, "Pair style {}: dampflag must be 0 or 1, not {}", force->pair_style, arg[5]);
  if (history && params.kt == 0.0 && params.xmu > 0.0 && params.gammat > 0.0)
    error->all(FLERR, "Pair style {}: Kt = 0 with tangential damping divides by Kt in the Coulomb cap",
               force->pair_style);
  create_default_fix();
}

/* fix GRIDDEM with default options, unless the script already defined a fix griddem; made when
   the pair style is defined so that thermo_style can name f_GRIDDEM before the first run */

void PairGriddemHookeHistory::create_default_fix()
{
  Fix *existing = modify->get_fix_by_id(AUTO_FIX_ID);
  if (existing && history && dynamic_cast<FixGriddem *>(existing)->slots == 0)
    modify->delete_fix(AUTO_FIX_ID);    // made by griddem/hooke, which keeps no history
  else if (!modify->get_fix_by_style("^griddem$").empty())
    return;
  modify->add_fix(fmt::format("{} all griddem{}", AUTO_FIX_ID, history ? "" : " contacts 0"));
}

void PairGriddemHookeHistory::coeff(int narg, char **arg)
{
  if (narg != 2)
    error->all(FLERR, "Pair coeff for {} takes only the two atom types (the model is set by pair_style), got {} arguments",
               force->pair_style, narg);
  if (!allocated) allocate();

  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) error->all(FLERR, "Pair coeff for {}: no atom types in {} {}", force->pair_style, arg[0], arg[1]);
}

void PairGriddemHookeHistory::init_style()
{
  const char *style = force->pair_style;
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag)
    error->all(FLERR, "Pair style {} requires atom attributes radius, rmass, omega (atom_style sphere)", style);
  if (comm->ghost_velocity == 0)
    error->all(FLERR, "Pair style {} requires ghost atoms store velocity: use comm_modify vel yes", style);
  if (domain->dimension != 3)
    error->all(FLERR, "Pair style {} supports 3d simulations only", style);
  if (atom->molecular != Atom::ATOMIC)
    error->all(FLERR, "Pair style {} does not support molecular systems (special bonds)", style);
  for (const auto &ifix : modify->get_fix_list())
    if (ifix->rigid_flag)
      error->all(FLERR, "Pair style {} does not support rigid bodies (fix {})", style, ifix->style);

  // grid options and history: the user's fix griddem, else the default one settings() made
  auto fixes = modify->get_fix_by_style("^griddem$");
  if (fixes.size() > 1 && modify->get_fix_by_id(AUTO_FIX_ID)) {
    modify->delete_fix(AUTO_FIX_ID);
    fixes = modify->get_fix_by_style("^griddem$");
  }
  if (fixes.size() > 1) error->all(FLERR, "Only one fix griddem may be defined");
  if (fixes.empty()) {
    create_default_fix();
    fixes = modify->get_fix_by_style("^griddem$");
  }
  fix = dynamic_cast<FixGriddem *>(fixes.front());
  if (history && fix->slots == 0)
    error->all(FLERR, "Pair style {} needs contact history: fix {} has contacts 0", style, fix->id);
  if (fix->igroup != 0) error->all(FLERR, "Fix griddem {} must be defined for group all", fix->id);

  auto freezes = modify->get_fix_by_style("^freeze");
  if (freezes.size() > 1) error->all(FLERR, "Only one fix freeze command at a time allowed");
  freeze_group_bit = freezes.empty() ? 0 : freezes.front()->groupbit;

  find_radius_range();

  // NN4DEM stability rule: dt <= pi/5 sqrt(m/k) for the lightest atom
  double mlocal = INFINITY, mmin;
  for (int i = 0; i < atom->nlocal; i++) mlocal = MIN(mlocal, atom->rmass[i]);
  MPI_Allreduce(&mlocal, &mmin, 1, MPI_DOUBLE, MPI_MIN, world);
  if (std::isfinite(mmin) && params.kn > 0.0) {
    const double limit = MathConst::MY_PI / 5.0 * sqrt(mmin / params.kn);
    if (update->dt > limit && comm->me == 0)
      error->warning(FLERR, "Pair style {}: timestep {} exceeds the stability limit pi/5*sqrt(m/Kn) = {} of the lightest atom (mass {})",
                     style, update->dt, limit, mmin);
  }
}

/* cutoff = sum of the largest radii of the two types, including atoms fix pour/deposit will add */

double PairGriddemHookeHistory::init_one(int i, int j)
{
  if (!allocated) allocate();
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
  return maxrad[i] + maxrad[j];
}

void PairGriddemHookeHistory::find_radius_range()
{
  double local[2] = {INFINITY, 0.0}, global[2];
  for (int i = 0; i < atom->nlocal; i++) {
    local[0] = MIN(local[0], atom->radius[i]);
    local[1] = MAX(local[1], atom->radius[i]);
  }
  local[1] = -local[1];
  MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_MIN, world);
  rmin = global[0];
  rmax = -global[1];
  if (rmax > 0.0 && !(rmin > 0.0))
    error->all(FLERR, "Pair style {} requires positive radii: smallest radius is {}", force->pair_style, rmin);
}

/* NN4DEM rule: no atom may cross more than one exact-mode cell (d_min/sqrt(3)) per step */

void PairGriddemHookeHistory::check_motion(double h_nn4dem)
{
  double **v = atom->v;
  const double dt = update->dt;
  double vmax2 = 0.0;
  int fastest = -1;
  for (int i = 0; i < atom->nlocal; i++) {
    const double v2 = v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2];
    if (!std::isfinite(v2))
      error->one(FLERR, "Pair style {}: atom {} has a non-finite velocity ({} {} {})", force->pair_style,
                 atom->tag[i], v[i][0], v[i][1], v[i][2]);
    if (v2 > vmax2) {
      vmax2 = v2;
      fastest = i;
    }
  }
  const double moved = sqrt(vmax2) * dt;
  fix->stats.max_cells_moved = moved / grid.h;
  if (fastest >= 0 && moved > h_nn4dem)
    error->one(FLERR, "Pair style {}: atom {} moves {} per step (speed {}), more than the {} one grid cell allows (dt <= dx/v_max); reduce the timestep",
               force->pair_style, atom->tag[fastest], moved, sqrt(vmax2), h_nn4dem);
}

void PairGriddemHookeHistory::report_fault(const griddem_sweep_result &r)
{
  tagint *tag = atom->tag;
  double **x = atom->x;
  const int i = r.fault_i, j = r.fault_j;
  if (r.fault == GRIDDEM_FAULT_COINCIDENT)
    error->one(FLERR, "Pair style {}: atoms {} and {} are at the same position ({} {} {}): the contact normal is undefined",
               force->pair_style, tag[i], tag[j], x[i][0], x[i][1], x[i][2]);
  if (r.fault == GRIDDEM_FAULT_HISTORY_FULL)
    error->one(FLERR, "Pair style {}: atom {} touches more than {} atoms (the last one {}); raise fix griddem contacts",
               force->pair_style, tag[i], fix->slots, tag[j]);
}

void PairGriddemHookeHistory::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);

  double **x = atom->x;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;

  const int bad = griddem_first_nonfinite(nall, x[0]);
  if (bad >= 0)
    error->one(FLERR, "Pair style {}: atom {} has a non-finite position ({} {} {})", force->pair_style,
               atom->tag[bad], x[bad][0], x[bad][1], x[bad][2]);

  if (neighbor->ago == 0) find_radius_range();
  if (rmax == 0.0) return;    // no atoms yet

  const double h_nn4dem = griddem_cell_edge(GRIDDEM_CELL_EXACT, rmin, rmax, 0.0);
  const double h = griddem_cell_edge(fix->cell_mode, rmin, rmax, fix->cell_edge);
  const long max_cells = 32L * nall + 65536L;
  if (griddem_grid_cover(&grid, domain->boxlo, nall, x[0], h, max_cells) && !coarsened_warned) {
    coarsened_warned = 1;
    error->warning(FLERR, "Pair style {}: cell edge enlarged from {} to {} so that the grid over this process's atoms stays within {} cells",
                   force->pair_style, h, grid.h, max_cells);
  }
  if (griddem_bin_points(&bins, &grid, nall, x[0], atom->tag, sizeof(tagint)) != 0 )
    error->one(FLERR, "Pair style {}: out of memory binning {} atoms into {} cells", force->pair_style, nall, grid.ncell);

  griddem_particles part;
  part.nlocal = nlocal;
  part.nall = nall;
  part.x = x[0];
  part.v = atom->v[0];
  part.omega = atom->omega[0];
  part.radius = atom->radius;
  part.rmass = atom->rmass;
  part.tag = atom->tag;
  part.tag_bytes = sizeof(tagint);
  part.mask = freeze_group_bit ? atom->mask : nullptr;
  part.frozen_bit = freeze_group_bit;
  if (griddem_channels_fill(&channels, &bins, &part) != 0)
    error->one(FLERR, "Pair style {}: out of memory for {} atoms' channels", force->pair_style, nall);

  griddem_history hist;
  hist.rows = fix->history ? fix->history[0] : nullptr;
  hist.stride = fix->stride;
  hist.slots = fix->slots;

  griddem_sweep_result result;
  const int shearupdate = update->setupflag ? 0 : 1;
  griddem_sweep(&grid, &bins, &channels, nlocal, rmax, &params, update->dt, shearupdate,
                history ? &hist : nullptr, atom->f[0], atom->torque[0],
                vflag_atom ? vatom[0] : nullptr, vflag_global, &result);
  if (result.fault != GRIDDEM_FAULT_NONE) report_fault(result);

  if (vflag_global)
    for (int k = 0; k < 6; k++) virial[k] += result.virial[k];

  fix->stats.occupied_cells = bins.occupied;
  fix->stats.max_occupancy = bins.max_occupancy;
  fix->stats.cell_edge = grid.h;
  fix->stats.contacts = result.contacts;
  fix->stats.max_contacts = result.max_contacts;
  fix->stats.elastic_energy = result.energy;
  check_motion(h_nn4dem);
}

void PairGriddemHookeHistory::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) fwrite(&setflag[i][j], sizeof(int), 1, fp);
}

void PairGriddemHookeHistory::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      if (comm->me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
    }
}

void PairGriddemHookeHistory::write_restart_settings(FILE *fp)
{
  double values[5] = {params.kn, params.kt, params.gamman, params.gammat, params.xmu};
  int flags[2] = {dampflag, params.limit_damping};
  fwrite(values, sizeof(double), 5, fp);
  fwrite(flags, sizeof(int), 2, fp);
}

void PairGriddemHookeHistory::read_restart_settings(FILE *fp)
{
  double values[5];
  int flags[2];
  if (comm->me == 0) {
    utils::sfread(FLERR, values, sizeof(double), 5, fp, nullptr, error);
    utils::sfread(FLERR, flags, sizeof(int), 2, fp, nullptr, error);
  }
  MPI_Bcast(values, 5, MPI_DOUBLE, 0, world);
  MPI_Bcast(flags, 2, MPI_INT, 0, world);
  params.kn = values[0], params.kt = values[1], params.gamman = values[2];
  params.gammat = values[3], params.xmu = values[4];
  dampflag = flags[0];
  params.limit_damping = flags[1];
}

double PairGriddemHookeHistory::memory_usage()
{
  return (double) bins.ncell_cap * sizeof(int) + (double) bins.n_cap * (sizeof(int) + sizeof(long)) +
      (double) channels.cap * (11 * sizeof(double) + sizeof(int64_t) + 1);
}
