/* The CPU contact-history store; see griddem_history.h. */
#include "griddem_history.h"
#include "griddem_search.h"
#include "griddem_threads.h"

#include <stdlib.h>
#include <string.h>

void griddem_history_init(griddem_history *h, int values)
{
  memset(h, 0, sizeof(*h));
  h->values = values;
}

static void pool_free(griddem_history_pool *p)
{
  free(p->start), free(p->count), free(p->partner), free(p->value);
  memset(p, 0, sizeof(*p));
}

void griddem_history_free(griddem_history *h)
{
  pool_free(&h->cur);
  pool_free(&h->next);
  for (int k = 0; k < h->noverflow; k++) {
    griddem_history_overflow *o = &h->overflow[k];
    free(o->slot), free(o->partner), free(o->value);
  }
  free(h->overflow);
  memset(h, 0, sizeof(*h));
}

/* Make *ptr hold at least need elements of elem bytes, with headroom; contents are kept. */
static int ensure(void **ptr, long *cap, long need, size_t elem)
{
  if (*ptr && need <= *cap) return 0;
  const long grown = need + need / 2 + 64;
  void *p = realloc(*ptr, elem * (size_t) grown);
  if (!p) return -1;
  *ptr = p, *cap = grown;
  return 0;
}

/* Room in a pool for rows rows (and the end mark) and entries entries; contents are kept. */
static int pool_reserve(griddem_history_pool *p, int rows, long entries, int values)
{
  long rows_cap = p->rows_cap, entries_cap = p->entries_cap;
  if (ensure((void **) &p->start, &rows_cap, rows + 1, sizeof(long)) != 0) return -1;
  rows_cap = p->rows_cap;
  if (ensure((void **) &p->count, &rows_cap, rows + 1, sizeof(int)) != 0) return -1;
  if (ensure((void **) &p->partner, &entries_cap, entries, sizeof(int64_t)) != 0) return -1;
  entries_cap = p->entries_cap;
  if (ensure((void **) &p->value, &entries_cap, entries, sizeof(double) * (size_t) (values > 0 ? values : 1)) != 0)
    return -1;
  p->rows_cap = rows_cap, p->entries_cap = entries_cap;
  if (p->nrows == 0) p->start[0] = p->used;
  return 0;
}

int griddem_history_count(const griddem_history *h, int row)
{
  return (row < 0 || row >= h->cur.nrows) ? 0 : h->cur.count[row];
}

void griddem_history_get_row(const griddem_history *h, int row, double *entries)
{
  const int nv = h->values, count = griddem_history_count(h, row);
  for (int k = 0; k < count; k++)
    griddem_history_get(h->cur.partner, h->cur.value, nv, h->cur.start[row] + k,
                        entries + (size_t) GRIDDEM_HISTORY_ENTRY(nv) * k);
}

int griddem_history_add_row(griddem_history *h, int count, const double *entries, int entry_values)
{
  griddem_history_pool *p = &h->cur;
  const int nv = h->values;
  if (pool_reserve(p, p->nrows + 1, p->used + count, nv) != 0) return -1;
  const long first = p->used;
  for (int k = 0; k < count; k++) {
    const double *m = entries + (size_t) GRIDDEM_HISTORY_ENTRY(entry_values) * k;
    p->partner[first + k] = (int64_t) m[0];
    for (int v = 0; v < nv; v++) p->value[(size_t) nv * (first + k) + v] = v < entry_values ? m[1 + v] : 0.0;
  }
  p->start[p->nrows] = first;
  p->count[p->nrows] = count;
  p->used = first + count;
  p->start[p->nrows + 1] = p->used;
  if (count > h->max_count) h->max_count = count;
  return p->nrows++;
}

int griddem_history_message_length(const griddem_history *h, int row)
{
  return GRIDDEM_ROW_MESSAGE_LENGTH(griddem_history_count(h, row), h->values);
}

int griddem_history_longest_message(const griddem_history *h)
{
  return GRIDDEM_ROW_MESSAGE_LENGTH(h->max_count, h->values);
}

int griddem_history_get_message(const griddem_history *h, int row, double *message)
{
  message[0] = griddem_history_count(h, row);
  griddem_history_get_row(h, row, message + 1);
  return griddem_history_message_length(h, row);
}

int griddem_history_put_message(griddem_history *h, const double *message, int values)
{
  return griddem_history_add_row(h, (int) message[0], message + 1, values);
}

int griddem_history_reserve(griddem_history *h, int rows, long entries)
{
  return pool_reserve(&h->cur, rows, entries, h->values) != 0 ||
          pool_reserve(&h->next, rows, entries + (long) GRIDDEM_HISTORY_MARGIN * rows, h->values) != 0
      ? -1
      : 0;
}

static double pool_memory(const griddem_history_pool *p, int values)
{
  return (double) p->rows_cap * (sizeof(long) + sizeof(int)) +
      (double) p->entries_cap * (sizeof(int64_t) + sizeof(double) * (values > 0 ? values : 1));
}

