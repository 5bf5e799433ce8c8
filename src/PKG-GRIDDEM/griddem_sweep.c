/* CPU stencil sweep; see griddem_sweep.h. */
#include "griddem_sweep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GROW(ptr, type, count) ((ptr) = (type *) realloc((ptr), sizeof(type) * (size_t) (count)))

int griddem_channels_fill(griddem_channels *ch, const griddem_bins *b, const griddem_particles *p)
{
  const int n = b->n;
  if (n > ch->cap) {
    const int cap = n + n / 4 + 16;
    if (!GROW(ch->x, double, cap) || !GROW(ch->y, double, cap) || !GROW(ch->z, double, cap) ||
        !GROW(ch->vx, double, cap) || !GROW(ch->vy, double, cap) || !GROW(ch->vz, double, cap) ||
        !GROW(ch->wx, double, cap) || !GROW(ch->wy, double, cap) || !GROW(ch->wz, double, cap) ||
        !GROW(ch->rad, double, cap) || !GROW(ch->mass, double, cap) ||
        !GROW(ch->tag, int64_t, cap) || !GROW(ch->frozen, unsigned char, cap))
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
    ch->frozen[s] = (p->mask && (p->mask[i] & p->frozen_bit)) ? 1 : 0;
  }
  return 0;
}

