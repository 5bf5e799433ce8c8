/* GRIDDEM: whether a pass over many points runs on OpenMP's threads. */
#ifndef GRIDDEM_THREADS_H
#define GRIDDEM_THREADS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Where there are several threads and at least this many points: a parallel region allocates its
 * team even for one thread, and below this a pass costs less than that */
#define GRIDDEM_THREADED_MIN 16384
int griddem_threaded(int n);

#ifdef __cplusplus
}
#endif

#endif
