/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: 4. the sweep: the contact law over each owned particle's list.
   (pair_griddem_kokkos.h: the pipeline these kernels make.)
------------------------------------------------------------------------- */

#ifndef LMP_GRIDDEM_KK_SWEEP_H
#define LMP_GRIDDEM_KK_SWEEP_H

#include "fix_griddem_kokkos.h"
#include "griddem_contact.h"
#include "griddem_exclusions.h"
#include "griddem_kk_sorted.h"

namespace LAMMPS_NS {

/* The contact law over each owned particle's list: the thread sums its particle's force and
   torque (the law is exactly odd under i <-> j, so each side is evaluated on its own: no atomics)
   and, for laws with history, writes the atom's new row into fix griddem/kk's other pool, at the
   place laid out from its list's length (the contacts of this step, with their values found in
   the last step's row and advanced).
   Classic: every type pair uses the gran/hooke laws (griddem_classic.h), so the kernel is compiled
   without the composed sub-models; on a GPU that halves the registers a thread holds. */
template <class DeviceType, typename Real, bool Classic>
struct GriddemKKSweep : public GriddemKKSorted<DeviceType, Real> {
  typedef DeviceType device_type;
  typedef GriddemKKSweepValue value_type;
  typedef ArrayTypes<DeviceType> AT;

  int frozen_bit, eflag_global, vflag_global, vflag_atom;
  double dt;
  int history_update;    // 0 in setup: stored values are read, not advanced
  int track;             // model.track_contacts: rows are kept
  int nv;                // values per contact
  Kokkos::View<const Real *[7], Kokkos::LayoutRight, DeviceType> state;    // v, omega, mass
  typename AT::t_tagint_1d_randomread tag;                                // by atom index
  int keyed_by_image;    // the box has image axes: contacts keyed by partner and periodic image
  Kokkos::View<const int *, DeviceType> image;    // by atom index: image codes (keyed_by_image)
  Kokkos::View<const griddem_pair_params *, DeviceType> params;
  typename FixGriddemKokkos<DeviceType>::Rows rows;    // fix griddem/kk's rows
  Kokkos::View<int *, DeviceType> last;    // by atom index: its list's length, for the next layout
  typename AT::t_f_array f, torque;
  typename AT::t_virial_array vatom;
  int heat;    // some type pair conducts heat (the composed law only): by atom index, the
               // temperatures read and each owned atom's heat from its contacts written
  Kokkos::View<const double *, DeviceType> temperature;
  Kokkos::View<double *, DeviceType> heatflow;

  KOKKOS_INLINE_FUNCTION void init(value_type &s) const
  {
    for (int k = 0; k < 6; k++) s.v[k] = 0.0;
    s.energy = 0.0;
    s.contacts = 0;
    s.most = 0;
  }
  KOKKOS_INLINE_FUNCTION void join(value_type &s, const value_type &o) const
  {
    for (int k = 0; k < 6; k++) s.v[k] += o.v[k];
    s.energy += o.energy;
    s.contacts += o.contacts;
    if (o.most > s.most) s.most = o.most;
  }

  // the entry of partner p in atom i's last row, or -1
  KOKKOS_INLINE_FUNCTION long find(int i, int64_t p) const
  {
    return griddem_history_entry(rows.partner.data(), rows.first(i), rows.count(i), p);
  }

  // history values per contact the kernel holds: loops over nhist with constant bounds let a
  // GPU keep them in registers
  static constexpr int nhist = Classic ? 3 : GRIDDEM_MAX_HISTORY;

