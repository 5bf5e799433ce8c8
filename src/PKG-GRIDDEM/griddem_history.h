/* GRIDDEM contact history: per particle, the partners it touched last step and the history
 * values of each contact (tangential and rolling displacements), in compressed rows. The sweep
 * reads last step's rows and logs each evaluated contact; the log is then sorted into new rows,
 * one per sorted slot, which become the history. Rows are dense and read and written in sorted
 * order, so the history costs memory traffic in proportion to the contacts, not to a fixed
 * number of entries per particle. */
#ifndef GRIDDEM_HISTORY_H
#define GRIDDEM_HISTORY_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* One thread's record of the contacts it evaluated: (slot a, slot b, b owned, values) each. */
typedef struct griddem_history_log {
  double *records;
  long n;     /* records */
  long cap;   /* allocated doubles */
} griddem_history_log;

typedef struct griddem_history {
  int values;            /* history values per contact */
  int nrows;
  int max_count;         /* most entries in one row (sizes exchange messages) */
  long *row_start;       /* [nrows + 1]: first entry of each row */
  double *entries;       /* (partner tag, value_1 .. value_values) per entry */
  long rows_cap, entries_cap;           /* allocated elements of row_start, entries */
  /* the sweep's scratch */
  long *next_start;
  double *next_entries;
  long next_rows_cap, next_entries_cap;
  griddem_history_log *logs;
  int nlogs;
} griddem_history;

#define GRIDDEM_HISTORY_ENTRY(values) (1 + (values))

void griddem_history_init(griddem_history *h, int values);
void griddem_history_free(griddem_history *h);

/* Contacts in row (0 for a row that does not exist, such as -1) and a pointer to its first entry. */
int griddem_history_count(const griddem_history *h, int row);
const double *griddem_history_row(const griddem_history *h, int row);

/* The values of row's entry for partner (a tag, as stored), or NULL if the row has none. */
const double *griddem_history_find(const griddem_history *h, int row, double partner);

/* Append a row of count entries written with entry_values values each (converted to h->values:
 * values kept up to the shorter length, the rest zero). Returns its index, or -1 without memory. */
int griddem_history_add_row(griddem_history *h, int count, const double *entries, int entry_values);

/* Make room for rows holding entries contacts in all, now and after the next sweep. 0, or -1. */
int griddem_history_reserve(griddem_history *h, int rows, long entries);

/* Bytes allocated. */
double griddem_history_memory(const griddem_history *h);

/* Change the values per contact of every row (a model with other sub-models). 0, or -1. */
int griddem_history_set_values(griddem_history *h, int values);

/* For the sweep: make nthreads logs empty; append one contact of slots a and b to a log, with
 * the values seen from a (b gets the mirrored entry too if b_owned; 0, or -1 without memory);
 * then build the rows of nslot slots from the logs, given each slot's contact count, and make
 * them the history (the row of slot s is row s). tag_of_slot names each slot's particle for its
 * partners; parity turns values seen from a into values seen from b. */
int griddem_history_begin(griddem_history *h, int nthreads);
int griddem_history_log_contact(griddem_history_log *log, int values, int a, int b, int b_owned,
                                const double *v);
int griddem_history_build(griddem_history *h, int nslot, const int *count, const int64_t *tag_of_slot,
                          const double *parity);

#ifdef __cplusplus
}
#endif

#endif
