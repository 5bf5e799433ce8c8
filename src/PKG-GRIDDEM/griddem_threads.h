/* GRIDDEM: the core's one view of OpenMP (which the core builds without too): whether a pass over
 * many points runs on threads, and the thread counts a threaded pass divides its work by. */
#ifndef GRIDDEM_THREADS_H
#define GRIDDEM_THREADS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Where there are several threads and at least this many points: a parallel region allocates its
 * team even for one thread, and below this a pass costs less than that */
#define GRIDDEM_THREADED_MIN 16384
int griddem_threaded(int n);

/* OpenMP's thread count for the next parallel region, this thread's number in its team and the
 * team's size (1, 0 and 1 without OpenMP) */
int griddem_max_threads(void);
int griddem_thread_num(void);
int griddem_team_size(void);

#ifdef __cplusplus
}
#endif

#endif
