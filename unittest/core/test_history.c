/* The CPU contact-history store: rows appended from messages keep their entries and the longest
 * is known (it sizes exchange messages); conversion between values per contact keeps the common
 * values and zeroes the new ones; a sweep's writes give each slot its own entries, with room for
 * its particle's last count plus the margin, and entries beyond the room are folded in; partner
 * tags stay exact integers beyond a double's 2^53. Image keys: a contact's key is the partner tag
 * where the images match and in boxes without image axes, tells apart the images of one partner
 * that can touch a sphere together, does not change when either atom wraps across the boundary,
 * and stays exact as a double. */
#include "check.h"
#include "griddem_history.h"
#include "griddem_threads.h"

#ifdef _OPENMP
#include <omp.h>
#endif
#include <string.h>

#ifdef _OPENMP
/* the next pool's row layout (a prefix sum over the slots) and the longest row on two threads,
 * from GRIDDEM_THREADED_MIN slots on: one thread's; the ghosts' slots get no room */
static void check_threaded_layout(void)
{
  enum { NSLOT = 3 * GRIDDEM_THREADED_MIN + 7, NLOCAL = 2 * GRIDDEM_THREADED_MIN };
  static int order[NSLOT], row_of[NLOCAL];
  static long start[2][NSLOT + 1];
  int most[2];
  for (int s = 0; s < NSLOT; s++) order[s] = (int) ((7L * s + 3) % NSLOT);    /* a permutation */
  for (int i = 0; i < NLOCAL; i++) row_of[i] = i % 5 == 0 ? -1 : i / 3;
  for (int k = 0; k < 2; k++) {
    griddem_history h;
    griddem_history_init(&h, 3);
    /* rows 0..NLOCAL/3 of r % 7 contacts each (partner, then three values per contact) */
    double entries[7 * 4] = {0.0};
    for (int e = 0; e < 7; e++) entries[4 * e] = 100 + e;
    for (int r = 0; r <= NLOCAL / 3; r++) griddem_history_add_row(&h, r % 7, entries, 3);
    omp_set_num_threads(k + 1);
    CHECK(griddem_threaded(NSLOT) == k, "%d thread(s): layout threaded %d", k + 1, k);
    CHECK(griddem_history_begin(&h, k + 1, NSLOT, order, row_of, NLOCAL) == 0, "begin on %d thread(s)", k + 1);
    memcpy(start[k], h.next.start, sizeof(long) * (NSLOT + 1));
    CHECK(griddem_history_end(&h) == 0, "end");
    most[k] = h.max_count;
    griddem_history_free(&h);
  }
  omp_set_num_threads(1);
  int same = start[0][NSLOT] == start[1][NSLOT] && start[0][NSLOT] > 0;
  for (int s = 0; s <= NSLOT; s++) same &= start[0][s] == start[1][s];
  CHECK(same, "two threads lay %d rows out as one (%ld entries of room)", NSLOT, start[1][NSLOT]);
  /* each slot's room counted here: its row's r % 7 contacts and the margin, none for a ghost or
     for a particle without a row beyond the margin */
  long wrong = 0;
  for (int s = 0; s < NSLOT; s++) {
    const int i = order[s], row = i < NLOCAL ? row_of[i] : -1;
    const long room = i < NLOCAL ? (row >= 0 ? row % 7 : 0) + GRIDDEM_HISTORY_MARGIN : 0;
    wrong += start[0][s + 1] - start[0][s] != room;
  }
  CHECK(wrong == 0, "%ld of %d slots laid out with other room than their last count and the margin", wrong, NSLOT);
  CHECK(most[0] == most[1], "longest row %d and %d", most[0], most[1]);
}
#endif

