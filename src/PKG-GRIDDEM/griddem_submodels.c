/* The sub-model table and what follows from it; see griddem_submodels.h. Coefficient conversions
 * are those of LAMMPS's gran_sub_mod_*.cpp coeffs_to_local() and init(). */
#include "griddem_submodels.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

/* effective Young's and shear moduli of two materials (pair granular's mix_stiffnessE/G) */
static double mix_young(double e1, double e2, double poiss1, double poiss2)
{
  const double factor1 = (1 - poiss1 * poiss1) / e1;
  const double factor2 = (1 - poiss2 * poiss2) / e2;
  return 1 / (factor1 + factor2);
}

static double mix_shear(double e1, double e2, double poiss1, double poiss2)
{
  const double factor1 = 2 * (2 - poiss1) * (1 + poiss1) / e1;
  const double factor2 = 2 * (2 - poiss2) * (1 + poiss2) / e2;
  return 1 / (factor1 + factor2);
}

/* E_eff of a material spec: a line's own (E, nu) describe both atoms; a mixed spec holds it */
static double effective_young(const griddem_pair_spec *s)
{
  const double *c = s->coeffs[GRIDDEM_AXIS_NORMAL];
  return s->mixed ? c[0] : mix_young(c[0], c[0], c[2], c[2]);
}

static int fail(char *why, size_t nwhy, const char *text, const char *name)
{
  snprintf(why, nwhy, text, name);
  return -1;
}

/* ---- normal ---- */

/* hooke, hertz: k as given */
static int setup_normal_k(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) why, (void) nwhy;
  p->normal.model = s->sub[GRIDDEM_AXIS_NORMAL]->model;
  p->normal.k = s->coeffs[GRIDDEM_AXIS_NORMAL][0];
  return 0;
}

/* hertz/material, dmt, jkr: k = 4/3 E_eff */
static int setup_material(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  const griddem_submodel *m = s->sub[GRIDDEM_AXIS_NORMAL];
  if (!(s->coeffs[GRIDDEM_AXIS_NORMAL][0] > 0.0))
    return fail(why, nwhy, "%s needs E > 0", m->name);
  p->normal.model = m->model;
  p->normal.emix = effective_young(s);
  p->normal.k = 4.0 / 3.0 * p->normal.emix;
  p->normal.cohesion = m->ncoeff > 3 ? s->coeffs[GRIDDEM_AXIS_NORMAL][3] : 0.0;
  return 0;
}

/* ---- damping: the coefficient is the normal model's second ---- */

static double normal_damp(const griddem_pair_spec *s)
{
  return s->coeffs[GRIDDEM_AXIS_NORMAL][1];
}

static int setup_damping_plain(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) why, (void) nwhy;
  p->damping.model = s->sub[GRIDDEM_AXIS_DAMPING]->model;
  p->damping.damp = normal_damp(s);
  return 0;
}

/* Tsuji et al.'s fit of the damping ratio to the restitution coefficient */
static int setup_tsuji(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) why, (void) nwhy;
  const double e = normal_damp(s);
  double damp = 1.2728 - 4.2783 * e + 11.087 * (e * e);
  damp += -22.348 * (e * e * e) + 27.467 * (e * e * e * e);
  damp += -18.022 * (e * e * e * e * e) + 4.8218 * (e * e * e * e * e * e);
  p->damping.model = GRIDDEM_DAMPING_TSUJI;
  p->damping.damp = damp;
  return 0;
}

/* the damping that gives restitution e for a linear (hooke) or Hertzian spring */
static int setup_coeff_restitution(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  const double cor = normal_damp(s);
  if (!(cor > 0.0)) return fail(why, nwhy, "%s needs a restitution coefficient > 0 (the normal model's damping coefficient)", "coeff_restitution");
  const double logcor = log(cor);
  double damp;
  if (s->sub[GRIDDEM_AXIS_NORMAL]->model == GRIDDEM_NORMAL_HOOKE) {
    damp = -2 * logcor / sqrt(PI * PI + logcor * logcor);
  } else {
    damp = -1.22474487139158894067 * 1.82574185835055380345 * logcor; /* sqrt(3/2) 2/sqrt(5/6) */
    damp /= sqrt(PI * PI + logcor * logcor);
  }
  p->damping.model = GRIDDEM_DAMPING_COEFF_RESTITUTION;
  p->damping.damp = damp;
  return 0;
}

