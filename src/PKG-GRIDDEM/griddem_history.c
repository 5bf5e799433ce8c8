/* The CPU contact-history store; see griddem_history.h. */
#include "griddem_history.h"
#include "griddem_contact.h"
#include "griddem_grid.h"
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
  free(p->start), free(p->count), free(p->room), free(p->written), free(p->partner), free(p->owned_partner), free(p->value);
  memset(p, 0, sizeof(*p));
}

static void overflow_free(griddem_history_overflow *o)
{
  free(o->particle), free(o->partner), free(o->owned_partner), free(o->value);
  memset(o, 0, sizeof(*o));
}

void griddem_history_free(griddem_history *h)
{
  pool_free(&h->cur);
  pool_free(&h->spare);
  for (int k = 0; k < h->noverflow; k++) overflow_free(&h->overflow[k]);
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

/* Room in a pool for rows rows and entries entries; contents are kept. */
static int pool_reserve(griddem_history_pool *p, int rows, long entries, int values)
{
  long rows_cap = p->rows_cap, entries_cap = p->entries_cap;
  if (ensure((void **) &p->start, &rows_cap, rows + 1, sizeof(long)) != 0) return -1;
  rows_cap = p->rows_cap;
  if (ensure((void **) &p->count, &rows_cap, rows + 1, sizeof(int)) != 0) return -1;
  rows_cap = p->rows_cap;
  if (ensure((void **) &p->room, &rows_cap, rows + 1, sizeof(int)) != 0) return -1;
  rows_cap = p->rows_cap;
  if (ensure((void **) &p->written, &rows_cap, rows + 1, sizeof(int)) != 0) return -1;
  if (ensure((void **) &p->partner, &entries_cap, entries, sizeof(int64_t)) != 0) return -1;
  entries_cap = p->entries_cap;
  if (ensure((void **) &p->owned_partner, &entries_cap, entries, sizeof(int)) != 0) return -1;
  entries_cap = p->entries_cap;
  if (ensure((void **) &p->value, &entries_cap, entries, sizeof(double) * (size_t) (values > 0 ? values : 1)) != 0)
    return -1;
  p->rows_cap = rows_cap, p->entries_cap = entries_cap;
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

/* A new row of count entries and room room at the pool's end (its entries not yet written): its
 * index, or -1 without memory */
static int append_row(griddem_history_pool *p, int count, int room, int values)
{
  if (pool_reserve(p, p->nrows + 1, p->used + room, values) != 0) return -1;
  p->start[p->nrows] = p->used;
  p->count[p->nrows] = count;
  p->room[p->nrows] = room;
  p->written[p->nrows] = 0;
  p->used += room;
  return p->nrows++;
}

int griddem_history_add_row(griddem_history *h, int count, const double *entries, int entry_values)
{
  griddem_history_pool *p = &h->cur;
  const int nv = h->values, row = append_row(p, count, count, nv);
  if (row < 0) return -1;
  const long first = p->start[row];
  for (int k = 0; k < count; k++) {
    const double *m = entries + (size_t) GRIDDEM_HISTORY_ENTRY(entry_values) * k;
    p->partner[first + k] = (int64_t) m[0] | h->mark;
    p->owned_partner[first + k] = -1;
    for (int v = 0; v < nv; v++) p->value[(size_t) nv * (first + k) + v] = v < entry_values ? m[1 + v] : 0.0;
  }
  if (count > h->max_count) h->max_count = count;
  return row;
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

/* The own entry of a message, or NULL */
static double *own_entry(const double *message, int values)
{
  const int count = (int) message[0], width = GRIDDEM_HISTORY_ENTRY(values);
  for (int e = 0; e < count; e++)
    if (message[1 + (size_t) width * e] == (double) GRIDDEM_OWN_KEY) return (double *) message + 1 + (size_t) width * e;
  return NULL;
}

int griddem_message_with_own_tag(double *message, int values, int64_t tag)
{
  double *own = own_entry(message, values);
  if (!own) {
    own = message + 1 + (size_t) GRIDDEM_HISTORY_ENTRY(values) * (size_t) message[0];
    message[0] += 1;
    own[0] = (double) GRIDDEM_OWN_KEY;
    for (int v = 1; v < values; v++) own[1 + v] = 0.0;
  }
  own[1] = (double) tag;
  return GRIDDEM_ROW_MESSAGE_LENGTH((int) message[0], values);
}

/* The index of tag among the n sorted tags, or -1 */
static long sorted_index(const int64_t *tags, long n, int64_t tag)
{
  long lo = 0, hi = n;
  while (lo < hi) {
    const long mid = lo + (hi - lo) / 2;
    if (tags[mid] < tag) lo = mid + 1;
    else hi = mid;
  }
  return lo < n && tags[lo] == tag ? lo : -1;
}

int griddem_message_partners(const double *message, int values, int64_t *tags)
{
  const int count = (int) message[0], width = GRIDDEM_HISTORY_ENTRY(values);
  int n = 0;
  for (int e = 0; e < count; e++) {
    const int64_t key = (int64_t) message[1 + (size_t) width * e];
    if (key != GRIDDEM_OWN_KEY) tags[n++] = griddem_key_tag(key);
  }
  return n;
}

int griddem_message_renumber(double *message, int values, const int64_t *old_tag, const int64_t *new_tag, long n)
{
  const int count = (int) message[0], width = GRIDDEM_HISTORY_ENTRY(values);
  int kept = 0;
  for (int e = 0; e < count; e++) {
    const double *from = message + 1 + (size_t) width * e;
    int64_t key = (int64_t) from[0];
    if (key != GRIDDEM_OWN_KEY) {
      const long k = sorted_index(old_tag, n, griddem_key_tag(key));
      if (k < 0) continue;
      key = griddem_key_retagged(key, new_tag[k]);
    }
    double *to = message + 1 + (size_t) width * kept++;
    memmove(to + 1, from + 1, sizeof(double) * (size_t) values);
    to[0] = (double) key;
  }
  message[0] = kept;
  return GRIDDEM_ROW_MESSAGE_LENGTH(kept, values);
}

int griddem_history_reserve(griddem_history *h, int rows, long entries)
{
  const long room = entries + (long) GRIDDEM_HISTORY_MARGIN * rows;
  return pool_reserve(&h->cur, rows, room, h->values) != 0 || pool_reserve(&h->spare, rows, room, h->values) != 0
      ? -1
      : 0;
}

static double pool_memory(const griddem_history_pool *p, int values)
{
  return (double) p->rows_cap * (sizeof(long) + 3 * sizeof(int)) +
      (double) p->entries_cap * (sizeof(int64_t) + sizeof(int) + sizeof(double) * (values > 0 ? values : 1));
}

double griddem_history_memory(const griddem_history *h)
{
  double bytes = pool_memory(&h->cur, h->values) + pool_memory(&h->spare, h->values);
  for (int k = 0; k < h->noverflow; k++)
    bytes += (double) h->overflow[k].cap * (2 * sizeof(int) + sizeof(int64_t) + sizeof(double) * (h->values > 0 ? h->values : 1));
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
  /* the spare pool and the overflow lists are laid out afresh for the new width */
  pool_free(&h->spare);
  for (int k = 0; k < h->noverflow; k++) overflow_free(&h->overflow[k]);
  h->values = values;
  return 0;
}

/* nthreads empty overflow lists. 0, or -1 without memory. */
static int empty_overflow(griddem_history *h, int nthreads)
{
  if (nthreads > h->noverflow) {
    griddem_history_overflow *o = (griddem_history_overflow *) realloc(h->overflow, sizeof(*o) * (size_t) nthreads);
    if (!o) return -1;
    memset(o + h->noverflow, 0, sizeof(*o) * (size_t) (nthreads - h->noverflow));
    h->overflow = o, h->noverflow = nthreads;
  }
  for (int k = 0; k < h->noverflow; k++) h->overflow[k].n = 0;
  return 0;
}

int griddem_history_begin(griddem_history *h, int nthreads)
{
  if (empty_overflow(h, nthreads) != 0) return -1;
  h->mark ^= GRIDDEM_HISTORY_MARK;
  return 0;
}

int griddem_history_overflow_append(griddem_history_overflow *o, int values, int particle, int64_t partner,
                                    int owned_partner, const double *v, int stride)
{
  long cap = o->cap;
  if (ensure((void **) &o->particle, &cap, o->n + 1, sizeof(int)) != 0) return -1;
  cap = o->cap;
  if (ensure((void **) &o->partner, &cap, o->n + 1, sizeof(int64_t)) != 0) return -1;
  cap = o->cap;
  if (ensure((void **) &o->owned_partner, &cap, o->n + 1, sizeof(int)) != 0) return -1;
  cap = o->cap;
  if (ensure((void **) &o->value, &cap, o->n + 1, sizeof(double) * (size_t) (values > 0 ? values : 1)) != 0) return -1;
  o->cap = cap;
  o->particle[o->n] = particle;
  o->owned_partner[o->n] = owned_partner;
  griddem_history_put_strided(o->partner, o->value, values, o->n++, partner, v, stride);
  return 0;
}

/* n entries of pool from, from entry a on, copied to pool to (which may be from) from entry b on,
 * where they do not overlap: partner keys, owned partners and values (rows hold a few: no call) */
static inline void copy_entries(const griddem_history_pool *from, long a, griddem_history_pool *to, long b, long n,
                                int values)
{
  for (long k = 0; k < n; k++) {
    to->partner[b + k] = from->partner[a + k], to->owned_partner[b + k] = from->owned_partner[a + k];
    for (int v = 0; v < values; v++) to->value[(size_t) values * (b + k) + v] = from->value[(size_t) values * (a + k) + v];
  }
}

/* Whether some of rows r0 .. r1 - 1 hold entries the sweep did not write (compared in vector
 * lanes, without a branch per row) */
GRIDDEM_VECTOR_COPIES static int some_unwritten(const int *restrict count, const int *restrict written, int r0, int r1)
{
  int differ = 0;
  for (int r = r0; r < r1; r++) differ |= count[r] ^ written[r];
  return differ != 0;
}

/* Rows r0 .. r1 - 1 keep the entries the sweep wrote (those holding mark), in their order: only
 * rows with entries it did not write are read, found a block of rows at a time */
static void keep_written(griddem_history_pool *p, int values, int64_t mark, int r0, int r1)
{
  enum { BLOCK = 64 };
  const int64_t *partner = p->partner;
  const long *start = p->start;
  int *count = p->count, *written = p->written;
  for (int b0 = r0; b0 < r1; b0 += BLOCK) {
    const int b1 = r1 - b0 < BLOCK ? r1 : b0 + BLOCK;
    for (int r = some_unwritten(count, written, b0, b1) ? b0 : b1; r < b1; r++) {
      const int n = count[r];
      if (written[r] == n) continue;
      const long first = start[r];
      int kept = 0;
      for (int k = 0; k < n; k++) {
        if ((partner[first + k] & GRIDDEM_HISTORY_MARK) != mark) continue;
        if (kept != k) copy_entries(p, first + k, p, first + kept, 1, values);
        kept++;
      }
      count[r] = kept;
    }
    memset(written + b0, 0, sizeof(int) * (size_t) (b1 - b0));
  }
}

/* The overflowed contacts into their particles' rows: a row that cannot hold its particle's moves
 * to the pool's end with the margin to spare, a particle without a row gets one. The contacts
 * of each row still to place are counted in the spare pool's count array, free until a layout. */
static int fold_overflow(griddem_history *h, int *row_of)
{
  griddem_history_pool *p = &h->cur;
  const int nv = h->values;
  for (int k = 0; k < h->noverflow; k++) {
    const griddem_history_overflow *o = &h->overflow[k];
    for (long m = 0; m < o->n; m++) {
      const int i = o->particle[m];
      if (row_of[i] < 0 && (row_of[i] = append_row(p, 0, 0, nv)) < 0) return -1;
    }
  }
  if (pool_reserve(&h->spare, p->nrows, 0, nv) != 0) return -1;
  int *extra = h->spare.count;
  for (int k = 0; k < h->noverflow; k++) {
    const griddem_history_overflow *o = &h->overflow[k];
    for (long m = 0; m < o->n; m++) extra[row_of[o->particle[m]]] = 0;
  }
  for (int k = 0; k < h->noverflow; k++) {
    const griddem_history_overflow *o = &h->overflow[k];
    for (long m = 0; m < o->n; m++) extra[row_of[o->particle[m]]]++;
  }
  for (int k = 0; k < h->noverflow; k++) {
    const griddem_history_overflow *o = &h->overflow[k];
    for (long m = 0; m < o->n; m++) {
      const int r = row_of[o->particle[m]];
      if (p->count[r] == p->room[r]) { /* moved with room for the rest of its overflow */
        const int room = p->count[r] + extra[r] + GRIDDEM_HISTORY_MARGIN;
        if (pool_reserve(p, p->nrows, p->used + room, nv) != 0) return -1;
        copy_entries(p, p->start[r], p, p->used, p->count[r], nv);
        p->start[r] = p->used, p->room[r] = room, p->used += room, h->moved += room;
      }
      const long e = p->start[r] + p->count[r]++;
      griddem_history_put(p->partner, p->value, nv, e, o->partner[m] | h->mark, o->value + (size_t) nv * m);
      p->owned_partner[e] = o->owned_partner[m];
      extra[r]--;
    }
  }
  return 0;
}

/* The rows laid out afresh in the spare pool, which becomes the history: the row of slot s
 * (particle order[s], owned) is s, with its contacts and the margin for room; other owned
 * particles have none */
static int lay_out(griddem_history *h, int nslot, const int *order, int nlocal, int *row_of)
{
  griddem_history_pool *from = &h->cur, *to = &h->spare;
  const int nv = h->values;
  long total = 0;
  if (pool_reserve(to, nslot, 0, nv) != 0) return -1;
  for (int s = 0; s < nslot; s++) {
    const int i = order[s];
    const int row = i < nlocal ? row_of[i] : -1;
    const int count = row >= 0 ? from->count[row] : 0;
    to->start[s] = total, to->count[s] = count, to->room[s] = i < nlocal ? count + GRIDDEM_HISTORY_MARGIN : 0;
    to->written[s] = 0;
    total += to->room[s];
  }
  if (pool_reserve(to, nslot, total, nv) != 0) return -1;
  for (int s = 0; s < nslot; s++) {
    const int i = order[s];
    if (i >= nlocal || row_of[i] < 0) continue;
    copy_entries(from, from->start[row_of[i]], to, to->start[s], to->count[s], nv);
  }
  to->nrows = nslot, to->used = total;
  h->moved = 0;
  for (int i = 0; i < nlocal; i++) row_of[i] = -1;
  for (int s = 0; s < nslot; s++)
    if (order[s] < nlocal) row_of[order[s]] = s;
  const griddem_history_pool laid = *to;
  *to = *from, *from = laid;
  to->nrows = 0, to->used = 0;
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

int griddem_history_end(griddem_history *h, int nslot, const int *order, int nlocal, int *row_of)
{
  griddem_history_pool *p = &h->cur;
  const int nrows = p->nrows;
  if (griddem_threaded(nrows)) {
#pragma omp parallel
    {
      const int t = griddem_thread_num(), nt = griddem_team_size();
      keep_written(p, h->values, h->mark, (int) ((long) nrows * t / nt), (int) ((long) nrows * (t + 1) / nt));
    }
  } else {
    keep_written(p, h->values, h->mark, 0, nrows);
  }
  long overflowed = 0;
  for (int k = 0; k < h->noverflow; k++) overflowed += h->overflow[k].n;
  if (overflowed && fold_overflow(h, row_of) != 0) return -1;
  h->entries = griddem_history_counts(p->count, p->nrows, &h->max_count);
  /* the sweep reads rows in slot order, which moved rows leave and a fresh layout restores: once
     as much room has moved as there are contacts (a layout copies them), or holes (rows moved or
     of atoms gone, room beyond the margin) fill half the pool, or rows outnumber twice the slots
     (rows of atoms gone, which each step's pass over the rows would walk: fix griddem/rom's store
     takes most of a bed out at once) */
  if ((h->moved > h->entries || p->used > 2 * (h->entries + (long) GRIDDEM_HISTORY_MARGIN * nslot) + 1024 ||
       p->nrows > 2L * nslot + 1024) &&
      lay_out(h, nslot, order, nlocal, row_of) != 0)
    return -1;
  h->one_sided = 1;
  return 0;
}

/* (tag, index) of a particle, sorted by tag */
typedef struct tagged_index {
  int64_t tag;
  int index;
} tagged_index;

static int by_tag(const void *a, const void *b)
{
  const int64_t x = ((const tagged_index *) a)->tag, y = ((const tagged_index *) b)->tag;
  return (x > y) - (x < y);
}

/* The owned particle of tag, found in the particles sorted by tag (*sorted, built at first use),
 * or -1. -2 without memory. */
static int owner_of(int64_t tag, const void *tags, int tag_bytes, int nlocal, tagged_index **sorted)
{
  if (!*sorted) {
    if (!(*sorted = (tagged_index *) malloc(sizeof(tagged_index) * (size_t) (nlocal > 0 ? nlocal : 1)))) return -2;
    for (int i = 0; i < nlocal; i++) (*sorted)[i].tag = griddem_key_at(tags, tag_bytes, i), (*sorted)[i].index = i;
    qsort(*sorted, (size_t) nlocal, sizeof(tagged_index), by_tag);
  }
  int lo = 0, hi = nlocal;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if ((*sorted)[mid].tag < tag) lo = mid + 1;
    else hi = mid;
  }
  return lo < nlocal && (*sorted)[lo].tag == tag ? (*sorted)[lo].index : -1;
}

int griddem_history_mirror(griddem_history *h, int nlocal, int *row_of, const void *tag, int tag_bytes,
                           const int *type, int ntypes, const double *parity)
{
  if (!h->one_sided) return 0;
  if (empty_overflow(h, 1) != 0) return -1;
  griddem_history_pool *p = &h->cur;
  griddem_history_overflow *o = &h->overflow[0];
  const int nv = h->values;
  const int64_t tag_mask = ((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1;
  tagged_index *sorted = NULL;
  int failed = 0;
  for (int i = 0; i < nlocal && !failed; i++) {
    const int row = row_of[i];
    if (row < 0 || row >= p->nrows) continue;
    const int64_t self = griddem_key_at(tag, tag_bytes, i);
    /* the row's own entries: those mirrored into it below come after them */
    const int n = p->count[row];
    for (int k = 0; k < n && !failed; k++) {
      const long e = p->start[row] + k;
      int j = p->owned_partner[e];
      if (j < 0) continue;
      p->owned_partner[e] = -1;
      const int64_t key = p->partner[e];
      if (j >= nlocal || griddem_key_at(tag, tag_bytes, j) != (key & tag_mask))
        if ((j = owner_of(key & tag_mask, tag, tag_bytes, nlocal, &sorted)) < 0) {
          failed = j == -2;
          continue;
        }
      const int64_t mirrored = griddem_image_key_mirrored(key & ~GRIDDEM_HISTORY_MARK, self);
      if (griddem_history_find_entry(h, row_of[j], mirrored) >= 0) continue;
      const double *sign = parity + GRIDDEM_MAX_HISTORY * ((size_t) (ntypes + 1) * type[i] + type[j]);
      double v[GRIDDEM_MAX_HISTORY];
      for (int q = 0; q < nv && q < GRIDDEM_MAX_HISTORY; q++) v[q] = sign[q] * p->value[(size_t) nv * e + q];
      const long f = griddem_history_append(p, row_of[j]);
      if (f >= 0) {
        griddem_history_put(p->partner, p->value, nv, f, mirrored | h->mark, v);
        p->owned_partner[f] = -1;
      } else if (griddem_history_overflow_append(o, nv, j, mirrored, -1, v, 1) != 0)
        failed = 1;
    }
  }
  free(sorted);
  if (failed || (o->n && fold_overflow(h, row_of) != 0)) return -1;
  h->entries = griddem_history_counts(p->count, p->nrows, &h->max_count);
  h->one_sided = 0;
  return 0;
}
