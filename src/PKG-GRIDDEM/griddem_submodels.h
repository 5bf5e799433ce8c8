/* The contact sub-models GRIDDEM knows, one descriptor row each (griddem_submodels.c): the
 * pair granular keyword, coefficient count and mixing rule, history values and their sign under
 * i <-> j, and the function that turns coefficients into the parameters the inline law reads.
 * Parsing, mixing, history layout, exchange and restart sizes all follow from these rows, so a
 * new sub-model is its inline function in its axis header plus one row. */
#ifndef GRIDDEM_SUBMODELS_H
#define GRIDDEM_SUBMODELS_H

#include "griddem_contact.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

enum griddem_axis {
  GRIDDEM_AXIS_NORMAL = 0,
  GRIDDEM_AXIS_DAMPING,
  GRIDDEM_AXIS_TANGENTIAL,
  GRIDDEM_AXIS_ROLLING,
  GRIDDEM_AXIS_TWISTING,
  GRIDDEM_AXIS_HEAT,
  GRIDDEM_NAXES
};

#define GRIDDEM_MAX_COEFFS 4
#define GRIDDEM_NULL_COEFF (-1.0) /* a coefficient given as NULL (to be derived) */

/* how a coefficient of unlike types is mixed from the like types' */
enum griddem_mix_rule {
  GRIDDEM_MIX_GEOM = 0,     /* sqrt(a b) */
  GRIDDEM_MIX_YOUNG = 1,    /* effective Young's modulus, Poisson's ratio in coefficient 3 */
  GRIDDEM_MIX_GEOM_NULL = 2 /* sqrt(a b), or NULL if either is NULL */
};

enum griddem_submodel_flags {
  GRIDDEM_SUBMODEL_MATERIAL = 1,       /* coefficients are E, damping, Poisson's ratio, ... */
  GRIDDEM_SUBMODEL_COHESIVE = 2,       /* attractive normal force */
  GRIDDEM_SUBMODEL_BEYOND_CONTACT = 4, /* pairs interact past touching once they have touched */
  GRIDDEM_SUBMODEL_CONTACT_RADIUS = 8, /* reads the contact radius */
  GRIDDEM_SUBMODEL_NO_COHESION = 16,   /* cannot be combined with a cohesive normal model */
  GRIDDEM_SUBMODEL_INTERNAL = 32       /* not a pair granular keyword: the gran/hooke styles' laws */
};

typedef struct griddem_pair_spec griddem_pair_spec;

typedef struct griddem_submodel {
  int axis;
  const char *name;
  int model;                                 /* the axis's enum value the law switches on */
  int ncoeff;
  int history;                               /* values per contact */
  signed char parity[4];                     /* of each history value under i <-> j */
  unsigned char mix[GRIDDEM_MAX_COEFFS];     /* enum griddem_mix_rule per coefficient */
  int flags;
  /* fill this axis of p from s (earlier axes already filled); 0, or -1 with a reason in why */
  int (*setup)(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy);
  /* a law that shows this sub-model: pair_coeff's arguments for two atom types, whose unlike
   * pair is mixed. The tests evaluate every row's example (against stock pair granular, and
   * seen from both atoms); NULL where another row's example shows this one. */
  const char *example[2];
} griddem_submodel;

/* A model pair granular has that this table does not evaluate: refused naming it. */
typedef struct griddem_stock_only {
  const char *keyword; /* an axis's name */
  const char *name;
} griddem_stock_only;

/* One type pair's sub-models as given in pair_coeff (or mixed from two like pairs). */
struct griddem_pair_spec {
  const griddem_submodel *sub[GRIDDEM_NAXES];
  double coeffs[GRIDDEM_NAXES][GRIDDEM_MAX_COEFFS];
  int limit_damping;
  double cutoff; /* < 0: from the radii */
  int mixed;     /* mixed from two like-type specs: material moduli are already effective */
};

const char *griddem_axis_name(int axis);

/* The row for a name on an axis, or NULL. */
const griddem_submodel *griddem_submodel_find(int axis, const char *name);

/* Row k of the table, or NULL past the last (rows of an axis are consecutive). */
const griddem_submodel *griddem_submodel_at(size_t k);

/* Entry k of the models pair granular has and this table does not, or NULL past the last. */
const griddem_stock_only *griddem_stock_only_at(size_t k);

/* A spec with pair granular's defaults: damping viscoelastic, rolling, twisting and heat none,
 * no normal or tangential model yet. */
void griddem_spec_init(griddem_pair_spec *s);

/* Mix the specs of two like type pairs as pair granular does. Returns -1, or the first axis whose
 * sub-models differ (which cannot be mixed). */
int griddem_spec_mix(const griddem_pair_spec *a, const griddem_pair_spec *b, griddem_pair_spec *out);

/* Check a complete spec (required axes, allowed combinations) and turn it into parameters.
 * 0, or -1 with a reason naming the sub-model in why. */
int griddem_spec_to_params(const griddem_pair_spec *s, griddem_pair_params *p, char *why, size_t nwhy);

/* History values per contact of a spec, and their signs under i <-> j (parity may be NULL). */
int griddem_spec_history(const griddem_pair_spec *s, double *parity);

/* Whether a spec's pairs interact past touching (keep contacts without history values). */
int griddem_spec_beyond_contact(const griddem_pair_spec *s);

/* Largest distance beyond touching at which atoms of radii radi, radj interact under p. */
double griddem_pair_reach_extra(const griddem_pair_params *p, double radi, double radj);

#ifdef __cplusplus
}
#endif

#endif