  KOKKOS_INLINE_FUNCTION void operator()(const int s, value_type &sum) const
  {
    const int i = this->order(s);
    if (i >= this->nlocal || this->report().retry) return;
    const double radi = this->radius_of(s), mi = state(s, 6);
    const int itype = this->tm(s, 0), imask = this->tm(s, 1);
    double corner[3] = {0.0, 0.0, 0.0};    // separation() reads it in single precision only
    if constexpr (!GriddemKKSorted<DeviceType, Real>::atom_positions)
      this->grids.cell_corner(this->slot_cell(s), corner);
    double fsum[3] = {0.0, 0.0, 0.0}, tsum[3] = {0.0, 0.0, 0.0};
    double w[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}, energy = 0.0;
    const int head = this->first(s), n = this->count(s);
    const int out = track ? rows.first_out(i) : 0;
    int stored = 0, ncontact = 0;
    double heat_in = 0.0;

    for (int e = head; e < head + n; e++) {
      const int u = this->list(e);
      double sep[3], radj;
      const double rsq = this->separation(s, u, corner, sep, radj);
      const double dx = sep[0], dy = sep[1], dz = sep[2];
      const int jtype = this->tm(u, 0), jmask = this->tm(u, 1);
      const griddem_pair_params *law = &params(itype * (this->ntypes + 1) + jtype);
      const int j = this->order(u);
      const int64_t partner = !track ? 0 : keyed_by_image ? griddem_image_key(tag(j), image(i), image(j)) : tag(j);
      const long found = track ? find(i, partner) : -1;
      if (this->reach_extra > 0.0 && !griddem_contact_touch(law, rsq, radi, radj, found >= 0)) continue;

      griddem_contact c;
      const double vi[3] = {state(s, 0), state(s, 1), state(s, 2)}, wi[3] = {state(s, 3), state(s, 4), state(s, 5)};
      const double vj[3] = {state(u, 0), state(u, 1), state(u, 2)}, wj[3] = {state(u, 3), state(u, 4), state(u, 5)};
      griddem_contact_setup(&c, sep, rsq, radi, radj, vi, vj, wi, wj, mi, state(u, 6), (imask & frozen_bit) != 0,
                            (jmask & frozen_bit) != 0, dt, history_update);
      if (!Classic && heat) c.temp_i = temperature(i), c.temp_j = temperature(j);
      double hist[nhist];
      for (int h = 0; h < nhist; h++)
        hist[h] = (found >= 0 && h < nv) ? rows.value(found * nv + h) : 0.0;
      double fc[3], ti[3], tj[3];
      const double uel = Classic ? griddem_classic_eval(law, &c, hist, fc, ti, tj, griddem_classic_hertz(law))
                                 : griddem_contact_eval(law, &c, hist, fc, ti, tj);
      if (track) {    // griddem_history_put's layout, its loop bound constant (hist stays in registers)
        const long o = out + stored++;
        rows.partner_out(o) = partner;
        for (int h = 0; h < nhist; h++)
          if (h < nv) rows.value_out(o * nv + h) = hist[h];
      }
      for (int d = 0; d < 3; d++) fsum[d] += fc[d], tsum[d] += ti[d];
      if (!Classic && heat) heat_in += c.heat;
      if (eflag_global) energy += 0.5 * uel;
      ncontact++;
      if (vflag_global || vflag_atom) {
        w[0] += 0.5 * dx * fc[0], w[1] += 0.5 * dy * fc[1], w[2] += 0.5 * dz * fc[2];
        w[3] += 0.5 * dx * fc[1], w[4] += 0.5 * dx * fc[2], w[5] += 0.5 * dy * fc[2];
      }
    }

    last(i) = n;
    if (track) rows.count_out(i) = stored;
    sum.contacts += ncontact;
    if (ncontact > sum.most) sum.most = ncontact;
    for (int d = 0; d < 3; d++) f(i, d) += fsum[d], torque(i, d) += tsum[d];
    if (!Classic && heat) heatflow(i) = heat_in;
    sum.energy += energy;
    if (vflag_global)
      for (int k = 0; k < 6; k++) sum.v[k] += w[k];
    if (vflag_atom)
      for (int k = 0; k < 6; k++) vatom(i, k) += w[k];
  }
};

}    // namespace LAMMPS_NS

#endif