/* ---- tangential ---- */

static int setup_tangential_k_xt_mu(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  const griddem_submodel *m = s->sub[GRIDDEM_AXIS_TANGENTIAL];
  const double *c = s->coeffs[GRIDDEM_AXIS_TANGENTIAL];
  p->tangential.model = m->model;
  p->tangential.k = c[0], p->tangential.xt = c[1], p->tangential.mu = c[2];
  if (m->mix[0] == GRIDDEM_MIX_GEOM_NULL && c[0] == GRIDDEM_NULL_COEFF) {
    const griddem_submodel *normal = s->sub[GRIDDEM_AXIS_NORMAL];
    if (!(normal->flags & GRIDDEM_SUBMODEL_MATERIAL))
      return fail(why, nwhy, "tangential %s with k NULL needs a normal model with material properties (hertz/material, dmt, jkr)", m->name);
    const double *nc = s->coeffs[GRIDDEM_AXIS_NORMAL];
    p->tangential.k = 8.0 * mix_shear(nc[0], nc[0], nc[2], nc[2]);
  }
  if (p->tangential.k == 0.0 && p->tangential.mu > 0.0)
    return fail(why, nwhy, "%s with kt = 0 divides by kt in the Coulomb cap", m->name);
  return 0;
}

static int setup_linear_nohistory(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) why, (void) nwhy;
  const double *c = s->coeffs[GRIDDEM_AXIS_TANGENTIAL];
  p->tangential.model = s->sub[GRIDDEM_AXIS_TANGENTIAL]->model;
  p->tangential.k = 0.0, p->tangential.xt = c[0], p->tangential.mu = c[1];
  return 0;
}

/* gran/hooke/history and gran/hooke: (Kt,) gamma_t, xmu, in their own arithmetic */
static int setup_gran_hooke(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  const griddem_submodel *m = s->sub[GRIDDEM_AXIS_TANGENTIAL];
  const double *c = s->coeffs[GRIDDEM_AXIS_TANGENTIAL];
  const int history = m->history > 0;
  p->tangential.model = m->model;
  p->tangential.k = history ? c[0] : 0.0;
  p->tangential.gamma_mass = c[history];
  p->tangential.mu = c[history + 1];
  p->classic = 1;
  if (history && p->tangential.k == 0.0 && p->tangential.gamma_mass > 0.0)
    return fail(why, nwhy, "%s: Kt = 0 with tangential damping divides by Kt in the Coulomb cap", m->name);
  return 0;
}

/* the gran/hooke styles without friction (xmu = 0) */
static int setup_tangential_none(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) why, (void) nwhy;
  p->tangential.model = s->sub[GRIDDEM_AXIS_TANGENTIAL]->model;
  p->classic = 1;
  return 0;
}

/* ---- rolling, twisting ---- */

/* spring, dashpot and slider (rolling and twisting sds): k, gamma, mu */
static int setup_sds(const double *c, double *k, double *gamma, double *mu, const char *name,
                     const char *kname, char *why, size_t nwhy)
{
  *k = c[0], *gamma = c[1], *mu = c[2];
  if (*k == 0.0 && *mu > 0.0) {
    snprintf(why, nwhy, "%s with %s = 0 divides by %s in the Coulomb cap", name, kname, kname);
    return -1;
  }
  return 0;
}

static int setup_rolling_sds(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  p->rolling.model = GRIDDEM_ROLLING_SDS;
  return setup_sds(s->coeffs[GRIDDEM_AXIS_ROLLING], &p->rolling.k, &p->rolling.gamma, &p->rolling.mu,
                   "rolling sds", "k_roll", why, nwhy);
}

