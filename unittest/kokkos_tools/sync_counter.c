/* A Kokkos Tools library (loaded through KOKKOS_TOOLS_LIBS) that counts the blocking host
 * synchronisations inside each profiling region named "griddem/kk:compute" (one pair compute()
 * each), as a device with memory of its own has them: a synchronisation is a run of fences with
 * no kernel launched between them (a second fence with no new work costs the host no further
 * wait), with the allocations made in it (a View that grew; allocations of no bytes are not
 * counted). A DualView's sync fences even when it copies nothing where host and device share
 * their memory (a host build) and does not fence where they do not (a GPU), so its fence is
 * counted only after a deep copy. At exit it writes one line per region to the file
 * GRIDDEM_SYNC_LOG names: "synchronisations allocations" and, where it allocated, the first
 * allocation's bytes and label, so that a failing check names the View. It also writes each fill
 * of a View that has room (the initialization Kokkos gives an allocation unless told not to), in
 * the whole run, as a line "bytes label" of the file named GRIDDEM_SYNC_LOG with ".fills" added.
 * Plain C: the Kokkos Tools interface is a set of C symbols, so no Kokkos header is needed. */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *region_name = "griddem/kk:compute";
static int depth;            /* profiling regions open */
static int inside;           /* depth of the griddem region, 0: not in it */
static int in_run;           /* the last event in the region was a fence */
static int copied;           /* a deep copy began since the last kernel */
static int count;            /* synchronisations of the open region */
static int allocated;        /* allocations in it */
static char first[128];      /* the open region's first allocation: bytes and label */
static int *counts;          /* two per finished region: count, allocated */
static char (*firsts)[128];  /* one per finished region */
static size_t ncounts, capacity;
static char allocated_label[128];  /* the last allocation's label and bytes: a fill follows it */
static uint64_t allocated_bytes;
static char *fills;                /* "bytes label\n" per fill of a View with room */
static size_t nfills;

void kokkosp_init_library(const int seq, const uint64_t version, const uint32_t ndevices,
                          void *devices)
{
  (void) seq, (void) version, (void) ndevices, (void) devices;
}

/* Kokkos_Tools_ToolSettings (Kokkos_Profiling_C_Interface.h): without it Kokkos fences before
 * every kernel for the tool, and those fences would be counted */
struct Kokkos_Tools_ToolSettings {
  bool requires_global_fencing;
  bool padding[255];
};

void kokkosp_request_tool_settings(const uint32_t n, struct Kokkos_Tools_ToolSettings *settings)
{
  (void) n;
  settings->requires_global_fencing = false;
}

void kokkosp_push_profile_region(const char *name)
{
  depth++;
  if (!inside && strcmp(name, region_name) == 0) inside = depth, count = allocated = 0, in_run = 0, first[0] = 0;
}

void kokkosp_pop_profile_region(void)
{
  if (inside == depth) {
    if (ncounts + 2 > capacity) {
      capacity = capacity ? 2 * capacity : 1024;
      counts = (int *) realloc(counts, capacity * sizeof(int));
      firsts = (char (*)[128]) realloc(firsts, capacity / 2 * sizeof *firsts);
    }
    memcpy(firsts[ncounts / 2], first, sizeof first);
    counts[ncounts++] = count;
    counts[ncounts++] = allocated;
    inside = 0;
  }
  depth--;
}

static void launched(void) { in_run = 0, copied = 0; }

/* Kokkos names a View's initialization "Kokkos::View::initialization [label]..." */
static void record_fill(const char *name)
{
  static const char prefix[] = "Kokkos::View::initialization [";
  if (strncmp(name, prefix, sizeof prefix - 1) != 0) return;
  const char *label = name + sizeof prefix - 1, *end = strchr(label, ']');
  const size_t n = end ? (size_t) (end - label) : 0;
  if (!n || strlen(allocated_label) != n || strncmp(label, allocated_label, n) != 0 || allocated_bytes == 0)
    return;
  char line[160];
  const int len = snprintf(line, sizeof line, "%llu %s\n", (unsigned long long) allocated_bytes, allocated_label);
  fills = (char *) realloc(fills, nfills + (size_t) len + 1);
  memcpy(fills + nfills, line, (size_t) len + 1);
  nfills += (size_t) len;
}

void kokkosp_begin_parallel_for(const char *name, const uint32_t dev, uint64_t *id)
{
  (void) dev, (void) id;
  record_fill(name);
  launched();
}
void kokkosp_begin_parallel_reduce(const char *name, const uint32_t dev, uint64_t *id)
{
  (void) name, (void) dev, (void) id;
  launched();
}
void kokkosp_begin_parallel_scan(const char *name, const uint32_t dev, uint64_t *id)
{
  (void) name, (void) dev, (void) id;
  launched();
}

void kokkosp_begin_fence(const char *name, const uint32_t dev, uint64_t *id)
{
  (void) dev, (void) id;
  if (!copied && strcmp(name, "Kokkos::DualView<>::sync: fence after syncing DualView") == 0) return;
  if (inside && !in_run) count++, in_run = 1;
}

struct SpaceHandle {
  char name[64];
};

void kokkosp_allocate_data(const struct SpaceHandle space, const char *label, const void *ptr,
                           const uint64_t size)
{
  (void) space, (void) ptr;
  snprintf(allocated_label, sizeof allocated_label, "%s", label);
  allocated_bytes = size;
  // Kokkos's CUDA team launch asks for its level-1 scratch even when a kernel needs none: no
  // memory, nothing grew
  if (size == 0) return;
  if (inside && !allocated++) snprintf(first, sizeof first, "%llu %s", (unsigned long long) size, label);
}

void kokkosp_begin_deep_copy(struct SpaceHandle dst, const char *dst_name, const void *dst_ptr,
                             struct SpaceHandle src, const char *src_name, const void *src_ptr,
                             uint64_t size)
{
  (void) dst, (void) dst_name, (void) dst_ptr, (void) src, (void) src_name, (void) src_ptr;
  (void) size;
  copied = 1;
}
void kokkosp_end_fence(const uint64_t id) { (void) id; }

void kokkosp_finalize_library(void)
{
  const char *path = getenv("GRIDDEM_SYNC_LOG");
  FILE *out = path ? fopen(path, "w") : NULL;
  if (!out) return;
  for (size_t k = 0; k < ncounts; k += 2)
    fprintf(out, "%d %d%s%s\n", counts[k], counts[k + 1], firsts[k / 2][0] ? " " : "", firsts[k / 2]);
  fclose(out);
  char fills_path[4096];
  snprintf(fills_path, sizeof fills_path, "%s.fills", path);
  if ((out = fopen(fills_path, "w"))) {
    if (nfills) fputs(fills, out);
    fclose(out);
  }
}
