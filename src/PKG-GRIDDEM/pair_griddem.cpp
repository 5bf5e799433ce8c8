/* ----------------------------------------------------------------------
   GRIDDEM package: the part every griddem pair style shares (see pair_griddem.h).
   Ghosts receive no force (newton off across processes), so no reverse communication is needed.
------------------------------------------------------------------------- */

#include "pair_griddem.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_griddem.h"
#include "force.h"
#include "group.h"
#include "math_const.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static const char AUTO_FIX_ID[] = "GRIDDEM";

PairGriddem::PairGriddem(LAMMPS *lmp) :
    Pair(lmp), model(), fix(nullptr), coarsened_warned(0), rmin(0.0), rmax(0.0), grid(), bins(),
    channels(), freeze_group_bit(0), exclusions()
{
  no_virial_fdotr_compute = 1;    // ghosts get no force: the virial is tallied pair by pair
  single_enable = 1;
  // what single() reports besides the force, as the stock styles: tangential force and its size,
  // then hooke: normal and tangential relative velocity; granular: rolling force and its size,
  // twisting torque (0: no twisting model), separation vector
  single_extra = 12;
  svector = new double[single_extra];
}

PairGriddem::~PairGriddem()
{
  delete[] svector;
  griddem_bins_free(&bins);
  griddem_channels_free(&channels);
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
}

/* fix GRIDDEM with default options, unless the script already defined a fix griddem; made when
   the pair style is defined so that thermo_style can name f_GRIDDEM before the first run */

void PairGriddem::create_default_fix()
{
  Fix *existing = modify->get_fix_by_id(AUTO_FIX_ID);
  if (existing && model.history_size && dynamic_cast<FixGriddem *>(existing)->slots == 0)
    modify->delete_fix(AUTO_FIX_ID);    // made for a style that keeps no history
  else if (!modify->get_fix_by_style("^griddem$").empty())
    return;
  modify->add_fix(fmt::format("{} all griddem{}", AUTO_FIX_ID, model.history_size ? "" : " contacts 0"));
}