static int setup_twisting_sds(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  p->twisting.model = GRIDDEM_TWISTING_SDS;
  return setup_sds(s->coeffs[GRIDDEM_AXIS_TWISTING], &p->twisting.k, &p->twisting.damp, &p->twisting.mu,
                   "twisting sds", "k_twist", why, nwhy);
}

static int setup_marshall(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) s;
  p->twisting.model = GRIDDEM_TWISTING_MARSHALL;
  p->twisting.k = p->tangential.k, p->twisting.mu = p->tangential.mu;
  if (p->twisting.k == 0.0)
    return fail(why, nwhy, "twisting %s takes its stiffness from the tangential model, whose k is 0 (it would divide by 0)", "marshall");
  return 0;
}

static int setup_none(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) s, (void) p, (void) why, (void) nwhy;
  return 0;
}

/* ---- heat ---- */

/* radius: conductivity; area: heat transfer coefficient. The law's arithmetic is not the classic
 * styles' (they conduct no heat). */
static int setup_heat(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  (void) why, (void) nwhy;
  p->heat.model = s->sub[GRIDDEM_AXIS_HEAT]->model;
  p->heat.k = s->coeffs[GRIDDEM_AXIS_HEAT][0];
  p->classic = 0;
  return 0;
}

/* ---- the table ---- */

#define ODD3 {-1, -1, -1, 0}
#define EVEN3 {1, 1, 1, 0}
#define MATERIAL_MIX {GRIDDEM_MIX_YOUNG, GRIDDEM_MIX_GEOM, GRIDDEM_MIX_GEOM, GRIDDEM_MIX_GEOM}
#define MINDLIN_MIX {GRIDDEM_MIX_GEOM_NULL, GRIDDEM_MIX_GEOM, GRIDDEM_MIX_GEOM, GRIDDEM_MIX_GEOM}
enum { N = GRIDDEM_AXIS_NORMAL, D = GRIDDEM_AXIS_DAMPING, T = GRIDDEM_AXIS_TANGENTIAL,
       R = GRIDDEM_AXIS_ROLLING, W = GRIDDEM_AXIS_TWISTING, H = GRIDDEM_AXIS_HEAT };
enum { MAT = GRIDDEM_SUBMODEL_MATERIAL, COH = GRIDDEM_SUBMODEL_COHESIVE,
       BEYOND = GRIDDEM_SUBMODEL_BEYOND_CONTACT, RAD = GRIDDEM_SUBMODEL_CONTACT_RADIUS,
       NOCOH = GRIDDEM_SUBMODEL_NO_COHESION, INTERNAL = GRIDDEM_SUBMODEL_INTERNAL };

/* The examples' twisting damping stays below I/dt of the lightest sphere of the tests' scenes
 * (twisting torques act on the angular velocity directly). */
