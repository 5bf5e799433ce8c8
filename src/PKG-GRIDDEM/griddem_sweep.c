/* CPU stencil sweep; see griddem_sweep.h. */
#define _POSIX_C_SOURCE 200112L /* posix_memalign */
#include "griddem_sweep.h"

#include "griddem_classic_batch.h"
#include "griddem_search.h"
#include "griddem_threads.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Cache-line aligned array of count elements of size bytes (contents not kept). */
static int grow_aligned(void **ptr, size_t size, int count)
{
  free(*ptr);
  *ptr = NULL;
  return posix_memalign(ptr, 64, size * (size_t) count) == 0 ? 0 : -1;
}

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#define GRIDDEM_SWEEP_GATHER 1
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

/* Slot s of the channels: particle i's centre, radius, key and image */
static inline void fill_slot(griddem_channels *ch, int i, const griddem_particles *p, int s)
{
  ch->x[s] = p->x[3 * (size_t) i];
  ch->y[s] = p->x[3 * (size_t) i + 1];
  ch->z[s] = p->x[3 * (size_t) i + 2];
  ch->r[s] = p->radius[i];
  ch->xf[s] = (float) ch->x[s], ch->yf[s] = (float) ch->y[s], ch->zf[s] = (float) ch->z[s], ch->rf[s] = (float) ch->r[s];
  ch->tag[s] = griddem_key_at(p->tag, p->tag_bytes, i);
  if (p->image) ch->image[s] = p->image[i];
  ch->ncontact[s] = 0;
}

/* What a fill learns of its slots: the smallest and largest radius */
typedef struct fill_range {
  double rmin, rmax;
} fill_range;

static fill_range range_of(const griddem_channels *ch, int s0, int s1)
{
  fill_range m = {INFINITY, 0.0};
  for (int s = s0; s < s1; s++)
    m.rmin = ch->r[s] < m.rmin ? ch->r[s] : m.rmin, m.rmax = ch->r[s] > m.rmax ? ch->r[s] : m.rmax;
  return m;
}

/* Slots s0 .. s1 - 1 of the channels, of particles order[s]: one at a time, and four at a time by
 * AVX2's gathers (the same values); returns their range */
static fill_range fill_plain(griddem_channels *ch, const int *order, const griddem_particles *p, int s0, int s1)
{
  for (int s = s0; s < s1; s++) fill_slot(ch, order[s], p, s);
  return range_of(ch, s0, s1);
}

#ifdef GRIDDEM_SWEEP_GATHER
/* Indices of particles widened to 64 bits and times three: where their three doubles start */
__attribute__((target("avx2"), always_inline)) static inline __m256i first_of_three(__m128i i)
{
  const __m256i wide = _mm256_cvtepi32_epi64(i);
  return _mm256_add_epi64(wide, _mm256_add_epi64(wide, wide));
}

__attribute__((target("avx2"))) static fill_range fill_avx2(griddem_channels *ch, const int *order,
                                                            const griddem_particles *p, int s0, int s1)
{
  int s = s0;
  __m256d rmin = _mm256_set1_pd(INFINITY), rmax = _mm256_setzero_pd();
  for (; s + 4 <= s1; s += 4) {
    const __m128i i4 = _mm_loadu_si128((const __m128i *) (order + s));
    const __m256i i3 = first_of_three(i4);
    const __m256d x = _mm256_i64gather_pd(p->x, i3, 8), y = _mm256_i64gather_pd(p->x + 1, i3, 8),
                  z = _mm256_i64gather_pd(p->x + 2, i3, 8), r = _mm256_i32gather_pd(p->radius, i4, 8);
    _mm256_storeu_pd(ch->x + s, x), _mm256_storeu_pd(ch->y + s, y), _mm256_storeu_pd(ch->z + s, z);
    _mm256_storeu_pd(ch->r + s, r);
    _mm_storeu_ps(ch->xf + s, _mm256_cvtpd_ps(x)), _mm_storeu_ps(ch->yf + s, _mm256_cvtpd_ps(y));
    _mm_storeu_ps(ch->zf + s, _mm256_cvtpd_ps(z)), _mm_storeu_ps(ch->rf + s, _mm256_cvtpd_ps(r));
    rmin = _mm256_min_pd(rmin, r), rmax = _mm256_max_pd(rmax, r);
    const __m256i tag = p->tag_bytes == 8 ? _mm256_i32gather_epi64((const long long *) p->tag, i4, 8)
                                          : _mm256_cvtepi32_epi64(_mm_i32gather_epi32((const int *) p->tag, i4, 4));
    _mm256_storeu_si256((__m256i *) (ch->tag + s), tag);
    if (p->image) _mm_storeu_si128((__m128i *) (ch->image + s), _mm_i32gather_epi32(p->image, i4, 4));
    _mm_storeu_si128((__m128i *) (ch->ncontact + s), _mm_setzero_si128());
  }
  fill_range m = fill_plain(ch, order, p, s, s1);
  double lane[2][4];
  _mm256_storeu_pd(lane[0], rmin), _mm256_storeu_pd(lane[1], rmax);
  for (int k = 0; k < 4; k++)
    m.rmin = lane[0][k] < m.rmin ? lane[0][k] : m.rmin, m.rmax = lane[1][k] > m.rmax ? lane[1][k] : m.rmax;
  return m;
}
#endif

int griddem_channels_fill(griddem_channels *ch, const griddem_bins *b, const griddem_particles *p)
{
  const int n = b->n;
  if (n > ch->cap || !ch->xf) {    /* room for the float copies' padding even where n is 0 */
    const int cap = n + n / 4 + 16;
    if (grow_aligned((void **) &ch->x, sizeof(double), cap) != 0 ||
        grow_aligned((void **) &ch->y, sizeof(double), cap) != 0 ||
        grow_aligned((void **) &ch->z, sizeof(double), cap) != 0 ||
        grow_aligned((void **) &ch->r, sizeof(double), cap) != 0 ||
        grow_aligned((void **) &ch->xf, sizeof(float), cap + GRIDDEM_SEARCH_PAD) != 0 ||
        grow_aligned((void **) &ch->yf, sizeof(float), cap + GRIDDEM_SEARCH_PAD) != 0 ||
        grow_aligned((void **) &ch->zf, sizeof(float), cap + GRIDDEM_SEARCH_PAD) != 0 ||
        grow_aligned((void **) &ch->rf, sizeof(float), cap + GRIDDEM_SEARCH_PAD) != 0 ||
        grow_aligned((void **) &ch->tag, sizeof(int64_t), cap) != 0 ||
        grow_aligned((void **) &ch->ncontact, sizeof(int), cap) != 0)
      return -1;
    ch->cap = cap;
  }
  /* the images only in boxes that have image axes */
  if (p->image && ch->cap > ch->image_cap) {
    if (grow_aligned((void **) &ch->image, sizeof(int), ch->cap) != 0) return ch->image_cap = 0, -1;
    ch->image_cap = ch->cap;
  }
  ch->n = n;
  ch->p = p;
  ch->keyed_by_image = p->image != NULL;
  fill_range (*fill)(griddem_channels *, const int *, const griddem_particles *, int, int) = fill_plain;
#ifdef GRIDDEM_SWEEP_GATHER
  if (griddem_vector_reads()) fill = fill_avx2;
#endif
  double rmin = INFINITY, rmax = 0.0;
  if (griddem_threaded(n)) {
    enum { BLOCK = 4096 };    /* slots a thread fills at once */
    const int nblock = (n + BLOCK - 1) / BLOCK;
#pragma omp parallel for schedule(static) reduction(max : rmax) reduction(min : rmin)
    for (int k = 0; k < nblock; k++) {
      const fill_range m = fill(ch, b->order, p, k * BLOCK, k == nblock - 1 ? n : (k + 1) * BLOCK);
      rmin = m.rmin < rmin ? m.rmin : rmin, rmax = m.rmax > rmax ? m.rmax : rmax;
    }
  } else {
    const fill_range m = fill(ch, b->order, p, 0, n);
    rmin = m.rmin, rmax = m.rmax;
  }
  ch->same_radius = n > 0 && rmin == rmax;
  for (int s = n; s < n + GRIDDEM_SEARCH_PAD; s++) ch->xf[s] = ch->yf[s] = ch->zf[s] = ch->rf[s] = 0.0f;
  return 0;
}

void griddem_channels_free(griddem_channels *ch)
{
  free(ch->x), free(ch->y), free(ch->z), free(ch->r), free(ch->tag), free(ch->image), free(ch->ncontact);
  free(ch->xf), free(ch->yf), free(ch->zf), free(ch->rf);
  free(ch->slab), free(ch->slots), free(ch->first);
  memset(ch, 0, sizeof(*ch));
}

static void record_fault(griddem_sweep_result *r, int fault, int i, int j)
{
#pragma omp critical(griddem_fault)
  if (r->fault == GRIDDEM_FAULT_NONE) {
    r->fault = fault;
    r->fault_i = i;
    r->fault_j = j;
  }
}

/* The history key of slot to's particle seen from slot from's: its tag, with the relative image
 * where the box has image axes */
static inline int64_t contact_key(const griddem_channels *ch, int from, int to)
{
  return ch->keyed_by_image ? griddem_image_key(ch->tag[to], ch->image[from], ch->image[to]) : ch->tag[to];
}

/* The laws a sweep's pair body is compiled for. Where every type pair's law is one of the gran
 * styles' own arithmetic (classic: gran/hooke, gran/hooke/history, gran/hertz/history), the body
 * calls it directly, with the normal model and the history size of those styles as constants;
 * where it is one and the same law with shear history for every type pair and the history
 * advances (a step of a run), the contacts are gathered into batches that evaluate the law as
 * vector lanes (griddem_classic_batch.h). Where every type pair's law is composed of the
 * sub-models of one row of COMPILED_LAWS, the body evaluates them with the models and the history
 * size as constants. Every other model (and a mix of laws across type pairs) takes the composed
 * law with its models read at run time, the reference the tests compare the others with. */
