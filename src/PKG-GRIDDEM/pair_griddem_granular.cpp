/* ----------------------------------------------------------------------
   GRIDDEM package: pair style griddem/granular.
   Takes pair granular's coefficient syntax for normal hooke | hertz | hertz/material, damping
   velocity | mass_velocity | viscoelastic | tsuji, tangential linear_nohistory | linear_history,
   rolling sds, and the cutoff and limit_damping keywords; other sub-models are refused by name.
   Coefficients of unlike types mix as in pair granular.
------------------------------------------------------------------------- */

#include "pair_griddem_granular.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_griddem.h"
#include "force.h"
#include "math_special.h"
#include "memory.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static const char *const NORMAL_NAMES[] = {"hooke", "hertz", "hertz/material"};
static const int NORMAL_NCOEFFS[] = {2, 2, 3};
static const char *const DAMPING_NAMES[] = {"velocity", "mass_velocity", "viscoelastic", "tsuji"};
static const char *const TANGENTIAL_NAMES[] = {"", "linear_nohistory", "linear_history"};
static const int TANGENTIAL_NCOEFFS[] = {0, 2, 3};

// names pair granular knows that griddem/granular does not evaluate, per keyword
static const char *const UNSUPPORTED[][2] = {
    {"normal", "dmt"}, {"normal", "jkr"}, {"normal", "mdr"}, {"normal", "none"},
    {"damping", "none"}, {"damping", "coeff_restitution"}, {"tangential", "none"},
    {"tangential", "linear_history_classic"}, {"tangential", "mindlin_classic"},
    {"tangential", "mindlin"}, {"tangential", "mindlin/force"}, {"tangential", "mindlin_rescale"},
    {"tangential", "mindlin_rescale/force"}, {"rolling", "none"}, {"twisting", "marshall"},
    {"twisting", "sds"}, {"heat", "radius"}, {"heat", "area"}};

static int find_name(const char *name, const char *const *names, int n)
{
  for (int k = 0; k < n; k++)
    if (strcmp(name, names[k]) == 0) return k;
  return -1;
}

static double mix_geom(double a, double b)
{
  return sqrt(a * b);
}

// effective Young's modulus of two materials, as pair granular's mix_stiffnessE
static double mix_stiffness_e(double e1, double e2, double poiss1, double poiss2)
{
  const double factor1 = (1 - poiss1 * poiss1) / e1;
  const double factor2 = (1 - poiss2 * poiss2) / e2;
  return 1 / (factor1 + factor2);
}

PairGriddemGranular::PairGriddemGranular(LAMMPS *lmp) :
    PairGriddem(lmp), cutoff_global(-1.0), layout_set(0)
{
  model.law = GRIDDEM_LAW_GRANULAR;
  model.history_size = 0;
}

/* [cutoff], as pair granular */

void PairGriddemGranular::settings(int narg, char **arg)
{
  if (narg > 1) error->all(FLERR, "Pair style griddem/granular takes at most one argument (cutoff), got {}", narg);
  cutoff_global = narg == 1 ? utils::numeric(FLERR, arg[0], false, lmp) : -1.0;
  if (narg == 1 && cutoff_global <= 0.0)
    error->all(FLERR, "Pair style griddem/granular: cutoff must be > 0, not {}", arg[0]);
  create_default_fix();
}