#define EXAMPLE(type1, type2) {type1, type2}
static const griddem_submodel SUBMODELS[] = {
    /* axis, name, model, coefficients, history, parity, mixing, flags, setup, example */
    {N, "hooke", GRIDDEM_NORMAL_HOOKE, 2, 0, {0}, {0}, 0, setup_normal_k,
     EXAMPLE("hooke 1e4 50 damping mass_velocity tangential linear_history 3e3 0.5 0.5",
             "hooke 2e4 30 damping mass_velocity tangential linear_history 5e3 0.4 0.3")},
    {N, "hertz", GRIDDEM_NORMAL_HERTZ, 2, 0, {0}, {0}, RAD, setup_normal_k,
     EXAMPLE("hertz 1e5 20 damping viscoelastic tangential linear_history 3e4 0.5 0.5 rolling sds 500 5 0.1",
             "hertz 2e5 10 tangential linear_history 2e4 0.6 0.4 rolling sds 300 3 0.2")},
    {N, "hertz/material", GRIDDEM_NORMAL_HERTZ, 3, 0, {0}, MATERIAL_MIX, MAT | RAD, setup_material,
     EXAMPLE("hertz/material 1e6 0.8 0.3 damping tsuji tangential linear_nohistory 1.0 0.5 limit_damping",
             "hertz/material 5e5 0.6 0.25 damping tsuji tangential linear_nohistory 0.8 0.3 limit_damping")},
    /* cohesive normal models take viscoelastic, velocity or mass_velocity damping and no
     * limit_damping (stock refuses the others) */
    {N, "dmt", GRIDDEM_NORMAL_DMT, 4, 0, {0}, MATERIAL_MIX, MAT | COH | RAD, setup_material,
     EXAMPLE("dmt 1e6 20 0.3 500 tangential mindlin NULL 0.5 0.5 rolling sds 500 5 0.1 twisting sds 200 0.01 0.1",
             "dmt 5e5 10 0.25 300 tangential mindlin 3e5 0.6 0.4 rolling sds 300 3 0.2 twisting sds 100 0.005 0.2")},
    /* pull-off distances 0.005-0.02 at the tests' radii (0.05-0.15) */
    {N, "jkr", GRIDDEM_NORMAL_JKR, 4, 0, {0}, MATERIAL_MIX, MAT | COH | BEYOND | RAD, setup_material,
     EXAMPLE("jkr 1e6 20 0.3 2000 tangential mindlin_rescale NULL 0.5 0.5 twisting marshall",
             "jkr 5e5 10 0.25 1000 tangential mindlin_rescale 3e5 0.4 0.3 twisting marshall")},
    {D, "velocity", GRIDDEM_DAMPING_VELOCITY, 0, 0, {0}, {0}, 0, setup_damping_plain,
     EXAMPLE("hooke 1e4 5 damping velocity tangential linear_nohistory 0.5 0.5 rolling sds 200 1 0.2",
             "hooke 3e4 5 damping velocity tangential linear_nohistory 0.5 0.5 rolling sds 100 2 0.1")},
    {D, "mass_velocity", GRIDDEM_DAMPING_MASS_VELOCITY, 0, 0, {0}, {0}, 0, setup_damping_plain, EXAMPLE(NULL, NULL)},
    {D, "viscoelastic", GRIDDEM_DAMPING_VISCOELASTIC, 0, 0, {0}, {0}, RAD, setup_damping_plain, EXAMPLE(NULL, NULL)},
    {D, "tsuji", GRIDDEM_DAMPING_TSUJI, 0, 0, {0}, {0}, NOCOH, setup_tsuji, EXAMPLE(NULL, NULL)},
    /* the normal model's damping coefficient is the restitution coefficient */
    {D, "coeff_restitution", GRIDDEM_DAMPING_COEFF_RESTITUTION, 0, 0, {0}, {0}, NOCOH, setup_coeff_restitution,
     EXAMPLE("hooke 1e4 0.8 damping coeff_restitution tangential linear_history 3e3 0.5 0.5",
             "hooke 2e4 0.6 damping coeff_restitution tangential linear_history 5e3 0.4 0.3")},
    {T, "linear_nohistory", GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY, 2, 0, {0}, {0}, 0, setup_linear_nohistory, EXAMPLE(NULL, NULL)},
    {T, "linear_history", GRIDDEM_TANGENTIAL_LINEAR_HISTORY, 3, 3, ODD3, {0}, 0, setup_tangential_k_xt_mu, EXAMPLE(NULL, NULL)},
    {T, "linear_history_classic", GRIDDEM_TANGENTIAL_LINEAR_HISTORY_CLASSIC, 3, 3, ODD3, {0}, RAD, setup_tangential_k_xt_mu,
     EXAMPLE("hooke 1e4 5 damping velocity tangential linear_history_classic 3e3 0.5 0.5",
             "hooke 2e4 8 damping velocity tangential linear_history_classic 5e3 0.4 0.3")},
    /* gran/hertz/history's friction in pair granular's syntax (its normal hertz and damping
     * mass_velocity); kt is a number, as stock's reads it */
    {T, "mindlin_classic", GRIDDEM_TANGENTIAL_MINDLIN_CLASSIC, 3, 3, ODD3, {0}, RAD, setup_tangential_k_xt_mu,
     EXAMPLE("hertz 1e5 20 damping mass_velocity tangential mindlin_classic 3e4 0.5 0.5 rolling sds 500 5 0.1",
             "hertz 2e5 10 damping mass_velocity tangential mindlin_classic 2e4 0.6 0.4 rolling sds 300 3 0.2")},
    /* k NULL: 8 G_eff from the (mixed) material properties; the Hertzian coeff_restitution */
    {T, "mindlin", GRIDDEM_TANGENTIAL_MINDLIN, 3, 3, ODD3, MINDLIN_MIX, RAD, setup_tangential_k_xt_mu,
     EXAMPLE("hertz/material 1e6 0.8 0.3 damping coeff_restitution tangential mindlin NULL 0.5 0.5",
             "hertz/material 5e5 0.7 0.25 damping coeff_restitution tangential mindlin NULL 0.4 0.3")},
    /* k NULL for type 1 and given for type 2: the mixed pair falls back to the material's 8 G */
    {T, "mindlin/force", GRIDDEM_TANGENTIAL_MINDLIN_FORCE, 3, 3, ODD3, MINDLIN_MIX, RAD, setup_tangential_k_xt_mu,
     EXAMPLE("hertz/material 1e6 20 0.3 tangential mindlin/force NULL 0.5 0.5 twisting marshall",
             "hertz/material 5e5 10 0.25 tangential mindlin/force 3e5 0.4 0.3 twisting marshall")},
    {T, "mindlin_rescale", GRIDDEM_TANGENTIAL_MINDLIN_RESCALE, 3, 4, {-1, -1, -1, 1}, MINDLIN_MIX, RAD, setup_tangential_k_xt_mu,
     EXAMPLE("hertz 1e5 20 tangential mindlin_rescale 3e4 0.5 0.5 twisting sds 200 0.01 0.1",
             "hertz 2e5 10 tangential mindlin_rescale 2e4 0.6 0.4 twisting sds 100 0.005 0.2")},
    {T, "mindlin_rescale/force", GRIDDEM_TANGENTIAL_MINDLIN_RESCALE_FORCE, 3, 4, {-1, -1, -1, 1}, MINDLIN_MIX, RAD, setup_tangential_k_xt_mu,
     EXAMPLE("hertz/material 1e6 20 0.3 tangential mindlin_rescale/force NULL 0.5 0.5 rolling sds 500 5 0.1",
             "hertz/material 5e5 10 0.25 tangential mindlin_rescale/force NULL 0.4 0.3 rolling sds 300 3 0.2")},
    {T, "gran/hooke/history", GRIDDEM_TANGENTIAL_HOOKE_HISTORY, 3, 3, ODD3, {0}, INTERNAL, setup_gran_hooke,
     EXAMPLE("hooke 1e3 20 damping mass_velocity tangential gran/hooke/history 300 10 0.4",
             "hooke 2e3 10 damping mass_velocity tangential gran/hooke/history 500 5 0.3")},
    {T, "gran/hooke", GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY, 2, 0, {0}, {0}, INTERNAL, setup_gran_hooke,
     EXAMPLE("hooke 1e3 20 damping mass_velocity tangential gran/hooke 10 0.4",
             "hooke 2e3 10 damping mass_velocity tangential gran/hooke 5 0.3")},
    {T, "none", GRIDDEM_TANGENTIAL_NONE, 0, 0, {0}, {0}, INTERNAL, setup_tangential_none,
     EXAMPLE("hooke 1e3 20 damping mass_velocity tangential none", "hooke 2e3 10 damping mass_velocity tangential none")},
    {R, "none", GRIDDEM_ROLLING_NONE, 0, 0, {0}, {0}, 0, setup_none, EXAMPLE(NULL, NULL)},
    {R, "sds", GRIDDEM_ROLLING_SDS, 3, 3, EVEN3, {0}, 0, setup_rolling_sds, EXAMPLE(NULL, NULL)},
    {W, "none", GRIDDEM_TWISTING_NONE, 0, 0, {0}, {0}, 0, setup_none, EXAMPLE(NULL, NULL)},
    {W, "sds", GRIDDEM_TWISTING_SDS, 3, 1, {1}, {0}, 0, setup_twisting_sds, EXAMPLE(NULL, NULL)},
    {W, "marshall", GRIDDEM_TWISTING_MARSHALL, 0, 1, {1}, {0}, RAD, setup_marshall, EXAMPLE(NULL, NULL)},
    {H, "none", GRIDDEM_HEAT_NONE, 0, 0, {0}, {0}, 0, setup_none, EXAMPLE(NULL, NULL)},
    {H, "radius", GRIDDEM_HEAT_RADIUS, 1, 0, {0}, {0}, RAD, setup_heat,
     EXAMPLE("hertz 1e5 20 tangential linear_history 3e4 0.5 0.5 heat radius 2.0",
             "hertz 2e5 10 tangential linear_history 2e4 0.6 0.4 heat radius 0.5")},
    {H, "area", GRIDDEM_HEAT_AREA, 1, 0, {0}, {0}, RAD, setup_heat,
     EXAMPLE("hooke 1e4 50 damping mass_velocity tangential linear_nohistory 0.5 0.5 heat area 30.0",
             "hooke 2e4 30 damping mass_velocity tangential linear_nohistory 0.4 0.3 heat area 10.0")},
};