enum sweep_law {
  SWEEP_COMPOSED,
  SWEEP_CLASSIC_BATCH,      /* gran/hooke/history or gran/hertz/history, one law, in batches */
  SWEEP_HOOKE_SHEAR,        /* gran/hooke/history: 3 shear values per contact */
  SWEEP_HOOKE_NO_HISTORY,   /* gran/hooke (or no friction): no history, no contacts kept */
  SWEEP_HERTZ_SHEAR,        /* gran/hertz/history */
  SWEEP_HERTZ_NO_HISTORY,   /* gran/hertz/history without friction */
  SWEEP_COMPILED            /* + k: the models of COMPILED_LAWS[k] */
};

/* The composed laws of the examples' and bench's scenes: the sub-models of each axis, and the
 * history values per contact they keep (0: no contacts kept). The coefficients may differ by
 * type pair. */
typedef struct compiled_law {
  griddem_law_models models;
  int values;
} compiled_law;

static const compiled_law COMPILED_LAWS[] = {
    /* examples/rom-blade and rom-hopper */
    {{GRIDDEM_NORMAL_HOOKE, GRIDDEM_DAMPING_COEFF_RESTITUTION, GRIDDEM_TANGENTIAL_LINEAR_HISTORY, GRIDDEM_ROLLING_SDS,
      GRIDDEM_TWISTING_NONE, GRIDDEM_HEAT_NONE},
     6},
    /* examples/hopper, packing, sliding and free-fall */
    {{GRIDDEM_NORMAL_HOOKE, GRIDDEM_DAMPING_VELOCITY, GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY, GRIDDEM_ROLLING_NONE,
      GRIDDEM_TWISTING_NONE, GRIDDEM_HEAT_NONE},
     0},
    /* examples/heat-bed */
    {{GRIDDEM_NORMAL_HERTZ, GRIDDEM_DAMPING_VISCOELASTIC, GRIDDEM_TANGENTIAL_LINEAR_NOHISTORY, GRIDDEM_ROLLING_NONE,
      GRIDDEM_TWISTING_NONE, GRIDDEM_HEAT_RADIUS},
     0}};
#define NCOMPILED ((int) (sizeof COMPILED_LAWS / sizeof COMPILED_LAWS[0]))

/* The pair body's law argument: the composed law with its models read at run time, a classic
 * law (CLASSIC_BATCHED: the one law of SWEEP_CLASSIC_BATCH, evaluated in batches), or
 * COMPILED + k: COMPILED_LAWS[k]'s */
enum { COMPOSED = 0, CLASSIC_HOOKE = 1, CLASSIC_HERTZ = 2, CLASSIC_BATCHED = 3, COMPILED = 4 };
#define IS_CLASSIC(body) ((body) >= CLASSIC_HOOKE && (body) <= CLASSIC_BATCHED)

static int same_models(griddem_law_models a, griddem_law_models b)
{
  return a.normal == b.normal && a.damping == b.damping && a.tangential == b.tangential && a.rolling == b.rolling &&
         a.twisting == b.twisting && a.heat == b.heat;
}

/* SWEEP_COMPILED + k where every type pair's law is composed of COMPILED_LAWS[k]'s models and
 * keeps its history (hist: the store's layout); otherwise SWEEP_COMPOSED */
static int compiled_law_of(const griddem_model *m, const griddem_history *hist)
{
  for (int k = 0; k < NCOMPILED; k++) {
    const compiled_law *law = COMPILED_LAWS + k;
    int all = law->values ? m->track_contacts && m->history_size == law->values && hist->values == law->values
                          : !m->track_contacts && m->history_size == 0;
    for (int i = 1; all && i <= m->ntypes; i++)
      for (int j = 1; all && j <= m->ntypes; j++) {
        const griddem_pair_params *p = griddem_model_pair(m, i, j);
        all = !p->classic && same_models(griddem_law_models_of(p), law->models);
      }
    if (all) return SWEEP_COMPILED + k;
  }
  return SWEEP_COMPOSED;
}

/* Whether two classic laws compute the same: what griddem_classic_contact reads of them */
static int same_classic_law(const griddem_pair_params *a, const griddem_pair_params *b)
{
  return a->normal.model == b->normal.model && a->normal.k == b->normal.k && a->damping.damp == b->damping.damp &&
         a->tangential.model == b->tangential.model && a->tangential.k == b->tangential.k &&
         a->tangential.gamma_mass == b->tangential.gamma_mass && a->tangential.mu == b->tangential.mu &&
         a->limit_damping == b->limit_damping;
}

static int sweep_law_of(const griddem_model *m, const griddem_history *hist, int history_update)
{
  if (m->reach_extra != 0.0) return SWEEP_COMPOSED;
  const griddem_pair_params *first = griddem_model_pair(m, 1, 1);
  if (!first->classic) return compiled_law_of(m, hist);
  const int hertz = griddem_classic_hertz(first);
  int one_law = griddem_classic_batchable(first);
  for (int i = 1; i <= m->ntypes; i++)
    for (int j = 1; j <= m->ntypes; j++) {
      const griddem_pair_params *p = griddem_model_pair(m, i, j);
      if (!p->classic || griddem_classic_hertz(p) != hertz) return SWEEP_COMPOSED;
      one_law &= same_classic_law(p, first);
    }
  if (m->track_contacts && m->history_size == 3 && hist->values == 3)
    return one_law && history_update ? SWEEP_CLASSIC_BATCH : (hertz ? SWEEP_HERTZ_SHEAR : SWEEP_HOOKE_SHEAR);
  if (!m->track_contacts && m->history_size == 0) return hertz ? SWEEP_HERTZ_NO_HISTORY : SWEEP_HOOKE_NO_HISTORY;
  return SWEEP_COMPOSED;
}

struct contact_batch;

/* Everything one sweep reads, shared by the threads. */
typedef struct sweep_context {
  const int *order;      /* particle of each slot of the channels */
  griddem_channels *ch;
  int nlocal;
  const griddem_model *model;
  int law;               /* enum sweep_law */
  const griddem_exclusions *excl;
  int both_bits, apart_bits;    /* excl's group bits, where they are all it excludes by (else 0) */
  double dt;
  int history_update;
  griddem_history *hist;
  const int *row_of;
  double *f, *torque;    /* of the particles, added into where owned */
  double *vatom;
  int tally;    /* GRIDDEM_TALLY_* */
  griddem_sweep_result *result;
  griddem_spheres spheres;        /* the channels' centres and radii, and their float copies */
  griddem_touching_fn touching;   /* the candidate test */
  int cluster;                    /* its width */
  void (*gather)(const struct sweep_context *, struct contact_batch *);    /* a batch's inputs */
} sweep_context;

/* A thread's contacts waiting for SWEEP_CLASSIC_BATCH's law: the slots of each pair (a owned)
 * and their particles, as the pairs were found, and the particles' types and group bits, one
 * array each (read and written four at a time: a batch holds whole vectors of four), then per
 * contact what is kept for its end (kept: neither coincident nor excluded) and the law's lanes */
typedef char batch_of_whole_vectors[GRIDDEM_CLASSIC_BATCH % 4 == 0 ? 1 : -1];
typedef struct contact_batch {
  int a[GRIDDEM_CLASSIC_BATCH], b[GRIDDEM_CLASSIC_BATCH], ia[GRIDDEM_CLASSIC_BATCH], ib[GRIDDEM_CLASSIC_BATCH];
  int type_a[GRIDDEM_CLASSIC_BATCH], type_b[GRIDDEM_CLASSIC_BATCH];
  int ma[GRIDDEM_CLASSIC_BATCH], mb[GRIDDEM_CLASSIC_BATCH];
  int excluded[GRIDDEM_CLASSIC_BATCH];    /* by the sweep's group-bit exclusions (excluded_bits) */
  int64_t key_b[GRIDDEM_CLASSIC_BATCH], key_a[GRIDDEM_CLASSIC_BATCH];    /* b seen from a, a from b */
  long entry_a[GRIDDEM_CLASSIC_BATCH], entry_b[GRIDDEM_CLASSIC_BATCH];  /* their history entries */
  int kept[GRIDDEM_CLASSIC_BATCH];
  griddem_classic_batch lanes;
} contact_batch;

/* Accumulators one thread adds up over its pairs, and its batch (SWEEP_CLASSIC_BATCH) */
typedef struct sweep_sums {
  double virial[6];
  double energy;
  griddem_history_overflow *overflow;
  contact_batch *batch;
} sweep_sums;

/* A body the compiler copies into each caller, specialized for the constant arguments it gets */
#ifdef __GNUC__
#define SWEEP_SPECIALIZED static inline __attribute__((always_inline))
#else
#define SWEEP_SPECIALIZED static inline
#endif

/* The classic law out of line once per normal model, with hertz a constant in each copy */
#ifdef __GNUC__
#define CLASSIC_LAW static __attribute__((noinline, flatten))
#else
#define CLASSIC_LAW static
#endif
CLASSIC_LAW double classic_hooke(const griddem_pair_params *p, griddem_contact *c, double *hist, double *f, double *ti,
                                 double *tj)
{
  return griddem_classic_eval(p, c, hist, f, ti, tj, 0);
}

CLASSIC_LAW double classic_hertz(const griddem_pair_params *p, griddem_contact *c, double *hist, double *f, double *ti,
                                 double *tj)
{
  return griddem_classic_eval(p, c, hist, f, ti, tj, 1);
}

/* The composed law out of line once per row of COMPILED_LAWS, its models constants in each copy */
#define COMPILED_LAW_EVAL(k)                                                                                        \
  CLASSIC_LAW double compiled_law_##k(const griddem_pair_params *p, griddem_contact *c, double *hist, double *f,    \
                                      double *ti, double *tj)                                                      \
  {                                                                                                                 \
    return griddem_contact_eval_models(p, COMPILED_LAWS[k].models, c, hist, f, ti, tj);                            \
  }
COMPILED_LAW_EVAL(0)
COMPILED_LAW_EVAL(1)
COMPILED_LAW_EVAL(2)
static double (*const COMPILED_EVAL[])(const griddem_pair_params *, griddem_contact *, double *, double *, double *,
                                       double *) = {compiled_law_0, compiled_law_1, compiled_law_2};
typedef char one_evaluation_per_compiled_law[sizeof COMPILED_EVAL / sizeof COMPILED_EVAL[0] == NCOMPILED ? 1 : -1];

/* The law of body (COMPOSED or COMPILED + k), a constant of each copy of the pair body, so that
 * the table's entry is a direct call */