double griddem_history_memory(const griddem_history *h)
{
  double bytes = pool_memory(&h->cur, h->values) + pool_memory(&h->next, h->values);
  for (int k = 0; k < h->noverflow; k++)
    bytes += (double) h->overflow[k].cap * (sizeof(int) + sizeof(int64_t) + sizeof(double) * (h->values > 0 ? h->values : 1));
  return bytes;
}

int griddem_history_set_values(griddem_history *h, int values)
{
  if (values == h->values) return 0;
  griddem_history_pool *p = &h->cur;
  const long n = p->used;
  double *converted = (double *) malloc(sizeof(double) * (size_t) ((values > 0 ? values : 1) * (p->entries_cap + 1)));
  if (!converted) return -1;
  for (long e = 0; e < n; e++)
    for (int v = 0; v < values; v++) converted[(size_t) values * e + v] = v < h->values ? p->value[(size_t) h->values * e + v] : 0.0;
  free(p->value);
  p->value = converted;
  /* the next pool and the overflow lists are laid out afresh for the new width */
  pool_free(&h->next);
  for (int k = 0; k < h->noverflow; k++) {
    griddem_history_overflow *o = &h->overflow[k];
    free(o->slot), free(o->partner), free(o->value);
    memset(o, 0, sizeof(*o));
  }
  h->values = values;
  return 0;
}

/* The room of rows s0 .. s1 - 1 into room[]: its particle's last count (rows of nrows, count[])
 * and a margin, none for a ghost. One at a time, and eight at a time by AVX2's masked gathers
 * (which read no row of a ghost or a missing row), chosen as the sweep's other reads
 * (griddem_touching_gathers). */
static void rooms_plain(const int *order, const int *row_of, const int *count, int nlocal, int nrows, int s0, int s1,
                        long *room)
{
  for (int s = s0; s < s1; s++) {
    const int i = order[s];
    if (i >= nlocal) {
      room[s] = 0;
      continue;
    }
    const int row = row_of[i];
    room[s] = (row >= 0 && row < nrows ? count[row] : 0) + GRIDDEM_HISTORY_MARGIN;
  }
}

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define GRIDDEM_HISTORY_GATHER 1

__attribute__((target("avx2"))) static void rooms_avx2(const int *order, const int *row_of, const int *count,
                                                       int nlocal, int nrows, int s0, int s1, long *room)
{
  const __m256i locals = _mm256_set1_epi32(nlocal), rows = _mm256_set1_epi32(nrows), none = _mm256_set1_epi32(-1);
  const __m256i margin = _mm256_set1_epi32(GRIDDEM_HISTORY_MARGIN);
  int s = s0;
  for (; s + 8 <= s1; s += 8) {
    const __m256i i = _mm256_loadu_si256((const __m256i *) (order + s));
    const __m256i owned = _mm256_cmpgt_epi32(locals, i);
    const __m256i row = _mm256_mask_i32gather_epi32(none, row_of, i, owned, 4);
    const __m256i in = _mm256_and_si256(_mm256_cmpgt_epi32(row, none), _mm256_cmpgt_epi32(rows, row));
    const __m256i last = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), count, row, in, 4);
    const __m256i r = _mm256_and_si256(owned, _mm256_add_epi32(last, margin));
    _mm256_storeu_si256((__m256i *) (room + s), _mm256_cvtepi32_epi64(_mm256_castsi256_si128(r)));
    _mm256_storeu_si256((__m256i *) (room + s + 4), _mm256_cvtepi32_epi64(_mm256_extracti128_si256(r, 1)));
  }
  rooms_plain(order, row_of, count, nlocal, nrows, s, s1, room);
}
#endif

/* Rows s0 .. s1 - 1 of pool p laid out from entry at on (their rooms), empty; returns the entry
 * after them */
static long lay_rows(griddem_history_pool *p, const int *order, const int *row_of, const int *count, int nlocal,
                     int nrows, int s0, int s1, long at)
{
#ifdef GRIDDEM_HISTORY_GATHER
  if (griddem_touching_gathers()) rooms_avx2(order, row_of, count, nlocal, nrows, s0, s1, p->start);
  else
#endif
    rooms_plain(order, row_of, count, nlocal, nrows, s0, s1, p->start);
  for (int s = s0; s < s1; s++) {
    const long room = p->start[s];
    p->start[s] = at, at += room, p->count[s] = 0;
  }
  return at;
}