void PairGriddemGranular::coeff(int narg, char **arg)
{
  if (narg < 3) error->all(FLERR, "Pair coeff for griddem/granular needs two types and a normal model");
  if (!allocated) {
    allocate();
    const int n = atom->ntypes + 1;
    specs.assign(n * n, Spec());
    params.assign(n * n, griddem_granular_params());
  }
  int ilo, ihi, jlo, jhi;
  utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
  utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);

  auto refuse_unsupported = [&](const char *keyword, const char *name) {
    for (const auto &u : UNSUPPORTED)
      if (strcmp(u[0], keyword) == 0 && strcmp(u[1], name) == 0)
        error->all(FLERR, "Pair style griddem/granular does not support {} model {} (supported: normal hooke, hertz, hertz/material; damping velocity, mass_velocity, viscoelastic, tsuji; tangential linear_nohistory, linear_history; rolling sds)",
                   keyword, name);
    error->all(FLERR, "Pair coeff for griddem/granular: unknown {} model {}", keyword, name);
  };
  auto read_coeffs = [&](int &iarg, int count, double *out, const char *model_name) {
    if (iarg + count > narg)
      error->all(FLERR, "Pair coeff for griddem/granular: {} needs {} coefficients", model_name, count);
    for (int k = 0; k < count; k++) {
      out[k] = utils::numeric(FLERR, arg[iarg + k], false, lmp);
      if (out[k] < 0.0)
        error->all(FLERR, "Pair coeff for griddem/granular: {} coefficient {} must be >= 0, not {}",
                   model_name, k + 1, arg[iarg + k]);
    }
    iarg += count;
  };

  Spec s = {};
  s.damping = GRIDDEM_DAMPING_VISCOELASTIC;    // pair granular's default
  s.tangential = GRIDDEM_TANGENTIAL_NONE;
  s.rolling = GRIDDEM_ROLLING_NONE;
  s.cutoff = -1.0;
  int iarg = 2;
  s.normal = find_name(arg[iarg], NORMAL_NAMES, 3);
  if (s.normal < 0) refuse_unsupported("normal", arg[iarg]);
  iarg++;
  read_coeffs(iarg, NORMAL_NCOEFFS[s.normal], s.normal_coeffs, NORMAL_NAMES[s.normal]);
  if (s.normal == HERTZ_MATERIAL && !(s.normal_coeffs[0] > 0.0))
    error->all(FLERR, "Pair coeff for griddem/granular: hertz/material needs E > 0, not {}", s.normal_coeffs[0]);

  while (iarg < narg) {
    const char *keyword = arg[iarg];
    if (strcmp(keyword, "limit_damping") == 0) {
      s.limit_damping = 1;
      iarg++;
      continue;
    }
    if (iarg + 1 >= narg) error->all(FLERR, "Pair coeff for griddem/granular: {} needs a model name", keyword);
    const char *name = arg[iarg + 1];
    iarg += 2;
    if (strcmp(keyword, "cutoff") == 0) {
      s.cutoff = utils::numeric(FLERR, name, false, lmp);
      if (s.cutoff <= 0.0) error->all(FLERR, "Pair coeff for griddem/granular: cutoff must be > 0, not {}", name);
    } else if (strcmp(keyword, "damping") == 0) {
      s.damping = find_name(name, DAMPING_NAMES, 4);
      if (s.damping < 0) refuse_unsupported(keyword, name);
    } else if (strcmp(keyword, "tangential") == 0) {
      s.tangential = find_name(name, TANGENTIAL_NAMES, 3);
      if (s.tangential <= 0) refuse_unsupported(keyword, name);
      read_coeffs(iarg, TANGENTIAL_NCOEFFS[s.tangential], s.tangential_coeffs, name);
    } else if (strcmp(keyword, "rolling") == 0) {
      if (strcmp(name, "sds") != 0) refuse_unsupported(keyword, name);
      s.rolling = GRIDDEM_ROLLING_SDS;
      read_coeffs(iarg, 3, s.rolling_coeffs, name);
    } else if (strcmp(keyword, "twisting") == 0 || strcmp(keyword, "heat") == 0) {
      if (strcmp(name, "none") != 0) refuse_unsupported(keyword, name);
    } else {
      error->all(FLERR, "Pair coeff for griddem/granular: unknown keyword {}", keyword);
    }
  }
  if (s.tangential == GRIDDEM_TANGENTIAL_NONE)
    error->all(FLERR, "Pair coeff for griddem/granular: a tangential model is required (linear_nohistory or linear_history), as in pair granular");

  // every type pair keeps the same history values per contact, so one atom's row has one layout
  griddem_granular_params p = {};
  p.tangential = s.tangential;
  p.rolling = s.rolling;
  const int size = griddem_granular_history_size(&p);
  if (layout_set && size != model.history_size)
    error->all(FLERR, "Pair coeff for griddem/granular: types {} {} use tangential {} and rolling {}, but earlier pair_coeff lines chose another tangential/rolling combination; all type pairs must share it",
               arg[0], arg[1], TANGENTIAL_NAMES[s.tangential], s.rolling ? "sds" : "none");
  layout_set = 1;
  model.history_size = size;
  int k = 0;
  if (s.tangential == GRIDDEM_TANGENTIAL_HISTORY)
    for (; k < 3; k++) model.history_parity[k] = -1.0;    // tangential displacement is odd in i<->j
  for (; k < size; k++) model.history_parity[k] = 1.0;    // rolling displacement is even
  create_default_fix();

  const int n = atom->ntypes + 1;
  int count = 0;
  for (int i = ilo; i <= ihi; i++)
    for (int j = MAX(jlo, i); j <= jhi; j++) {
      specs[i * n + j] = specs[j * n + i] = s;
      setflag[i][j] = 1;
      count++;
    }
  if (count == 0) error->all(FLERR, "Pair coeff for griddem/granular: no atom types in {} {}", arg[0], arg[1]);
}