SWEEP_SPECIALIZED double composed_law(const int body, const griddem_pair_params *p, griddem_contact *c, double *hist,
                                      double *f, double *ti, double *tj)
{
  return body >= COMPILED ? COMPILED_EVAL[body - COMPILED](p, c, hist, f, ti, tj)
                          : griddem_contact_eval(p, c, hist, f, ti, tj);
}

/* What precedes the law of the pair of slots a (owned) and b, of particles ia and ib (of types
 * type_a and type_b, group bits ma and mb; key_b the key of b seen from a, key_a of a seen from
 * b), at squared distance rsq (within reach): the pair is left where its centres coincide (a
 * fault), it is excluded by excl (NULL: none, or tested already), or (past touching) it is out of
 * reach; otherwise its law is set (*law_of) and its history entry found (-1: none, or contacts
 * not tracked): in a's row (*entry_a), or where a's has none and b is owned, in b's, where it is
 * kept while the contact was evaluated from b (*entry_b). Returns whether the pair is kept. body
 * and track are constants of each specialization. */
SWEEP_SPECIALIZED int pair_begin(const sweep_context *cx, int a, int b, int ia, int ib, int type_a, int type_b, int ma,
                                 int mb, int64_t key_b, int64_t key_a, const griddem_exclusions *excl, double rsq,
                                 const int body, const int track, const griddem_pair_params **law_of,
                                 long *entry_a, long *entry_b)
{
  const griddem_channels *ch = cx->ch;
  const griddem_model *m = cx->model;
  if (GRIDDEM_RARELY(rsq == 0.0)) {
    record_fault(cx->result, GRIDDEM_FAULT_COINCIDENT, ia, ib);
    return 0;
  }
  const griddem_particles *p = ch->p;
  if (excl && (griddem_excluded(excl, type_a, ma, type_b, mb) ||
               (excl->nmolecule && griddem_excluded_molecules(excl, griddem_key_at(p->molecule, p->tag_bytes, ia), ma,
                                                              griddem_key_at(p->molecule, p->tag_bytes, ib), mb))))
    return 0;
  /* the batches' pairs all have the one law */
  const griddem_pair_params *law = body == CLASSIC_BATCHED ? griddem_model_pair(m, 1, 1) : griddem_model_pair(m, type_a, type_b);
  *entry_a = track ? griddem_history_find_entry(cx->hist, cx->row_of[ia], key_b) : -1;
  *entry_b = track && *entry_a < 0 && ib < cx->nlocal ? griddem_history_find_entry(cx->hist, cx->row_of[ib], key_a) : -1;
  /* past touching (reach_extra > 0) only pairs that touched before may still interact */
  if (!IS_CLASSIC(body) && m->reach_extra > 0.0 &&
      !griddem_contact_touch(law, rsq, ch->r[a], ch->r[b], *entry_a >= 0 || *entry_b >= 0))
    return 0;
  *law_of = law;
  return 1;
}

/* The nv history values a pair_begin found (a's entry, or b's seen from a; none: 0) into hv, apart
 * doubles apart (a constant: 1, or a batch's lanes) */
SWEEP_SPECIALIZED void stored_values(const sweep_context *cx, const griddem_pair_params *law, long entry_a,
                                     long entry_b, const int nv, double *hv, const int apart)
{
  const int stride = cx->hist ? cx->hist->values : 0;
  const double *value = cx->hist ? cx->hist->cur.value : NULL;
  for (int v = 0; v < GRIDDEM_MAX_HISTORY && v < nv; v++)
    hv[v * apart] = entry_a >= 0   ? value[(size_t) stride * entry_a + v]
                    : entry_b >= 0 ? law->parity[v] * value[(size_t) stride * entry_b + v]
                                   : 0.0;
}

/* v += w and v -= w for three doubles w[0], w[stride], w[2 stride] (stride: a constant of each
 * inlined copy, 1 or a batch's lanes), the first two in one SSE2 operation */
static inline void add3(double *v, const double *w, const int stride)
{
#ifdef __SSE2__
  const __m128d first_two = stride == 1 ? _mm_loadu_pd(w) : _mm_loadh_pd(_mm_load_sd(w), w + stride);
  _mm_storeu_pd(v, _mm_add_pd(_mm_loadu_pd(v), first_two));
  v[2] += w[2 * stride];
#else
  for (int d = 0; d < 3; d++) v[d] += w[d * stride];
#endif
}

static inline void subtract3(double *v, const double *w, const int stride)
{
#ifdef __SSE2__
  const __m128d first_two = stride == 1 ? _mm_loadu_pd(w) : _mm_loadh_pd(_mm_load_sd(w), w + stride);
  _mm_storeu_pd(v, _mm_sub_pd(_mm_loadu_pd(v), first_two));
  v[2] -= w[2 * stride];
#else
  for (int d = 0; d < 3; d++) v[d] -= w[d * stride];
#endif
}

/* What follows the law (law) of the contact of slots a and b, particles ia and ib, that pair_begin
 * kept (separation dx, seen from a; key_b the key of b seen from a; entry_a its entry in a's row):
 * its history values hv (seen from a; track: contacts are kept, values of them a contact) written
 * to a's row, with b's index if b is owned (griddem_history_mirror), the contact counted for each
 * owned particle; the force fc on a (b gets -fc) and the torques ta and tb added to the owned particles,
 * the heat into a (if heat) likewise; its elastic energy (with_energy: the sweep tallies it) and
 * (virial: likewise) its virial tallied. */
SWEEP_SPECIALIZED void pair_end(const sweep_context *cx, sweep_sums *sums, int a, int b, int ia, int ib,
                                int64_t key_b, long entry_a, const double *dx,
                                const double *hv, const double *fc,
                                const double *ta, const double *tb, const int stride, double energy, const int heat,
                                double heat_into_a, const int track, const int values, const int virial,
                                const int with_energy)
{
  griddem_channels *ch = cx->ch;
  const int b_owned = ib < cx->nlocal;
  if (track) {
    if (GRIDDEM_RARELY(griddem_history_write(cx->hist, sums->overflow, values, ia, cx->row_of[ia], entry_a, key_b,
                                             b_owned ? ib : -1, hv, stride) != 0))
      record_fault(cx->result, GRIDDEM_FAULT_MEMORY, ia, ib);
  }

  add3(cx->f + 3 * (size_t) ia, fc, stride), add3(cx->torque + 3 * (size_t) ia, ta, stride);
  if (b_owned) subtract3(cx->f + 3 * (size_t) ib, fc, stride), add3(cx->torque + 3 * (size_t) ib, tb, stride);
  ch->ncontact[a]++;
  if (b_owned) ch->ncontact[b]++;
  if (heat) {
    ch->p->heatflow[ia] += heat_into_a;
    if (b_owned) ch->p->heatflow[ib] -= heat_into_a;
  }

  /* a pair shared with another process is tallied half here, half there */
  const double share = b_owned ? 1.0 : 0.5;
  if (with_energy) sums->energy += share * energy;
  if (!virial) return;
  const double x[3] = {dx[0], dx[stride], dx[2 * stride]}, y[3] = {fc[0], fc[stride], fc[2 * stride]};
  const double w[6] = {x[0] * y[0], x[1] * y[1], x[2] * y[2], x[0] * y[1], x[0] * y[2], x[1] * y[2]};
  for (int k = 0; k < 6; k++) sums->virial[k] += share * w[k];
  if (cx->vatom) {
    double *va = cx->vatom + 6 * (size_t) ia;
    for (int k = 0; k < 6; k++) va[k] += 0.5 * w[k];
    if (b_owned) {
      double *vb = cx->vatom + 6 * (size_t) ib;
      for (int k = 0; k < 6; k++) vb[k] += 0.5 * w[k];
    }
  }
}

/* A batch's inputs read from the slots and particles of its pairs: separations (x_a - x_b, and
 * its squared length summed left to right, as the sweep's test sums it), radii, velocities, spins,
 * masses, types and group bits, and whether each particle is frozen. The plain reading, and
 * where the processor has them (chosen once per sweep) AVX2's gathers, four lanes at a time,
 * which read the same values. */
static void gather_plain(const sweep_context *cx, contact_batch *q)
{
  const griddem_channels *ch = cx->ch;
  const griddem_particles *p = ch->p;
  griddem_classic_batch *l = &q->lanes;
  for (int k = 0; k < l->n; k++) {
    const int a = q->a[k], b = q->b[k];
    const size_t ia = (size_t) q->ia[k], ib = (size_t) q->ib[k];
    const double dx[3] = {ch->x[a] - ch->x[b], ch->y[a] - ch->y[b], ch->z[a] - ch->z[b]};
    for (int d = 0; d < 3; d++) {
      l->dx[d][k] = dx[d];
      l->vi[d][k] = p->v[3 * ia + d], l->vj[d][k] = p->v[3 * ib + d];
      l->wi[d][k] = p->omega[3 * ia + d], l->wj[d][k] = p->omega[3 * ib + d];
    }
    l->rsq[k] = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
    l->radi[k] = ch->r[a], l->radj[k] = ch->r[b];
    l->mi[k] = p->rmass[ia], l->mj[k] = p->rmass[ib];
    q->type_a[k] = p->type[ia], q->type_b[k] = p->type[ib], q->ma[k] = p->mask[ia], q->mb[k] = p->mask[ib];
    l->frozen_i[k] = (q->ma[k] & p->frozen_bit) != 0, l->frozen_j[k] = (q->mb[k] & p->frozen_bit) != 0;
    q->excluded[k] = griddem_excluded_by_bits(cx->both_bits, cx->apart_bits, q->ma[k], q->mb[k]);
    q->key_b[k] = contact_key(ch, a, b), q->key_a[k] = contact_key(ch, b, a);
  }
}

