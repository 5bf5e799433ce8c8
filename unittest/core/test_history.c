/* The CPU contact-history store: rows appended from messages keep their entries and the longest
 * is known (it sizes exchange messages); conversion between values per contact keeps the common
 * values and zeroes the new ones; a sweep's writes give each slot its own entries, with room for
 * its particle's last count plus the margin, and entries beyond the room are folded in; partner
 * tags stay exact integers beyond a double's 2^53. */
#include "check.h"
#include "griddem_history.h"

#include <string.h>

int main(void)
{
  griddem_history h;
  griddem_history_init(&h, 3);
  const double a[] = {7, 1, 2, 3, 9, 4, 5, 6}; /* partners 7 and 9 */
  const double b[] = {5, -1, -2, -3};
  CHECK(griddem_history_add_row(&h, 2, a, 3) == 0, "first row index");
  CHECK(griddem_history_add_row(&h, 1, b, 3) == 1, "second row index");
  CHECK(griddem_history_count(&h, 0) == 2 && griddem_history_count(&h, 1) == 1, "row counts");
  CHECK(griddem_history_count(&h, -1) == 0 && griddem_history_count(&h, 5) == 0, "no row, no contacts");
  double m[64];
  griddem_history_get_row(&h, 0, m);
  CHECK(memcmp(m, a, sizeof(a)) == 0, "row 0 reads back as its message");
  const double *f9 = griddem_history_find(&h, 0, 9), *f5 = griddem_history_find(&h, 1, 5);
  CHECK(f9 && f9[0] == 4 && f9[2] == 6 && f5 && f5[2] == -3.0, "entries found by partner");
  CHECK(!griddem_history_find(&h, 0, 5) && !griddem_history_find(&h, -1, 7), "no entry for another partner or row");
  CHECK(h.max_count == 2, "longest row: %d entries", h.max_count);

  /* 3 -> 6 values: the first three kept, rolling values start from zero */
  CHECK(griddem_history_set_values(&h, 6) == 0, "convert to 6 values");
  griddem_history_get_row(&h, 0, m);
  CHECK(m[0] == 7 && m[1] == 1 && m[3] == 3 && m[4] == 0 && m[6] == 0 && m[7] == 9 && m[10] == 6,
        "converted row 0");
  griddem_history_get_row(&h, 1, m);
  CHECK(m[3] == -3.0 && m[6] == 0.0, "converted row 1");

  /* a sweep over slots 0..3 holding particles 1, 0, 2 and the ghost 3 (particle 0 has row 0 with
     2 contacts, particle 1 row 1 with 1): slot 0 gets room for 1 + margin, slot 1 for 2 + margin,
     slot 2 for the margin, the ghost none */
  const int order[4] = {1, 0, 2, 3}, row_of[3] = {0, 1, -1};
  CHECK(griddem_history_begin(&h, 2, 4, order, row_of, 3) == 0, "begin");
  const int64_t big = 9007199254740993; /* 2^53 + 1: not a double */
  double v[6] = {1, 2, 3, 4, 5, 6};
  int failed = 0;
  for (int k = 0; k < 1 + GRIDDEM_HISTORY_MARGIN + 2; k++) { /* two beyond slot 0's room */
    v[0] = 10 + k;
    failed |= griddem_history_write(&h, &h.overflow[k % 2], h.values, 0, big + k, v);
  }
  v[0] = -1;
  failed |= griddem_history_write(&h, &h.overflow[0], h.values, 2, 42, v);
  CHECK(!failed && h.overflow[0].n + h.overflow[1].n == 2, "two entries overflowed");
  CHECK(griddem_history_end(&h) == 0, "end");
  CHECK(h.cur.nrows == 4 && griddem_history_count(&h, 0) == 5 && griddem_history_count(&h, 1) == 0 &&
            griddem_history_count(&h, 2) == 1 && griddem_history_count(&h, 3) == 0,
        "rows by slot: %d %d %d %d", griddem_history_count(&h, 0), griddem_history_count(&h, 1),
        griddem_history_count(&h, 2), griddem_history_count(&h, 3));
  CHECK(h.max_count == 5, "longest row after the sweep: %d", h.max_count);
  for (int k = 0; k < 5; k++) {
    const double *e = griddem_history_find(&h, 0, big + k);
    CHECK(e && e[0] == 10 + k && e[5] == 6, "slot 0's entry for partner 2^53+1+%d (overflowed or not)", k);
  }
  CHECK(!griddem_history_find(&h, 0, big + 5) && griddem_history_find(&h, 2, 42)[0] == -1, "no other entries");

  /* the next sweep without overflow: the written pool becomes the history as it is */
  const int order2[2] = {0, 1}, row_of2[2] = {2, 0};
  CHECK(griddem_history_begin(&h, 1, 2, order2, row_of2, 2) == 0, "begin again");
  v[0] = 7;
  CHECK(griddem_history_write(&h, &h.overflow[0], h.values, 1, 3, v) == 0 && h.overflow[0].n == 0, "written in place");
  CHECK(griddem_history_end(&h) == 0 && griddem_history_count(&h, 0) == 0 && griddem_history_count(&h, 1) == 1 &&
            griddem_history_find(&h, 1, 3)[0] == 7 && h.max_count == 1,
        "second sweep's rows");
  CHECK(griddem_history_memory(&h) > 0.0, "memory reported");
  griddem_history_free(&h);
  return check_summary();
}
