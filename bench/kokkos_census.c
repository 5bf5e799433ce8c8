/* A Kokkos Tools library that counts and times each kernel, fence and deep copy of a run by name,
 * so the kernels a step launches (and, on host back ends, where its time goes) can be read without
 * a GPU profiler. Written against the documented C callback interface of Kokkos Tools
 * (kokkosp_*); it includes nothing of Kokkos. Build and use (bench/README.md):
 *   cc -O2 -shared -fPIC bench/kokkos_census.c -o build-kk/kokkos_census.so
 *   KOKKOS_TOOLS_LIBS=build-kk/kokkos_census.so GRIDDEM_CENSUS=census.txt lmp -k on ... -in in.x
 * The table (kind, calls, seconds, name) goes to the file GRIDDEM_CENSUS names, else stderr; with
 * several MPI ranks each appends its own. With a tool loaded Kokkos fences the device before
 * each callback (the tools' default, global fencing), so on a GPU too a kernel's seconds are its
 * run's; those fences are listed as "Kokkos Profile Tool Fence" and make the whole run slower. */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CENSUS_NAMES 512
#define CENSUS_DEPTH 64

struct census_entry {
  char kind; /* F(or), R(educe), S(can), f(ence), c(opy) */
  char name[200];
  long calls;
  double seconds;
};

struct Kokkos_Profiling_SpaceHandle {
  char name[64];
};
struct Kokkos_Profiling_KokkosPDeviceInfo {
  size_t deviceID;
};

static struct census_entry table[CENSUS_NAMES];
static int nentries, overflowed;
static struct {
  int entry;
  double start;
} open_regions[CENSUS_DEPTH];
static int depth;

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double) t.tv_sec + 1e-9 * (double) t.tv_nsec;
}

static int entry_of(char kind, const char *name)
{
  for (int e = 0; e < nentries; e++)
    if (table[e].kind == kind && strncmp(table[e].name, name, sizeof(table[e].name) - 1) == 0)
      return e;
  if (nentries == CENSUS_NAMES) {
    overflowed = 1;
    return -1;
  }
  table[nentries].kind = kind;
  snprintf(table[nentries].name, sizeof(table[nentries].name), "%s", name);
  return nentries++;
}

static void begin(char kind, const char *name, uint64_t *id)
{
  const int e = entry_of(kind, name);
  *id = (uint64_t) depth;
  if (depth < CENSUS_DEPTH) open_regions[depth].entry = e, open_regions[depth].start = now();
  depth++;
}

static void end(void)
{
  if (depth == 0) return;
  depth--;
  if (depth >= CENSUS_DEPTH || open_regions[depth].entry < 0) return;
  struct census_entry *t = &table[open_regions[depth].entry];
  t->calls++;
  t->seconds += now() - open_regions[depth].start;
}

void kokkosp_init_library(const int level, const uint64_t version, const uint32_t ndevices,
                          struct Kokkos_Profiling_KokkosPDeviceInfo *info)
{
  (void) level, (void) version, (void) ndevices, (void) info;
}

/* the begin and end callbacks of one kind of region (kernels of each pattern, fences) */
#define CENSUS_REGION(begin_name, end_name, kind)                                            \
  void begin_name(const char *name, const uint32_t dev, uint64_t *id)                        \
  {                                                                                          \
    (void) dev;                                                                              \
    begin(kind, name, id);                                                                   \
  }                                                                                          \
  void end_name(const uint64_t id) { (void) id, end(); }

CENSUS_REGION(kokkosp_begin_parallel_for, kokkosp_end_parallel_for, 'F')
CENSUS_REGION(kokkosp_begin_parallel_reduce, kokkosp_end_parallel_reduce, 'R')
CENSUS_REGION(kokkosp_begin_parallel_scan, kokkosp_end_parallel_scan, 'S')
CENSUS_REGION(kokkosp_begin_fence, kokkosp_end_fence, 'f')

void kokkosp_begin_deep_copy(struct Kokkos_Profiling_SpaceHandle dst, const char *dst_name,
                             const void *dst_ptr, struct Kokkos_Profiling_SpaceHandle src,
                             const char *src_name, const void *src_ptr, uint64_t size)
{
  (void) dst, (void) dst_ptr, (void) src, (void) src_name, (void) src_ptr, (void) size;
  uint64_t id;
  begin('c', dst_name, &id);
}
void kokkosp_end_deep_copy(void) { end(); }

void kokkosp_finalize_library(void)
{
  const char *path = getenv("GRIDDEM_CENSUS");
  FILE *out = path ? fopen(path, "a") : NULL;
  if (!out) out = stderr;
  fprintf(out, "# kind calls seconds name (F for, R reduce, S scan, f fence, c deep copy)%s\n",
          overflowed ? "; more names than the table holds, some not counted" : "");
  for (int e = 0; e < nentries; e++)
    fprintf(out, "%c %ld %.6f %s\n", table[e].kind, table[e].calls, table[e].seconds,
            table[e].name);
  if (out != stderr) fclose(out);
}
