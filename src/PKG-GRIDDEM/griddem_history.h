/* GRIDDEM contact history: per particle, the partners it touched last step (their tags, as exact
 * integers) and the history values of each contact (tangential and rolling displacements). A pool
 * holds the entries; a row is a start, a count and a room in it. How an entry is found and
 * written, and the row message that carries a row between processes and into restart files, are
 * shared with the Kokkos store (fix griddem/kk), whose pools live on the device.
 *
 * The CPU store is updated in place, as a neighbor list's history is: the sweep finds a contact in
 * the row of the particle it is evaluated from, and writes it back where it was read, so a contact
 * that lasts costs no copy. A contact of two owned particles is kept in that one row (the other
 * row's copy is read only where the contact was last evaluated from its other side); every other
 * reader (exchange, restart files, single()) first mirrors such contacts into the partner's row,
 * as fix neigh/history fills both partners' arrays before atoms migrate. A new contact goes into
 * its row's spare room, or into its thread's overflow list; the end of the sweep drops the
 * entries no contact wrote this step, moves each row that overflowed to the pool's end with room
 * to grow, and lays every row out afresh in slot order once as much room has moved as there are
 * contacts, or holes fill half the pool. */
#ifndef GRIDDEM_HISTORY_H
#define GRIDDEM_HISTORY_H

#include "griddem_portable.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Entries: partner tags and values per contact, and rows as (start, count, room) into them. */
typedef struct griddem_history_pool {
  int nrows;
  long used;          /* entries up to the end of the last row's room */
  long *start;        /* [nrows]: first entry of each row */
  int *count;         /* [nrows]: entries of each row */
  int *room;          /* [nrows]: entries a row holds before it moves */
  int *written;       /* [nrows]: entries the sweep under way wrote (0 between sweeps) */
  int64_t *partner;   /* [entries]: partner tag */
  int *owned_partner; /* [entries]: the partner's index where the sweep saw it owned, else -1 */
  double *value;      /* [entries * values] */
  long rows_cap, entries_cap;
} griddem_history_pool;

/* One thread's contacts that did not fit their row's room: (particle, partner, owned partner,
 * values) each. */
typedef struct griddem_history_overflow {
  long n, cap;
  int *particle;
  int64_t *partner;
  int *owned_partner;
  double *value;
} griddem_history_overflow;

typedef struct griddem_history {
  int values;     /* history values per contact */
  int max_count;  /* most entries in one row (sizes exchange messages) */
  long entries;   /* entries in all rows (after a sweep, a contact of two owned particles in one) */
  griddem_history_pool cur;   /* the history */
  griddem_history_pool spare; /* where a fresh layout of the rows is written */
  griddem_history_overflow *overflow;
  int noverflow;
  int one_sided;  /* a sweep has left contacts of owned pairs in one row (griddem_history_mirror) */
  int64_t mark;   /* GRIDDEM_HISTORY_MARK or 0: what every entry holds, and the sweep under way sets */
  long moved;     /* room given to rows moved since the rows were last laid out in slot order */
} griddem_history;

/* Contacts keyed by partner and periodic image. Where a periodic box is narrower than twice the
 * largest contact distance along some axes (its image axes), a sphere can touch two images of one
 * partner, or images of itself; each such contact keeps its own history under a key that holds,
 * above the partner tag, the partner's periodic image relative to the particle's, per image axis
 * modulo 2^GRIDDEM_IMAGE_BITS. A particle's image m (per axis: its shift from its owner's position
 * minus its owner's LAMMPS image flag, so m = -image for an owned particle and each ghost adds its
 * periodic shift) makes the pair's relative image m_partner - m_self, which does not change while
 * the contact lasts (wraps across the boundary change shift and flag together), migrates and
 * goes into restart files with the row. Images of one partner that touch one sphere at once differ
 * by less than 2 contact distance / width per axis: told apart while an axis is at least 1/8 of
 * the contact distance wide (GRIDDEM_IMAGE_MIN_WIDTH). Along other axes, and in boxes without image
 * axes, the image is 0 and a key is the partner tag. Keys stay below 2^53 (exact in row messages)
 * for tags below 2^GRIDDEM_KEY_TAG_BITS. */
#define GRIDDEM_IMAGE_BITS 4
#define GRIDDEM_IMAGE_MASK ((1 << GRIDDEM_IMAGE_BITS) - 1)
#define GRIDDEM_IMAGE_MIN_WIDTH(contact) (2.0 * (contact) / (1 << GRIDDEM_IMAGE_BITS))
#define GRIDDEM_KEY_TAG_BITS (53 - 3 * GRIDDEM_IMAGE_BITS)