#ifdef GRIDDEM_SWEEP_GATHER
__attribute__((target("avx2"))) static void gather_avx2(const sweep_context *cx, contact_batch *q)
{
  const griddem_channels *ch = cx->ch;
  const griddem_particles *p = ch->p;
  griddem_classic_batch *l = &q->lanes;
  const int n = l->n;
  for (int k = n; k % 4; k++) /* a last partial vector reads the first pair again (within the batch) */
    q->a[k] = q->a[0], q->b[k] = q->b[0], q->ia[k] = q->ia[0], q->ib[k] = q->ib[0];
  for (int k = 0; k < n; k += 4) {
    const __m128i a = _mm_loadu_si128((const __m128i *) (q->a + k)), b = _mm_loadu_si128((const __m128i *) (q->b + k));
    const __m128i ia4 = _mm_loadu_si128((const __m128i *) (q->ia + k));
    const __m128i ib4 = _mm_loadu_si128((const __m128i *) (q->ib + k));
    const __m128i ma = _mm_i32gather_epi32(p->mask, ia4, 4), mb = _mm_i32gather_epi32(p->mask, ib4, 4);
    _mm_storeu_si128((__m128i *) (q->ma + k), ma), _mm_storeu_si128((__m128i *) (q->mb + k), mb);
    _mm_storeu_si128((__m128i *) (q->type_a + k), _mm_i32gather_epi32(p->type, ia4, 4));
    _mm_storeu_si128((__m128i *) (q->type_b + k), _mm_i32gather_epi32(p->type, ib4, 4));
    /* frozen: 1 where a particle's group bits hold the frozen bit */
    const __m128i frozen = _mm_set1_epi32(p->frozen_bit), none = _mm_setzero_si128(), one = _mm_set1_epi32(1);
    _mm_storeu_si128((__m128i *) (l->frozen_i + k),
                     _mm_andnot_si128(_mm_cmpeq_epi32(_mm_and_si128(ma, frozen), none), one));
    _mm_storeu_si128((__m128i *) (l->frozen_j + k),
                     _mm_andnot_si128(_mm_cmpeq_epi32(_mm_and_si128(mb, frozen), none), one));
    const __m128i both = _mm_and_si128(_mm_and_si128(ma, mb), _mm_set1_epi32(cx->both_bits));
    const __m128i apart = _mm_and_si128(_mm_or_si128(ma, mb), _mm_set1_epi32(cx->apart_bits));
    _mm_storeu_si128((__m128i *) (q->excluded + k),
                     _mm_andnot_si128(_mm_cmpeq_epi32(_mm_or_si128(both, apart), none), one));
    const __m256i ia3 = first_of_three(ia4), ib3 = first_of_three(ib4);
    const __m256d d0 = _mm256_sub_pd(_mm256_i32gather_pd(ch->x, a, 8), _mm256_i32gather_pd(ch->x, b, 8));
    const __m256d d1 = _mm256_sub_pd(_mm256_i32gather_pd(ch->y, a, 8), _mm256_i32gather_pd(ch->y, b, 8));
    const __m256d d2 = _mm256_sub_pd(_mm256_i32gather_pd(ch->z, a, 8), _mm256_i32gather_pd(ch->z, b, 8));
    _mm256_storeu_pd(l->dx[0] + k, d0), _mm256_storeu_pd(l->dx[1] + k, d1), _mm256_storeu_pd(l->dx[2] + k, d2);
    _mm256_storeu_pd(l->rsq + k,
                     _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(d0, d0), _mm256_mul_pd(d1, d1)), _mm256_mul_pd(d2, d2)));
    _mm256_storeu_pd(l->radi + k, _mm256_i32gather_pd(ch->r, a, 8));
    _mm256_storeu_pd(l->radj + k, _mm256_i32gather_pd(ch->r, b, 8));
    for (int d = 0; d < 3; d++) {
      _mm256_storeu_pd(l->vi[d] + k, _mm256_i64gather_pd(p->v + d, ia3, 8));
      _mm256_storeu_pd(l->vj[d] + k, _mm256_i64gather_pd(p->v + d, ib3, 8));
      _mm256_storeu_pd(l->wi[d] + k, _mm256_i64gather_pd(p->omega + d, ia3, 8));
      _mm256_storeu_pd(l->wj[d] + k, _mm256_i64gather_pd(p->omega + d, ib3, 8));
    }
    _mm256_storeu_pd(l->mi + k, _mm256_i32gather_pd(p->rmass, ia4, 8));
    _mm256_storeu_pd(l->mj + k, _mm256_i32gather_pd(p->rmass, ib4, 8));
    if (!ch->keyed_by_image) { /* the keys are the tags */
      _mm256_storeu_si256((__m256i *) (q->key_b + k), _mm256_i32gather_epi64((const long long *) ch->tag, b, 8));
      _mm256_storeu_si256((__m256i *) (q->key_a + k), _mm256_i32gather_epi64((const long long *) ch->tag, a, 8));
    }
  }
  if (ch->keyed_by_image)
    for (int k = 0; k < n; k++)
      q->key_b[k] = contact_key(ch, q->a[k], q->b[k]), q->key_a[k] = contact_key(ch, q->b[k], q->a[k]);
}
#endif

/* The batch's reading of its inputs (griddem_vector_reads) */
static void (*batch_gather(void))(const sweep_context *, contact_batch *)
{
#ifdef GRIDDEM_SWEEP_GATHER
  if (griddem_vector_reads()) return gather_avx2;
#endif
  return gather_plain;
}

/* The ends of a batch's evaluated contacts, in the order they were found; virial and energy
 * (whether the sweep tallies each, and the lanes hold their energies) constants of each copy */
SWEEP_SPECIALIZED void finish_lanes(const sweep_context *cx, sweep_sums *sums, const contact_batch *q, int n,
                                    const int virial, const int energy)
{
  const griddem_classic_batch *l = &q->lanes;
  for (int k = 0; k < n; k++) {
    if (!q->kept[k]) continue;
    pair_end(cx, sums, q->a[k], q->b[k], q->ia[k], q->ib[k], q->key_b[k], q->entry_a[k], &l->dx[0][k],
             &l->shear[0][k], &l->f[0][k], &l->ti[0][k], &l->tj[0][k], GRIDDEM_CLASSIC_BATCH,
             energy ? l->energy[k] : 0.0, 0, 0.0, 1, 3, virial, energy);
  }
}

/* Evaluate the batch's contacts (those that pair_begin keeps, in the order they were found: a
 * coincident pair's fault comes before the contacts' own) and finish each in that order */
static void flush_batch(const sweep_context *shared, sweep_sums *sums)
{
  contact_batch *q = sums->batch;
  griddem_classic_batch *l = &q->lanes;
  const int n = l->n;
  if (n == 0) return;
  shared->gather(shared, q);
  /* the context, the history's pool and the channels' pointers copied where no store or call of
     the loops below can reach them (no call takes their address), so that they stay in registers
     instead of being read through the shared context at every pair (none changes in a sweep) */
  sweep_context context = *shared;
  griddem_history hist;
  griddem_channels channels = *shared->ch;
  if (shared->hist) hist = *shared->hist, context.hist = &hist;
  context.ch = &channels;
  const sweep_context *cx = &context;
  /* exclusions by group bits alone (neigh_modify exclude group, fix griddem/rom's) tested here with
     their bits at hand; a coincident pair still goes on to pair_begin's fault */
  const griddem_exclusions *excl = cx->excl;
  const int by_bits = excl && griddem_exclusions_by_bits(excl);
  const griddem_pair_params *law_of_all = griddem_model_pair(cx->model, 1, 1);
  for (int k = 0; k < n; k++) {
    const int ma = q->ma[k], mb = q->mb[k];
    if (GRIDDEM_RARELY(q->excluded[k] && l->rsq[k] != 0.0)) {
      q->kept[k] = 0;
      for (int d = 0; d < 3; d++) l->shear[d][k] = 0.0;
      continue;
    }
    const griddem_pair_params *law;    /* the one law */
    q->kept[k] = pair_begin(cx, q->a[k], q->b[k], q->ia[k], q->ib[k], q->type_a[k], q->type_b[k], ma, mb, q->key_b[k],
                            q->key_a[k], by_bits ? NULL : excl, l->rsq[k], CLASSIC_BATCHED, 1, &law, &q->entry_a[k],
                            &q->entry_b[k]);
    /* a lane left out is evaluated on its inputs as they are, and its results dropped */
    if (q->kept[k])
      stored_values(cx, law_of_all, q->entry_a[k], q->entry_b[k], 3, &l->shear[0][k], GRIDDEM_CLASSIC_BATCH);
    else
      for (int d = 0; d < 3; d++) l->shear[d][k] = 0.0;
  }
  const int energy = (cx->tally & GRIDDEM_TALLY_ENERGY) != 0;
  griddem_classic_batch_eval(griddem_model_pair(cx->model, 1, 1), l, cx->dt, energy);    /* every pair's law */
  if ((cx->tally & GRIDDEM_TALLY_VIRIAL) || cx->vatom)
    energy ? finish_lanes(cx, sums, q, n, 1, 1) : finish_lanes(cx, sums, q, n, 1, 0);
  else
    energy ? finish_lanes(cx, sums, q, n, 0, 1) : finish_lanes(cx, sums, q, n, 0, 0);
  l->n = 0;
}

/* A pair of slots a (owned) and b (within reach), of particles ia and ib, into the thread's batch,
 * which is evaluated when it is full */
static inline void batch_pair(const sweep_context *cx, sweep_sums *sums, int a, int b, int ia, int ib)
{
  contact_batch *q = sums->batch;
  const int k = q->lanes.n;
  q->a[k] = a, q->b[k] = b, q->ia[k] = ia, q->ib[k] = ib;
  if (++q->lanes.n == GRIDDEM_CLASSIC_BATCH) flush_batch(cx, sums);
}

/* Evaluate the contact of slots a and b (separation dx = x_a - x_b of squared length rsq, within
 * reach) seen from a, which is owned; b receives its share if it is owned too. body (CLASSIC_HOOKE
 * or CLASSIC_HERTZ: every law is that classic one, and nothing interacts past touching; COMPOSED;
 * COMPILED + k; a CLASSIC_BATCHED sweep's pairs go to batch_pair instead) and values (the history
 * values per contact, or -1: the model's, with contacts kept as it says) are constants of each
 * specialization. */
