/* ----------------------------------------------------------------------
   GRIDDEM package: compute griddem/grid.
   Bins the group's atoms by centre into an Nx x Ny x Nz grid over the box and gives per cell the
   number of centres, the binned solid (sphere volumes of the centres in the cell over the cell
   volume: not bounded by 1) and the mass-averaged velocity, as LAMMPS grid data: dump grid and
   dump grid/vtk write it. Contributions are summed over processes with one reduction of the whole
   grid, so the grid should stay moderate (each process holds 5 values per cell while summing).
------------------------------------------------------------------------- */

#include "compute_griddem_grid.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "grid3d.h"
#include "griddem_grid.h"
#include "math_const.h"
#include "memory.h"
#include "update.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static const char *const FIELD_NAMES[] = {"count", "binned_solid", "vx", "vy", "vz"};
enum { SUM_COUNT, SUM_VOLUME, SUM_PX, SUM_PY, SUM_PZ, SUM_MASS, NSUM };

ComputeGriddemGrid::ComputeGriddemGrid(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), grid3d(nullptr), array3d(nullptr)
{
  if (narg < 7) utils::missing_cmd_args(FLERR, "compute griddem/grid", error);
  if (!domain->box_exist) error->all(FLERR, "Compute griddem/grid command before simulation box is defined");
  if (domain->dimension != 3) error->all(FLERR, "Compute griddem/grid requires a 3d simulation");
  if (domain->triclinic) error->all(FLERR, "Compute griddem/grid does not support triclinic boxes");
  if (!atom->radius_flag || !atom->rmass_flag)
    error->all(FLERR, "Compute griddem/grid requires atom attributes radius and rmass (atom_style sphere)");
  for (int d = 0; d < 3; d++) {
    ncell[d] = utils::inumeric(FLERR, arg[3 + d], false, lmp);
    if (ncell[d] <= 0 || ncell[d] > 100000)
      error->all(FLERR, "Compute griddem/grid: grid count {} must be between 1 and 100000, not {}",
                 "xyz"[d], arg[3 + d]);
  }
  for (int iarg = 6; iarg < narg; iarg++) {
    int k = 0;
    while (k < NFIELDS && strcmp(arg[iarg], FIELD_NAMES[k]) != 0) k++;
    if (strcmp(arg[iarg], "solid") == 0)
      error->all(FLERR, "Compute griddem/grid: no value solid: binned_solid is the sphere volume "
                 "binned by centre over the cell volume (above 1 in cells under a few diameters "
                 "wide); compute griddem/cg solid is a solid fraction");
    if (k == NFIELDS)
      error->all(FLERR, "Compute griddem/grid: unknown value {} (count, binned_solid, vx, vy, vz)",
                 arg[iarg]);
    fields.push_back(k);
  }
  pergrid_flag = 1;
  allocate_grid();
}

ComputeGriddemGrid::~ComputeGriddemGrid()
{
  deallocate_grid();
}

void ComputeGriddemGrid::init()
{
  if (domain->triclinic)
    error->all(FLERR, "Compute griddem/grid does not support triclinic boxes (the box became one)");
}

void ComputeGriddemGrid::allocate_grid()
{
  grid3d = new Grid3d(lmp, world, ncell[0], ncell[1], ncell[2]);
  grid3d->setup_grid(lo_in[0], hi_in[0], lo_in[1], hi_in[1], lo_in[2], hi_in[2], lo_out[0],
                     hi_out[0], lo_out[1], hi_out[1], lo_out[2], hi_out[2]);
  columns.assign(fields.size(), nullptr);
  for (auto &column : columns)
    memory->create3d_offset(column, lo_out[2], hi_out[2], lo_out[1], hi_out[1], lo_out[0],
                            hi_out[0], "griddem/grid:column");
  if (fields.size() > 1)
    memory->create4d_offset_last(array3d, lo_out[2], hi_out[2], lo_out[1], hi_out[1], lo_out[0],
                                 hi_out[0], (int) fields.size(), "griddem/grid:array3d");
}

void ComputeGriddemGrid::deallocate_grid()
{
  delete grid3d;
  grid3d = nullptr;
  for (auto &column : columns) memory->destroy3d_offset(column, lo_out[2], lo_out[1], lo_out[0]);
  columns.clear();
  memory->destroy4d_offset_last(array3d, lo_out[2], lo_out[1], lo_out[0]);
}

