/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem/rom, adaptive reduced-order DEM (see doc/fix_griddem_rom.md).
------------------------------------------------------------------------- */

#include "fix_griddem_rom.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "grid3d.h"
#include "group.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "region.h"
#include "pair.h"
#include "update.h"
#include "variable.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

using namespace LAMMPS_NS;
using namespace FixConst;

FixGriddemRom::FixGriddemRom(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), kinematic_bit(0), grid(), ncontrol(0), lambda(0.0), eps(-1.0), v0(-1.0),
    overlap_max(0.1), resolved(nullptr), period(1), state(nullptr), fpair(nullptr), nmax(0), counts(),
    grid3d(nullptr), lo_in(), hi_in(), lo_out(), hi_out(), grid_values(), check_grid(), check_bins()
{
  std::string model_file;
  int every = 0;
  int iarg = 3;
  while (iarg < narg) {
    const std::string word = arg[iarg];
    if (word == "control") {
      iarg++;
      while (iarg < narg && utils::strmatch(arg[iarg], "^v_")) control_names.emplace_back(arg[iarg++] + 2);
      if (control_names.empty()) error->all(FLERR, "Fix griddem/rom: keyword control needs v_name arguments");
      continue;
    }
    if (iarg + 2 > narg) error->all(FLERR, "Fix griddem/rom: keyword {} needs a value", word);
    if (word == "model") model_file = arg[iarg + 1];
    else if (word == "eps") eps = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "v0") v0 = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "every") every = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "overlap") overlap_max = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
    else if (word == "resolved") resolved_id = arg[iarg + 1];
    else error->all(FLERR, "Fix griddem/rom: unknown keyword {}", word);
    iarg += 2;
  }
  if (model_file.empty()) error->all(FLERR, "Fix griddem/rom: keyword model is required");
  if (eps < 0.0) error->all(FLERR, "Fix griddem/rom: keyword eps is required and must be >= 0");
  if (v0 <= 0.0) error->all(FLERR, "Fix griddem/rom: keyword v0 is required and must be > 0");
  if (every <= 0) error->all(FLERR, "Fix griddem/rom: keyword every is required and must be > 0");
  if (overlap_max <= 0.0) error->all(FLERR, "Fix griddem/rom: keyword overlap must be > 0");
  if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
    error->all(FLERR, "Fix griddem/rom requires atom_style sphere");
  period = every;    // end_of_step runs each step (the per-atom state follows the atoms)

  read_model(model_file.c_str());
  if ((int) control_names.size() != ncontrol)
    error->all(FLERR, "Fix griddem/rom: model {} has {} controls, the fix names {} (keyword control)",
               model_file, ncontrol, control_names.size());

  const int igroup_kin = group->find_or_create((std::string(id) + "_kinematic").c_str());
  kinematic_bit = group->bitmask[igroup_kin];

  peratom_flag = 1;
  size_peratom_cols = 0;
  peratom_freq = 1;
  vector_flag = 1;
  size_vector = 8;
  global_freq = 1;
  extvector = 0;
  comm_forward = 1;
  pergrid_flag = 1;
  pergrid_freq = every;

  FixGriddemRom::grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  fill_state();
}

FixGriddemRom::~FixGriddemRom()
{
  atom->delete_callback(id, Atom::GROW);
  memory->destroy(state);
  memory->destroy(fpair);
  griddem_bins_free(&check_bins);
  deallocate_grid();
}

int FixGriddemRom::setmask()
{
  return PRE_REVERSE | POST_FORCE | END_OF_STEP;
}

/* The model file (format version 1; doc/fix_griddem_rom.md): '#' starts a comment; then
     griddem/rom 1
     grid NX NY NZ
     box XLO XHI YLO YHI ZLO ZHI
     controls NC
     lambda L
     weights NROW NCOL        (NROW = 3 NX NY NZ, NCOL = 1 + NX NY NZ + NC)
   and NROW x NCOL numbers: row 3 m + d gives velocity component d of voxel m = i + NX (j + NY k)
   as bias + sum_m' w density(m') + sum_c w control(c). Read on rank 0; every mismatch is an
   error that names it. */
