/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke/history, the grid twin of gran/hooke/history.
   Takes the arguments of gran/hooke/history; the engine is PairGriddem.
------------------------------------------------------------------------- */

#include "pair_griddem_hooke_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "memory.h"

#include <cstring>

using namespace LAMMPS_NS;

PairGriddemHookeHistory::PairGriddemHookeHistory(LAMMPS *lmp) :
    PairGriddem(lmp), dampflag(1), style_tangential(GRIDDEM_TANGENTIAL_HISTORY)
{
  model.law = GRIDDEM_LAW_HOOKE;
  single_extra = 10;    // tangential force (3) and its size, normal and tangential velocity (3+3)
  select_tangential();
}

/* The style's tangential model, unless its coefficients make the tangential force zero
   (xmu = 0, or no tangential damping without history): then none is evaluated or stored,
   so a scene without friction pays nothing for it. */

void PairGriddemHookeHistory::select_tangential()
{
  int tangential = style_tangential;
  if (model.hooke.xmu == 0.0 ||
      (tangential == GRIDDEM_TANGENTIAL_DAMPED && model.hooke.gammat == 0.0))
    tangential = GRIDDEM_TANGENTIAL_NONE;
  model.hooke.tangential = tangential;
  model.history_size = tangential == GRIDDEM_TANGENTIAL_HISTORY ? 3 : 0;
  for (int k = 0; k < 3; k++) model.history_parity[k] = -1.0;    // shear seen from j is -shear
}

/* Kn Kt gamma_n gamma_t xmu dampflag [limit_damping], as gran/hooke/history */

void PairGriddemHookeHistory::settings(int narg, char **arg)
{
  if (narg != 6 && narg != 7)
    error->all(FLERR, "Pair style {} expects Kn Kt gamma_n gamma_t xmu dampflag [limit_damping], got {} arguments",
               force->pair_style, narg);

  model.hooke.kn = utils::numeric(FLERR, arg[0], false, lmp);
  model.hooke.kt = strcmp(arg[1], "NULL") == 0 ? model.hooke.kn * 2.0 / 7.0
                                          : utils::numeric(FLERR, arg[1], false, lmp);
  model.hooke.gamman = utils::numeric(FLERR, arg[2], false, lmp);
  model.hooke.gammat = strcmp(arg[3], "NULL") == 0 ? 0.5 * model.hooke.gamman
                                              : utils::numeric(FLERR, arg[3], false, lmp);
  model.hooke.xmu = utils::numeric(FLERR, arg[4], false, lmp);
  dampflag = utils::inumeric(FLERR, arg[5], false, lmp);
  if (dampflag == 0) model.hooke.gammat = 0.0;
  model.hooke.limit_damping = 0;
  if (narg == 7) {
    if (strcmp(arg[6], "limit_damping") != 0)
      error->all(FLERR, "Pair style {}: unknown keyword {} (only limit_damping)", force->pair_style,
                 arg[6]);
    model.hooke.limit_damping = 1;
  }

  if (model.hooke.kn < 0.0) error->all(FLERR, "Pair style {}: Kn must be >= 0, not {}", force->pair_style, arg[0]);
  if (model.hooke.kt < 0.0) error->all(FLERR, "Pair style {}: Kt must be >= 0, not {}", force->pair_style, arg[1]);
  if (model.hooke.gamman < 0.0)
    error->all(FLERR, "Pair style {}: gamma_n must be >= 0, not {}", force->pair_style, arg[2]);
  if (model.hooke.gammat < 0.0)
    error->all(FLERR, "Pair style {}: gamma_t must be >= 0, not {}", force->pair_style, arg[3]);
  if (model.hooke.xmu < 0.0 || model.hooke.xmu > 10000.0)
    error->all(FLERR, "Pair style {}: xmu must be in [0,10000], not {}", force->pair_style, arg[4]);
  if (dampflag < 0 || dampflag > 1)
    error->all(FLERR, "Pair style {}: dampflag must be 0 or 1, not {}", force->pair_style, arg[5]);
  select_tangential();
  if (model.hooke.tangential == GRIDDEM_TANGENTIAL_HISTORY && model.hooke.kt == 0.0 && model.hooke.gammat > 0.0)
    error->all(FLERR, "Pair style {}: Kt = 0 with tangential damping divides by Kt in the Coulomb cap",
               force->pair_style);
  create_default_fix();
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

/* cutoff = sum of the largest radii of the two types, including atoms fix pour/deposit will add */

double PairGriddemHookeHistory::init_one(int i, int j)
{
  if (!allocated) allocate();
  return type_radius[i] + type_radius[j];
}

double PairGriddemHookeHistory::linear_normal_stiffness()
{
  return model.hooke.kn;
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
  double values[5] = {model.hooke.kn, model.hooke.kt, model.hooke.gamman, model.hooke.gammat, model.hooke.xmu};
  int flags[2] = {dampflag, model.hooke.limit_damping};
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
  model.hooke.kn = values[0], model.hooke.kt = values[1], model.hooke.gamman = values[2];
  model.hooke.gammat = values[3], model.hooke.xmu = values[4];
  dampflag = flags[0];
  model.hooke.limit_damping = flags[1];
  select_tangential();
}