/* A particle's image m (3 integers) packed, its components along the image axes (bit d of axes:
 * axis d) modulo 2^GRIDDEM_IMAGE_BITS, the others 0. */
GRIDDEM_INLINE int griddem_image_code(const int *m, int axes)
{
  int code = 0;
  for (int d = 0; d < 3; d++)
    if (axes >> d & 1) code |= (m[d] & GRIDDEM_IMAGE_MASK) << (GRIDDEM_IMAGE_BITS * d);
  return code;
}

/* The code of an image shifted by shift (3 integers: the periodic shift of a ghost made from it). */
GRIDDEM_INLINE int griddem_image_shifted(int code, const int *shift, int axes)
{
  int m[3];
  for (int d = 0; d < 3; d++) m[d] = (code >> (GRIDDEM_IMAGE_BITS * d)) + shift[d];
  return griddem_image_code(m, axes);
}

/* The key of a contact with partner tag seen from a particle of image code self, the partner's
 * being code partner: the tag, and above it the relative image (0 for the same images). */
GRIDDEM_INLINE int64_t griddem_image_key(int64_t tag, int self, int partner)
{
  int relative = 0;
  for (int d = 0; d < 3; d++) {
    const int shift = GRIDDEM_IMAGE_BITS * d;
    relative |= (((partner >> shift) - (self >> shift)) & GRIDDEM_IMAGE_MASK) << shift;
  }
  return tag | (int64_t) relative << GRIDDEM_KEY_TAG_BITS;
}

/* A key's partner tag, and the key with its partner tag replaced (the relative image above it kept) */
GRIDDEM_INLINE int64_t griddem_key_tag(int64_t key)
{
  return key & (((int64_t) 1 << GRIDDEM_KEY_TAG_BITS) - 1);
}

GRIDDEM_INLINE int64_t griddem_key_retagged(int64_t key, int64_t tag)
{
  return key - griddem_key_tag(key) + tag;
}

/* A bit above a key that the CPU store turns over at each sweep and sets as it writes an entry
 * (griddem_history.mark), so that the end of a sweep tells the entries it wrote from those it did
 * not; keys are found, and travel in messages, without it. */
#define GRIDDEM_HISTORY_MARK ((int64_t) 1 << 62)

/* Room a layout gives a row beyond its contacts: new contacts before the row moves. */
#define GRIDDEM_HISTORY_MARGIN 2

/* The entry of partner tag in a row (count entries from first) of a pool's partner tags, or -1:
 * the one history find of the CPU sweep, single() and the Kokkos kernels. */
GRIDDEM_INLINE long griddem_history_entry(const int64_t *partner, long first, int count, int64_t tag)
{
  for (long e = first; e < first + count; e++)
    if ((partner[e] & ~GRIDDEM_HISTORY_MARK) == tag) return e;
  return -1;
}

/* Write entry e of a pool: the partner tag and its values (values per contact), read stride
 * doubles apart at v (a batch's lanes), or next to each other. */
GRIDDEM_INLINE void griddem_history_put_strided(int64_t *partner, double *value, int values, long e, int64_t tag,
                                                const double *v, int stride)
{
  partner[e] = tag;
  for (int k = 0; k < values; k++) value[(size_t) values * e + k] = v[k * stride];
}

GRIDDEM_INLINE void griddem_history_put(int64_t *partner, double *value, int values, long e, int64_t tag,
                                        const double *v)
{
  griddem_history_put_strided(partner, value, values, e, tag, v, 1);
}

/* Entry e of a pool as a message entry (GRIDDEM_HISTORY_ENTRY(values) doubles at m, below): the
 * partner tag, then its values; the reverse of griddem_history_put from m + 1. */
GRIDDEM_INLINE void griddem_history_get(const int64_t *partner, const double *value, int values, long e,
                                        double *m)
{
  m[0] = (double) (partner[e] & ~GRIDDEM_HISTORY_MARK);
  for (int k = 0; k < values; k++) m[1 + k] = value[(size_t) values * e + k];
}

/* A row as a message (how rows travel with their atoms and into restart files): the count, then
 * per entry the partner tag (exact as a double below 2^53) and its values. */
#define GRIDDEM_HISTORY_ENTRY(values) (1 + (values))
#define GRIDDEM_ROW_MESSAGE_LENGTH(count, values) (1 + (count) * GRIDDEM_HISTORY_ENTRY(values))