/* keys of contacts between periodic images (griddem_history.h) */
static void check_image_keys(void)
{
  const int z = 4; /* image axes: z alone */
  const int zero[3] = {0, 0, 0}, up[3] = {0, 0, 1}, down[3] = {0, 0, -1}, x_shift[3] = {1, 0, 0};
  const int64_t tag = 12345;
  /* an owned atom of image flags (0, 0, 2): m = (0, 0, -2); its ghosts shifted by +-1 along z */
  const int flags2[3] = {0, 0, -2};
  const int self = griddem_image_code(flags2, z);
  const int above = griddem_image_shifted(self, up, z), below = griddem_image_shifted(self, down, z);
  CHECK(griddem_image_key(tag, self, self) == tag, "same image: the key is the tag");
  CHECK(griddem_image_code(x_shift, z) == 0 && griddem_image_key(tag, 0, griddem_image_code(x_shift, z)) == tag,
        "a shift along an axis that is not an image axis leaves the key the tag");
  const int64_t k_up = griddem_image_key(tag, self, above), k_down = griddem_image_key(tag, self, below);
  CHECK(k_up != tag && k_down != tag && k_up != k_down, "the images above and below have keys of their own");
  CHECK(k_up == griddem_image_key(tag, 0, griddem_image_code(up, z)), "the key holds the relative image only");
  /* the owned atom wraps (flags 2 -> 3, its position down a box): its ghosts' shifts grow by one */
  const int flags3[3] = {0, 0, -3};
  const int wrapped = griddem_image_code(flags3, z);
  CHECK(griddem_image_key(tag, wrapped, griddem_image_shifted(above, down, z)) == k_up,
        "a wrap of the atom keeps its contact's key");
  CHECK(griddem_image_key(tag, self, griddem_image_shifted(self, zero, z)) == tag, "an unshifted ghost has the tag");
  /* images up to 15 apart differ; 16 apart alias (the width limit keeps them from touching one sphere) */
  int distinct = 1;
  for (int a = 0; a < 16; a++)
    for (int b = a + 1; b < 16; b++) {
      const int ma[3] = {0, 0, a}, mb[3] = {0, 0, b};
      distinct &= griddem_image_key(tag, 0, griddem_image_code(ma, z)) != griddem_image_key(tag, 0, griddem_image_code(mb, z));
    }
  const int m16[3] = {0, 0, 16};
  CHECK(distinct && griddem_image_key(tag, 0, griddem_image_code(m16, 7)) == tag, "images 0..15 apart distinct, 16 aliased");
  /* every pair of codes: the relative image is each axis's difference modulo 2^GRIDDEM_IMAGE_BITS */
  long wrong = 0;
  for (int a = 0; a < 1 << (3 * GRIDDEM_IMAGE_BITS); a++)
    for (int b = 0; b < 1 << (3 * GRIDDEM_IMAGE_BITS); b++) {
      int64_t want = 0;
      for (int d = 0; d < 3; d++) {
        const int field = (a >> (GRIDDEM_IMAGE_BITS * d) & GRIDDEM_IMAGE_MASK) - (b >> (GRIDDEM_IMAGE_BITS * d) & GRIDDEM_IMAGE_MASK);
        want |= (int64_t) ((field + (1 << GRIDDEM_IMAGE_BITS)) % (1 << GRIDDEM_IMAGE_BITS)) << (GRIDDEM_IMAGE_BITS * d);
      }
      wrong += griddem_image_key(tag, b, a) != (tag | want << GRIDDEM_KEY_TAG_BITS);
    }
  CHECK(wrong == 0, "relative images of every pair of codes: %ld wrong", wrong);
  /* the largest key: tag below 2^GRIDDEM_KEY_TAG_BITS, every axis's image 15 */
  const int m15[3] = {15, 15, 15};
  const int64_t most = griddem_image_key(((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1, 0, griddem_image_code(m15, 7));
  CHECK(most < ((int64_t) 1 << 53) && (int64_t) (double) most == most, "keys stay exact doubles: %lld", (long long) most);
  CHECK((most & (((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1)) == ((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1,
        "the tag is kept below the image");
}

int main(void)
{
  check_image_keys();
#ifdef _OPENMP
  check_threaded_layout();
#endif
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
