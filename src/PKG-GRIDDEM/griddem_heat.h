/* Heat conduction sub-models of LAMMPS's pair granular (gran_sub_mod_heat.cpp): the heat that
 * flows into i through the contact, from j's temperature to i's, through the contact radius
 * (radius) or the contact area (area). Odd under i <-> j; no history. */
#ifndef GRIDDEM_HEAT_H
#define GRIDDEM_HEAT_H

#include "griddem_contact_geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GRIDDEM_HEAT_PI 3.14159265358979323846 /* LAMMPS's MY_PI */

enum griddem_heat_model { GRIDDEM_HEAT_NONE = 0, GRIDDEM_HEAT_RADIUS = 1, GRIDDEM_HEAT_AREA = 2 };

typedef struct griddem_heat_params {
  enum griddem_heat_model model;
  double k; /* radius: conductivity; area: heat transfer coefficient */
} griddem_heat_params;

/* Heat into i per unit time, from c->contact_radius and the temperatures c->temp_i, c->temp_j. */
GRIDDEM_INLINE double griddem_heat_flow(const griddem_heat_params *p, const griddem_contact *c)
{
  switch (p->model) {
    case GRIDDEM_HEAT_RADIUS: return 2 * p->k * c->contact_radius * (c->temp_j - c->temp_i);
    case GRIDDEM_HEAT_AREA: return p->k * GRIDDEM_HEAT_PI * c->contact_radius * c->contact_radius * (c->temp_j - c->temp_i);
    case GRIDDEM_HEAT_NONE: break;
  }
  return 0.0;
}

#ifdef __cplusplus
}
#endif

#endif