/* fix griddem's per-atom restart record: its length in doubles (counting itself: LAMMPS's
 * readers of per-atom restart data step over a record by it), the history values per contact,
 * then the row message. The CPU and Kokkos stores write and read this one format. */
#define GRIDDEM_RESTART_HEADER 2

/* Frame a row message of message_length doubles written at record + GRIDDEM_RESTART_HEADER;
 * returns the record's length. */
GRIDDEM_INLINE int griddem_restart_frame(double *record, int values, int message_length)
{
  record[0] = GRIDDEM_RESTART_HEADER + message_length;
  record[1] = values;
  return GRIDDEM_RESTART_HEADER + message_length;
}

/* The nth of an atom's per-atom restart records (each led by its length). */
GRIDDEM_INLINE const double *griddem_restart_record(const double *records, int nth)
{
  int m = 0;
  for (int k = 0; k < nth; k++) m += (int) records[m];
  return records + m;
}

/* A record's history values per contact, and its row message. */
GRIDDEM_INLINE int griddem_restart_values(const double *record)
{
  return (int) record[1];
}
GRIDDEM_INLINE const double *griddem_restart_message(const double *record)
{
  return record + GRIDDEM_RESTART_HEADER;
}

/* What one step of the CPU engine reads and rewrites of a store: the history and each particle's
 * row in it (-1: none). */
typedef struct griddem_history_rows {
  griddem_history *hist;
  int *row_of;
} griddem_history_rows;

void griddem_history_init(griddem_history *h, int values);
void griddem_history_free(griddem_history *h);

/* Contacts in row (0 for a row that does not exist, such as -1). */
int griddem_history_count(const griddem_history *h, int row);

/* The entry of row's contact with partner, or -1 if the row (-1: none) has none; the values of
 * that entry, or NULL (inline: the CPU sweep finds once per contact and side). */
static inline long griddem_history_find_entry(const griddem_history *h, int row, int64_t partner)
{
  if (row < 0 || row >= h->cur.nrows) return -1;
  return griddem_history_entry(h->cur.partner, h->cur.start[row], h->cur.count[row], partner);
}

static inline const double *griddem_history_find(const griddem_history *h, int row, int64_t partner)
{
  const long e = griddem_history_find_entry(h, row, partner);
  return e < 0 ? NULL : h->cur.value + (size_t) h->values * e;
}

/* Write row's entries as a message (GRIDDEM_HISTORY_ENTRY(values) doubles each). */
void griddem_history_get_row(const griddem_history *h, int row, double *entries);

/* Append a row of count message entries written with entry_values values each (converted to
 * h->values: values kept up to the shorter length, the rest zero). Returns its index, or -1
 * without memory. */
int griddem_history_add_row(griddem_history *h, int count, const double *entries, int entry_values);

/* Rows as whole messages: the doubles of row's message, of the longest row's; write row's
 * message (returns its length); append a row from a message written with `values` values per
 * contact (its index, or -1 without memory). */
int griddem_history_message_length(const griddem_history *h, int row);
int griddem_history_longest_message(const griddem_history *h);
int griddem_history_get_message(const griddem_history *h, int row, double *message);
int griddem_history_put_message(griddem_history *h, const double *message, int values);
/* A row's own atom's ID, carried in its message as an entry of key GRIDDEM_OWN_KEY (no atom has
 * ID 0) whose first value is the ID, so that the IDs its other keys name partners by can be told
 * from its atoms' IDs after they are given new ones (delete_atoms compress yes, reset_atoms id).
 * fix griddem writes it at a run's end and into restart files, and finds it as the entry of that
 * key; a sweep, which finds no partner of that key, drops it as it rewrites the row. Needs a
 * history of at least one value. */
#define GRIDDEM_OWN_KEY 0

/* The message with its own atom's ID set to tag: its own entry rewritten, or one appended (the
 * message then needs room for GRIDDEM_HISTORY_ENTRY(values) doubles more). Returns its length. */
int griddem_message_with_own_tag(double *message, int values, int64_t tag);

/* The partners' tags of a row message's entries (its own entry left out) into tags (room for
 * the message's count), in order. Returns how many. */
int griddem_message_partners(const double *message, int values, int64_t *tags);

/* A row message (values per contact) after its atoms were given new IDs: the n pairs
 * old_tag[k] -> new_tag[k], sorted by old tag, hold every partner that remains under the ID the
 * message's keys name it by; each key takes its partner's new tag (the relative image kept), an
 * entry whose partner the pairs lack (deleted since) is dropped, and the own entry is kept as it
 * is; all in order. Returns the message's length. */
