/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/granular.
   Takes pair granular's coefficient syntax for the sub-models listed in griddem_submodels.c (the
   table drives parsing, mixing, restart and the refusals): pair granular's other sub-models are
   refused by name, with the table's list. Restart files
   hold each type pair's sub-model names and coefficients, checked on read as pair granular does.
------------------------------------------------------------------------- */

#include "pair_griddem_granular.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"

#include <cstring>
#include <string>

using namespace LAMMPS_NS;

// the keywords' models as the table lists them: "normal hooke, hertz, ...; damping ..."
static std::string supported_models()
{
  std::string list;
  int axis = -1;
  for (size_t k = 0; const griddem_submodel *m = griddem_submodel_at(k); k++) {
    if (m->flags & GRIDDEM_SUBMODEL_INTERNAL) continue;
    if (m->axis != axis) {
      list += (axis < 0 ? "" : "; ") + std::string(griddem_axis_name(m->axis)) + " ";
      axis = m->axis;
    } else {
      list += ", ";
    }
    list += m->name;
  }
  return list;
}

// whether pair granular has a model that griddem/granular does not evaluate
static bool stock_only(const char *keyword, const char *name)
{
  for (size_t k = 0; const griddem_stock_only *u = griddem_stock_only_at(k); k++)
    if (strcmp(u->keyword, keyword) == 0 && strcmp(u->name, name) == 0) return true;
  return false;
}

PairGriddemGranular::PairGriddemGranular(LAMMPS *lmp) : PairGriddem(lmp) {}

/* [cutoff], as pair granular */

void PairGriddemGranular::settings(int narg, char **arg)
{
  if (narg > 1) error->all(FLERR, "Pair style griddem/granular takes at most one argument (cutoff), got {}", narg);
  cutoff_global = narg == 1 ? utils::numeric(FLERR, arg[0], false, lmp) : -1.0;
  if (narg == 1 && cutoff_global <= 0.0)
    error->all(FLERR, "Pair style griddem/granular: cutoff must be > 0, not {}", arg[0]);
  create_default_fix();
}

/* the table's row for a keyword's model name, or an error naming it */

const griddem_submodel *PairGriddemGranular::find_submodel(int axis, const char *name)
{
  const griddem_submodel *m = griddem_submodel_find(axis, name);
  if (m && !(m->flags & GRIDDEM_SUBMODEL_INTERNAL)) return m;
  const char *keyword = griddem_axis_name(axis);
  if (stock_only(keyword, name))
    error->all(FLERR, "Pair style griddem/granular does not support {} model {} (supported: {})", keyword, name,
               supported_models());
  error->all(FLERR, "Pair coeff for griddem/granular: unknown {} model {}", keyword, name);
  return nullptr;
}

void PairGriddemGranular::coeff(int narg, char **arg)
{
  if (narg < 3) error->all(FLERR, "Pair coeff for griddem/granular needs two types and a normal model");
  griddem_pair_spec s;
  griddem_spec_init(&s);

  // a sub-model name and its coefficients (NULL where the row lets it be derived)
  int iarg = 2;
  auto read_submodel = [&](int axis) {
    const griddem_submodel *m = find_submodel(axis, arg[iarg]);
    iarg++;
    if (iarg + m->ncoeff > narg)
      error->all(FLERR, "Pair coeff for griddem/granular: {} needs {} coefficients", m->name, m->ncoeff);
    for (int k = 0; k < m->ncoeff; k++, iarg++) {
      double &c = s.coeffs[axis][k];
      if (m->mix[k] == GRIDDEM_MIX_GEOM_NULL && strcmp(arg[iarg], "NULL") == 0) {
        c = GRIDDEM_NULL_COEFF;
        continue;
      }
      c = utils::numeric(FLERR, arg[iarg], false, lmp);
      if (c < 0.0)
        error->all(FLERR, "Pair coeff for griddem/granular: {} coefficient {} must be >= 0, not {}",
                   m->name, k + 1, arg[iarg]);
    }
    s.sub[axis] = m;
  };

  read_submodel(GRIDDEM_AXIS_NORMAL);
  while (iarg < narg) {
    const char *keyword = arg[iarg];
    if (strcmp(keyword, "limit_damping") == 0) {
      s.limit_damping = 1;
      iarg++;
      continue;
    }
    int axis = GRIDDEM_AXIS_DAMPING;
    while (axis < GRIDDEM_NAXES && strcmp(keyword, griddem_axis_name(axis)) != 0) axis++;
    const bool cutoff = strcmp(keyword, "cutoff") == 0;
    if (axis == GRIDDEM_NAXES && !cutoff) error->all(FLERR, "Pair coeff for griddem/granular: unknown keyword {}", keyword);
    if (iarg + 1 >= narg)
      error->all(FLERR, "Pair coeff for griddem/granular: {} needs {}", keyword, cutoff ? "a value" : "a model name");
    iarg++;
    if (cutoff) {
      s.cutoff = utils::numeric(FLERR, arg[iarg], false, lmp);
      if (s.cutoff <= 0.0) error->all(FLERR, "Pair coeff for griddem/granular: cutoff must be > 0, not {}", arg[iarg]);
      iarg++;
    } else {
      read_submodel(axis);
    }
  }
  set_specs(arg[0], arg[1], s);
}

