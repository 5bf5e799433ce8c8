/* CPU stencil sweep; see griddem_sweep.h. */
#include "griddem_sweep.h"

#include <math.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include <stdlib.h>
#include <string.h>

#define GROW(ptr, type, count) ((ptr) = (type *) realloc((ptr), sizeof(type) * (size_t) (count)))

int griddem_channels_fill(griddem_channels *ch, const griddem_bins *b, const griddem_particles *p)
{
  const int n = b->n;
  if (n > ch->cap) {
    const int cap = n + n / 4 + 16;
    double **reals[] = {&ch->x,  &ch->y,  &ch->z,  &ch->vx, &ch->vy, &ch->vz, &ch->wx, &ch->wy, &ch->wz,
                        &ch->rad, &ch->mass, &ch->fx, &ch->fy, &ch->fz, &ch->tx, &ch->ty, &ch->tz};
    for (size_t k = 0; k < sizeof(reals) / sizeof(reals[0]); k++)
      if (!GROW(*reals[k], double, cap)) return -1;
    if (!GROW(ch->tag, int64_t, cap) || !GROW(ch->type, int, cap) || !GROW(ch->mask, int, cap) ||
        !GROW(ch->ncontact, int, cap) || !GROW(ch->frozen, unsigned char, cap))
      return -1;
    ch->cap = cap;
  }
  ch->n = n;
  const int *tag32 = (const int *) p->tag;
  const int64_t *tag64 = (const int64_t *) p->tag;
#pragma omp parallel for schedule(static)
  for (int s = 0; s < n; s++) {
    const int i = b->order[s];
    ch->x[s] = p->x[3 * i];
    ch->y[s] = p->x[3 * i + 1];
    ch->z[s] = p->x[3 * i + 2];
    ch->vx[s] = p->v[3 * i];
    ch->vy[s] = p->v[3 * i + 1];
    ch->vz[s] = p->v[3 * i + 2];
    ch->wx[s] = p->omega[3 * i];
    ch->wy[s] = p->omega[3 * i + 1];
    ch->wz[s] = p->omega[3 * i + 2];
    ch->rad[s] = p->radius[i];
    ch->mass[s] = p->rmass[i];
    ch->tag[s] = p->tag_bytes == 8 ? tag64[i] : (int64_t) tag32[i];
    ch->type[s] = p->type[i];
    ch->mask[s] = p->mask[i];
    ch->frozen[s] = (p->mask[i] & p->frozen_bit) ? 1 : 0;
    ch->fx[s] = ch->fy[s] = ch->fz[s] = ch->tx[s] = ch->ty[s] = ch->tz[s] = 0.0;
    ch->ncontact[s] = 0;
  }
  return 0;
}

void griddem_channels_free(griddem_channels *ch)
{
  double *reals[] = {ch->x,  ch->y,  ch->z,  ch->vx, ch->vy, ch->vz, ch->wx, ch->wy, ch->wz,
                     ch->rad, ch->mass, ch->fx, ch->fy, ch->fz, ch->tx, ch->ty, ch->tz};
  for (size_t k = 0; k < sizeof(reals) / sizeof(reals[0]); k++) free(reals[k]);
  free(ch->tag), free(ch->type), free(ch->mask), free(ch->ncontact), free(ch->frozen);
  memset(ch, 0, sizeof(*ch));
}

/* Cell along axis d holding coordinate v, clamped to the grid; as griddem_cell_of. */
static inline int clamp_cell(const griddem_grid *g, int d, double v)
{
  const double c = floor((v - g->anchor[d]) * g->hinv) - (double) g->k0[d];
  if (c < 0.0) return 0;
  if (c >= (double) g->n[d]) return g->n[d] - 1;
  return (int) c;
}

