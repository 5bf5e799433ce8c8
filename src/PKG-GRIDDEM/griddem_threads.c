/* GRIDDEM threads; see griddem_threads.h. */
#include "griddem_threads.h"

#ifdef _OPENMP
#include <omp.h>
#endif

int griddem_max_threads(void)
{
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

int griddem_thread_num(void)
{
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

int griddem_team_size(void)
{
#ifdef _OPENMP
  return omp_get_num_threads();
#else
  return 1;
#endif
}

int griddem_threaded(int n)
{
  return n >= GRIDDEM_THREADED_MIN && griddem_max_threads() > 1;
}
