/* The classic laws (griddem_classic.h: gran/hooke/history's and gran/hertz/history's) over a batch
 * of contacts, lane by lane. Each lane computes what griddem_classic_eval computes for one contact,
 * the same operations in the same order, and no lane reads another's, so the compiler runs the
 * lanes as vector lanes; every copy rounds as the scalar law does (no fused multiply-add), so a
 * batch gives each contact the bits griddem_classic_eval gives it. The CPU sweep gathers a
 * thread's contacts into a batch, evaluates it, and adds the forces in the order the contacts
 * were found. */
#ifndef GRIDDEM_CLASSIC_BATCH_H
#define GRIDDEM_CLASSIC_BATCH_H

#include "griddem_contact.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Contacts in one batch */
#define GRIDDEM_CLASSIC_BATCH 64

/* A batch of n contacts of atoms i and j, each in a lane: the inputs as griddem_contact_setup
 * takes them, the shear history (read, and advanced where the history advances), the outputs as
 * griddem_classic_eval returns them. */
typedef struct griddem_classic_batch {
  int n;
  double dx[3][GRIDDEM_CLASSIC_BATCH], rsq[GRIDDEM_CLASSIC_BATCH];
  double radi[GRIDDEM_CLASSIC_BATCH], radj[GRIDDEM_CLASSIC_BATCH];
  double vi[3][GRIDDEM_CLASSIC_BATCH], vj[3][GRIDDEM_CLASSIC_BATCH];
  double wi[3][GRIDDEM_CLASSIC_BATCH], wj[3][GRIDDEM_CLASSIC_BATCH];
  double mi[GRIDDEM_CLASSIC_BATCH], mj[GRIDDEM_CLASSIC_BATCH];
  int frozen_i[GRIDDEM_CLASSIC_BATCH], frozen_j[GRIDDEM_CLASSIC_BATCH];
  double shear[3][GRIDDEM_CLASSIC_BATCH];
  double f[3][GRIDDEM_CLASSIC_BATCH], ti[3][GRIDDEM_CLASSIC_BATCH], tj[3][GRIDDEM_CLASSIC_BATCH];
  double energy[GRIDDEM_CLASSIC_BATCH];
} griddem_classic_batch;

/* Whether a pair's law can be evaluated in a batch: classic, with the tangential model of
 * gran/hooke/history and gran/hertz/history (the shear history). */
int griddem_classic_batchable(const griddem_pair_params *p);

/* Evaluate the batch's lanes with law p (griddem_classic_batchable) and time step dt, the history
 * advancing (griddem_contact's history_update: a step of a run); each lane's energy is set only
 * where energy is nonzero (a copy without it computes none). */
void griddem_classic_batch_eval(const griddem_pair_params *p, griddem_classic_batch *b, double dt, int energy);

#ifdef __cplusplus
}
#endif

#endif
