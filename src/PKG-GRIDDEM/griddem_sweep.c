/* CPU stencil sweep; see griddem_sweep.h. */
#define _POSIX_C_SOURCE 200112L /* posix_memalign */
#include "griddem_sweep.h"

#include <math.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <stdlib.h>
#include <string.h>

/* Cache-line aligned array of count elements of size bytes (contents not kept). */
static int grow_aligned(void **ptr, size_t size, int count)
{
  free(*ptr);
  *ptr = NULL;
  return posix_memalign(ptr, 64, size * (size_t) count) == 0 ? 0 : -1;
}

int griddem_channels_fill(griddem_channels *ch, const griddem_bins *b, const griddem_particles *p)
{
  const int n = b->n;
  if (n > ch->cap) {
    const int cap = n + n / 4 + 16;
    void **arrays[] = {(void **) &ch->x, (void **) &ch->y, (void **) &ch->z, (void **) &ch->rad,
                       (void **) &ch->tag};
    for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); k++)
      if (grow_aligned(arrays[k], 8, cap) != 0) return -1;
    if (grow_aligned((void **) &ch->state, sizeof(griddem_slot_state), cap) != 0 ||
        grow_aligned((void **) &ch->sum, sizeof(griddem_slot_sum), cap) != 0 ||
        grow_aligned((void **) &ch->ncontact, sizeof(int), cap) != 0)
      return -1;
    ch->cap = cap;
  }
  ch->n = n;
  ch->frozen_bit = p->frozen_bit;
  double vmax2 = 0.0;
  int nonfinite = 0;
#pragma omp parallel for schedule(static) reduction(max : vmax2) reduction(| : nonfinite)
  for (int s = 0; s < n; s++) {
    const int i = b->order[s];
    if (i < p->nlocal) {
      const double *v = p->v + 3 * (size_t) i;
      const double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
      nonfinite |= !isfinite(v2);
      vmax2 = v2 > vmax2 ? v2 : vmax2;
    }
    ch->x[s] = p->x[3 * i];
    ch->y[s] = p->x[3 * i + 1];
    ch->z[s] = p->x[3 * i + 2];
    ch->rad[s] = p->radius[i];
    griddem_slot_state *st = &ch->state[s];
    for (int d = 0; d < 3; d++) st->v[d] = p->v[3 * i + d], st->w[d] = p->omega[3 * i + d];
    st->mass = p->rmass[i];
    st->type = p->type[i];
    st->mask = p->mask[i];
    ch->tag[s] = griddem_key_at(p->tag, p->tag_bytes, i);
    memset(&ch->sum[s], 0, sizeof(griddem_slot_sum));
    ch->ncontact[s] = 0;
  }
  ch->vmax2 = vmax2;
  ch->nonfinite = nonfinite;
  return 0;
}