void FixGriddemRom::read_model(const char *file)
{
  std::string msg;
  std::vector<double> head(13, 0.0);
  if (comm->me == 0) {
    std::ifstream in(file);
    std::vector<std::string> tok;
    if (!in) msg = fmt::format("cannot open model file {}", file);
    else {
      std::string line;
      while (std::getline(in, line)) {
        const auto hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        std::istringstream ss(line);
        std::string t;
        while (ss >> t) tok.push_back(t);
      }
    }
    size_t p = 0;
    auto expect = [&](const char *key, int nvalues) -> bool {
      if (!msg.empty()) return false;
      if (p >= tok.size() || tok[p] != key) {
        msg = fmt::format("model file {}: expected '{}' at word {}, found '{}'", file, key, p + 1,
                          p < tok.size() ? tok[p] : std::string("end of file"));
        return false;
      }
      if (p + nvalues >= tok.size()) {
        msg = fmt::format("model file {}: '{}' needs {} values", file, key, nvalues);
        return false;
      }
      p++;
      return true;
    };
    auto number = [&](double &out) {
      if (!msg.empty()) return;
      char *end = nullptr;
      out = strtod(tok[p].c_str(), &end);
      if (end == tok[p].c_str() || *end != '\0' || !std::isfinite(out))
        msg = fmt::format("model file {}: '{}' (word {}) is not a finite number", file, tok[p], p + 1);
      p++;
    };
    if (expect("griddem/rom", 1)) {
      number(head[0]);
      if (msg.empty() && head[0] != GRIDDEM_ROM_VERSION)
        msg = fmt::format("model file {}: format version {} is not supported (this build reads version {})",
                          file, tok[p - 1], GRIDDEM_ROM_VERSION);
    }
    if (expect("grid", 3))
      for (int d = 0; d < 3; d++) number(head[1 + d]);
    if (msg.empty())
      for (int d = 0; d < 3; d++)
        if (head[1 + d] < 1 || head[1 + d] != std::floor(head[1 + d]) || head[1 + d] > 1e4)
          msg = fmt::format("model file {}: grid size {} {} {} must be positive integers", file,
                            head[1], head[2], head[3]);
    if (expect("box", 6))
      for (int d = 0; d < 6; d++) number(head[4 + d]);
    if (msg.empty())
      for (int d = 0; d < 3; d++)
        if (!(head[5 + 2 * d] > head[4 + 2 * d]))
          msg = fmt::format("model file {}: box bounds along axis {} are not increasing", file, d);
    if (expect("controls", 1)) number(head[10]);
    if (msg.empty() && (head[10] < 0 || head[10] != std::floor(head[10])))
      msg = fmt::format("model file {}: number of controls {} is not a count", file, head[10]);
    if (expect("lambda", 1)) number(head[11]);
    double nrow = 0, ncol = 0;
    if (expect("weights", 2)) {
      number(nrow);
      number(ncol);
    }
    const double nvox = head[1] * head[2] * head[3];
    if (msg.empty() && nrow != 3 * nvox)
      msg = fmt::format("model file {}: weights has {} rows; grid size {} {} {} needs 3 x {} = {}",
                        file, nrow, head[1], head[2], head[3], nvox, 3 * nvox);
    if (msg.empty() && ncol != 1 + nvox + head[10])
      msg = fmt::format("model file {}: weights has {} columns; grid size {} {} {} and {} controls "
                        "need 1 + {} + {} = {}", file, ncol, head[1], head[2], head[3], head[10],
                        nvox, head[10], 1 + nvox + head[10]);
    if (msg.empty() && tok.size() - p != (size_t) (nrow * ncol))
      msg = fmt::format("model file {}: {} weight values, expected {} x {} = {}", file, tok.size() - p,
                        nrow, ncol, nrow * ncol);
    if (msg.empty()) {
      weights.resize((size_t) (nrow * ncol));
      for (auto &w : weights) number(w);
    }
    head[12] = nrow * ncol;
  }
  int len = msg.size();
  MPI_Bcast(&len, 1, MPI_INT, 0, world);
  msg.resize(len);
  MPI_Bcast(&msg[0], len, MPI_CHAR, 0, world);
  if (len) error->all(FLERR, "Fix griddem/rom: {}", msg);
  MPI_Bcast(head.data(), 13, MPI_DOUBLE, 0, world);
  for (int d = 0; d < 3; d++) {
    grid.n[d] = (int) head[1 + d];
    grid.lo[d] = head[4 + 2 * d];
    grid.hi[d] = head[5 + 2 * d];
  }
  ncontrol = (int) head[10];
  lambda = head[11];
  weights.resize((size_t) head[12]);
  MPI_Bcast(weights.data(), weights.size(), MPI_DOUBLE, 0, world);
  const int nvox = griddem_rom_nvoxel(&grid);
  density.assign(nvox, 0.0);
  feature.assign(1 + nvox + ncontrol, 0.0);
  field.assign(3 * nvox, 0.0);
}