void griddem_channels_free(griddem_channels *ch)
{
  free(ch->x), free(ch->y), free(ch->z), free(ch->vx), free(ch->vy), free(ch->vz);
  free(ch->wx), free(ch->wy), free(ch->wz), free(ch->rad), free(ch->mass);
  free(ch->tag), free(ch->frozen);
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

int griddem_sweep(const griddem_grid *g, const griddem_bins *b, const griddem_channels *ch,
                  int nlocal, double cut_extra, const griddem_hooke_params *params, double dt,
                  int shearupdate, griddem_history *hist, double *f, double *torque, double *vatom,
                  int want_virial, griddem_sweep_result *result)
{
  const int use_history = params->tangential == GRIDDEM_TANGENTIAL_HISTORY;
  const int slots = use_history ? hist->slots : 0;
  const int *start = b->cell_start;
  const int *order = b->order;
  const long nx = g->n[0], nxy = (long) g->n[0] * g->n[1];
  double v0 = 0.0, v1 = 0.0, v2 = 0.0, v3 = 0.0, v4 = 0.0, v5 = 0.0;
  double energy = 0.0;
  long contacts = 0;
  int most = 0;

  memset(result, 0, sizeof(*result));

#pragma omp parallel reduction(+ : v0, v1, v2, v3, v4, v5, energy, contacts) reduction(max : most)
  {
    /* this particle's new history, built while its old one is still read */
    double *fresh = use_history ? (double *) malloc(sizeof(double) * 4 * (size_t) slots) : NULL;

#pragma omp for schedule(dynamic, 256)
    for (int s = 0; s < b->n; s++) {
      const int i = order[s];
      if (i >= nlocal) continue;
      const double xi = ch->x[s], yi = ch->y[s], zi = ch->z[s], radi = ch->rad[s];
      const double cut = (radi + cut_extra) * (1.0 + 1e-9) + 1e-9 * g->h;
      const double cut2 = cut * cut;
      double *row = use_history ? hist->rows + (size_t) i * hist->stride : NULL;
      const int nold = use_history ? (int) row[0] : 0;
      int nnew = 0;
      double fx = 0.0, fy = 0.0, fz = 0.0, tx = 0.0, ty = 0.0, tz = 0.0;
      double w0 = 0.0, w1 = 0.0, w2 = 0.0, w3 = 0.0, w4 = 0.0, w5 = 0.0;
      int ncontact = 0;

      const int cz0 = clamp_cell(g, 2, zi - cut);
      const int cz1 = clamp_cell(g, 2, zi + cut);
      const int cy0 = clamp_cell(g, 1, yi - cut);
      const int cy1 = clamp_cell(g, 1, yi + cut);
      for (int cz = cz0; cz <= cz1; cz++) {
        const double gz = slab_gap(zi, g->lo[2], g->h, cz);
        for (int cy = cy0; cy <= cy1; cy++) {
          const double gy = slab_gap(yi, g->lo[1], g->h, cy);
          const double g2 = gy * gy + gz * gz;
          if (g2 > cut2) continue;
          const double ext = sqrt(cut2 - g2);
          const long rowcell = nx * cy + nxy * cz;
          const int jbegin = start[rowcell + clamp_cell(g, 0, xi - ext)];
          const int jend = start[rowcell + clamp_cell(g, 0, xi + ext) + 1];
          for (int t = jbegin; t < jend; t++) {
            const double delx = xi - ch->x[t], dely = yi - ch->y[t], delz = zi - ch->z[t];
            const double rsq = delx * delx + dely * dely + delz * delz;
            const double radsum = radi + ch->rad[t];
            if (rsq >= radsum * radsum || t == s) continue;
            if (rsq == 0.0) {
              record_fault(result, GRIDDEM_FAULT_COINCIDENT, i, order[t]);
              continue;
            }
            griddem_contact_in c;
            c.delx = delx, c.dely = dely, c.delz = delz, c.rsq = rsq;
            c.radi = radi, c.radj = ch->rad[t];
            c.vr1 = ch->vx[s] - ch->vx[t];
            c.vr2 = ch->vy[s] - ch->vy[t];
            c.vr3 = ch->vz[s] - ch->vz[t];
            c.wi1 = ch->wx[s], c.wi2 = ch->wy[s], c.wi3 = ch->wz[s];
            c.wj1 = ch->wx[t], c.wj2 = ch->wy[t], c.wj3 = ch->wz[t];
            c.meff = griddem_effective_mass(ch->mass[s], ch->mass[t], ch->frozen[s], ch->frozen[t]);

            double shear[3] = {0.0, 0.0, 0.0};
            if (use_history) {
              const double partner = (double) ch->tag[t];
              for (int k = 0; k < nold; k++)
                if (row[1 + 4 * k] == partner) {
                  shear[0] = row[2 + 4 * k], shear[1] = row[3 + 4 * k], shear[2] = row[4 + 4 * k];
                  break;
                }
            }
            double fc[3], tor[3];
            griddem_hooke_contact(params, &c, dt, shearupdate, shear, fc, tor);
            if (use_history) {
              if (nnew == slots) {
                record_fault(result, GRIDDEM_FAULT_HISTORY_FULL, i, order[t]);
              } else {
                double *slot = fresh + 4 * nnew++;
                slot[0] = (double) ch->tag[t];
                slot[1] = shear[0], slot[2] = shear[1], slot[3] = shear[2];
              }
            }
            ncontact++;
            /* half of the pair's spring energy from each side */
            const double overlap = radsum - sqrt(rsq);
            energy += 0.25 * (params->kn * overlap * overlap +
                              params->kt * (shear[0] * shear[0] + shear[1] * shear[1] + shear[2] * shear[2]));
            fx += fc[0], fy += fc[1], fz += fc[2];
            tx -= radi * tor[0], ty -= radi * tor[1], tz -= radi * tor[2];
            if (want_virial || vatom) {
              w0 += 0.5 * delx * fc[0], w1 += 0.5 * dely * fc[1], w2 += 0.5 * delz * fc[2];
              w3 += 0.5 * delx * fc[1], w4 += 0.5 * delx * fc[2], w5 += 0.5 * dely * fc[2];
            }
          }
        }
      }
      f[3 * i] += fx, f[3 * i + 1] += fy, f[3 * i + 2] += fz;
      torque[3 * i] += tx, torque[3 * i + 1] += ty, torque[3 * i + 2] += tz;
      if (vatom) {
        double *va = vatom + 6 * (size_t) i;
        va[0] += w0, va[1] += w1, va[2] += w2, va[3] += w3, va[4] += w4, va[5] += w5;
      }
      v0 += w0, v1 += w1, v2 += w2, v3 += w3, v4 += w4, v5 += w5;
      if (use_history) {
        row[0] = (double) nnew;
        memcpy(row + 1, fresh, sizeof(double) * 4 * (size_t) nnew);
      }
      contacts += ncontact;
      if (ncontact > most) most = ncontact;
    }
    free(fresh);
  }
  result->virial[0] = v0, result->virial[1] = v1, result->virial[2] = v2;
  result->virial[3] = v3, result->virial[4] = v4, result->virial[5] = v5;
  result->energy = energy;
  result->contacts = contacts;
  result->max_contacts = most;
  return result->fault;
}