/* restart: per type pair, each axis's model name and coefficients, then limit_damping, cutoff
   and whether it was mixed */

void PairGriddemGranular::write_spec(FILE *fp, const griddem_pair_spec &s)
{
  for (int axis = 0; axis < GRIDDEM_NAXES; axis++) {
    const griddem_submodel *m = s.sub[axis];
    const int length = (int) strlen(m->name);
    fwrite(&length, sizeof(int), 1, fp);
    fwrite(m->name, sizeof(char), length, fp);
    fwrite(&m->ncoeff, sizeof(int), 1, fp);
    fwrite(s.coeffs[axis], sizeof(double), m->ncoeff, fp);
  }
  fwrite(&s.limit_damping, sizeof(int), 1, fp);
  fwrite(&s.cutoff, sizeof(double), 1, fp);
  fwrite(&s.mixed, sizeof(int), 1, fp);
}

griddem_pair_spec PairGriddemGranular::read_spec(FILE *fp)
{
  griddem_pair_spec s;
  griddem_spec_init(&s);
  const int me = comm->me;
  for (int axis = 0; axis < GRIDDEM_NAXES; axis++) {
    int length = 0, ncoeff = 0;
    if (me == 0) utils::sfread(FLERR, &length, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&length, 1, MPI_INT, 0, world);
    if (length < 0 || length > 256)
      error->all(FLERR, "Pair style griddem/granular: restart file is corrupt ({} model name of {} characters)",
                 griddem_axis_name(axis), length);
    std::string name(length, ' ');
    if (me == 0) utils::sfread(FLERR, &name[0], sizeof(char), length, fp, nullptr, error);
    MPI_Bcast(&name[0], length, MPI_CHAR, 0, world);
    const griddem_submodel *m = griddem_submodel_find(axis, name.c_str());
    if (!m || (m->flags & GRIDDEM_SUBMODEL_INTERNAL))
      error->all(FLERR, "Pair style griddem/granular: restart file names {} model {}, which this build does not know",
                 griddem_axis_name(axis), name);
    if (me == 0) utils::sfread(FLERR, &ncoeff, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&ncoeff, 1, MPI_INT, 0, world);
    if (ncoeff != m->ncoeff)
      error->all(FLERR, "Pair style griddem/granular: restart file gives {} coefficients for {} model {}, which takes {}",
                 ncoeff, griddem_axis_name(axis), name, m->ncoeff);
    if (me == 0) utils::sfread(FLERR, s.coeffs[axis], sizeof(double), ncoeff, fp, nullptr, error);
    MPI_Bcast(s.coeffs[axis], ncoeff, MPI_DOUBLE, 0, world);
    s.sub[axis] = m;
  }
  if (me == 0) {
    utils::sfread(FLERR, &s.limit_damping, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, &s.cutoff, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &s.mixed, sizeof(int), 1, fp, nullptr, error);
  }
  MPI_Bcast(&s.limit_damping, 1, MPI_INT, 0, world);
  MPI_Bcast(&s.cutoff, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&s.mixed, 1, MPI_INT, 0, world);
  return s;
}

void PairGriddemGranular::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  const int n = atom->ntypes + 1;
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) write_spec(fp, specs[i * n + j]);
    }
}

void PairGriddemGranular::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int n = atom->ntypes + 1;
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) {
      if (comm->me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (!setflag[i][j]) continue;
      specs[i * n + j] = specs[j * n + i] = read_spec(fp);
      adopt_layout(specs[i * n + j]);
    }
}

void PairGriddemGranular::write_restart_settings(FILE *fp)
{
  fwrite(&cutoff_global, sizeof(double), 1, fp);
}

void PairGriddemGranular::read_restart_settings(FILE *fp)
{
  if (comm->me == 0) utils::sfread(FLERR, &cutoff_global, sizeof(double), 1, fp, nullptr, error);
  MPI_Bcast(&cutoff_global, 1, MPI_DOUBLE, 0, world);
}