int griddem_history_begin(griddem_history *h, int nthreads, int nslot, const int *order, const int *row_of,
                          int nlocal)
{
  if (nthreads > h->noverflow) {
    griddem_history_overflow *o = (griddem_history_overflow *) realloc(h->overflow, sizeof(*o) * (size_t) nthreads);
    if (!o) return -1;
    memset(o + h->noverflow, 0, sizeof(*o) * (size_t) (nthreads - h->noverflow));
    h->overflow = o, h->noverflow = nthreads;
  }
  for (int k = 0; k < h->noverflow; k++) h->overflow[k].n = 0;
  griddem_history_pool *p = &h->next;
  p->nrows = 0, p->used = 0;
  if (pool_reserve(p, nslot, 0, h->values) != 0) return -1;
  const int nrows = h->cur.nrows, *count = h->cur.count;
  long total = 0;
  if (griddem_threaded(nslot)) {
    /* a prefix sum in two passes over one range of slots per thread: each range laid out from 0
       for its length, then again from the lengths of the ranges before it */
    long part[nthreads + 1];
#pragma omp parallel num_threads(nthreads)
    {
      const int t = griddem_thread_num(), nt = griddem_team_size();
      const int s0 = (int) ((long) nslot * t / nt), s1 = (int) ((long) nslot * (t + 1) / nt);
      part[t + 1] = lay_rows(p, order, row_of, count, nlocal, nrows, s0, s1, 0);
#pragma omp barrier
#pragma omp single
      {
        part[0] = 0;
        for (int k = 0; k < nt; k++) part[k + 1] += part[k];
        total = part[nt];
      }
      lay_rows(p, order, row_of, count, nlocal, nrows, s0, s1, part[t]);
    }
  } else {
    total = lay_rows(p, order, row_of, count, nlocal, nrows, 0, nslot, 0);
  }
  p->start[nslot] = total;
  if (pool_reserve(p, nslot, total, h->values) != 0) return -1;
  p->nrows = nslot, p->used = total;
  return 0;
}

int griddem_history_overflow_append(griddem_history_overflow *o, int values, int slot, int64_t partner,
                                    const double *v)
{
  long cap = o->cap;
  if (ensure((void **) &o->slot, &cap, o->n + 1, sizeof(int)) != 0) return -1;
  cap = o->cap;
  if (ensure((void **) &o->partner, &cap, o->n + 1, sizeof(int64_t)) != 0) return -1;
  cap = o->cap;
  if (ensure((void **) &o->value, &cap, o->n + 1, sizeof(double) * (size_t) (values > 0 ? values : 1)) != 0) return -1;
  o->cap = cap;
  o->slot[o->n] = slot;
  griddem_history_put(o->partner, o->value, values, o->n++, partner, v);
  return 0;
}

/* Lay the next pool's rows and the overflow lists out compactly in the current pool (whose
 * history the sweep no longer reads), each row's entries first, then its overflow in list order. */
static int fold_overflow(griddem_history *h)
{
  griddem_history_pool *from = &h->next, *to = &h->cur;
  const int nslot = from->nrows, nv = h->values;
  to->nrows = 0, to->used = 0;
  if (pool_reserve(to, nslot, 0, nv) != 0) return -1;
  for (int s = 0; s < nslot; s++) to->count[s] = from->count[s];
  for (int k = 0; k < h->noverflow; k++)
    for (long m = 0; m < h->overflow[k].n; m++) to->count[h->overflow[k].slot[m]]++;
  long total = 0;
  for (int s = 0; s < nslot; s++) to->start[s] = total, total += to->count[s];
  to->start[nslot] = total;
  if (pool_reserve(to, nslot, total, nv) != 0) return -1;
  for (int s = 0; s < nslot; s++) {
    const long a = from->start[s], b = to->start[s];
    memcpy(to->partner + b, from->partner + a, sizeof(int64_t) * (size_t) from->count[s]);
    memcpy(to->value + (size_t) nv * b, from->value + (size_t) nv * a, sizeof(double) * (size_t) nv * from->count[s]);
  }
  for (int k = 0; k < h->noverflow; k++) {
    const griddem_history_overflow *o = &h->overflow[k];
    for (long m = 0; m < o->n; m++) {
      const long e = to->start[o->slot[m]] + from->count[o->slot[m]]++;
      griddem_history_put(to->partner, to->value, nv, e, o->partner[m], o->value + (size_t) nv * m);
    }
  }
  to->nrows = nslot, to->used = total;
  return 0;
}

GRIDDEM_VECTOR_COPIES long griddem_history_counts(const int *count, int nrows, int *most)
{
  long entries = 0;
  int m = 0;
  if (griddem_threaded(nrows)) {
#pragma omp parallel for simd schedule(static) reduction(+ : entries) reduction(max : m)
    for (int s = 0; s < nrows; s++) entries += count[s], m = count[s] > m ? count[s] : m;
  } else {
    for (int s = 0; s < nrows; s++) entries += count[s], m = count[s] > m ? count[s] : m;
  }
  *most = m;
  return entries;
}

int griddem_history_end(griddem_history *h)
{
  long overflowed = 0;
  for (int k = 0; k < h->noverflow; k++) overflowed += h->overflow[k].n;
  if (overflowed) {
    if (fold_overflow(h) != 0) return -1;
  } else {
    const griddem_history_pool written = h->next;
    h->next = h->cur, h->cur = written;
  }
  h->entries = griddem_history_counts(h->cur.count, h->cur.nrows, &h->max_count);
  return 0;
}
