/* The CPU contact-history store: rows appended from messages keep their entries and the longest
 * is known (it sizes exchange messages); conversion between values per contact keeps the common
 * values and zeroes the new ones; a sweep writes lasting contacts in place, drops those it did not
 * write, gives new ones the row's room or moves the row (a particle without one gets one), lays
 * the rows out afresh in slot order once they are mostly holes or outnumber twice the slots (rows
 * of particles gone), and on any thread count keeps the
 * same; the contacts of owned pairs kept in one row are mirrored into the partner's, found by its
 * tag where its index moved; partner tags stay exact integers beyond a double's 2^53. Image keys:
 * a contact's key is the partner tag where the images match and in boxes without image axes,
 * tells apart the images of one partner that can touch a sphere together, does not change when
 * either atom wraps across the boundary, is mirrored into the partner's key of the same contact,
 * and stays exact as a double. */
#include "check.h"
#include "griddem_contact.h"
#include "griddem_history.h"
#include "griddem_threads.h"

#ifdef _OPENMP
#include <omp.h>
#endif
#include <string.h>

#ifdef _OPENMP
/* the end of a sweep on two threads, from GRIDDEM_THREADED_MIN rows on, keeps what one thread
 * keeps: of rows of r % 7 contacts, those written (partners of even index), in their order */