void PairGriddem::init_style()
{
  const char *style = force->pair_style;
  // the sweep finds every pair on the grid, whatever pair hybrid would assign to other styles
  if (force->pair != this)
    error->all(FLERR, "The griddem pair styles cannot be sub-styles of pair {}: they find all contacts on their own grid",
               style);
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
  if (model.history_size && fix->slots == 0)
    error->all(FLERR, "Pair style {} needs contact history: fix {} has contacts 0", style, fix->id);
  if (fix->igroup != 0) error->all(FLERR, "Fix griddem {} must be defined for group all", fix->id);
  fix->set_values(model.history_size);

  auto freezes = modify->get_fix_by_style("^freeze");
  if (freezes.size() > 1) error->all(FLERR, "Only one fix freeze command at a time allowed");
  freeze_group_bit = freezes.empty() ? 0 : freezes.front()->groupbit;

  setup_exclusions();
  find_radius_range();
  type_radius = max_radius_by_type();

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
  // group bits from the group indices: neighbor sets its own bits only after pair styles init
  for (int k = 0; k < neighbor->nex_group; k++) {
    excluded_groups.push_back(group->bitmask[neighbor->ex1_group[k]]);
    excluded_groups.push_back(group->bitmask[neighbor->ex2_group[k]]);
  }
  if (neighbor->nex_mol)
    error->all(FLERR, "Pair style {} does not support neigh_modify exclude molecule/inter or molecule/intra",
               force->pair_style);
  exclusions.type_pair = excluded_types.empty() ? nullptr : excluded_types.data();
  exclusions.ntypes = atom->ntypes;
  exclusions.ngroup_pairs = neighbor->nex_group;
  exclusions.group_bits = excluded_groups.data();
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

void PairGriddem::check_motion(double h_nn4dem)
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

void PairGriddem::report_fault(const griddem_sweep_result &r)
{
  tagint *tag = atom->tag;
  double **x = atom->x;
  const int i = r.fault_i, j = r.fault_j;
  if (r.fault == GRIDDEM_FAULT_COINCIDENT)
    error->one(FLERR, "Pair style {}: atoms {} and {} are at the same position ({} {} {}): the contact normal is undefined",
               force->pair_style, tag[i], tag[j], x[i][0], x[i][1], x[i][2]);
  if (r.fault == GRIDDEM_FAULT_STENCIL)
    error->one(FLERR, "Pair style {}: contact distance {} spans more than {} cells of edge {} (radius ratio {}); use fix griddem cell multi or a larger edge",
               force->pair_style, 2.0 * rmax, GRIDDEM_MAX_REACH, grid.h, rmax / rmin);
  if (r.fault == GRIDDEM_FAULT_MEMORY)
    error->one(FLERR, "Pair style {}: out of memory for the contact history", force->pair_style);
  if (r.fault == GRIDDEM_FAULT_HISTORY_FULL)
    error->one(FLERR, "Pair style {}: atom {} touches more than {} atoms (the last one {}); raise fix griddem contacts",
               force->pair_style, tag[i], fix->slots, tag[j]);
}

void PairGriddem::compute(int eflag, int vflag)
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
  part.type = atom->type;
  part.mask = atom->mask;
  part.frozen_bit = freeze_group_bit;
  if (griddem_channels_fill(&channels, &bins, &part) != 0)
    error->one(FLERR, "Pair style {}: out of memory for {} atoms' channels", force->pair_style, nall);

  griddem_sweep_result result;
  const int history_update = update->setupflag ? 0 : 1;
  griddem_sweep(&grid, &bins, &channels, nlocal, rmax, &model, &exclusions, update->dt,
                history_update, &fix->hist, fix->row_of, atom->f[0], atom->torque[0],
                vflag_atom ? vatom[0] : nullptr, vflag_global, &result);
  if (result.fault != GRIDDEM_FAULT_NONE) report_fault(result);
  if (model.history_size) fix->adopt_rows(bins.n, bins.order, nlocal);

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

/* One pair's contact for compute pair/local: the force over the distance in fforce, the parts
   in svector (layout above, as gran/hooke/history and pair granular); its history is read, not
   advanced. */

double PairGriddem::single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/,
                           double /*factor_lj*/, double &fforce)
{
  fforce = 0.0;
  for (int m = 0; m < single_extra; m++) svector[m] = 0.0;
  const double *radius = atom->radius;
  const double radsum = radius[i] + radius[j];
  if (rsq >= radsum * radsum || rsq == 0.0) return 0.0;

  double **x = atom->x, **v = atom->v, **omega = atom->omega;
  griddem_contact_in c;
  c.delx = x[i][0] - x[j][0], c.dely = x[i][1] - x[j][1], c.delz = x[i][2] - x[j][2];
  c.rsq = rsq;
  c.radi = radius[i], c.radj = radius[j];
  c.vr1 = v[i][0] - v[j][0], c.vr2 = v[i][1] - v[j][1], c.vr3 = v[i][2] - v[j][2];
  c.wi1 = omega[i][0], c.wi2 = omega[i][1], c.wi3 = omega[i][2];
  c.wj1 = omega[j][0], c.wj2 = omega[j][1], c.wj3 = omega[j][2];
  const int *mask = atom->mask;
  c.meff = griddem_effective_mass(atom->rmass[i], atom->rmass[j], (mask[i] & freeze_group_bit) != 0,
                                  (mask[j] & freeze_group_bit) != 0);

  // the pair's history, from whichever of the two atoms this process owns
  double hv[GRIDDEM_MAX_HISTORY] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  const int nv = model.history_size;
  if (nv && (i < atom->nlocal || j < atom->nlocal)) {
    const int owner = i < atom->nlocal ? i : j;
    const double partner = (double) atom->tag[owner == i ? j : i];
    const double *stored = griddem_history_find(&fix->hist, fix->row_of[owner], partner);
    if (stored)
      for (int m = 0; m < nv; m++) hv[m] = owner == i ? stored[m] : model.history_parity[m] * stored[m];
  }

  double f[3], ti[3], tj[3];
  griddem_contact_detail d;
  griddem_pair_contact(&model, itype, jtype, &c, update->dt, 0, hv, f, ti, tj, &d);
  fforce = d.fnormal_over_r;
  for (int k = 0; k < 3; k++) svector[k] = d.fs[k];
  svector[3] = sqrt(d.fs[0] * d.fs[0] + d.fs[1] * d.fs[1] + d.fs[2] * d.fs[2]);
  if (model.law == GRIDDEM_LAW_HOOKE) {
    for (int k = 0; k < 3; k++) svector[4 + k] = d.vn[k], svector[7 + k] = d.vt[k];
  } else {
    for (int k = 0; k < 3; k++) svector[4 + k] = d.fr[k];
    svector[7] = sqrt(d.fr[0] * d.fr[0] + d.fr[1] * d.fr[1] + d.fr[2] * d.fr[2]);
    svector[9] = c.delx, svector[10] = c.dely, svector[11] = c.delz;
  }
  return 0.0;
}

double PairGriddem::memory_usage()
{
  return (double) bins.ncell_cap * sizeof(int) + (double) bins.n_cap * (sizeof(int) + sizeof(long)) +
      (double) channels.cap * (4 * sizeof(double) + sizeof(griddem_slot_state) + sizeof(griddem_slot_sum) +
                               sizeof(int64_t) + sizeof(int));
}