/* pair granular's models that have no row */
static const griddem_stock_only STOCK_ONLY[] = {
    {"normal", "mdr"}, {"normal", "none"}, {"damping", "none"}, {"tangential", "none"},
};

const char *griddem_axis_name(int axis)
{
  static const char *const names[GRIDDEM_NAXES] = {"normal", "damping", "tangential", "rolling", "twisting", "heat"};
  return axis >= 0 && axis < GRIDDEM_NAXES ? names[axis] : "?";
}

const griddem_submodel *griddem_submodel_find(int axis, const char *name)
{
  for (size_t k = 0; k < sizeof(SUBMODELS) / sizeof(SUBMODELS[0]); k++)
    if (SUBMODELS[k].axis == axis && strcmp(SUBMODELS[k].name, name) == 0) return &SUBMODELS[k];
  return NULL;
}

const griddem_submodel *griddem_submodel_at(size_t k)
{
  return k < sizeof(SUBMODELS) / sizeof(SUBMODELS[0]) ? &SUBMODELS[k] : NULL;
}

const griddem_stock_only *griddem_stock_only_at(size_t k)
{
  return k < sizeof(STOCK_ONLY) / sizeof(STOCK_ONLY[0]) ? &STOCK_ONLY[k] : NULL;
}

void griddem_spec_init(griddem_pair_spec *s)
{
  memset(s, 0, sizeof(*s));
  s->sub[GRIDDEM_AXIS_DAMPING] = griddem_submodel_find(GRIDDEM_AXIS_DAMPING, "viscoelastic");
  s->sub[GRIDDEM_AXIS_ROLLING] = griddem_submodel_find(GRIDDEM_AXIS_ROLLING, "none");
  s->sub[GRIDDEM_AXIS_TWISTING] = griddem_submodel_find(GRIDDEM_AXIS_TWISTING, "none");
  s->sub[GRIDDEM_AXIS_HEAT] = griddem_submodel_find(GRIDDEM_AXIS_HEAT, "none");
  s->cutoff = -1.0;
}