void FixGriddemRom::init()
{
  if (!force->pair || !utils::strmatch(force->pair_style, "^griddem/"))
    error->all(FLERR, "Fix griddem/rom needs a griddem pair style (it skips kinematic-kinematic "
               "pairs through the pair's exclusions); pair style is {}",
               force->pair ? force->pair_style : "none");
  for (int d = 0; d < 3; d++) {
    grid.periodic[d] = domain->periodicity[d];
    const double len = domain->boxhi[d] - domain->boxlo[d];
    if (fabs(grid.lo[d] - domain->boxlo[d]) > 1e-9 * len || fabs(grid.hi[d] - domain->boxhi[d]) > 1e-9 * len)
      error->all(FLERR, "Fix griddem/rom: model box {} {} along axis {} differs from the simulation box {} {}",
                 grid.lo[d], grid.hi[d], "xyz"[d], domain->boxlo[d], domain->boxhi[d]);
  }
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
  // kinematic atoms must leave the step with no force: this fix zeroes them after all others
  const int me = modify->find_fix(id);
  for (int i = me + 1; i < modify->nfix; i++)
    if (modify->fmask[i] & POST_FORCE)
      error->all(FLERR, "Fix griddem/rom must be defined after fix {} ({}), which adds forces",
                 modify->fix[i]->id, modify->fix[i]->style);
  gravities.clear();
  for (auto &ifix : modify->get_fix_by_style("^gravity")) {
    int dim = 0;
    auto gvec = (const double *) ifix->extract("gvec", dim);
    if (gvec) gravities.emplace_back(ifix->groupbit, gvec);
  }
}

void FixGriddemRom::setup(int vflag)
{
  post_force(vflag);
  fill_state();
}

void FixGriddemRom::setup_pre_reverse(int eflag, int vflag)
{
  pre_reverse(eflag, vflag);
}

/* The pair has run and no fix has added forces yet (griddem styles give ghosts nothing, so the
   owned atoms' forces are final): f is the contact forces, kept for the kinematic atoms. */
void FixGriddemRom::pre_reverse(int, int)
{
  double **f = atom->f;
  const int *mask = atom->mask;
  for (int i = 0; i < atom->nlocal; i++)
    if (mask[i] & kinematic_bit)
      for (int d = 0; d < 3; d++) fpair[i][d] = f[i][d];
}

void FixGriddemRom::post_force(int)
{
  zero_kinematic_forces();
}

/* A kinematic atom is released (made dynamic, keeping its force) when the force on it other than
   its contacts with atoms and gravity would change its velocity by more than eps v0 within a
   classification period: |f - f_pair - m g| N dt / m > eps v0: a wall it is driven into, or
   another fix's force. Its contacts with dynamic atoms do not count: in a resting pile a
   kinematic atom carries the weight of dynamic ones above it, which is no reason to release it
   (counting it released most of a loaded pile every step); a dynamic atom that hits it is judged
   by the hit test at the next classification. Gravity is the field's business. The others lose
   their force and torque. */
void FixGriddemRom::zero_kinematic_forces()
{
  int *mask = atom->mask;
  double **f = atom->f, **torque = atom->torque;
  const double *rmass = atom->rmass;
  const double scale = period * update->dt, threshold = eps * v0;
  int released = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & kinematic_bit)) continue;
    double fo[3] = {f[i][0] - fpair[i][0], f[i][1] - fpair[i][1], f[i][2] - fpair[i][2]};
    for (const auto &g : gravities)
      if (mask[i] & g.first)
        for (int d = 0; d < 3; d++) fo[d] -= rmass[i] * g.second[d];
    const double fm2 = fo[0] * fo[0] + fo[1] * fo[1] + fo[2] * fo[2];
    if (sqrt(fm2) * scale > threshold * rmass[i]) {
      mask[i] &= ~kinematic_bit;
      released++;
      continue;
    }
    for (int d = 0; d < 3; d++) f[i][d] = torque[i][d] = 0.0;
  }
  int any = released, all = 0;
  MPI_Allreduce(&any, &all, 1, MPI_INT, MPI_SUM, world);
  if (all) {
    comm->forward_comm(this);    // the ghosts of released atoms too
    counts[5] += all;
    counts[0] -= all;
  }
}

void FixGriddemRom::end_of_step()
{
  if (update->ntimestep % period == 0) classify();
  fill_state();
}