void griddem_channels_free(griddem_channels *ch)
{
  free(ch->x), free(ch->y), free(ch->z), free(ch->rad), free(ch->tag);
  free(ch->state), free(ch->sum), free(ch->ncontact);
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

/* Everything one sweep reads, shared by the threads. */
typedef struct sweep_context {
  const int *order;      /* particle of each slot of the channels */
  griddem_channels *ch;
  int nlocal;
  const griddem_model *model;
  const griddem_exclusions *excl;
  double dt;
  int history_update;
  griddem_history *hist;
  const int *row_of;
  double *vatom;
  int want_virial;
  griddem_sweep_result *result;
} sweep_context;

/* Accumulators one thread adds up over its pairs. */
typedef struct sweep_sums {
  double virial[6];
  double energy;
  griddem_history_log *log;
} sweep_sums;

/* Evaluate the contact of slots a and b (distance squared rsq, within reach) seen from a, which is
 * owned; b receives its share if it is owned too. */
static void sweep_pair(const sweep_context *cx, sweep_sums *sums, int a, int b, double rsq)
{
  griddem_channels *ch = cx->ch;
  const griddem_model *m = cx->model;
  const int *order = cx->order;
  const int ia = order[a], ib = order[b];
  const int b_owned = ib < cx->nlocal;
  const int nv = m->history_size;

  if (rsq == 0.0) {
    record_fault(cx->result, GRIDDEM_FAULT_COINCIDENT, ia, ib);
    return;
  }
  const griddem_slot_state *A = &ch->state[a], *B = &ch->state[b];
  if (cx->excl && griddem_excluded(cx->excl, A->type, A->mask, B->type, B->mask)) return;

  const griddem_pair_params *law = griddem_model_pair(m, A->type, B->type);
  const double *stored = m->track_contacts
      ? griddem_history_find(cx->hist, cx->row_of[ia], (double) ch->tag[b]) : NULL;
  /* past touching (reach_extra > 0) only pairs that touched before may still interact */
  if (m->reach_extra > 0.0 && !griddem_contact_touch(law, rsq, ch->rad[a], ch->rad[b], stored != NULL))
    return;

  griddem_contact c;
  c.dx[0] = ch->x[a] - ch->x[b], c.dx[1] = ch->y[a] - ch->y[b], c.dx[2] = ch->z[a] - ch->z[b];
  c.rsq = rsq;
  c.radi = ch->rad[a], c.radj = ch->rad[b];
  for (int d = 0; d < 3; d++) c.vr[d] = A->v[d] - B->v[d], c.wi[d] = A->w[d], c.wj[d] = B->w[d];
  c.meff = griddem_effective_mass(A->mass, B->mass, (A->mask & ch->frozen_bit) != 0,
                                  (B->mask & ch->frozen_bit) != 0);
  c.dt = cx->dt;
  c.history_update = cx->history_update;

  double hv[GRIDDEM_MAX_HISTORY];
  for (int v = 0; v < nv; v++) hv[v] = stored ? stored[v] : 0.0;

  double fc[3], ta[3], tb[3];
  const double energy = griddem_contact_eval(law, &c, hv, fc, ta, tb);
  if (m->track_contacts && griddem_history_log_contact(sums->log, nv, a, b, b_owned, hv) != 0)
    record_fault(cx->result, GRIDDEM_FAULT_MEMORY, ia, ib);

  griddem_slot_sum *sa = &ch->sum[a], *sb = &ch->sum[b];
  for (int d = 0; d < 3; d++) sa->f[d] += fc[d], sa->t[d] += ta[d];
  ch->ncontact[a]++;
  if (b_owned) {
    for (int d = 0; d < 3; d++) sb->f[d] -= fc[d], sb->t[d] += tb[d];
    ch->ncontact[b]++;
  }

  /* a pair shared with another process is tallied half here, half there */
  const double share = b_owned ? 1.0 : 0.5;
  sums->energy += share * energy;
  if (!cx->want_virial && !cx->vatom) return;
  const double w[6] = {c.dx[0] * fc[0], c.dx[1] * fc[1], c.dx[2] * fc[2],
                       c.dx[0] * fc[1], c.dx[0] * fc[2], c.dx[1] * fc[2]};
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

/* One row of the forward half stencil: cells (dx, dy, dz) for dx in [dxlo, dxhi]. */
typedef struct stencil_row {
  int dy, dz, dxlo, dxhi;
} stencil_row;

#define MAX_REACH GRIDDEM_MAX_REACH
#define MAX_ROWS ((MAX_REACH + 1) * (2 * MAX_REACH + 1))

/* Rows of cells that can hold a centre within cutmax of a centre in cell (0,0,0) and come after
 * it in sorted order: the row (0,0) from the cell itself on, rows dy > 0 of layer dz = 0, and
 * all rows of layers dz > 0; the corners are pruned by the smallest cell-to-cell distance. */
static int build_stencil(const griddem_grid *g, double cutmax, stencil_row *rows)
{
  const double h = g->h, c2 = cutmax * cutmax;
  const int reach = griddem_stencil_reach(h, cutmax);
  if (reach > MAX_REACH) return 0;
  int n = 0;
  for (int dz = 0; dz <= reach; dz++)
    for (int dy = dz == 0 ? 0 : -reach; dy <= reach; dy++) {
      const double gz = dz > 1 ? (dz - 1) * h : 0.0;
      const double gy = abs(dy) > 1 ? (abs(dy) - 1) * h : 0.0;
      const double g2 = gy * gy + gz * gz;
      if (g2 >= c2) continue;
      int dx = (int) ceil(sqrt(c2 - g2) / h);
      if (dx > reach) dx = reach;
      rows[n].dy = dy, rows[n].dz = dz;
      rows[n].dxlo = (dy == 0 && dz == 0) ? 0 : -dx;
      rows[n].dxhi = dx;
      n++;
    }
  return n;
}

#define CANDIDATE_BLOCK 64

/* Evaluate slot s's touching candidates hits[0 .. *nhit-1] and empty the list. The partners'
 * state and sums are requested from memory first, so their loads overlap. */
static void sweep_hits(const sweep_context *cx, sweep_sums *sums, int s, const int *hits, int *nhit)
{
  const griddem_channels *ch = cx->ch;
  const int *order = cx->order;
#ifdef __GNUC__
  for (int q = 0; q < *nhit; q++) {
    __builtin_prefetch(&ch->state[hits[q]]);
    __builtin_prefetch(&ch->sum[hits[q]], 1);
  }
#endif
  const int s_owned = order[s] < cx->nlocal;
  const double xi = ch->x[s], yi = ch->y[s], zi = ch->z[s];
  for (int q = 0; q < *nhit; q++) {
    const int t = hits[q];
    const int t_owned = order[t] < cx->nlocal;
    if (!s_owned && !t_owned) continue;
    const double dx = xi - ch->x[t], dy = yi - ch->y[t], dz = zi - ch->z[t];
    const double rsq = dx * dx + dy * dy + dz * dz;
    if (s_owned) sweep_pair(cx, sums, s, t, rsq);
    else sweep_pair(cx, sums, t, s, rsq);
  }
  *nhit = 0;
}

/* Pairs (s, t) of the slots s in cell (x,y,z) of class grid k with the slots t > s of its forward
 * stencil (slots of the channels are the class's slots + k->base). */
static void sweep_cell(const sweep_context *cx, sweep_sums *sums, const griddem_class_grid *k,
                       const stencil_row *rows, int nrows, int x, int y, int z)
{
  const griddem_grid *g = k->g;
  const griddem_channels *ch = cx->ch;
  const int *start = k->b->cell_start, base = k->base;
  const long nx = g->n[0], nxy = (long) g->n[0] * g->n[1];
  const long cell = x + nx * y + nxy * z;
  const double *X = ch->x, *Y = ch->y, *Z = ch->z, *R = ch->rad;

  /* slot ranges of the stencil rows, shared by the cell's centres */
  int lo[MAX_ROWS], hi[MAX_ROWS], nrange = 0;
  for (int r = 0; r < nrows; r++) {
    const int yy = y + rows[r].dy, zz = z + rows[r].dz;
    if (yy < 0 || yy >= g->n[1] || zz >= g->n[2]) continue;
    const int x0 = x + rows[r].dxlo < 0 ? 0 : x + rows[r].dxlo;
    const int x1 = x + rows[r].dxhi >= g->n[0] ? g->n[0] - 1 : x + rows[r].dxhi;
    const long rowcell = nx * yy + nxy * zz;
    lo[nrange] = base + start[rowcell + x0];
    hi[nrange] = base + start[rowcell + x1 + 1];
    if (hi[nrange] > lo[nrange] || r == 0) nrange++;
  }

  int hits[CANDIDATE_BLOCK];
  const double reach = cx->model->reach_extra;
  for (int s = base + start[cell]; s < base + start[cell + 1]; s++) {
    const double xi = X[s], yi = Y[s], zi = Z[s], radi = R[s] + reach;
    int nhit = 0;
    for (int q = 0; q < nrange; q++) {
      const int jbegin = q == 0 ? s + 1 : lo[q], jend = hi[q];
      /* branch-free distance test over runs of candidates; the few that touch are collected */
      for (int t0 = jbegin; t0 < jend; t0 += CANDIDATE_BLOCK / 2) {
        const int t1 = t0 + CANDIDATE_BLOCK / 2 < jend ? t0 + CANDIDATE_BLOCK / 2 : jend;
        for (int t = t0; t < t1; t++) {
          const double dx = xi - X[t], dy = yi - Y[t], dz = zi - Z[t];
          const double rs = radi + R[t];
          hits[nhit] = t;
          nhit += (dx * dx + dy * dy + dz * dz < rs * rs);
        }
        if (nhit > CANDIDATE_BLOCK / 2) sweep_hits(cx, sums, s, hits, &nhit);
      }
    }
    sweep_hits(cx, sums, s, hits, &nhit);
  }
}

/* Pairs of the slots slots[0..n-1] (of a smaller class) with the particles of the coarser class
 * grid l (l holds the larger spheres): every cell of l within reach of the slot's cell, the slot
 * on its own side. */
static void sweep_across(const sweep_context *cx, sweep_sums *sums, const griddem_class_grid *l,
                         int reach, const int *slots, int n)
{
  const griddem_grid *g = l->g;
  const griddem_channels *ch = cx->ch;
  const int *start = l->b->cell_start;
  const long nx = g->n[0], nxy = (long) g->n[0] * g->n[1];
  const double *X = ch->x, *Y = ch->y, *Z = ch->z, *R = ch->rad;
  const double extra = cx->model->reach_extra;
  int hits[CANDIDATE_BLOCK];
  for (int q = 0; q < n; q++) {
    const int s = slots[q];
    const double xi = X[s], yi = Y[s], zi = Z[s], radi = R[s] + extra;
    const long c = griddem_cell_of(g, xi, yi, zi);
    const int x = (int) (c % nx), y = (int) ((c / nx) % g->n[1]), z = (int) (c / nxy);
    const int x0 = x - reach < 0 ? 0 : x - reach, x1 = x + reach >= g->n[0] ? g->n[0] - 1 : x + reach;
    int nhit = 0;
    for (int zz = z - reach; zz <= z + reach; zz++)
      for (int yy = y - reach; yy <= y + reach; yy++) {
        if (zz < 0 || zz >= g->n[2] || yy < 0 || yy >= g->n[1]) continue;
        const long rowcell = nx * yy + nxy * zz;
        const int jend = l->base + start[rowcell + x1 + 1];
        for (int t = l->base + start[rowcell + x0]; t < jend; t++) {
          const double dx = xi - X[t], dy = yi - Y[t], dz = zi - Z[t];
          const double rs = radi + R[t];
          hits[nhit] = t;
          nhit += (dx * dx + dy * dy + dz * dz < rs * rs);
          if (nhit == CANDIDATE_BLOCK) sweep_hits(cx, sums, s, hits, &nhit);
        }
      }
    sweep_hits(cx, sums, s, hits, &nhit);
  }
}

/* Layers of cells per slab for nthreads threads: about four slabs per thread, at least reach
 * thick; one slab for one thread (so one thread visits in sorted order) */
static int slab_thickness(int nz, int nthreads, int reach)
{
  if (nthreads == 1) return nz;
  const int thick = nz / (4 * nthreads);
  return thick < reach ? reach : thick;
}

/* A thread's empty accumulators, logging into its own history log */
static sweep_sums thread_sums(const griddem_model *model, griddem_history *hist)
{
  sweep_sums sums;
  memset(&sums, 0, sizeof(sums));
#ifdef _OPENMP
  if (model->track_contacts) sums.log = &hist->logs[omp_get_thread_num()];
#else
  if (model->track_contacts) sums.log = &hist->logs[0];
#endif
  return sums;
}

/* Largest contact distance between spheres of radii up to r1 and r2, with a margin for the
 * rounding of coordinates into the cells of g */
static double contact_reach(const griddem_grid *g, double r1, double r2, double extra)
{
  double extent = 0.0;
  for (int d = 0; d < 3; d++) extent = fmax(extent, fabs(g->lo[d]) + g->n[d] * g->h);
  return (r1 + r2 + extra) * (1.0 + 1e-10) + 1e-14 * extent;
}

int griddem_sweep(const griddem_class_grid *cls, int ncls, const int *order, griddem_channels *ch,
                  int nlocal, const griddem_model *model, const griddem_exclusions *excl, double dt,
                  int history_update, griddem_history *hist, const int *row_of, double *f,
                  double *torque, double *vatom, int want_virial, griddem_sweep_result *result)
{
  const sweep_context cx = {order, ch, nlocal, model,
                            (excl && (excl->type_pair || excl->ngroup_pairs || excl->both_bit)) ? excl : NULL,
                            dt, history_update, hist, row_of, vatom, want_virial, result};
  memset(result, 0, sizeof(*result));
  int nthreads = 1;
#ifdef _OPENMP
  nthreads = omp_get_max_threads();
#endif
  if (model->track_contacts && griddem_history_begin(hist, nthreads) != 0) {
    result->fault = GRIDDEM_FAULT_MEMORY;
    return result->fault;
  }

  double v0 = 0.0, v1 = 0.0, v2 = 0.0, v3 = 0.0, v4 = 0.0, v5 = 0.0, energy = 0.0;
  for (int kc = 0; kc < ncls; kc++) {
    /* pairs within class kc on its own grid */
    const griddem_class_grid *k = &cls[kc];
    const griddem_grid *g = k->g;
    const griddem_bins *b = k->b;
    if (b->n == 0) continue;
    const long nxy = (long) g->n[0] * g->n[1];
    stencil_row rows[MAX_ROWS];
    const int nrows = build_stencil(g, contact_reach(g, k->rmax, k->rmax, model->reach_extra), rows);
    if (nrows == 0) {
      result->fault = GRIDDEM_FAULT_STENCIL;
      return result->fault;
    }
    const int reach = rows[nrows - 1].dz;

    /* slabs of cell layers along z, thick enough that a slot's pairs stay within the next slab */
    const int thick = slab_thickness(g->n[2], nthreads, reach);
    const int nslab = (g->n[2] + thick - 1) / thick;
    for (int colour = 0; colour < 2; colour++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : v0, v1, v2, v3, v4, v5, energy)
      for (int q = colour; q < nslab; q += 2) {
        sweep_sums sums = thread_sums(model, hist);
        const int zlo = q * thick, zhi = (q + 1) * thick < g->n[2] ? (q + 1) * thick : g->n[2];
        /* occupied cells only, found through their slots: a dilute grid costs nothing extra */
        for (int s = b->cell_start[zlo * nxy]; s < b->cell_start[zhi * nxy];) {
          const long c = b->cell[b->order[s]];
          sweep_cell(&cx, &sums, k, rows, nrows, (int) (c % g->n[0]), (int) ((c / g->n[0]) % g->n[1]),
                     (int) (c / nxy));
          s = b->cell_start[c + 1];
        }
        v0 += sums.virial[0], v1 += sums.virial[1], v2 += sums.virial[2];
        v3 += sums.virial[3], v4 += sums.virial[4], v5 += sums.virial[5];
        energy += sums.energy;
      }
    }
  }

  /* pairs across classes, from the smaller sphere into the coarser grid. Threads take the small
     spheres by slabs of the coarse grid's cell layers (at least the reach thick) in three colours:
     the partners of slabs q and q+3 lie in disjoint slabs, so no two threads write one particle */
  for (int kc = 1; kc < ncls; kc++)
    for (int lc = 0; lc < kc; lc++) {
      const griddem_class_grid *k = &cls[kc], *l = &cls[lc];
      const int nk = k->b->n;
      if (nk == 0 || l->b->n == 0) continue;
      const griddem_grid *g = l->g;
      const int reach = griddem_stencil_reach(g->h, contact_reach(g, k->rmax, l->rmax, model->reach_extra));
      if (reach > MAX_REACH) {
        result->fault = GRIDDEM_FAULT_STENCIL;
        return result->fault;
      }
      const int thick = slab_thickness(g->n[2], nthreads, reach);
      const int nslab = (g->n[2] + thick - 1) / thick;
      /* the small spheres' slots by slab of the coarse grid (a stable counting sort) */
      int *slab = (int *) malloc(sizeof(int) * (size_t) nk), *slots = (int *) malloc(sizeof(int) * (size_t) nk);
      int *first = (int *) calloc((size_t) nslab + 1, sizeof(int));
      if (!slab || !slots || !first) {
        free(slab), free(slots), free(first);
        result->fault = GRIDDEM_FAULT_MEMORY;
        return result->fault;
      }
      const long nxy = (long) g->n[0] * g->n[1];
      for (int q = 0; q < nk; q++) {
        const int s = k->base + q;
        slab[q] = (int) (griddem_cell_of(g, ch->x[s], ch->y[s], ch->z[s]) / nxy) / thick;
        first[slab[q] + 1]++;
      }
      for (int q = 0; q < nslab; q++) first[q + 1] += first[q];
      for (int q = 0; q < nk; q++) slots[first[slab[q]]++] = k->base + q;
      for (int q = nslab; q > 0; q--) first[q] = first[q - 1];
      first[0] = 0;
      for (int colour = 0; colour < 3; colour++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : v0, v1, v2, v3, v4, v5, energy)
        for (int q = colour; q < nslab; q += 3) {
          sweep_sums sums = thread_sums(model, hist);
          sweep_across(&cx, &sums, l, reach, slots + first[q], first[q + 1] - first[q]);
          v0 += sums.virial[0], v1 += sums.virial[1], v2 += sums.virial[2];
          v3 += sums.virial[3], v4 += sums.virial[4], v5 += sums.virial[5];
          energy += sums.energy;
        }
      }
      free(slab), free(slots), free(first);
    }

  int nslot = 0;
  for (int kc = 0; kc < ncls; kc++) nslot += cls[kc].b->n;
  if (model->track_contacts &&
      griddem_history_build(hist, nslot, ch->ncontact, ch->tag, model->history_parity) != 0)
    record_fault(result, GRIDDEM_FAULT_MEMORY, 0, 0);

  long contacts = 0;
  int most = 0;
  for (int s = 0; s < nslot; s++) {
    const int i = order[s];
    if (i >= nlocal) continue;
    for (int d = 0; d < 3; d++) f[3 * i + d] += ch->sum[s].f[d], torque[3 * i + d] += ch->sum[s].t[d];
    contacts += ch->ncontact[s];
    if (ch->ncontact[s] > most) most = ch->ncontact[s];
  }
  result->virial[0] = v0, result->virial[1] = v1, result->virial[2] = v2;
  result->virial[3] = v3, result->virial[4] = v4, result->virial[5] = v5;
  result->energy = energy;
  result->contacts = contacts;
  result->max_contacts = most;
  return result->fault;
}