static void check_threaded_end(void)
{
  enum { NROW = 3 * GRIDDEM_THREADED_MIN + 7 };
  static int row_of[NROW], order[NROW];
  static double kept[2][NROW][7];
  int most[2];
  long entries[2];
  for (int r = 0; r < NROW; r++) order[r] = r;
  for (int k = 0; k < 2; k++) {
    griddem_history h;
    griddem_history_init(&h, 3);
    double entries_in[7 * 4] = {0.0};
    for (int e = 0; e < 7; e++) entries_in[4 * e] = 100 + e, entries_in[4 * e + 1] = e;
    for (int r = 0; r < NROW; r++) row_of[r] = griddem_history_add_row(&h, r % 7, entries_in, 3);
    omp_set_num_threads(k + 1);
    CHECK(griddem_threaded(NROW) == k, "%d thread(s): end threaded %d", k + 1, k);
    CHECK(griddem_history_begin(&h, k + 1) == 0, "begin on %d thread(s)", k + 1);
    for (int r = 0; r < NROW; r++)
      for (int e = 0; e < r % 7; e += 2) {
        const double v[3] = {10.0 * r + e, 0.0, 0.0};
        griddem_history_write(&h, &h.overflow[0], 3, r, row_of[r], griddem_history_find_entry(&h, row_of[r], 100 + e),
                              100 + e, -1, v, 1);
      }
    CHECK(griddem_history_end(&h, NROW, order, NROW, row_of) == 0, "end");
    for (int r = 0; r < NROW; r++)
      for (int e = 0; e < 7; e++) {
        const double *f = griddem_history_find(&h, row_of[r], 100 + e);
        kept[k][r][e] = f ? f[0] : -1.0;
      }
    most[k] = h.max_count, entries[k] = h.entries;
    griddem_history_free(&h);
  }
  omp_set_num_threads(1);
  long wrong = 0;
  for (int r = 0; r < NROW; r++)
    for (int e = 0; e < 7; e++) {
      const double want = e < r % 7 && e % 2 == 0 ? 10.0 * r + e : -1.0;
      wrong += kept[0][r][e] != want || kept[1][r][e] != want;
    }
  CHECK(wrong == 0, "%ld entries of %d rows kept otherwise than written, on 1 or 2 threads", wrong, NROW);
  CHECK(most[0] == most[1] && most[0] == 3 && entries[0] == entries[1], "longest row %d and %d, entries %ld and %ld",
        most[0], most[1], entries[0], entries[1]);
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
  /* a key mirrored is the partner's key of the contact, for every pair of codes */
  long unmirrored = 0;
  for (int a = 0; a < 1 << (3 * GRIDDEM_IMAGE_BITS); a += 7)
    for (int b = 0; b < 1 << (3 * GRIDDEM_IMAGE_BITS); b++)
      unmirrored += griddem_image_key_mirrored(griddem_image_key(tag, a, b), 777) != griddem_image_key(777, b, a);
  CHECK(unmirrored == 0, "keys mirrored: %ld wrong", unmirrored);
  /* the largest key: tag below 2^GRIDDEM_KEY_TAG_BITS, every axis's image 15 */
  const int m15[3] = {15, 15, 15};
  const int64_t most = griddem_image_key(((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1, 0, griddem_image_code(m15, 7));
  CHECK(most < ((int64_t) 1 << 53) && (int64_t) (double) most == most, "keys stay exact doubles: %lld", (long long) most);
  CHECK((most & (((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1)) == ((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1,
        "the tag is kept below the image");
}

/* The own ID a message holds as fix griddem finds it: the entry of key GRIDDEM_OWN_KEY of the row
 * a store makes of it, or -1 */
static double own_tag_found(const double *message, int values)
{
  griddem_history h;
  griddem_history_init(&h, values);
  const double *own = griddem_history_find(&h, griddem_history_put_message(&h, message, values), GRIDDEM_OWN_KEY);
  const double tag = own ? own[0] : -1;
  griddem_history_free(&h);
  return tag;
}

/* A row message after renumbering: keys take their partners' new tags with their relative
 * images, an entry of a deleted partner goes, the rest keep their order and values. */
static void check_renumbered_message(void)
{
  const int z = 4;
  const int up[3] = {0, 0, 1};
  const int64_t above = griddem_image_key(40, 0, griddem_image_code(up, z));
  /* partners 40 (same image), 40 one image up, 17 (deleted) and 25, 2 values each */
  double m[1 + 4 * 3] = {4, 40, 1.5, -1.5, (double) above, 2.5, -2.5, 17, 3.5, -3.5, 25, 4.5, -4.5};
  int64_t partners[4] = {0};
  CHECK(griddem_message_partners(m, 2, partners) == 4 && partners[0] == 40 && partners[1] == 40 &&
            partners[2] == 17 && partners[3] == 25,
        "the message's partners, an image's by its tag: %lld %lld %lld %lld", (long long) partners[0],
        (long long) partners[1], (long long) partners[2], (long long) partners[3]);
  const int64_t old_tag[] = {3, 25, 40, 41}, new_tag[] = {3, 24, 37, 38}; /* sorted by old tag */
  const int n = griddem_message_renumber(m, 2, old_tag, new_tag, 4);
  CHECK(n == 1 + 3 * 3 && m[0] == 3, "three entries kept: length %d, count %g", n, m[0]);
  CHECK(m[1] == 37 && m[2] == 1.5 && m[3] == -1.5, "partner 40 is now 37");
  CHECK((int64_t) m[4] == griddem_image_key(37, 0, griddem_image_code(up, z)) && m[5] == 2.5 && m[6] == -2.5,
        "its image above keeps its relative image: %.17g", m[4]);
  CHECK(griddem_key_tag((int64_t) m[4]) == 37 && griddem_key_tag(above) == 40, "a key's tag");
  CHECK(m[7] == 24 && m[8] == 4.5 && m[9] == -4.5, "partner 25 is now 24, the deleted 17 gone");
  /* the own entry: appended, found, rewritten, kept by a renumbering as it is */
  double own[1 + 3 * 3] = {1, 24, 4.5, -4.5};
  CHECK(own_tag_found(own, 2) == -1, "no own entry yet");
  CHECK(griddem_message_with_own_tag(own, 2, 30) == 1 + 2 * 3 && own[0] == 2 && own_tag_found(own, 2) == 30,
        "own entry appended");
  CHECK(griddem_message_with_own_tag(own, 2, 31) == 1 + 2 * 3 && own_tag_found(own, 2) == 31 && own[4] == 0,
        "own entry rewritten in place");
  CHECK(griddem_message_partners(own, 2, partners) == 1 && partners[0] == 24, "the own entry is no partner");
  const int64_t back_old[] = {24}, back_new[] = {20};
  CHECK(griddem_message_renumber(own, 2, back_old, back_new, 1) == 1 + 2 * 3 && own[1] == 20 &&
            own_tag_found(own, 2) == 31,
        "a renumbering keeps the own entry, the partner renumbered");
  double empty[1] = {0};
  CHECK(griddem_message_renumber(empty, 2, old_tag, new_tag, 4) == 1 && empty[0] == 0, "an empty row stays empty");
}

int main(void)
{
  check_image_keys();
  check_renumbered_message();
#ifdef _OPENMP
  check_threaded_end();
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

  /* a sweep in place (particles 0, 1 and 2 owned; 0 has row 0 with partners 7 and 9, 1 row 1
     with partner 5, 2 none): 0's contact with 9 lasts and 7's ends, and four new ones overflow its
     row's room; 2 touches 42; 1's contact with 5, an owned particle (index 0), lasts */
  int row_of[3] = {0, 1, -1};
  const int order[3] = {1, 0, 2};
  CHECK(griddem_history_begin(&h, 2) == 0, "begin");
  const int64_t big = 9007199254740993; /* 2^53 + 1: not a double */
  double v[6] = {1, 2, 3, 4, 5, 6};
  int failed = griddem_history_write(&h, &h.overflow[0], h.values, 0, 0, griddem_history_find_entry(&h, 0, 9), 9, -1, v, 1);
  for (int k = 0; k < 4; k++) {
    v[0] = 10 + k;
    failed |= griddem_history_write(&h, &h.overflow[k % 2], h.values, 0, 0, griddem_history_find_entry(&h, 0, big + k),
                                    big + k, -1, v, 1);
  }
  /* these two read their values two doubles apart, as the sweep reads a batch's lanes (between
     them, values no contact has) */
  double lanes[12];
  for (int k = 0; k < 6; k++) lanes[2 * k] = v[k], lanes[2 * k + 1] = 1e300;
  lanes[0] = -1;
  failed |= griddem_history_write(&h, &h.overflow[0], h.values, 2, -1, -1, 42, -1, lanes, 2);
  lanes[0] = 8, lanes[2] = 0.5;
  failed |= griddem_history_write(&h, &h.overflow[1], h.values, 1, 1, griddem_history_find_entry(&h, 1, 5), 5, 0, lanes, 2);
  CHECK(!failed && h.overflow[0].n + h.overflow[1].n == 5, "five entries overflowed: %ld", h.overflow[0].n + h.overflow[1].n);
  CHECK(griddem_history_end(&h, 3, order, 3, row_of) == 0, "end");
  /* row 0 moved with room 7, particle 2's new row 3: more room moved than the 7 contacts, so the
     rows are laid out afresh in slot order */
  CHECK(row_of[1] == 0 && row_of[0] == 1 && row_of[2] == 2 && h.moved == 0, "rows by slot: %d %d %d", row_of[0],
        row_of[1], row_of[2]);
  const int r0 = row_of[0], r1 = row_of[1], r2 = row_of[2];
  CHECK(griddem_history_count(&h, r0) == 5 && griddem_history_count(&h, r1) == 1 && griddem_history_count(&h, r2) == 1,
        "contacts %d %d %d", griddem_history_count(&h, r0), griddem_history_count(&h, r1), griddem_history_count(&h, r2));
  CHECK(h.max_count == 5 && h.entries == 7 && h.one_sided, "longest row %d, %ld entries, one-sided", h.max_count, h.entries);
  griddem_history_get_row(&h, r0, m);
  CHECK(m[0] == 9 && m[1] == 1 && m[6] == 6, "the lasting contact first, written in place");
  /* then the new ones, by their threads' lists (0: k = 0, 2; 1: k = 1, 3) */
  for (int q = 0; q < 4; q++) {
    const int k = 2 * (q % 2) + q / 2;
    CHECK(m[7 * (q + 1)] == (double) (big + k) && m[7 * (q + 1) + 1] == 10 + k, "new contact %d in place %d", k, q + 1);
  }
  CHECK(!griddem_history_find(&h, r0, 7), "the contact that ended is gone");
  CHECK(griddem_history_find(&h, r2, 42)[0] == -1 && griddem_history_find(&h, r2, 42)[1] == 2 &&
            griddem_history_find(&h, r1, 5)[1] == 0.5,
        "other rows");
  /* a layout gives each row the margin to spare: a new contact next step stays in it */
  CHECK(griddem_history_begin(&h, 1) == 0, "begin again");
  for (int k = 0; k < 4; k++)
    failed |= griddem_history_write(&h, &h.overflow[0], h.values, 0, r0, griddem_history_find_entry(&h, r0, big + k),
                                    big + k, -1, v, 1);
  failed |= griddem_history_write(&h, &h.overflow[0], h.values, 0, r0, -1, 77, -1, v, 1);
  CHECK(!failed && h.overflow[0].n == 0, "the laid out row holds a new contact");
  CHECK(griddem_history_end(&h, 3, order, 3, row_of) == 0 && row_of[0] == r0 && griddem_history_count(&h, r0) == 5 &&
            griddem_history_count(&h, r1) == 0 && !griddem_history_find(&h, r0, 9) && griddem_history_find(&h, r0, 77),
        "second sweep: contacts of 9, 5 and 42 ended, 77 new, no row moved");

  /* mirrored: particle 1 (tag 11) keeps its contact with particle 0 (tag 5), recorded as owned
     partner 1 although particle 1 is at index 2 (moved since): found by its tag, mirrored into 1's
     row, the values times the parity */
  const int tags[3] = {5, 13, 11}, types[3] = {1, 1, 1};
  const double parity[4 * GRIDDEM_MAX_HISTORY] = {[3 * GRIDDEM_MAX_HISTORY] = -1, 1, -1, 1, 1, 1};
  int rows2[3] = {row_of[0], -1, row_of[1]};
  CHECK(griddem_history_begin(&h, 1) == 0, "begin a third time");
  v[0] = 3, v[1] = 4, v[2] = 5;
  failed |= griddem_history_write(&h, &h.overflow[0], h.values, 0, rows2[0], -1, 11, 1, v, 1);
  failed |= griddem_history_write(&h, &h.overflow[0], h.values, 0, rows2[0], -1, 99, -1, v, 1); /* a ghost */
  CHECK(griddem_history_end(&h, 3, order, 3, rows2) == 0 && h.one_sided, "end, one-sided");
  CHECK(!griddem_history_find(&h, rows2[2], 5), "the partner's row lacks the contact");
  CHECK(griddem_history_mirror(&h, 3, rows2, tags, 4, types, 1, parity) == 0 && !h.one_sided, "mirrored");
  const double *back = griddem_history_find(&h, rows2[2], 5);
  CHECK(back && back[0] == -3 && back[1] == 4 && back[2] == -5 && back[3] == 4, "the partner's copy, seen from it");
  CHECK(griddem_history_count(&h, rows2[0]) == 2 && griddem_history_count(&h, rows2[1]) == 0, "no other copies");
  CHECK(griddem_history_mirror(&h, 3, rows2, tags, 4, types, 1, parity) == 0 && griddem_history_count(&h, rows2[2]) == 1,
        "mirroring again changes nothing");
  /* the next sweep evaluates the contact from particle 0's side, and particle 0's contact with
     the ghost has ended: the partner's copy and that contact, not written, are dropped */
  CHECK(griddem_history_begin(&h, 1) == 0, "begin after mirroring");
  failed |= griddem_history_write(&h, &h.overflow[0], h.values, 0, rows2[0], griddem_history_find_entry(&h, rows2[0], 11),
                                  11, 1, v, 1);
  CHECK(!failed && griddem_history_end(&h, 3, order, 3, rows2) == 0 && griddem_history_count(&h, rows2[0]) == 1 &&
            griddem_history_count(&h, rows2[2]) == 0,
        "the copy not written dropped: rows of %d and %d contacts", griddem_history_count(&h, rows2[0]),
        griddem_history_count(&h, rows2[2]));

  /* rows mostly holes are laid out afresh in slot order: row of slot s is s, particles left out
     of the slots have none */
  griddem_history big_pool;
  griddem_history_init(&big_pool, 3);
  enum { NP = 600 };
  static int rows3[NP], order3[NP / 2];
  double seven[7 * 4] = {0.0}, one[3] = {1, 2, 3};
  for (int e = 0; e < 7; e++) seven[4 * e] = 3 + e;
  for (int i = 0; i < NP; i++) rows3[i] = griddem_history_add_row(&big_pool, 7, seven, 3);
  for (int s = 0; s < NP / 2; s++) order3[s] = NP - 1 - 2 * s; /* the odd particles, backwards */
  CHECK(griddem_history_begin(&big_pool, 1) == 0, "begin over %d rows", NP);
  for (int s = 0; s < NP / 2; s += 10) {
    const int i = order3[s];
    griddem_history_write(&big_pool, &big_pool.overflow[0], 3, i, rows3[i], griddem_history_find_entry(&big_pool, rows3[i], 3), 3, -1, one, 1);
  }
  CHECK(griddem_history_end(&big_pool, NP / 2, order3, NP, rows3) == 0 && big_pool.cur.nrows == NP / 2, "laid out afresh: %d rows",
        big_pool.cur.nrows);
  int laid = 1;
  for (int s = 0; s < NP / 2; s++) laid &= rows3[order3[s]] == s && griddem_history_count(&big_pool, s) == (s % 10 == 0);
  for (int i = 0; i < NP; i += 2) laid &= rows3[i] == -1;
  CHECK(laid && big_pool.entries == NP / 20, "rows by slot, contacts kept (%ld)", big_pool.entries);
  griddem_history_free(&big_pool);

  /* rows of particles gone without contacts (fix griddem/rom's store takes most of a bed out at
     once: no room, so the holes rule does not see them) are laid out afresh once they outnumber
     twice the slots, so that the pass over the rows at each sweep's end does not walk them */
  griddem_history gone;
  griddem_history_init(&gone, 3);
  enum { NGONE = 3000, NLEFT = 10 };
  static int rows4[NGONE], order4[NLEFT];
  for (int i = 0; i < NGONE; i++) rows4[i] = griddem_history_add_row(&gone, 0, NULL, 3);
  for (int s = 0; s < NLEFT; s++) order4[s] = s;
  CHECK(griddem_history_begin(&gone, 1) == 0, "begin over %d rows without contacts", NGONE);
  CHECK(griddem_history_end(&gone, NLEFT, order4, NLEFT, rows4) == 0 && gone.cur.nrows == NLEFT &&
            rows4[NLEFT - 1] == NLEFT - 1,
        "rows of particles gone laid out afresh: %d rows for %d slots", gone.cur.nrows, NLEFT);
  griddem_history_free(&gone);
  CHECK(griddem_history_memory(&h) > 0.0, "memory reported");
  griddem_history_free(&h);
  return check_summary();
}