int griddem_spec_mix(const griddem_pair_spec *a, const griddem_pair_spec *b, griddem_pair_spec *out)
{
  for (int axis = 0; axis < GRIDDEM_NAXES; axis++)
    if (a->sub[axis] != b->sub[axis]) return axis;
  *out = *a;
  for (int axis = 0; axis < GRIDDEM_NAXES; axis++) {
    const griddem_submodel *m = a->sub[axis];
    const double *ca = a->coeffs[axis], *cb = b->coeffs[axis];
    for (int k = 0; m && k < m->ncoeff; k++) {
      switch ((enum griddem_mix_rule) m->mix[k]) {
        case GRIDDEM_MIX_YOUNG: out->coeffs[axis][k] = mix_young(ca[k], cb[k], ca[2], cb[2]); break;
        case GRIDDEM_MIX_GEOM_NULL:
          if (ca[k] == GRIDDEM_NULL_COEFF || cb[k] == GRIDDEM_NULL_COEFF) {
            out->coeffs[axis][k] = GRIDDEM_NULL_COEFF;
            break;
          }
          /* fall through */
        case GRIDDEM_MIX_GEOM: out->coeffs[axis][k] = sqrt(ca[k] * cb[k]); break;
      }
    }
  }
  out->limit_damping = a->limit_damping > b->limit_damping ? a->limit_damping : b->limit_damping;
  out->cutoff = a->cutoff > b->cutoff ? a->cutoff : b->cutoff;
  out->mixed = 1;
  return -1;
}

