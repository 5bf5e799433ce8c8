/* Minimal checks for the C core tests: count, report each failure, print a closing line. */
#ifndef GRIDDEM_CHECK_H
#define GRIDDEM_CHECK_H
#include <math.h>
#include <stdio.h>

static int check_passed, check_failed;

#define CHECK(cond, ...)                                                \
  do {                                                                  \
    if (cond) {                                                         \
      check_passed++;                                                   \
    } else {                                                            \
      check_failed++;                                                   \
      fprintf(stderr, "%s:%d: FAILED %s: ", __FILE__, __LINE__, #cond); \
      fprintf(stderr, __VA_ARGS__);                                     \
      fprintf(stderr, "\n");                                            \
    }                                                                   \
  } while (0)

#define CHECK_CLOSE(a, b, rel, abs_tol)                                                  \
  CHECK(fabs((a) - (b)) <= (rel) * fabs(b) + (abs_tol), "%s = %.17g, %s = %.17g", #a, \
        (double) (a), #b, (double) (b))

static inline int check_summary(void)
{
  printf("%d passed, %d failed\n", check_passed, check_failed);
  return check_failed ? 1 : 0;
}

/* Deterministic uniform numbers in [0,1) (xorshift64*), so tests do not depend on libc rand. */
static unsigned long long check_rng_state = 88172645463325252ULL;
static inline double check_uniform(void)
{
  check_rng_state ^= check_rng_state >> 12;
  check_rng_state ^= check_rng_state << 25;
  check_rng_state ^= check_rng_state >> 27;
  return (double) ((check_rng_state * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}
#endif