SWEEP_SPECIALIZED void sweep_pair(const sweep_context *cx, sweep_sums *sums, int a, int b, const double *dx,
                                  double rsq, const int body, const int values)
{
  const griddem_model *m = cx->model;
  const int nv = values >= 0 ? values : m->history_size;
  const int track = values > 0 ? 1 : (values == 0 ? 0 : m->track_contacts);
  const griddem_channels *ch = cx->ch;
  const griddem_particles *p = ch->p;
  const int ia = cx->order[a], ib = cx->order[b], ma = p->mask[ia], mb = p->mask[ib];
  const griddem_pair_params *law;
  const int64_t key_b = track ? contact_key(ch, a, b) : 0;
  const int64_t key_a = track && ib < cx->nlocal ? contact_key(ch, b, a) : 0;
  long entry_a, entry_b;
  if (!pair_begin(cx, a, b, ia, ib, p->type[ia], p->type[ib], ma, mb, key_b, key_a, cx->excl, rsq, body, track,
                  &law, &entry_a, &entry_b))
    return;

  griddem_contact c;
  griddem_contact_setup(&c, dx, rsq, ch->r[a], ch->r[b], p->v + 3 * (size_t) ia, p->v + 3 * (size_t) ib,
                        p->omega + 3 * (size_t) ia, p->omega + 3 * (size_t) ib, p->rmass[ia], p->rmass[ib],
                        (ma & p->frozen_bit) != 0, (mb & p->frozen_bit) != 0, cx->dt, cx->history_update);
  const int heat = !IS_CLASSIC(body) && p->heatflow;    /* the classic laws conduct no heat */
  if (heat) c.temp_i = p->temperature[ia], c.temp_j = p->temperature[ib];

  double hv[GRIDDEM_MAX_HISTORY];
  stored_values(cx, law, entry_a, entry_b, nv, hv, 1);

  double fc[3], ta[3], tb[3];
  const double energy = body == CLASSIC_HERTZ  ? classic_hertz(law, &c, hv, fc, ta, tb)
                        : body == CLASSIC_HOOKE ? classic_hooke(law, &c, hv, fc, ta, tb)
                                                : composed_law(body, law, &c, hv, fc, ta, tb);
  pair_end(cx, sums, a, b, ia, ib, key_b, entry_a, c.dx, hv, fc, ta, tb, 1, energy, heat, heat ? c.heat : 0.0, track,
           track ? (values >= 0 ? values : cx->hist->values) : 0, (cx->tally & GRIDDEM_TALLY_VIRIAL) || cx->vatom,
           (cx->tally & GRIDDEM_TALLY_ENERGY) != 0);
}

/* Candidates a cluster's search tests at once: a cluster with more in its runs is searched sphere
 * by sphere, in parts of this many */
#define HITS_CAP 256

/* A thread's room for the touching pairs of one search (at most HITS_CAP candidates for each of
 * a cluster's spheres) */
typedef struct cluster_hits {
  int sphere[GRIDDEM_CLUSTER_MAX * HITS_CAP], slot[GRIDDEM_CLUSTER_MAX * HITS_CAP];
} cluster_hits;

/* The touching pairs of the spheres of slots i0 + k (k: the pairs' sphere) in the order found,
 * each seen from an owned slot, by the pair body specialized for (body, values) */
SWEEP_SPECIALIZED void evaluate_hits(const sweep_context *cx, sweep_sums *sums, int i0,
                                     const griddem_cluster_hits *hits, const int body, const int values)
{
  const griddem_channels *ch = cx->ch;
  const int *order = cx->order;
  for (int m = 0; m < hits->n; m++) {
    const int s = i0 + hits->sphere[m], t = hits->slot[m];
    const int s_owned = order[s] < cx->nlocal, t_owned = order[t] < cx->nlocal;
    if (!s_owned && !t_owned) continue;
    if (body == CLASSIC_BATCHED) {    /* read with the batch's other pairs */
      if (s_owned) batch_pair(cx, sums, s, t, order[s], order[t]);
      else batch_pair(cx, sums, t, s, order[t], order[s]);
      continue;
    }
    const double dx[3] = {ch->x[s] - ch->x[t], ch->y[s] - ch->y[t], ch->z[s] - ch->z[t]};
    const double rsq = dx[0] * dx[0] + dx[1] * dx[1] + dx[2] * dx[2];
    if (s_owned) sweep_pair(cx, sums, s, t, dx, rsq, body, values);
    else {    /* seen from t: the separation negated, exactly */
      const double dt[3] = {-dx[0], -dx[1], -dx[2]};
      sweep_pair(cx, sums, t, s, dt, rsq, body, values);
    }
  }
}

/* The touching pairs by a law evaluated pair by pair */
static void evaluate_each(const sweep_context *cx, sweep_sums *sums, int i0, const griddem_cluster_hits *hits)
{
  switch (cx->law) {
    case SWEEP_HOOKE_SHEAR: evaluate_hits(cx, sums, i0, hits, CLASSIC_HOOKE, 3); break;
    case SWEEP_HOOKE_NO_HISTORY: evaluate_hits(cx, sums, i0, hits, CLASSIC_HOOKE, 0); break;
    case SWEEP_HERTZ_SHEAR: evaluate_hits(cx, sums, i0, hits, CLASSIC_HERTZ, 3); break;
    case SWEEP_HERTZ_NO_HISTORY: evaluate_hits(cx, sums, i0, hits, CLASSIC_HERTZ, 0); break;
    case SWEEP_COMPILED: evaluate_hits(cx, sums, i0, hits, COMPILED, COMPILED_LAWS[0].values); break;
    case SWEEP_COMPILED + 1: evaluate_hits(cx, sums, i0, hits, COMPILED + 1, COMPILED_LAWS[1].values); break;
    case SWEEP_COMPILED + 2: evaluate_hits(cx, sums, i0, hits, COMPILED + 2, COMPILED_LAWS[2].values); break;
    default: evaluate_hits(cx, sums, i0, hits, COMPOSED, -1);
  }
}

/* Evaluate the touching pairs of the spheres of slots i0 + k, or queue them in the thread's batch
 * (a few stores each, done in place), and empty the list. */
SWEEP_SPECIALIZED void sweep_hits(const sweep_context *cx, sweep_sums *sums, int i0, griddem_cluster_hits *hits)
{
  if (cx->law == SWEEP_CLASSIC_BATCH) evaluate_hits(cx, sums, i0, hits, CLASSIC_BATCHED, 3);
  else evaluate_each(cx, sums, i0, hits);
  hits->n = 0;
}

/* Collect into hits (empty) slot s's touching candidates in the runs [lo[q], hi[q]) in parts of
 * at most HITS_CAP, evaluating them whenever the next part could overflow HITS_CAP: the path of
 * a cluster with more candidates than its search tests at once. */
static void collect_in_parts(const sweep_context *cx, sweep_sums *sums, int s, const int *lo, const int *hi,
                             int nruns, griddem_cluster_hits *hits)
{
  for (int q = 0; q < nruns; q++)
    for (int t0 = lo[q]; t0 < hi[q];) {
      if (hits->n + (hi[q] - t0) > HITS_CAP && hits->n > 0) sweep_hits(cx, sums, s, hits);
      const int t1 = hi[q] - t0 > HITS_CAP ? t0 + HITS_CAP : hi[q];
      cx->touching(&cx->spheres, cx->model->reach_extra, s, 1, 0, &t0, &t1, 1, hits);
      t0 = t1;
    }
}

/* The contacts of the cluster of slots i0 .. i0 + ni - 1 with the slots of the runs
 * [lo[q], hi[q]) (at most total of them), in the order the kernel finds them: the runs tested at
 * once where they hold at most HITS_CAP candidates, else sphere by sphere in parts. own: run 0 is
 * the cluster's own run, whose candidates of a sphere are the slots after it (lo[0] is then moved
 * to each sphere's). */
SWEEP_SPECIALIZED void search_cluster(const sweep_context *cx, sweep_sums *sums, cluster_hits *room, int i0, int ni,
                                      int own, int *lo, const int *hi, int nruns, int total)
{
  griddem_cluster_hits hits = {room->sphere, room->slot, 0};
  if (total <= HITS_CAP) {
    cx->touching(&cx->spheres, cx->model->reach_extra, i0, ni, own, lo, hi, nruns, &hits);
    if (hits.n) sweep_hits(cx, sums, i0, &hits);
  } else
    for (int c = 0; c < ni; c++) {
      if (own) lo[0] = i0 + c + 1;
      collect_in_parts(cx, sums, i0 + c, lo, hi, nruns, &hits);
      if (hits.n) sweep_hits(cx, sums, i0 + c, &hits);
    }
}

/* Whether one of the slots s0 .. s0 + n - 1 holds an owned particle */
static inline int any_owned(const sweep_context *cx, int s0, int n)
{
  int owned = 0;
  for (int k = 0; k < n; k++) owned |= cx->order[s0 + k] < cx->nlocal;
  return owned;
}

void griddem_owned_cells(const griddem_grid *g, const double lo[3], const double hi[3], int nowned, int owned_lo[3],
                         int owned_hi[3])
{
  for (int d = 0; d < 3; d++)
    if (nowned > 0) {
      griddem_axis_cells_within(lo[d], hi[d], 0.0, g->anchor[d], g->hinv, g->k0[d], g->n[d], &owned_lo[d], &owned_hi[d]);
    } else
      owned_lo[d] = INT_MAX, owned_hi[d] = INT_MIN;
}

/* A stencil's rows in one grid's cells: per row, where the slots of a cell's first and past its
 * last stencil cell begin, as offsets in cell_start from the cell row's first cell for the cell
 * x = 0 (nx dy + nx ny dz + dxlo, and + dxhi + 1), and its cells along x; the rows' extent in y
 * and z; the cells a cluster keeps from the row's ends for every stencil row to lie inside the
 * grid along x. Built once per sweep of a grid, so that a cell row away from the grid's faces
 * (all its stencil rows inside) costs nothing to set up: a row of a dilute grid holds a sphere or
 * two. */
typedef struct stencil_cells {
  int nrows;
  const griddem_stencil_row *row;
  const long *lo, *hi;
  const int *dxlo, *dxhi;
  int dymin, dymax, dzmin, dzmax, xsafe_lo, xsafe_hi;
} stencil_cells;

/* A thread's room for one cell row's runs, a place per stencil row in each array: the stencil rows
 * kept inside the grid (their cell offsets, x reaches and indices), each run's first cell start,
 * and the runs' slot ranges. Laid out once per slab, not once per cell row. */
