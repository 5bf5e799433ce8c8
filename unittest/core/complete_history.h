/* A store completed as fix griddem completes it before anything reads its rows: each contact of
 * two owned particles that the sweep kept in one row mirrored into the other's
 * (griddem_history_mirror), with the law's parity for each type pair. */
#ifndef GRIDDEM_TEST_COMPLETE_HISTORY_H
#define GRIDDEM_TEST_COMPLETE_HISTORY_H

#include "griddem_contact.h"
#include "griddem_history.h"

#include <stdlib.h>

static int complete_history(griddem_history *h, const griddem_model *m, int nlocal, int *row_of, const int *tag,
                            const int *type)
{
  const int n = m->ntypes + 1;
  double *parity = (double *) malloc(sizeof(double) * GRIDDEM_MAX_HISTORY * (size_t) (n * n));
  if (!parity) return -1;
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      for (int v = 0; v < GRIDDEM_MAX_HISTORY; v++)
        parity[GRIDDEM_MAX_HISTORY * (n * i + j) + v] = i && j ? griddem_model_pair(m, i, j)->parity[v] : 0.0;
  const int failed = griddem_history_mirror(h, nlocal, row_of, tag, 4, type, m->ntypes, parity);
  free(parity);
  return failed;
}

#endif