void ComputeGriddemGrid::reset_grid()
{
  deallocate_grid();
  allocate_grid();
}

void ComputeGriddemGrid::compute_pergrid()
{
  invoked_pergrid = update->ntimestep;

  // sum each atom into the cell holding its centre, over all processes
  const long ncells = (long) ncell[0] * ncell[1] * ncell[2];
  std::vector<double> local(NSUM * ncells, 0.0);
  global.assign(NSUM * ncells, 0.0);
  double **x = atom->x, **v = atom->v;
  const double *boxlo = domain->boxlo, *prd = domain->prd;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(atom->mask[i] & groupbit)) continue;
    const long index = griddem_box_cell(boxlo, prd, ncell, x[i]);
    const double m = atom->rmass[i], r = atom->radius[i];
    double *cell = &local[NSUM * index];
    cell[SUM_COUNT] += 1.0;
    cell[SUM_VOLUME] += 4.0 / 3.0 * MathConst::MY_PI * r * r * r;
    cell[SUM_PX] += m * v[i][0], cell[SUM_PY] += m * v[i][1], cell[SUM_PZ] += m * v[i][2];
    cell[SUM_MASS] += m;
  }
  MPI_Allreduce(local.data(), global.data(), (int) (NSUM * ncells), MPI_DOUBLE, MPI_SUM, world);

  const double cellvol = prd[0] * prd[1] * prd[2] / ncells;
  for (int iz = lo_in[2]; iz <= hi_in[2]; iz++)
    for (int iy = lo_in[1]; iy <= hi_in[1]; iy++)
      for (int ix = lo_in[0]; ix <= hi_in[0]; ix++) {
        const double *cell = &global[NSUM * (ix + (long) ncell[0] * (iy + (long) ncell[1] * iz))];
        const double minv = cell[SUM_MASS] > 0.0 ? 1.0 / cell[SUM_MASS] : 0.0;
        for (size_t n = 0; n < fields.size(); n++) {
          double value = 0.0;
          switch (fields[n]) {
            case COUNT: value = cell[SUM_COUNT]; break;
            case BINNED_SOLID: value = cell[SUM_VOLUME] / cellvol; break;
            case VX: value = cell[SUM_PX] * minv; break;
            case VY: value = cell[SUM_PY] * minv; break;
            case VZ: value = cell[SUM_PZ] * minv; break;
          }
          columns[n][iz][iy][ix] = value;
          if (array3d) array3d[iz][iy][ix][n] = value;
        }
      }
}

int ComputeGriddemGrid::get_grid_by_name(const std::string &name, int &dim)
{
  if (name != "grid") return -1;
  dim = 3;
  return 0;
}

void *ComputeGriddemGrid::get_grid_by_index(int index)
{
  return index == 0 ? grid3d : nullptr;
}

// data index 0: "data", all values (a per-grid array, or a vector with one value); 1 + n: value n
int ComputeGriddemGrid::get_griddata_by_name(int igrid, const std::string &name, int &ncol)
{
  if (igrid != 0) return -1;
  if (name == "data") {
    ncol = fields.size() == 1 ? 0 : (int) fields.size();
    return 0;
  }
  for (size_t n = 0; n < fields.size(); n++)
    if (name == FIELD_NAMES[fields[n]]) {
      ncol = 0;
      return 1 + (int) n;
    }
  return -1;
}

void *ComputeGriddemGrid::get_griddata_by_index(int index)
{
  // fix ave/grid reads grid data without clearing the invoked flags (compute_griddem_cg.cpp)
  if (grid3d && invoked_pergrid != update->ntimestep) compute_pergrid();
  if (index == 0) return fields.size() == 1 ? (void *) columns[0] : (void *) array3d;
  return index >= 1 && index <= (int) columns.size() ? (void *) columns[index - 1] : nullptr;
}

double ComputeGriddemGrid::memory_usage()
{
  const double owned = (double) (hi_out[0] - lo_out[0] + 1) * (hi_out[1] - lo_out[1] + 1) *
      (hi_out[2] - lo_out[2] + 1);
  return owned * fields.size() * (array3d ? 2 : 1) * sizeof(double) +
      (double) global.capacity() * 2 * sizeof(double);
}