typedef struct row_room {
  long *kept_lo, *kept_hi;
  int *kept_dxlo, *kept_dxhi, *kept_row, *lo, *hi;
  const int **row_lo, **row_hi;
} row_room;

/* The rows of the forward half stencil of reach 1 (the cell row itself, the next along y and the
 * three of the next layer along z): a constant, so that the common case's loop is unrolled */
#define FORWARD_ROWS 5

/* The slot ranges [lo[q], hi[q]) of the n stencil rows from cell xa to cell xb of a cell row
 * whose stencil lies inside the grid (row_lo, row_hi: each stencil row's cell starts from the cell
 * row's x = 0), and their total length */
SWEEP_SPECIALIZED int runs_inside(const int *const *row_lo, const int *const *row_hi, const int n, int into_base,
                                  int xa, int xb, int *lo, int *hi)
{
  int total = 0;
  for (int q = 0; q < n; q++) {
    lo[q] = into_base + row_lo[q][xa], hi[q] = into_base + row_hi[q][xb];
    total += hi[q] - lo[q];
  }
  return total;
}

/* Pairs (s, t) of the slots s in the cell row (y, z) of class grid k with the slots t of grid
 * `into`'s cells in their stencil: k's own (own 1: the forward stencil, t > s) or another class's
 * laid over the same cells (own 0: the full stencil; same_cells below). Slots of the channels
 * are a class's slots + its base. The row's slots are taken in clusters of consecutive slots
 * (the kernel's width), whose stencil rows' slot ranges cover the cells of all its spheres: a
 * candidate is loaded once for the cluster. A cluster's spheres then evaluate their contacts in
 * slot order, each in the order its candidates were found (hits: the thread's lists, empty). */
static void sweep_cell_row(const sweep_context *cx, sweep_sums *sums, cluster_hits *hits, const row_room *room,
                           const griddem_class_grid *k, const griddem_class_grid *into, const stencil_cells *sc, int own,
                           int y, int z)
{
  const griddem_grid *g = k->g;
  const griddem_bins *b = k->b;
  const int *start = b->cell_start, base = k->base, into_base = into->base, nx = g->n[0];
  const long nxy = (long) nx * g->n[1], rowcell = nx * (long) y + nxy * z;
  const int first = start[rowcell], last = start[rowcell + nx];
  if (first == last) return;
  /* a row outside the owned cells holds ghosts only; none has an owned candidate where the row's
     stencil misses them too */
  const int *olo = k->owned_lo, *ohi = k->owned_hi;
  if (y + sc->dymax < olo[1] || y + sc->dymin > ohi[1] || z + sc->dzmax < olo[2] || z + sc->dzmin > ohi[2]) return;
  const int ghost_row = y < olo[1] || y > ohi[1] || z < olo[2] || z > ohi[2];
  const int *row0 = into->b->cell_start + rowcell;

  /* the stencil rows inside the grid: all of them away from its faces */
  const int nrows = sc->nrows;
  const long *off_lo = sc->lo, *off_hi = sc->hi;
  const int *dxlo = sc->dxlo, *dxhi = sc->dxhi;
  int nvalid = nrows, xsafe_lo = sc->xsafe_lo, xsafe_hi = nx - 1 - sc->xsafe_hi;
  long *kept_lo = room->kept_lo, *kept_hi = room->kept_hi;
  int *kept_dxlo = room->kept_dxlo, *kept_dxhi = room->kept_dxhi, *kept_row = room->kept_row;
  const int *stencil_row = NULL;    /* of each run (NULL: run q is stencil row q) */
  if (y + sc->dymin < 0 || y + sc->dymax >= g->n[1] || z + sc->dzmin < 0 || z + sc->dzmax >= g->n[2]) {
    nvalid = 0, xsafe_lo = 0, xsafe_hi = nx - 1;
    for (int r = 0; r < nrows; r++) {
      const int yy = y + sc->row[r].dy, zz = z + sc->row[r].dz;
      if (yy < 0 || yy >= g->n[1] || zz < 0 || zz >= g->n[2]) continue;
      kept_lo[nvalid] = sc->lo[r], kept_hi[nvalid] = sc->hi[r];
      kept_dxlo[nvalid] = sc->dxlo[r], kept_dxhi[nvalid] = sc->dxhi[r], kept_row[nvalid] = r;
      if (-sc->dxlo[r] > xsafe_lo) xsafe_lo = -sc->dxlo[r];
      if (nx - 1 - sc->dxhi[r] < xsafe_hi) xsafe_hi = nx - 1 - sc->dxhi[r];
      nvalid++;
    }
    off_lo = kept_lo, off_hi = kept_hi, dxlo = kept_dxlo, dxhi = kept_dxhi, stencil_row = kept_row;
  }

  /* each stencil row's cell starts from this cell row's x = 0, the into grid's base added */
  const int **row_lo = room->row_lo, **row_hi = room->row_hi;
  for (int q = 0; q < nvalid; q++) row_lo[q] = row0 + off_lo[q], row_hi[q] = row0 + off_hi[q];
  int *lo = room->lo, *hi = room->hi;
  for (int s0 = first; s0 < last; s0 += cx->cluster) {
    const int ni = last - s0 < cx->cluster ? last - s0 : cx->cluster;
    const int xa = (int) (b->cell[b->order[s0]] - rowcell), xb = (int) (b->cell[b->order[s0 + ni - 1]] - rowcell);
    /* slot ranges of the stencil rows from the first sphere's cell to the last's; the own row
       starts after the first sphere (the kernel starts each sphere's after itself). Only
       clusters at the ends of the row clamp their stencil to the grid; a cluster of ghosts (cells
       outside the owned ones) clips it to the owned cells instead, rows outside them dropped, and
       tests its owned candidates only (the own run then starts past the cluster or is empty) */
    const int ghosts = ghost_row || xb < olo[0] || xa > ohi[0];
    int total = 0;
    if (!ghosts && xa >= xsafe_lo && xb <= xsafe_hi)
      total = nvalid == FORWARD_ROWS ? runs_inside(row_lo, row_hi, FORWARD_ROWS, into_base, xa, xb, lo, hi)
                                     : runs_inside(row_lo, row_hi, nvalid, into_base, xa, xb, lo, hi);
    else {
      const int xmin = ghosts ? olo[0] : 0, xmax = ghosts ? ohi[0] : nx - 1;
      for (int q = 0; q < nvalid; q++) {
        const griddem_stencil_row *r = &sc->row[stencil_row ? stencil_row[q] : q];
        const int yy = y + r->dy, zz = z + r->dz;
        const int x0 = xa + dxlo[q] < xmin ? xmin : xa + dxlo[q], x1 = xb + dxhi[q] > xmax ? xmax : xb + dxhi[q];
        if (x1 < x0 || (ghosts && (yy < olo[1] || yy > ohi[1] || zz < olo[2] || zz > ohi[2]))) lo[q] = hi[q] = 0;
        else lo[q] = into_base + row_lo[q][x0 - dxlo[q]], hi[q] = into_base + row_hi[q][x1 - dxhi[q]];
        total += hi[q] - lo[q];
      }
    }
    if (ghosts) {
      if (total == 0) continue;
    } else if (own)
      lo[0] = base + s0 + 1;
    search_cluster(cx, sums, hits, base + s0, ni, own, lo, hi, nvalid, total);
  }
}

/* A thread's empty accumulators, with its own history overflow list, and batch (its room on the
 * thread's stack) where the sweep's law is evaluated in batches */
static sweep_sums thread_sums(const sweep_context *cx, contact_batch *batch)
{
  sweep_sums sums;
  memset(&sums, 0, sizeof(sums));
  if (cx->model->track_contacts) sums.overflow = &cx->hist->overflow[griddem_thread_num()];
  if (cx->law == SWEEP_CLASSIC_BATCH) batch->lanes.n = 0, sums.batch = batch;
  return sums;
}

/* A thread's accumulators once its pairs are found: the contacts left in its batch evaluated */
static sweep_sums finished_sums(const sweep_context *cx, sweep_sums sums)
{
  if (sums.batch) flush_batch(cx, &sums), sums.batch = NULL;
  return sums;
}

/* Most rows of a cross-class block: (2 reach + 1)^2 */
#define MAX_BLOCK_ROWS ((2 * GRIDDEM_MAX_REACH + 1) * (2 * GRIDDEM_MAX_REACH + 1))

/* Pairs of the slots slots[0..n-1] (of one size class) with the particles of another class's grid
 * l: the cells of l that the box of half-edge cut (the longest contact distance between the two
 * classes) around the slot's centre overlaps, the slot on its own side. Consecutive slots whose
 * centres lie within one cell edge of l of each other along every axis form a cluster (up to the
 * kernel's width), searched at once over the block around their centres' box; consecutive
 * clusters mostly share that block, whose non-empty row ranges are then found once. A sphere's
 * hits come in the order of its own block's rows. Returns the sums of one thread's share. */