/* Distance from coordinate v to the slab of cell c along one axis. */
static inline double slab_gap(double v, double lo, double h, int c)
{
  const double a = lo + c * h;
  if (v < a) return a - v;
  if (v > a + h) return v - a - h;
  return 0.0;
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
  const griddem_grid *g;
  const griddem_bins *b;
  griddem_channels *ch;
  int nlocal;
  double cut_extra;
  const griddem_model *model;
  const griddem_exclusions *excl;
  double dt;
  int history_update;
  griddem_history *hist;
  double *vatom;
  griddem_sweep_result *result;
} sweep_context;

/* Accumulators one thread adds up over its pairs. */
typedef struct sweep_sums {
  double virial[6];
  double energy;
} sweep_sums;

static int excluded_pair(const griddem_exclusions *e, const griddem_channels *ch, int a, int b)
{
  if (e->type_pair && e->type_pair[ch->type[a] * (e->ntypes + 1) + ch->type[b]]) return 1;
  for (int k = 0; k < e->ngroup_pairs; k++) {
    const int b1 = e->group_bits[2 * k], b2 = e->group_bits[2 * k + 1];
    if (((ch->mask[a] & b1) && (ch->mask[b] & b2)) || ((ch->mask[a] & b2) && (ch->mask[b] & b1)))
      return 1;
  }
  return 0;
}

/* Append (partner, values) to the next row of slot s, the values multiplied by parity unless it
 * is NULL; 0 if the row is full. */
static int history_append(const griddem_history *h, int nv, int s, int64_t partner,
                          const double *values, const double *parity)
{
  double *row = h->next + (size_t) s * h->stride;
  const int count = (int) row[0];
  if (count == h->slots) return 0;
  double *entry = row + 1 + (size_t) (1 + nv) * count;
  entry[0] = (double) partner;
  for (int k = 0; k < nv; k++) entry[1 + k] = parity ? parity[k] * values[k] : values[k];
  row[0] = (double) (count + 1);
  return 1;
}

/* Evaluate the contact of slots a and b (distance squared rsq, already known to touch) seen from
 * a, which is owned; b receives its share if it is owned too. */
static void sweep_pair(const sweep_context *cx, sweep_sums *sums, int a, int b, double rsq)
{
  griddem_channels *ch = cx->ch;
  const griddem_model *m = cx->model;
  const int *order = cx->b->order;
  const int ia = order[a], ib = order[b];
  const int b_owned = ib < cx->nlocal;
  const int nv = m->history_size;

  if (rsq == 0.0) {
    record_fault(cx->result, GRIDDEM_FAULT_COINCIDENT, ia, ib);
    return;
  }
  if (cx->excl && excluded_pair(cx->excl, ch, a, b)) return;

  griddem_contact_in c;
  c.delx = ch->x[a] - ch->x[b], c.dely = ch->y[a] - ch->y[b], c.delz = ch->z[a] - ch->z[b];
  c.rsq = rsq;
  c.radi = ch->rad[a], c.radj = ch->rad[b];
  c.vr1 = ch->vx[a] - ch->vx[b], c.vr2 = ch->vy[a] - ch->vy[b], c.vr3 = ch->vz[a] - ch->vz[b];
  c.wi1 = ch->wx[a], c.wi2 = ch->wy[a], c.wi3 = ch->wz[a];
  c.wj1 = ch->wx[b], c.wj2 = ch->wy[b], c.wj3 = ch->wz[b];
  c.meff = griddem_effective_mass(ch->mass[a], ch->mass[b], ch->frozen[a], ch->frozen[b]);

  double hv[GRIDDEM_MAX_HISTORY] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  if (nv && cx->hist->row_of[ia] >= 0) {
    const double *row = cx->hist->rows + (size_t) cx->hist->row_of[ia] * cx->hist->stride;
    const int count = (int) row[0];
    const double partner = (double) ch->tag[b];
    for (int k = 0; k < count; k++) {
      const double *entry = row + 1 + (size_t) (1 + nv) * k;
      if (entry[0] == partner) {
        for (int v = 0; v < nv; v++) hv[v] = entry[1 + v];
        break;
      }
    }
  }

  double fc[3], ta[3], tb[3];
  const double energy = griddem_pair_contact(m, ch->type[a], ch->type[b], &c, cx->dt,
                                             cx->history_update, hv, fc, ta, tb);
  if (nv) {
    int ok = history_append(cx->hist, nv, a, ch->tag[b], hv, NULL);
    if (ok && b_owned) ok = history_append(cx->hist, nv, b, ch->tag[a], hv, m->history_parity);
    if (!ok) record_fault(cx->result, GRIDDEM_FAULT_HISTORY_FULL, ia, ib);
  }

  ch->fx[a] += fc[0], ch->fy[a] += fc[1], ch->fz[a] += fc[2];
  ch->tx[a] += ta[0], ch->ty[a] += ta[1], ch->tz[a] += ta[2];
  ch->ncontact[a]++;
  if (b_owned) {
    ch->fx[b] -= fc[0], ch->fy[b] -= fc[1], ch->fz[b] -= fc[2];
    ch->tx[b] += tb[0], ch->ty[b] += tb[1], ch->tz[b] += tb[2];
    ch->ncontact[b]++;
  }

  /* a pair shared with another process is tallied half here, half there */
  const double share = b_owned ? 1.0 : 0.5;
  const double w[6] = {c.delx * fc[0], c.dely * fc[1], c.delz * fc[2],
                       c.delx * fc[1], c.delx * fc[2], c.dely * fc[2]};
  for (int k = 0; k < 6; k++) sums->virial[k] += share * w[k];
  sums->energy += share * energy;
  if (cx->vatom) {
    double *va = cx->vatom + 6 * (size_t) ia;
    for (int k = 0; k < 6; k++) va[k] += 0.5 * w[k];
    if (b_owned) {
      double *vb = cx->vatom + 6 * (size_t) ib;
      for (int k = 0; k < 6; k++) vb[k] += 0.5 * w[k];
    }
  }
}

