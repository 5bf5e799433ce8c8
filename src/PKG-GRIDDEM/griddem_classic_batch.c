/* The classic laws over a batch of contacts; see griddem_classic_batch.h. This file is compiled
 * without contraction into fused multiply-adds (-ffp-contract=off), so that its vector copies
 * round as the scalar law, and with sqrt setting no errno and floating-point operations assumed
 * not to trap (-fno-math-errno, -fno-trapping-math), so that the law's branches become selects
 * between lanes (which changes no value). */
#include "griddem_classic_batch.h"

int griddem_classic_batchable(const griddem_pair_params *p)
{
  return p->classic && p->tangential.model == GRIDDEM_TANGENTIAL_HOOKE_HISTORY;
}

/* The lanes with hertz and energy (whether each lane's elastic energy is kept) constants, and the
 * law's tangential model the constant it is (a batchable law's), so that no branch on them stays
 * in the loop and a copy without energy computes none */
#ifdef __GNUC__
__attribute__((always_inline))
#endif
static inline void eval_lanes(const griddem_pair_params *p, griddem_classic_batch *restrict b, double dt,
                              const int hertz, const int energy)
{
  griddem_pair_params law = *p;
  law.tangential.model = GRIDDEM_TANGENTIAL_HOOKE_HISTORY;
  for (int k = 0; k < b->n; k++) {
    double dx[3], vi[3], vj[3], wi[3], wj[3], shear[3], f[3], ti[3], tj[3];
    for (int d = 0; d < 3; d++) {
      dx[d] = b->dx[d][k], vi[d] = b->vi[d][k], vj[d] = b->vj[d][k];
      wi[d] = b->wi[d][k], wj[d] = b->wj[d][k], shear[d] = b->shear[d][k];
    }
    griddem_contact c;
    griddem_contact_setup(&c, dx, b->rsq[k], b->radi[k], b->radj[k], vi, vj, wi, wj, b->mi[k], b->mj[k],
                          b->frozen_i[k], b->frozen_j[k], dt, 1);
    const double e = griddem_classic_eval(&law, &c, shear, f, ti, tj, hertz);
    if (energy) b->energy[k] = e;
    for (int d = 0; d < 3; d++) {
      b->shear[d][k] = shear[d];
      b->f[d][k] = f[d], b->ti[d][k] = ti[d], b->tj[d][k] = tj[d];
    }
  }
}

/* One function per normal model, with and without the energy, each in copies by processor */
#define EVAL_COPY(name, hertz, energy)                                                                  \
  GRIDDEM_VECTOR_COPIES static void name(const griddem_pair_params *p, griddem_classic_batch *b, double dt) \
  {                                                                                                     \
    eval_lanes(p, b, dt, hertz, energy);                                                                \
  }
EVAL_COPY(eval_hooke, 0, 0)
EVAL_COPY(eval_hooke_energy, 0, 1)
EVAL_COPY(eval_hertz, 1, 0)
EVAL_COPY(eval_hertz_energy, 1, 1)

void griddem_classic_batch_eval(const griddem_pair_params *p, griddem_classic_batch *b, double dt, int energy)
{
  if (griddem_classic_hertz(p)) energy ? eval_hertz_energy(p, b, dt) : eval_hertz(p, b, dt);
  else energy ? eval_hooke_energy(p, b, dt) : eval_hooke(p, b, dt);
}