/* The voxel density, the predicted velocity field, and the new state of each atom of the group. */
void FixGriddemRom::classify()
{
  const int nlocal = atom->nlocal, nvox = griddem_rom_nvoxel(&grid);
  double **x = atom->x, **v = atom->v, **omega = atom->omega, **f = atom->f, **torque = atom->torque;
  const double *radius = atom->radius, *rmass = atom->rmass;
  int *mask = atom->mask;

  std::vector<int> use(nlocal);
  for (int i = 0; i < nlocal; i++) use[i] = (mask[i] & groupbit) ? 1 : 0;
  std::vector<double> local(nvox, 0.0);
  if (nlocal) griddem_rom_deposit(&grid, nlocal, x[0], 3, rmass, use.data(), local.data());
  MPI_Allreduce(local.data(), density.data(), nvox, MPI_DOUBLE, MPI_SUM, world);
  feature[0] = 1.0;
  for (int m = 0; m < nvox; m++) feature[1 + m] = density[m];
  for (int c = 0; c < ncontrol; c++) feature[1 + nvox + c] = input->variable->compute_equal(control_vars[c]);
  griddem_rom_predict(3 * nvox, 1 + nvox + ncontrol, weights.data(), feature.data(), field.data());
  fill_grid();

  const double threshold = eps * v0;
  if (resolved) resolved->prematch();
  std::vector<int> next(nlocal, 0);
  std::vector<double> u(3 * (size_t) nlocal, 0.0);
  double made = 0, left = 0, jumps = 0;
  for (int i = 0; i < nlocal; i++) {
    if (!use[i]) continue;
    const int was = (mask[i] & kinematic_bit) ? 1 : 0;
    if (!griddem_rom_inside(&grid, x[i]) || (resolved && resolved->match(x[i][0], x[i][1], x[i][2]))) {
      left += was;
      continue;
    }
    griddem_rom_interpolate(&grid, field.data(), x[i], &u[3 * i]);
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
  if (nall && griddem_rom_check_contacts(nlocal, nall, x[0], v[0], radius, kinematic.data(), u.data(), threshold,
                                         overlap_max, next.data(), &hits, &overlaps, &check_grid, &check_bins) != 0)
    error->one(FLERR, "Fix griddem/rom: out of memory for the contact check of {} atoms", nall);

  double nkin = 0;
  for (int i = 0; i < nlocal; i++) {
    const int was = (mask[i] & kinematic_bit) ? 1 : 0;
    if (next[i]) {
      made += !was;
      nkin += 1;
      mask[i] |= kinematic_bit;
      for (int d = 0; d < 3; d++) {
        v[i][d] = u[3 * i + d];
        omega[i][d] = f[i][d] = torque[i][d] = 0.0;
      }
    } else
      mask[i] &= ~kinematic_bit;
  }
  comm->forward_comm(this);

  double mine[6] = {nkin, made, (double) hits, (double) overlaps, left, jumps}, all[6];
  MPI_Allreduce(mine, all, 6, MPI_DOUBLE, MPI_SUM, world);
  counts[0] = all[0];
  for (int k = 1; k < 5; k++) counts[k] += all[k];
  counts[6] += 1;
  counts[7] += all[5];
}

void FixGriddemRom::fill_state()
{
  for (int i = 0; i < atom->nlocal; i++) state[i] = (atom->mask[i] & kinematic_bit) ? 1.0 : 0.0;
}

void FixGriddemRom::grow_arrays(int n)
{
  memory->grow(state, n, "griddem/rom:state");
  memory->grow(fpair, n, 3, "griddem/rom:fpair");
  vector_atom = state;
  nmax = n;
}


int FixGriddemRom::pack_forward_comm(int n, int *list_, double *buf, int, int *)
{
  for (int i = 0; i < n; i++) buf[i] = (atom->mask[list_[i]] & kinematic_bit) ? 1.0 : 0.0;
  return n;
}

void FixGriddemRom::unpack_forward_comm(int n, int first, double *buf)
{
  int *mask = atom->mask;
  for (int i = 0; i < n; i++) {
    if (buf[i] != 0.0) mask[first + i] |= kinematic_bit;
    else mask[first + i] &= ~kinematic_bit;
  }
}

/* 1: kinematic atoms now; 2: atoms made kinematic; 3, 4, 5, 6: made dynamic again by a hit (a
   touching partner's relative speed), by an overlap, by leaving the model box or entering the
   resolved region, by a force; 7:
   classifications; 8: made dynamic by a jump of the field (2-6 and 8 summed over the run) */
double FixGriddemRom::compute_vector(int n)
{
  return counts[n];
}

void *FixGriddemRom::extract(const char *name, int &dim)
{
  dim = 0;
  if (strcmp(name, "kinematic_bit") == 0) return &kinematic_bit;
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
  return (double) nmax * 4 * sizeof(double) + (weights.size() + 4 * density.size()) * sizeof(double);
}
