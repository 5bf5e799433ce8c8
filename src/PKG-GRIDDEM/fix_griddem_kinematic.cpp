/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem/kinematic (fix_griddem_kinematic.h).

   In post_force, an atom of the group inside the region gets zero force and torque, the
   prescribed velocity and no rotation: the time integrator's two half steps then leave its
   velocity as set and move it by dt times that velocity. The fix therefore comes after every fix
   that adds forces (checked), as fix setforce must.
------------------------------------------------------------------------- */

#include "fix_griddem_kinematic.h"

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "input.h"
#include "modify.h"
#include "region.h"
#include "update.h"
#include "variable.h"

#include <cmath>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

FixGriddemKinematic::FixGriddemKinematic(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), region(nullptr), held(0)
{
  // fix ID group griddem/kinematic region R velocity VX VY VZ
  if (narg != 9) error->all(FLERR, "Illegal fix griddem/kinematic command: expected region R velocity VX VY VZ");
  if (strcmp(arg[3], "region") != 0)
    error->all(FLERR, "Fix griddem/kinematic: expected keyword 'region', got '{}'", arg[3]);
  region_id = arg[4];
  if (!domain->get_region_by_id(region_id))
    error->all(FLERR, "Fix griddem/kinematic: region {} does not exist", region_id);
  if (strcmp(arg[5], "velocity") != 0)
    error->all(FLERR, "Fix griddem/kinematic: expected keyword 'velocity', got '{}'", arg[5]);
  for (int d = 0; d < 3; d++) {
    const char *word = arg[6 + d];
    velocity[d].value = 0.0;
    velocity[d].index = -1;
    if (strncmp(word, "v_", 2) == 0)
      velocity[d].variable = word + 2;
    else
      velocity[d].value = utils::numeric(FLERR, word, false, lmp);
  }
  dynamic_group_allow = 1;
  scalar_flag = 1;
  global_freq = 1;
  extscalar = 0;
}

int FixGriddemKinematic::setmask()
{
  return POST_FORCE;
}

void FixGriddemKinematic::init()
{
  region = domain->get_region_by_id(region_id);
  if (!region) error->all(FLERR, "Fix griddem/kinematic: region {} does not exist", region_id);
  for (auto &c : velocity) {
    if (c.variable.empty()) continue;
    c.index = input->variable->find(c.variable.c_str());
    if (c.index < 0) error->all(FLERR, "Fix griddem/kinematic: variable {} does not exist", c.variable);
    if (!input->variable->equalstyle(c.index))
      error->all(FLERR, "Fix griddem/kinematic: variable {} is not equal-style", c.variable);
  }
  if (utils::strmatch(update->integrate_style, "^respa"))
    error->all(FLERR, "Fix griddem/kinematic does not support run style respa");
  // a later fix's forces would move the held atoms
  bool after = false;
  for (auto &fix : modify->get_fix_list()) {
    if (fix == this) {
      after = true;
    } else if (after && (fix->setmask() & POST_FORCE)) {
      error->all(FLERR, "Fix griddem/kinematic {} must come after fix {} ({}), which sets forces", id, fix->id,
                 fix->style);
    }
  }
}

void FixGriddemKinematic::setup(int vflag)
{
  post_force(vflag);
}

void FixGriddemKinematic::post_force(int /*vflag*/)
{
  double v[3];
  bool variables = false;
  for (int d = 0; d < 3; d++) variables |= !velocity[d].variable.empty();
  if (variables) modify->clearstep_compute();
  for (int d = 0; d < 3; d++)
    v[d] = velocity[d].variable.empty() ? velocity[d].value : input->variable->compute_equal(velocity[d].index);
  if (variables) modify->addstep_compute(update->ntimestep + 1);
  // an atom held in the xy plane of a 2d run stays there
  for (int d = 0; d < 3; d++)
    if (!std::isfinite(v[d]) || (d == 2 && domain->dimension == 2 && v[d] != 0.0))
      error->all(FLERR, "Fix griddem/kinematic {}: velocity along {} is {}{}{}", id, "xyz"[d], v[d],
                 velocity[d].variable.empty() ? std::string() : fmt::format(" (variable {})", velocity[d].variable),
                 std::isfinite(v[d]) ? ", and a 2d run needs 0" : "");

  region->prematch();
  double **x = atom->x, **vel = atom->v, **f = atom->f;
  double **omega = atom->omega_flag ? atom->omega : nullptr;
  double **torque = atom->torque_flag ? atom->torque : nullptr;
  const int *mask = atom->mask;
  held = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (!(mask[i] & groupbit) || !region->match(x[i][0], x[i][1], x[i][2])) continue;
    for (int d = 0; d < 3; d++) {
      f[i][d] = 0.0;
      vel[i][d] = v[d];
      if (omega) omega[i][d] = 0.0;
      if (torque) torque[i][d] = 0.0;
    }
    held++;
  }
}

// summed over the processes only when asked (thermo), not at every step
double FixGriddemKinematic::compute_scalar()
{
  bigint all = 0;
  MPI_Allreduce(&held, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  return (double) all;
}
