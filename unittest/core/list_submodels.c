/* Prints the sub-model table for the LAMMPS-level tests, one tab-separated line each:
 *   example <TAB> keyword name <TAB> type 1 arguments <TAB> type 2 arguments
 * for every row pair granular also has that carries an example, and
 *   stock_only <TAB> keyword <TAB> name
 * for every model pair granular has that the table does not evaluate. */
#include "griddem_submodels.h"

#include <stdio.h>

int main(void)
{
  for (size_t k = 0; griddem_submodel_at(k); k++) {
    const griddem_submodel *m = griddem_submodel_at(k);
    if (!(m->flags & GRIDDEM_SUBMODEL_INTERNAL) && m->example[0])
      printf("example\t%s %s\t%s\t%s\n", griddem_axis_name(m->axis), m->name, m->example[0], m->example[1]);
  }
  for (size_t k = 0; griddem_stock_only_at(k); k++)
    printf("stock_only\t%s\t%s\n", griddem_stock_only_at(k)->keyword, griddem_stock_only_at(k)->name);
  return 0;
}