/* unlike types without their own pair_coeff: pair granular's mixing */

PairGriddemGranular::Spec PairGriddemGranular::mix(const Spec &a, const Spec &b, int i, int j)
{
  if (a.normal != b.normal || a.damping != b.damping || a.tangential != b.tangential ||
      a.rolling != b.rolling)
    error->all(FLERR, "Pair style griddem/granular: types {} and {} use different sub-models; set pair_coeff {} {} explicitly",
               i, j, i, j);
  Spec m = a;
  for (int k = 0; k < 3; k++) {
    m.normal_coeffs[k] = mix_geom(a.normal_coeffs[k], b.normal_coeffs[k]);
    m.tangential_coeffs[k] = mix_geom(a.tangential_coeffs[k], b.tangential_coeffs[k]);
    m.rolling_coeffs[k] = mix_geom(a.rolling_coeffs[k], b.rolling_coeffs[k]);
  }
  if (a.normal == HERTZ_MATERIAL)
    m.normal_coeffs[0] = mix_stiffness_e(a.normal_coeffs[0], b.normal_coeffs[0], a.normal_coeffs[2],
                                         b.normal_coeffs[2]);
  m.limit_damping = MAX(a.limit_damping, b.limit_damping);
  m.cutoff = MAX(a.cutoff, b.cutoff);
  m.mixed = 1;
  return m;
}

griddem_granular_params PairGriddemGranular::to_params(const Spec &s)
{
  griddem_granular_params p = {};
  p.normal = s.normal == HOOKE ? GRIDDEM_NORMAL_HOOKE : GRIDDEM_NORMAL_HERTZ;
  p.kn = s.normal_coeffs[0];
  p.damp = s.normal_coeffs[1];
  // hertz/material: k = 4/3 E_eff; one line's E and poisson describe both atoms of the pair
  if (s.normal == HERTZ_MATERIAL)
    p.kn = 4.0 / 3.0 *
        (s.mixed ? s.normal_coeffs[0]
                 : mix_stiffness_e(s.normal_coeffs[0], s.normal_coeffs[0], s.normal_coeffs[2],
                                   s.normal_coeffs[2]));
  p.damping = s.damping;
  if (s.damping == GRIDDEM_DAMPING_TSUJI) {
    // Tsuji et al.'s fit of the damping ratio to the restitution coefficient, as pair granular
    using MathSpecial::powint;
    const double e = p.damp;
    double damp = 1.2728 - 4.2783 * e + 11.087 * MathSpecial::square(e);
    damp += -22.348 * MathSpecial::cube(e) + 27.467 * powint(e, 4);
    damp += -18.022 * powint(e, 5) + 4.8218 * powint(e, 6);
    p.damp = damp;
  }
  p.tangential = s.tangential;
  if (s.tangential == GRIDDEM_TANGENTIAL_HISTORY) {
    p.kt = s.tangential_coeffs[0], p.xt = s.tangential_coeffs[1], p.mu = s.tangential_coeffs[2];
    if (p.kt == 0.0 && p.mu > 0.0)
      error->all(FLERR, "Pair style griddem/granular: linear_history with kt = 0 divides by kt in the Coulomb cap");
  } else {
    p.kt = 0.0, p.xt = s.tangential_coeffs[0], p.mu = s.tangential_coeffs[1];
  }
  p.rolling = s.rolling;
  p.kroll = s.rolling_coeffs[0], p.gammaroll = s.rolling_coeffs[1], p.muroll = s.rolling_coeffs[2];
  if (p.rolling == GRIDDEM_ROLLING_SDS && p.kroll == 0.0 && p.muroll > 0.0)
    error->all(FLERR, "Pair style griddem/granular: rolling sds with k_roll = 0 divides by k_roll in the Coulomb cap");
  p.limit_damping = s.limit_damping;
  return p;
}

