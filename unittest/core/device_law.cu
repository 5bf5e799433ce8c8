/* The contact-law headers compiled as CUDA device code: every sub-model is reachable from a
 * kernel through griddem_contact_eval, so the header the CPU sweep uses is the one a GPU kernel
 * can use (a host-only construct in any of them fails this compile). */
#include "griddem_contact.h"

__global__ void griddem_device_law(const griddem_pair_params *p, griddem_contact *c, double *h,
                                   double *f, double *ti, double *tj, int *touch)
{
  *touch = griddem_contact_touch(p, c->rsq, c->radi, c->radj, 1);
  griddem_contact_eval(p, c, h, f, ti, tj);
}