int griddem_spec_history(const griddem_pair_spec *s, double *parity)
{
  int n = 0;
  for (int axis = 0; axis < GRIDDEM_NAXES; axis++)
    for (int k = 0; s->sub[axis] && k < s->sub[axis]->history; k++, n++)
      if (parity) parity[n] = s->sub[axis]->parity[k];
  return n;
}

int griddem_spec_beyond_contact(const griddem_pair_spec *s)
{
  return s->sub[GRIDDEM_AXIS_NORMAL] && (s->sub[GRIDDEM_AXIS_NORMAL]->flags & GRIDDEM_SUBMODEL_BEYOND_CONTACT);
}

int griddem_spec_to_params(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy)
{
  memset(p, 0, sizeof(*p));
  if (!s->sub[GRIDDEM_AXIS_TANGENTIAL])
    return fail(why, nwhy, "%s", "a tangential model is required (linear_nohistory, linear_history, ...), as in pair granular");
  const int cohesive = (s->sub[GRIDDEM_AXIS_NORMAL]->flags & GRIDDEM_SUBMODEL_COHESIVE) != 0;
  if (cohesive && s->limit_damping)
    return fail(why, nwhy, "limit_damping cannot be used with the cohesive normal model %s", s->sub[GRIDDEM_AXIS_NORMAL]->name);
  int offset = 0;
  for (int axis = 0; axis < GRIDDEM_NAXES; axis++) {
    const griddem_submodel *m = s->sub[axis];
    if (cohesive && (m->flags & GRIDDEM_SUBMODEL_NO_COHESION))
      return fail(why, nwhy, "damping %s cannot be used with a cohesive normal model (dmt, jkr)", m->name);
    if (m->setup(s, p, why, nwhy) != 0) return -1;
    if (m->flags & GRIDDEM_SUBMODEL_CONTACT_RADIUS) p->need_contact_radius = 1;
    if (axis == GRIDDEM_AXIS_ROLLING) p->hist_rolling = offset;
    if (axis == GRIDDEM_AXIS_TWISTING) p->hist_twisting = offset;
    offset += m->history;
  }
  p->limit_damping = s->limit_damping;
  griddem_spec_history(s, p->parity);
  return 0;
}

double griddem_pair_reach_extra(const griddem_pair_params *p, double radi, double radj)
{
  if (!(radi > 0.0 && radj > 0.0)) return 0.0;
  return griddem_normal_pulloff_distance(&p->normal, radi * radj / (radi + radj));
}