static sweep_sums sweep_across(const sweep_context *cx, const griddem_class_grid *l, double cut, const int *slots,
                               int n)
{
  contact_batch batch;
  sweep_sums sums = thread_sums(cx, &batch);
  const griddem_grid *g = l->g;
  const int *start = l->b->cell_start;
  const long nx = g->n[0], nxy = (long) g->n[0] * g->n[1];
  const griddem_channels *ch = cx->ch;
  cluster_hits hits;
  int lo[MAX_BLOCK_ROWS], hi[MAX_BLOCK_ROWS], nrange = 0, total = 0;
  int block[6] = {-1, -1, -1, -1, -1, -1}; /* cells x0, y0, z0, x1, y1, z1 of the block */
  for (int q = 0; q < n;) {
    const int s = slots[q];
    double box[6] = {ch->x[s], ch->y[s], ch->z[s], ch->x[s], ch->y[s], ch->z[s]};
    int ni = 1;
    for (; ni < cx->cluster && q + ni < n && slots[q + ni] == s + ni; ni++) {
      const double c[3] = {ch->x[s + ni], ch->y[s + ni], ch->z[s + ni]};
      int near = 1;
      /* (centres are finite: the engine's scan stops a step on any that is not) */
      double grown[6];
      for (int d = 0; d < 3; d++) {
        grown[d] = c[d] < box[d] ? c[d] : box[d], grown[3 + d] = c[d] > box[3 + d] ? c[d] : box[3 + d];
        near &= grown[3 + d] - grown[d] <= g->h;
      }
      if (!near) break;
      memcpy(box, grown, sizeof(box));
    }
    int b[6], empty = 0;
    const int ghosts = !any_owned(cx, s, ni);
    for (int d = 0; d < 3; d++) {
      griddem_axis_cells_within(box[d], box[3 + d], cut, g->anchor[d], g->hinv, g->k0[d], g->n[d], &b[d], &b[3 + d]);
      if (ghosts) { /* only their owned candidates: the block clipped to the owned cells */
        b[d] = b[d] < l->owned_lo[d] ? l->owned_lo[d] : b[d];
        b[3 + d] = b[3 + d] > l->owned_hi[d] ? l->owned_hi[d] : b[3 + d];
        empty |= b[3 + d] < b[d];
      }
    }
    if (empty) {
      q += ni;
      continue;
    }
    if (memcmp(b, block, sizeof(b)) != 0) {
      nrange = total = 0;
      for (int zz = b[2]; zz <= b[5]; zz++)
        for (int yy = b[1]; yy <= b[4]; yy++) {
          const long rowcell = nx * yy + nxy * zz;
          lo[nrange] = l->base + start[rowcell + b[0]], hi[nrange] = l->base + start[rowcell + b[3] + 1];
          if (hi[nrange] > lo[nrange]) total += hi[nrange] - lo[nrange], nrange++;
        }
      memcpy(block, b, sizeof(b));
    }
    search_cluster(cx, &sums, &hits, s, ni, 0, lo, hi, nrange, total);
    q += ni;
  }
  return finished_sums(cx, sums);
}

/* Room in the cross-class scratch for n small spheres and nslab slabs. 0, or -1 without memory. */
static int grow_across(griddem_channels *ch, int n, int nslab)
{
  if (n > ch->across_cap) {
    const int cap = n + n / 4 + 16;
    if (grow_aligned((void **) &ch->slab, sizeof(int), cap) != 0 ||
        grow_aligned((void **) &ch->slots, sizeof(int), cap) != 0)
      return ch->across_cap = 0, -1;
    ch->across_cap = cap;
  }
  if (nslab + 1 > ch->first_cap) {
    if (grow_aligned((void **) &ch->first, sizeof(int), nslab + 1) != 0) return ch->first_cap = 0, -1;
    ch->first_cap = nslab + 1;
  }
  return 0;
}

/* Layers of cells per slab for nthreads threads: about four slabs per thread, at least reach
 * thick; one slab for one thread (so one thread visits in sorted order) */
static int slab_thickness(int nz, int nthreads, int reach)
{
  if (nthreads == 1) return nz;
  const int thick = nz / (4 * nthreads);
  return thick < reach ? reach : thick;
}

/* A bound on |coordinate| within the cells of g */
static double grid_extent(const griddem_grid *g)
{
  double extent = 0.0;
  for (int d = 0; d < 3; d++) extent = fmax(extent, fabs(g->lo[d]) + g->n[d] * g->h);
  return extent;
}

/* Largest contact distance between spheres of radii up to r1 and r2, with a margin for the
 * rounding of coordinates into the cells of g */
static double contact_reach(const griddem_grid *g, double r1, double r2, double extra)
{
  return (r1 + r2 + extra) * (1.0 + 1e-10) + 1e-14 * grid_extent(g);
}

/* Slots of the cells x0..x1 of row (y, z) of grid g binned into b, clamped to the grid */
static long row_slots(const griddem_grid *g, const griddem_bins *b, int x0, int x1, int y, int z)
{
  if (y < 0 || y >= g->n[1] || z < 0 || z >= g->n[2]) return 0;
  x0 = x0 < 0 ? 0 : x0;
  x1 = x1 >= g->n[0] ? g->n[0] - 1 : x1;
  if (x1 < x0) return 0;
  const long row = (long) g->n[0] * y + (long) g->n[0] * g->n[1] * z;
  return b->cell_start[row + x1 + 1] - b->cell_start[row + x0];
}

/* The cross-class pass of classes a and b (either order): which class's spheres search which
 * one's grid, the contact distance cut between them (with the margin of the grid searched) and its
 * reach in that grid's cells. Either way finds the same pairs; the choice is the cheaper by an
 * estimate of block rows and candidates per searching sphere (a few large spheres among many small
 * ones search the fine grid, whose blocks are tight around them). Returns 0, or -1 where neither
 * grid's reach is within GRIDDEM_MAX_REACH. */
typedef struct across_pass {
  const griddem_class_grid *from, *into;
  double cut;
  int reach;
} across_pass;

static int across_direction(const griddem_class_grid *a, const griddem_class_grid *b, double reach_extra,
                            across_pass *pass)
{
  across_pass way[2] = {{a, b, 0.0, 0}, {b, a, 0.0, 0}};
  double cost[2];
  for (int w = 0; w < 2; w++) {
    const griddem_grid *g = way[w].into->g;
    way[w].cut = contact_reach(g, a->rmax, b->rmax, reach_extra);
    way[w].reach = griddem_stencil_reach(g->h, way[w].cut);
    const double side = 2.0 * way[w].reach + 1.0, occupancy = (double) way[w].into->b->n / (double) g->ncell;
    cost[w] = way[w].reach > GRIDDEM_MAX_REACH ? INFINITY : way[w].from->b->n * (side * side + side * side * side * occupancy);
  }
  if (cost[0] == INFINITY && cost[1] == INFINITY) return -1;
  *pass = way[cost[1] < cost[0]];
  return 0;
}

/* Whether two grids have the same cells (edge, faces and extent), so that a cell's index is the
 * same in both */
static int same_cells(const griddem_grid *a, const griddem_grid *b)
{
  for (int d = 0; d < 3; d++)
    if (a->anchor[d] != b->anchor[d] || a->k0[d] != b->k0[d] || a->n[d] != b->n[d]) return 0;
  return a->h == b->h;
}

/* Whether t is class k's kinematic twin: its kinematic particles over the same cells */
static int twins(const griddem_class_grid *k, const griddem_class_grid *t)
{
  return !k->kinematic && t->kinematic && same_cells(k->g, t->g);
}

/* A thread's sums added into totals (the virial's six components, then the energy) */
static void add_sums(double *totals, sweep_sums sums)
{
  for (int c = 0; c < 6; c++) totals[c] += sums.virial[c];
  totals[6] += sums.energy;
}

/* The pairs from class k's occupied cell rows in the cell layers zlo .. zhi - 1 (one slab), found
 * through their slots: a dilute grid costs nothing extra */
static sweep_sums sweep_slab(const sweep_context *cx, const griddem_class_grid *k, const griddem_class_grid *into,
                             const stencil_cells *sc, int own, int zlo, int zhi)
{
  const griddem_grid *g = k->g;
  const griddem_bins *b = k->b;
  const long nxy = (long) g->n[0] * g->n[1];
  contact_batch batch;
  sweep_sums sums = thread_sums(cx, &batch);
  cluster_hits hits;
  const int nrows = sc->nrows;
  long kept_lo[nrows], kept_hi[nrows];
  int kept_dxlo[nrows], kept_dxhi[nrows], kept_row[nrows], lo[nrows], hi[nrows];
  const int *row_lo[nrows], *row_hi[nrows];
  const row_room room = {kept_lo, kept_hi, kept_dxlo, kept_dxhi, kept_row, lo, hi, row_lo, row_hi};
  const int nx = g->n[0], ny = g->n[1];
  long row = -1;    /* the cell row last swept, (y, z) */
  int y = 0, z = 0;
  for (int s = b->cell_start[zlo * nxy]; s < b->cell_start[zhi * nxy]; s = b->cell_start[(row + 1) * nx]) {
    /* the next occupied row: the one after the last where it holds slot s (a dense grid's), else
       the row of slot s's cell, which takes two divisions */
    if (row >= 0 && b->cell_start[(row + 2) * nx] > s) {
      row++;
      if (++y == ny) y = 0, z++;
    } else {
      row = b->cell[b->order[s]] / nx;
      y = (int) (row % ny), z = (int) (row / ny);
    }
    sweep_cell_row(cx, &sums, &hits, &room, k, into, sc, own, y, z);
  }
  return finished_sums(cx, sums);
}

/* The pairs of class k's particles with those of `into` over the same cells, by k's occupied cell
 * rows: within k (into = k) over the forward stencil, or with a kinematic twin over the full one.
 * Threads take slabs of cell layers along z, at least the stencil's reach thick, in colours whose
 * slabs' partners lie in disjoint slabs: two for the forward stencil (slab q reaches q + 1), three
 * for the full one (q - 1 to q + 1), so no two threads write one particle. Adds the virial (6)
 * and the energy into totals. 0, or -1 where the contact distance spans more than
 * GRIDDEM_MAX_REACH cells. */
static int sweep_rows(const sweep_context *cx, const griddem_class_grid *k, const griddem_class_grid *into,
                      int nthreads, double *totals)
{
  const griddem_grid *g = k->g;
  const int own = into == k;
  griddem_stencil stencil;
  if (griddem_stencil_build(&stencil, g->h, contact_reach(g, k->rmax, into->rmax, cx->model->reach_extra),
                            own ? GRIDDEM_STENCIL_FORWARD : GRIDDEM_STENCIL_FULL) != 0)
    return -1;
  const int nrows = stencil.nrows, nx = g->n[0];
  long off_lo[nrows], off_hi[nrows];
  int dxlo[nrows], dxhi[nrows];
  stencil_cells sc = {nrows, stencil.row, off_lo, off_hi, dxlo, dxhi, 0, 0, 0, 0, 0, 0};
  for (int r = 0; r < nrows; r++) {
    const griddem_stencil_row *row = &stencil.row[r];
    const long offset = nx * (long) row->dy + (long) nx * g->n[1] * row->dz;
    off_lo[r] = offset + row->dxlo, off_hi[r] = offset + row->dxhi + 1;
    dxlo[r] = row->dxlo, dxhi[r] = row->dxhi;
    sc.dymin = row->dy < sc.dymin ? row->dy : sc.dymin, sc.dymax = row->dy > sc.dymax ? row->dy : sc.dymax;
    sc.dzmin = row->dz < sc.dzmin ? row->dz : sc.dzmin, sc.dzmax = row->dz > sc.dzmax ? row->dz : sc.dzmax;
    sc.xsafe_lo = -row->dxlo > sc.xsafe_lo ? -row->dxlo : sc.xsafe_lo;
    sc.xsafe_hi = row->dxhi > sc.xsafe_hi ? row->dxhi : sc.xsafe_hi;
  }
  const int reach = sc.dzmax;    /* the last layer it visits */
  const int thick = slab_thickness(g->n[2], nthreads, reach), colours = own ? 2 : 3;
  const int nslab = (g->n[2] + thick - 1) / thick;
  double part[7] = {0.0};
  if (nslab == 1)    /* one thread: no OpenMP region, which allocates its team even for one */
    add_sums(part, sweep_slab(cx, k, into, &sc, own, 0, g->n[2]));
  for (int colour = 0; colour < colours && nslab > 1; colour++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : part[:7])
    for (int q = colour; q < nslab; q += colours)
      add_sums(part, sweep_slab(cx, k, into, &sc, own, q * thick,
                                (q + 1) * thick < g->n[2] ? (q + 1) * thick : g->n[2]));
  }
  for (int c = 0; c < 7; c++) totals[c] += part[c];
  return 0;
}