double PairGriddemGranular::init_one(int i, int j)
{
  if (!allocated) allocate();
  const int n = atom->ntypes + 1;
  if (setflag[i][j] == 0) specs[i * n + j] = specs[j * n + i] = mix(specs[i * n + i], specs[j * n + j], i, j);
  const Spec &s = specs[i * n + j];
  params[i * n + j] = params[j * n + i] = to_params(s);
  model.ntypes = atom->ntypes;
  model.granular = params.data();

  if (s.cutoff > 0.0) return s.cutoff;
  if (cutoff_global > 0.0) return cutoff_global;
  return type_radius[i] + type_radius[j];
}

double PairGriddemGranular::linear_normal_stiffness()
{
  double kn = 0.0;
  const int n = atom->ntypes + 1;
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) {
      if (!setflag[i][j]) continue;
      if (specs[i * n + j].normal != HOOKE) return 0.0;
      kn = MAX(kn, specs[i * n + j].normal_coeffs[0]);
    }
  return kn;
}

void PairGriddemGranular::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  const int n = atom->ntypes + 1;
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) fwrite(&specs[i * n + j], sizeof(Spec), 1, fp);
    }
}

void PairGriddemGranular::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int n = atom->ntypes + 1;
  specs.assign(n * n, Spec());
  params.assign(n * n, griddem_granular_params());
  for (int i = 1; i < n; i++)
    for (int j = i; j < n; j++) {
      if (comm->me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (!setflag[i][j]) continue;
      if (comm->me == 0) utils::sfread(FLERR, &specs[i * n + j], sizeof(Spec), 1, fp, nullptr, error);
      MPI_Bcast(&specs[i * n + j], sizeof(Spec), MPI_BYTE, 0, world);
      specs[j * n + i] = specs[i * n + j];
    }
}

void PairGriddemGranular::write_restart_settings(FILE *fp)
{
  fwrite(&cutoff_global, sizeof(double), 1, fp);
  fwrite(&model.history_size, sizeof(int), 1, fp);
  fwrite(model.history_parity, sizeof(double), GRIDDEM_MAX_HISTORY, fp);
}

void PairGriddemGranular::read_restart_settings(FILE *fp)
{
  if (comm->me == 0) {
    utils::sfread(FLERR, &cutoff_global, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &model.history_size, sizeof(int), 1, fp, nullptr, error);
    utils::sfread(FLERR, model.history_parity, sizeof(double), GRIDDEM_MAX_HISTORY, fp, nullptr, error);
  }
  MPI_Bcast(&cutoff_global, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&model.history_size, 1, MPI_INT, 0, world);
  MPI_Bcast(model.history_parity, GRIDDEM_MAX_HISTORY, MPI_DOUBLE, 0, world);
  layout_set = 1;
}
