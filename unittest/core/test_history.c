/* Compressed contact history: rows appended by hand keep their entries and the longest is known
 * (it sizes exchange messages), conversion between
 * values per contact keeps the common values and zeroes the new ones, and a build from logged
 * contacts gives each slot its own entries plus the mirrored entries of its owned partners. */
#include "check.h"
#include "griddem_history.h"

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
  CHECK(griddem_history_row(&h, 0)[4] == 9.0 && griddem_history_row(&h, 1)[3] == -3.0, "entries kept");
  CHECK(h.max_count == 2, "longest row: %d entries", h.max_count);

  /* 3 -> 6 values: the first three kept, rolling values start from zero */
  CHECK(griddem_history_set_values(&h, 6) == 0, "convert to 6 values");
  const double *r = griddem_history_row(&h, 0);
  CHECK(r[0] == 7 && r[1] == 1 && r[3] == 3 && r[4] == 0 && r[6] == 0 && r[7] == 9 && r[10] == 6,
        "converted row 0");
  CHECK(griddem_history_row(&h, 1)[3] == -3.0 && griddem_history_row(&h, 1)[6] == 0.0, "converted row 1");

  /* build: slots 0,1,2 (tags 10,20,30); contacts (0,1) both owned, (0,2) with 2 a ghost */
  const int64_t tags[3] = {10, 20, 30};
  const double parity[6] = {-1, -1, -1, 1, 1, 1};
  const double v01[6] = {1, 2, 3, 4, 5, 6}, v02[6] = {7, 8, 9, 10, 11, 12};
  CHECK(griddem_history_begin(&h, 2) == 0, "logs");
  griddem_history_log_contact(&h.logs[1], 6, 0, 1, 1, v01);
  griddem_history_log_contact(&h.logs[0], 6, 0, 2, 0, v02);
  const int count[3] = {2, 1, 0};
  CHECK(griddem_history_build(&h, 3, count, tags, parity) == 0, "build");
  CHECK(h.nrows == 3 && griddem_history_count(&h, 0) == 2 && griddem_history_count(&h, 1) == 1 &&
            griddem_history_count(&h, 2) == 0, "built counts");
  CHECK(h.max_count == 2, "longest built row: %d entries", h.max_count);
  const double *s0 = griddem_history_row(&h, 0), *s1 = griddem_history_row(&h, 1);
  /* log 0 is read first: slot 0's partner 30, then 20 */
  CHECK(s0[0] == 30 && s0[1] == 7 && s0[6] == 12 && s0[7] == 20 && s0[8] == 1, "slot 0 entries");
  CHECK(s1[0] == 10 && s1[1] == -1 && s1[3] == -3 && s1[4] == 4 && s1[6] == 6, "slot 1 mirrored entry");
  griddem_history_free(&h);
  return check_summary();
}
