/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/hooke/history, the grid twin of gran/hooke/history (and,
   without shear history, of gran/hooke; with a Hertzian normal force, of gran/hertz/history).
   Takes their arguments and expresses them as sub-models: normal hooke or hertz (Kn, gamma_n)
   with mass_velocity damping and the gran/hooke(/history) tangential law (Kt, gamma_t, xmu), the
   same for all type pairs.
------------------------------------------------------------------------- */

#include "pair_griddem_hooke_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"

#include <cstring>

using namespace LAMMPS_NS;

PairGriddemHookeHistory::PairGriddemHookeHistory(LAMMPS *lmp) :
    PairGriddem(lmp), kn(0.0), kt(0.0), gamman(0.0), gammat(0.0), xmu(0.0), dampflag(1),
    limit_damping(0), shear_history(1), hertz(0)
{
  single_hooke_layout = 1;
  single_extra = 10;    // tangential force (3) and its size, normal and tangential velocity (3+3)
}

/* The style's sub-models. Coefficients that make the tangential force zero (xmu = 0, or no
   tangential damping without history) select no tangential model: nothing is evaluated or
   stored, so a scene without friction pays nothing for it. */

griddem_pair_spec PairGriddemHookeHistory::style_spec() const
{
  griddem_pair_spec s;
  griddem_spec_init(&s);
  s.sub[GRIDDEM_AXIS_NORMAL] = griddem_submodel_find(GRIDDEM_AXIS_NORMAL, hertz ? "hertz" : "hooke");
  s.coeffs[GRIDDEM_AXIS_NORMAL][0] = kn;
  s.coeffs[GRIDDEM_AXIS_NORMAL][1] = gamman;
  s.sub[GRIDDEM_AXIS_DAMPING] = griddem_submodel_find(GRIDDEM_AXIS_DAMPING, "mass_velocity");
  const char *tangential = shear_history ? "gran/hooke/history" : "gran/hooke";
  if (xmu == 0.0 || (!shear_history && gammat == 0.0)) tangential = "none";
  const griddem_submodel *t = griddem_submodel_find(GRIDDEM_AXIS_TANGENTIAL, tangential);
  s.sub[GRIDDEM_AXIS_TANGENTIAL] = t;
  const double coeffs[3] = {kt, gammat, xmu};
  for (int k = 0; k < t->ncoeff; k++) s.coeffs[GRIDDEM_AXIS_TANGENTIAL][k] = coeffs[k + 3 - t->ncoeff];
  s.limit_damping = limit_damping;
  return s;
}

/* the spec of the style's arguments for every type pair already set */

void PairGriddemHookeHistory::adopt_style_spec()
{
  const griddem_pair_spec s = style_spec();
  layout_set = 0;
  adopt_layout(s);
  if (!allocated) return;
  const int n = atom->ntypes + 1;
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++)
      if (setflag[i][j]) specs[i * n + j] = specs[j * n + i] = s;
}

/* Kn Kt gamma_n gamma_t xmu dampflag [limit_damping], as gran/hooke/history */

void PairGriddemHookeHistory::settings(int narg, char **arg)
{
  if (narg != 6 && narg != 7)
    error->all(FLERR, "Pair style {} expects Kn Kt gamma_n gamma_t xmu dampflag [limit_damping], got {} arguments",
               force->pair_style, narg);

  kn = utils::numeric(FLERR, arg[0], false, lmp);
  kt = strcmp(arg[1], "NULL") == 0 ? kn * 2.0 / 7.0 : utils::numeric(FLERR, arg[1], false, lmp);
  gamman = utils::numeric(FLERR, arg[2], false, lmp);
  gammat = strcmp(arg[3], "NULL") == 0 ? 0.5 * gamman : utils::numeric(FLERR, arg[3], false, lmp);
  xmu = utils::numeric(FLERR, arg[4], false, lmp);
  dampflag = utils::inumeric(FLERR, arg[5], false, lmp);
  if (dampflag == 0) gammat = 0.0;
  limit_damping = 0;
  if (narg == 7) {
    if (strcmp(arg[6], "limit_damping") != 0)
      error->all(FLERR, "Pair style {}: unknown keyword {} (only limit_damping)", force->pair_style, arg[6]);
    limit_damping = 1;
  }

  if (kn < 0.0) error->all(FLERR, "Pair style {}: Kn must be >= 0, not {}", force->pair_style, arg[0]);
  if (kt < 0.0) error->all(FLERR, "Pair style {}: Kt must be >= 0, not {}", force->pair_style, arg[1]);
  if (gamman < 0.0) error->all(FLERR, "Pair style {}: gamma_n must be >= 0, not {}", force->pair_style, arg[2]);
  if (gammat < 0.0) error->all(FLERR, "Pair style {}: gamma_t must be >= 0, not {}", force->pair_style, arg[3]);
  if (xmu < 0.0 || xmu > 10000.0)
    error->all(FLERR, "Pair style {}: xmu must be in [0,10000], not {}", force->pair_style, arg[4]);
  if (dampflag < 0 || dampflag > 1)
    error->all(FLERR, "Pair style {}: dampflag must be 0 or 1, not {}", force->pair_style, arg[5]);
  // gran/hertz/history takes Kn and Kt in pressure units
  if (hertz) kn /= force->nktv2p, kt /= force->nktv2p;
  griddem_pair_params p;
  char why[256];
  const griddem_pair_spec s = style_spec();
  if (griddem_spec_to_params(&s, &p, why, sizeof(why)) != 0)
    error->all(FLERR, "Pair style {}: {}", force->pair_style, why);
  adopt_style_spec();
  create_default_fix();
}

void PairGriddemHookeHistory::coeff(int narg, char **arg)
{
  if (narg != 2)
    error->all(FLERR, "Pair coeff for {} takes only the two atom types (the model is set by pair_style), got {} arguments",
               force->pair_style, narg);
  set_specs(arg[0], arg[1], style_spec());
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
  adopt_style_spec();
}

void PairGriddemHookeHistory::write_restart_settings(FILE *fp)
{
  double values[5] = {kn, kt, gamman, gammat, xmu};
  int flags[2] = {dampflag, limit_damping};
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
  kn = values[0], kt = values[1], gamman = values[2], gammat = values[3], xmu = values[4];
  dampflag = flags[0];
  limit_damping = flags[1];
}
