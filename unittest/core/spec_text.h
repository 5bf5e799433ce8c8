/* Tests' shorthand for a contact law: pair granular's coefficient syntax ("hooke 1e4 0.3
 * tangential linear_history 800 0.5 0.3 rolling sds 50 0.2 0.05"), read through the sub-model
 * table as the pair style reads it. */
#ifndef GRIDDEM_SPEC_TEXT_H
#define GRIDDEM_SPEC_TEXT_H

#include "griddem_submodels.h"

#include <stdlib.h>
#include <string.h>

/* 0, or -1 if a name or count is wrong */
static int spec_from_text(const char *text, griddem_pair_spec *s)
{
  char buf[512], *save = NULL;
  strncpy(buf, text, sizeof(buf) - 1);
  buf[sizeof(buf) - 1] = 0;
  griddem_spec_init(s);
  int axis = GRIDDEM_AXIS_NORMAL;
  for (char *word = strtok_r(buf, " ", &save); word; word = strtok_r(NULL, " ", &save)) {
    if (axis < 0) {
      if (strcmp(word, "limit_damping") == 0) {
        s->limit_damping = 1;
        continue;
      }
      for (axis = 0; axis < GRIDDEM_NAXES && strcmp(word, griddem_axis_name(axis)) != 0; axis++) {}
      if (axis == GRIDDEM_NAXES) return -1;
      continue;
    }
    const griddem_submodel *m = griddem_submodel_find(axis, word);
    if (!m) return -1;
    s->sub[axis] = m;
    for (int k = 0; k < m->ncoeff; k++) {
      word = strtok_r(NULL, " ", &save);
      if (!word) return -1;
      s->coeffs[axis][k] = strcmp(word, "NULL") == 0 ? GRIDDEM_NULL_COEFF : atof(word);
    }
    axis = -1;
  }
  return 0;
}

/* the law of a text; aborts the test on a bad text */
static griddem_pair_params law_from_text(const char *text)
{
  griddem_pair_spec s;
  griddem_pair_params p;
  char why[256];
  if (spec_from_text(text, &s) != 0 || griddem_spec_to_params(&s, &p, why, sizeof(why)) != 0) {
    fprintf(stderr, "bad law '%s'\n", text);
    exit(2);
  }
  return p;
}

#endif