double griddem_sweep_candidates(const griddem_class_grid *cls, int ncls, double reach_extra)
{
  double candidates = 0.0;
  for (int kc = 0; kc < ncls; kc++) {
    const griddem_grid *g = cls[kc].g;
    const griddem_bins *b = cls[kc].b;
    if (b->n == 0) continue;
    griddem_stencil stencil;    /* no rows (no candidates) past GRIDDEM_MAX_REACH; none among
                                   kinematic particles */
    stencil.nrows = 0;
    if (!cls[kc].kinematic)
      griddem_stencil_build(&stencil, g->h, contact_reach(g, cls[kc].rmax, cls[kc].rmax, reach_extra),
                            GRIDDEM_STENCIL_FORWARD);
    int run_lo[GRIDDEM_STENCIL_MAX_ROWS], run_hi[GRIDDEM_STENCIL_MAX_ROWS];
    /* the cross-class passes in which this class searches another's grid */
    across_pass passes[ncls];
    int npass = 0;
    for (int lc = 0; lc < ncls; lc++)
      if (lc != kc && !(cls[kc].kinematic && cls[lc].kinematic) &&
          across_direction(&cls[kc], &cls[lc], reach_extra, &passes[npass]) == 0 && passes[npass].from == &cls[kc])
        npass++;
    const long nx = g->n[0], nxy = nx * g->n[1];
    for (int s = 0; s < b->n;) {    /* occupied cells only, through their slots */
      const long cell = b->cell[b->order[s]];
      const int k[3] = {(int) (cell % nx), (int) (cell / nx % g->n[1]), (int) (cell / nxy)};
      const long n = b->cell_start[cell + 1] - b->cell_start[cell];
      const int nruns = griddem_stencil_runs(&stencil, g, b, cell, run_lo, run_hi);
      long reached = 0;
      for (int q = 0; q < nruns; q++) reached += run_hi[q] - run_lo[q];
      if (nruns) candidates += (double) n * reached - 0.5 * (double) n * (n + 1);    /* a cell's own pairs once */
      /* across classes, from this class's cells where it searches the other: the cells of the
         other grid within the contact distance of this cell */
      for (int q = 0; q < npass; q++) {
        const griddem_grid *gl = passes[q].into->g;
        int blo[3], bhi[3];
        for (int d = 0; d < 3; d++) {
          const double lo = g->lo[d] + k[d] * g->h;
          griddem_axis_cells_within(lo, lo + g->h, passes[q].cut, gl->anchor[d], gl->hinv, gl->k0[d], gl->n[d], &blo[d],
                                    &bhi[d]);
        }
        long block = 0;
        for (int zz = blo[2]; zz <= bhi[2]; zz++)
          for (int yy = blo[1]; yy <= bhi[1]; yy++) block += row_slots(gl, passes[q].into->b, blo[0], bhi[0], yy, zz);
        candidates += (double) n * block;
      }
      s = b->cell_start[cell + 1];
    }
  }
  return candidates;
}

int griddem_sweep(const griddem_class_grid *cls, int ncls, const int *order, griddem_channels *ch,
                  int nlocal, const griddem_model *model, const griddem_exclusions *excl, double dt,
                  int history_update, griddem_history *hist, int *row_of, double *f,
                  double *torque, double *vatom, int tally, griddem_sweep_result *result)
{
  /* the float test's slack from the grids' extent, which bounds every binned centre's coordinates
     (each grid covers its particles) */
  double rmax = 0.0, extent = 0.0;
  for (int kc = 0; kc < ncls; kc++)
    rmax = cls[kc].rmax > rmax ? cls[kc].rmax : rmax, extent = fmax(extent, grid_extent(cls[kc].g));
  griddem_spheres spheres = {ch->x, ch->y, ch->z, ch->r, ch->xf, ch->yf, ch->zf, ch->rf,
                             (float) griddem_search_slack(extent, rmax, model->reach_extra), 0, 0.0f, 0.0f};
  if (ch->same_radius) griddem_spheres_one_radius(&spheres, model->reach_extra);
  const griddem_exclusions *excluding =
      excl && (excl->type_pair || excl->ngroup_pairs || excl->nmolecule || excl->both_bit || excl->apart_bit ||
               excl->group_both_bits)
          ? excl
          : NULL;
  const int by_bits = excluding && griddem_exclusions_by_bits(excluding);
  const sweep_context cx = {order, ch, nlocal, model, sweep_law_of(model, hist, history_update), excluding,
                            by_bits ? excluding->both_bit | excluding->group_both_bits : 0,
                            by_bits ? excluding->apart_bit : 0,
                            dt, history_update, hist, row_of, f, torque, vatom, tally, result,
                            spheres,
                            griddem_touching(), griddem_touching_width(),
                            batch_gather()};
  memset(result, 0, sizeof(*result));
  const int nthreads = griddem_max_threads();
  int nslot = 0;
  for (int kc = 0; kc < ncls; kc++) nslot += cls[kc].b->n;
  if (model->track_contacts && griddem_history_begin(hist, nthreads) != 0) {
    result->fault = GRIDDEM_FAULT_MEMORY;
    return result->fault;
  }

  double totals[7] = {0.0};    /* the virial's six components and the energy */
  for (int kc = 0; kc < ncls; kc++) {
    /* pairs within class kc on its own grid, and with its kinematic twin (the class after it) */
    const griddem_class_grid *k = &cls[kc], *twin = kc + 1 < ncls && twins(k, &cls[kc + 1]) ? &cls[kc + 1] : NULL;
    if (k->b->n == 0 || k->kinematic) continue;
    if (sweep_rows(&cx, k, k, nthreads, totals) != 0 ||
        (twin && twin->b->n && sweep_rows(&cx, k, twin, nthreads, totals) != 0)) {
      result->fault = GRIDDEM_FAULT_STENCIL;
      return result->fault;
    }
  }

  /* pairs across classes: the spheres of one class searched in the other's grid, in the cheaper
     direction (across_direction). Threads take the searching spheres by slabs of the searched
     grid's cell layers (at least the reach thick) in three colours: the partners of slabs q and
     q+3 lie in disjoint slabs, so no two threads write one particle */
  for (int kc = 1; kc < ncls; kc++)
    for (int lc = 0; lc < kc; lc++) {
      if (cls[kc].b->n == 0 || cls[lc].b->n == 0 || (cls[kc].kinematic && cls[lc].kinematic) ||
          (lc == kc - 1 && twins(&cls[lc], &cls[kc])))    /* twins: swept above */
        continue;
      across_pass pass;
      if (across_direction(&cls[kc], &cls[lc], model->reach_extra, &pass) != 0) {
        result->fault = GRIDDEM_FAULT_STENCIL;
        return result->fault;
      }
      const griddem_class_grid *from = pass.from, *into = pass.into;
      const int nk = from->b->n;
      const griddem_grid *g = into->g;
      const int thick = slab_thickness(g->n[2], nthreads, pass.reach);
      const int nslab = (g->n[2] + thick - 1) / thick;
      /* the searching spheres' slots by slab of the searched grid (a stable counting sort) */
      if (grow_across(ch, nk, nslab) != 0) {
        result->fault = GRIDDEM_FAULT_MEMORY;
        return result->fault;
      }
      int *slab = ch->slab, *slots = ch->slots, *first = ch->first;
      memset(first, 0, sizeof(int) * ((size_t) nslab + 1));
      const long nxy = (long) g->n[0] * g->n[1];
      for (int q = 0; q < nk; q++) {
        const int t = from->base + q;
        slab[q] = (int) (griddem_cell_of(g, ch->x[t], ch->y[t], ch->z[t]) / nxy) / thick;
        first[slab[q] + 1]++;
      }
      for (int q = 0; q < nslab; q++) first[q + 1] += first[q];
      for (int q = 0; q < nk; q++) slots[first[slab[q]]++] = from->base + q;
      for (int q = nslab; q > 0; q--) first[q] = first[q - 1];
      first[0] = 0;
      double part[7] = {0.0};
      if (nslab == 1)    /* one thread: no OpenMP region */
        add_sums(part, sweep_across(&cx, into, pass.cut, slots, nk));
      for (int colour = 0; colour < 3 && nslab > 1; colour++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : part[:7])
        for (int q = colour; q < nslab; q += 3)
          add_sums(part, sweep_across(&cx, into, pass.cut, slots + first[q], first[q + 1] - first[q]));
      }
      for (int c = 0; c < 7; c++) totals[c] += part[c];
    }

  if (model->track_contacts && griddem_history_end(hist, nslot, order, nlocal, row_of) != 0)
    record_fault(result, GRIDDEM_FAULT_MEMORY, 0, 0);

  /* only owned particles' slots count contacts */
  int most = 0;
  const long contacts = griddem_history_counts(ch->ncontact, nslot, &most);
  for (int c = 0; c < 6; c++) result->virial[c] = totals[c];
  result->energy = totals[6];
  result->contacts = contacts;
  result->max_contacts = most;
  return result->fault;
}