int griddem_message_renumber(double *message, int values, const int64_t *old_tag, const int64_t *new_tag, long n);

/* The sum of n counts (entries of rows, contacts of slots) and the most of one, in vector lanes,
 * on threads where there are many */
long griddem_history_counts(const int *count, int n, int *most);

/* Make room for rows holding entries contacts in all, now and after the next sweep. 0, or -1. */
int griddem_history_reserve(griddem_history *h, int rows, long entries);

/* Bytes allocated. */
double griddem_history_memory(const griddem_history *h);

/* Change the values per contact of every row (a model with other sub-models). 0, or -1. */
int griddem_history_set_values(griddem_history *h, int values);

/* For the sweep: make nthreads overflow lists empty and turn the mark over (0, or -1 without
 * memory); write one contact of a particle (below); then keep what was written: rows lose the
 * entries no write reached, overflowed contacts join their rows (a particle without one gets one,
 * in row_of), and where rows have moved or left holes enough (above) the rows are laid out
 * afresh, the row of slot s (owned particle order[s], s < nslot) being s and other owned
 * particles' (below nlocal) none (0, or -1 without memory). */
int griddem_history_begin(griddem_history *h, int nthreads);
int griddem_history_end(griddem_history *h, int nslot, const int *order, int nlocal, int *row_of);

/* An entry beyond its row's room (its values stride doubles apart at v), kept in the thread's
 * overflow list. 0, or -1 without memory. */
int griddem_history_overflow_append(griddem_history_overflow *o, int values, int particle, int64_t partner,
                                    int owned_partner, const double *v, int stride);

/* The next entry of row (-1: none) of pool p, counted in it, or -1 where its room is full */
static inline long griddem_history_append(griddem_history_pool *p, int row)
{
  return row < 0 || p->count[row] == p->room[row] ? -1 : p->start[row] + p->count[row]++;
}

/* The sweep's write of particle's contact with partner (values v; owned_partner: the partner's
 * index if it is owned, else -1): at entry e where the step's find found it in the particle's
 * row, else appended to that row (row_of[particle], -1: none) or to the thread's overflow list.
 * values is h->values, passed so that a sweep compiled for one history size copies a constant
 * count; v's values lie stride doubles apart. 0, or -1 without memory. */
static inline int griddem_history_write(griddem_history *h, griddem_history_overflow *overflow, int values,
                                        int particle, int row, long e, int64_t partner, int owned_partner,
                                        const double *v, int stride)
{
  griddem_history_pool *p = &h->cur;
  if (GRIDDEM_RARELY(e < 0 && (e = griddem_history_append(p, row)) < 0))
    return griddem_history_overflow_append(overflow, values, particle, partner, owned_partner, v, stride);
  p->written[row]++;
  griddem_history_put_strided(p->partner, p->value, values, e, partner | h->mark, v, stride);
  p->owned_partner[e] = owned_partner;
  return 0;
}

/* The key of a contact seen from its partner: tag (the particle's own), the relative image
 * negated along each axis. */
GRIDDEM_INLINE int64_t griddem_image_key_mirrored(int64_t key, int64_t tag)
{
  const int relative = (int) (key >> GRIDDEM_KEY_TAG_BITS);
  int mirrored = 0;
  for (int d = 0; d < 3; d++) {
    const int shift = GRIDDEM_IMAGE_BITS * d;
    mirrored |= (-(relative >> shift) & GRIDDEM_IMAGE_MASK) << shift;
  }
  return tag | (int64_t) mirrored << GRIDDEM_KEY_TAG_BITS;
}

/* Give each contact the last sweep kept in one owned particle's row its copy in the partner's
 * row, seen from the partner: values times parity[(ntypes + 1) type_i + type_j][v] (every
 * GRIDDEM_MAX_HISTORY doubles a type pair; type: per particle), the key mirrored (tag: the
 * particles' tags, tag_bytes wide). The partner is the particle whose index the sweep recorded,
 * or where that index no longer holds its tag (a particle since moved), the owned particle
 * with the tag, if any. Particles without a row get one (row_of). A no-op unless the store is
 * one-sided. 0, or -1 without memory. */
int griddem_history_mirror(griddem_history *h, int nlocal, int *row_of, const void *tag, int tag_bytes,
                           const int *type, int ntypes, const double *parity);

#ifdef __cplusplus
}
#endif

#endif