#define CANDIDATE_BLOCK 64

/* All pairs (s, t > s) of slot s in contact, found over the forward half of its stencil. */
static void sweep_slot(const sweep_context *cx, sweep_sums *sums, int s)
{
  const griddem_grid *g = cx->g;
  const griddem_channels *ch = cx->ch;
  const int *start = cx->b->cell_start;
  const int *order = cx->b->order;
  const int s_owned = order[s] < cx->nlocal;
  const double *X = ch->x, *Y = ch->y, *Z = ch->z, *R = ch->rad;
  const double xi = X[s], yi = Y[s], zi = Z[s], radi = R[s];
  const double cut = (radi + cx->cut_extra) * (1.0 + 1e-9) + 1e-9 * g->h;
  const double cut2 = cut * cut;
  const long nx = g->n[0], nxy = (long) g->n[0] * g->n[1];
  const long cell = cx->b->cell[order[s]];
  const int czs = (int) (cell / nxy), cys = (int) ((cell % nxy) / nx);
  const int cz1 = clamp_cell(g, 2, zi + cut);
  const int cy0 = clamp_cell(g, 1, yi - cut), cy1 = clamp_cell(g, 1, yi + cut);
  int hits[CANDIDATE_BLOCK];

  for (int cz = czs; cz <= cz1; cz++) {
    const double gz = slab_gap(zi, g->lo[2], g->h, cz);
    for (int cy = (cz == czs ? cys : cy0); cy <= cy1; cy++) {
      const double gy = slab_gap(yi, g->lo[1], g->h, cy);
      const double g2 = gy * gy + gz * gz;
      if (g2 > cut2) continue;
      const double ext = sqrt(cut2 - g2);
      const long rowcell = nx * cy + nxy * cz;
      int jbegin = start[rowcell + clamp_cell(g, 0, xi - ext)];
      const int jend = start[rowcell + clamp_cell(g, 0, xi + ext) + 1];
      if (cz == czs && cy == cys && jbegin <= s) jbegin = s + 1;
      /* branch-free distance test over a block of candidates, then the few that touch */
      for (int t0 = jbegin; t0 < jend; t0 += CANDIDATE_BLOCK) {
        const int t1 = t0 + CANDIDATE_BLOCK < jend ? t0 + CANDIDATE_BLOCK : jend;
        int nhit = 0;
        for (int t = t0; t < t1; t++) {
          const double dx = xi - X[t], dy = yi - Y[t], dz = zi - Z[t];
          const double rs = radi + R[t];
          hits[nhit] = t;
          nhit += (dx * dx + dy * dy + dz * dz < rs * rs);
        }
        for (int k = 0; k < nhit; k++) {
          const int t = hits[k];
          const int t_owned = order[t] < cx->nlocal;
          if (!s_owned && !t_owned) continue;
          const double dx = xi - X[t], dy = yi - Y[t], dz = zi - Z[t];
          const double rsq = dx * dx + dy * dy + dz * dz;
          if (s_owned) sweep_pair(cx, sums, s, t, rsq);
          else sweep_pair(cx, sums, t, s, rsq);
        }
      }
    }
  }
}

