/* GRIDDEM threads; see griddem_threads.h. */
#include "griddem_threads.h"

#include <omp.h>

int griddem_threaded(int n)
{
  return n >= GRIDDEM_THREADED_MIN && omp_get_max_threads() > 1;
}
