/* Compressed contact history; see griddem_history.h. */
#include "griddem_history.h"

#include <stdlib.h>
#include <string.h>

void griddem_history_init(griddem_history *h, int values)
{
  memset(h, 0, sizeof(*h));
  h->values = values;
}

void griddem_history_free(griddem_history *h)
{
  free(h->row_start), free(h->entries), free(h->next_start), free(h->next_entries);
  for (int k = 0; k < h->nlogs; k++) free(h->logs[k].records);
  free(h->logs);
  memset(h, 0, sizeof(*h));
}

int griddem_history_count(const griddem_history *h, int row)
{
  return (row < 0 || row >= h->nrows) ? 0 : (int) (h->row_start[row + 1] - h->row_start[row]);
}

const double *griddem_history_row(const griddem_history *h, int row)
{
  return (row < 0 || row >= h->nrows) ? h->entries
                                      : h->entries + (size_t) GRIDDEM_HISTORY_ENTRY(h->values) * h->row_start[row];
}

const double *griddem_history_find(const griddem_history *h, int row, double partner)
{
  const int width = GRIDDEM_HISTORY_ENTRY(h->values), count = griddem_history_count(h, row);
  const double *entry = griddem_history_row(h, row);
  for (int k = 0; k < count; k++, entry += width)
    if (entry[0] == partner) return entry + 1;
  return NULL;
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

static int reserve(griddem_history *h, int rows, long entries)
{
  const size_t width = sizeof(double) * GRIDDEM_HISTORY_ENTRY(h->values);
  if (ensure((void **) &h->row_start, &h->rows_cap, rows + 1, sizeof(long)) != 0 ||
      ensure((void **) &h->entries, &h->entries_cap, entries, width) != 0)
    return -1;
  if (h->nrows == 0) h->row_start[0] = 0;
  return 0;
}

int griddem_history_reserve(griddem_history *h, int rows, long entries)
{
  const size_t width = sizeof(double) * GRIDDEM_HISTORY_ENTRY(h->values);
  if (reserve(h, rows, entries) != 0 ||
      ensure((void **) &h->next_start, &h->next_rows_cap, rows + 1, sizeof(long)) != 0 ||
      ensure((void **) &h->next_entries, &h->next_entries_cap, entries, width) != 0)
    return -1;
  return 0;
}

double griddem_history_memory(const griddem_history *h)
{
  double bytes = (double) (h->rows_cap + h->next_rows_cap) * sizeof(long) +
      (double) (h->entries_cap + h->next_entries_cap) * GRIDDEM_HISTORY_ENTRY(h->values) * sizeof(double);
  for (int k = 0; k < h->nlogs; k++) bytes += (double) h->logs[k].cap * sizeof(double);
  return bytes;
}

static void convert_entries(const double *from, int from_values, double *to, int values, int count)
{
  for (int k = 0; k < count; k++) {
    const double *a = from + (size_t) (1 + from_values) * k;
    double *b = to + (size_t) (1 + values) * k;
    for (int v = 0; v <= values; v++) b[v] = v <= from_values ? a[v] : 0.0;
  }
}

int griddem_history_add_row(griddem_history *h, int count, const double *entries, int entry_values)
{
  const long first = h->row_start ? h->row_start[h->nrows] : 0;
  if (reserve(h, h->nrows + 1, first + count) != 0) return -1;
  convert_entries(entries, entry_values, h->entries + (size_t) GRIDDEM_HISTORY_ENTRY(h->values) * first,
                  h->values, count);
  h->row_start[h->nrows + 1] = first + count;
  if (count > h->max_count) h->max_count = count;
  return h->nrows++;
}

int griddem_history_set_values(griddem_history *h, int values)
{
  if (values == h->values) return 0;
  const long total = h->row_start ? h->row_start[h->nrows] : 0;
  double *converted = (double *) malloc(sizeof(double) * (size_t) (GRIDDEM_HISTORY_ENTRY(values) * (total + 1)));
  if (!converted) return -1;
  if (h->entries) convert_entries(h->entries, h->values, converted, values, (int) total);
  free(h->entries);
  free(h->next_entries);
  h->next_entries = NULL, h->next_entries_cap = 0;
  h->entries = converted, h->entries_cap = total + 1;
  h->values = values;
  return 0;
}

int griddem_history_begin(griddem_history *h, int nthreads)
{
  if (nthreads > h->nlogs) {
    griddem_history_log *p = (griddem_history_log *) realloc(h->logs, sizeof(*p) * (size_t) nthreads);
    if (!p) return -1;
    memset(p + h->nlogs, 0, sizeof(*p) * (size_t) (nthreads - h->nlogs));
    h->logs = p, h->nlogs = nthreads;
  }
  for (int k = 0; k < h->nlogs; k++) h->logs[k].n = 0;
  return 0;
}

int griddem_history_log_contact(griddem_history_log *log, int values, int a, int b, int b_owned,
                                const double *v)
{
  const int width = 3 + values;
  if (ensure((void **) &log->records, &log->cap, (log->n + 1) * width, sizeof(double)) != 0) return -1;
  double *r = log->records + (size_t) width * log->n++;
  r[0] = a, r[1] = b, r[2] = b_owned;
  for (int k = 0; k < values; k++) r[3 + k] = v[k];
  return 0;
}

int griddem_history_build(griddem_history *h, int nslot, const int *count, const int64_t *tag_of_slot,
                          const double *parity)
{
  const int nv = h->values, width = GRIDDEM_HISTORY_ENTRY(nv);
  if (ensure((void **) &h->next_start, &h->next_rows_cap, nslot + 1, sizeof(long)) != 0) return -1;
  long total = 0;
  int most = 0;
  for (int s = 0; s < nslot; s++) {
    h->next_start[s] = total;
    total += count[s];
    if (count[s] > most) most = count[s];
  }
  h->next_start[nslot] = total;
  if (ensure((void **) &h->next_entries, &h->next_entries_cap, total, sizeof(double) * width) != 0)
    return -1;

  /* fill each row from its start; next_start[s] serves as the cursor, restored after */
  for (int k = 0; k < h->nlogs; k++) {
    const griddem_history_log *log = &h->logs[k];
    for (long m = 0; m < log->n; m++) {
      const double *r = log->records + (size_t) (3 + nv) * m;
      const int a = (int) r[0], b = (int) r[1];
      double *ea = h->next_entries + (size_t) width * h->next_start[a]++;
      ea[0] = (double) tag_of_slot[b];
      for (int v = 0; v < nv; v++) ea[1 + v] = r[3 + v];
      if (r[2] != 0.0) {
        double *eb = h->next_entries + (size_t) width * h->next_start[b]++;
        eb[0] = (double) tag_of_slot[a];
        for (int v = 0; v < nv; v++) eb[1 + v] = parity[v] * r[3 + v];
      }
    }
  }
  for (int s = nslot; s > 0; s--) h->next_start[s] = h->next_start[s - 1];
  h->next_start[0] = 0;

  /* the new rows become the history */
  long *start = h->row_start;
  double *entries = h->entries;
  const long rows_cap = h->rows_cap, entries_cap = h->entries_cap;
  h->row_start = h->next_start, h->entries = h->next_entries;
  h->rows_cap = h->next_rows_cap, h->entries_cap = h->next_entries_cap;
  h->next_start = start, h->next_entries = entries;
  h->next_rows_cap = rows_cap, h->next_entries_cap = entries_cap;
  h->nrows = nslot;
  h->max_count = most;
  return 0;
}