int griddem_sweep(const griddem_grid *g, const griddem_bins *b, griddem_channels *ch, int nlocal,
                  double cut_extra, const griddem_model *model, const griddem_exclusions *excl,
                  double dt, int history_update, griddem_history *hist, double *f, double *torque,
                  double *vatom, griddem_sweep_result *result)
{
  const sweep_context cx = {g, b, ch, nlocal, cut_extra, model,
                            (excl && (excl->type_pair || excl->ngroup_pairs)) ? excl : NULL,
                            dt, history_update, hist, vatom, result};
  const long nxy = (long) g->n[0] * g->n[1];
  memset(result, 0, sizeof(*result));
  if (model->history_size)
    for (int s = 0; s < b->n; s++)
      if (b->order[s] < nlocal) hist->next[(size_t) s * hist->stride] = 0.0;

  /* slabs of cell layers along z, thick enough that a slot's pairs stay within the next slab */
  const double cutmax = 2.0 * cut_extra * (1.0 + 1e-9) + 1e-9 * g->h;
  const int reach = (int) ceil(cutmax * g->hinv) + 1;
  int nthreads = 1;
#ifdef _OPENMP
  nthreads = omp_get_max_threads();
#endif
  int thick = g->n[2];
  if (nthreads > 1) {
    thick = g->n[2] / (4 * nthreads);
    if (thick < reach) thick = reach;
  }
  const int nslab = (g->n[2] + thick - 1) / thick;

  double v0 = 0.0, v1 = 0.0, v2 = 0.0, v3 = 0.0, v4 = 0.0, v5 = 0.0, energy = 0.0;
  for (int colour = 0; colour < 2; colour++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : v0, v1, v2, v3, v4, v5, energy)
    for (int k = colour; k < nslab; k += 2) {
      sweep_sums sums;
      memset(&sums, 0, sizeof(sums));
      const int zlo = k * thick, zhi = (k + 1) * thick < g->n[2] ? (k + 1) * thick : g->n[2];
      const int sbegin = b->cell_start[zlo * nxy], send = b->cell_start[zhi * nxy];
      for (int s = sbegin; s < send; s++) sweep_slot(&cx, &sums, s);
      v0 += sums.virial[0], v1 += sums.virial[1], v2 += sums.virial[2];
      v3 += sums.virial[3], v4 += sums.virial[4], v5 += sums.virial[5];
      energy += sums.energy;
    }
  }

  long contacts = 0;
  int most = 0;
  for (int s = 0; s < b->n; s++) {
    const int i = b->order[s];
    if (i >= nlocal) continue;
    f[3 * i] += ch->fx[s], f[3 * i + 1] += ch->fy[s], f[3 * i + 2] += ch->fz[s];
    torque[3 * i] += ch->tx[s], torque[3 * i + 1] += ch->ty[s], torque[3 * i + 2] += ch->tz[s];
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
