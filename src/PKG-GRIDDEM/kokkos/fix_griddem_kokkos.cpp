/* ----------------------------------------------------------------------
   GRIDDEM package, Kokkos: fix griddem/kk (fix_griddem_kokkos.h).
   A row message, as fix griddem's: count, then (partner tag, values) per contact.
------------------------------------------------------------------------- */

#include "fix_griddem_kokkos.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "error.h"
#include "memory_kokkos.h"

#include <cstring>

using namespace LAMMPS_NS;

template <class DeviceType>
FixGriddemKokkos<DeviceType>::FixGriddemKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixGriddem(lmp, narg, arg), capacity(0), nv(0), longest(0)
{
  kokkosable = 1;
  exchange_comm_device = sort_device = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = datamask_modify = EMPTY_MASK;
  kokkos_history = 1;

  capacity = MAX(contacts, 1);
  grow_arrays(atom->nmax);    // rows start empty (Views are zero-filled)
  maxexchange = 2 + capacity * (1 + nv);
}

template <class DeviceType> FixGriddemKokkos<DeviceType>::~FixGriddemKokkos()
{
  if (copymode) return;
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::init() {}

/* one name for CPU and Kokkos runs, so that restart files match either; here, not in the
   constructor, since Modify names a fix made through a suffix after constructing it */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("griddem");
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::sync_host()
{
  k_rows.sync_host();
  k_partner.sync_host();
  k_count.sync_host();
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::modify_host()
{
  k_rows.modify_host();
  k_partner.modify_host();
  k_count.modify_host();
}

/* DualView::resize keeps each element's contents on the side modified last */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::grow_arrays(int nmax)
{
  if (!k_count.d_view.data()) {
    k_rows = tdual_rows("griddem/kk:rows", nmax, capacity * nv);
    k_partner = tdual_partners("griddem/kk:partner", nmax, capacity);
    k_count = tdual_count("griddem/kk:count", nmax);
    return;
  }
  if (nmax <= (int) k_count.extent(0)) return;
  k_rows.resize(nmax, capacity * nv);
  k_partner.resize(nmax, capacity);
  k_count.resize(nmax);
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::reserve_entries(int entries)
{
  if (entries <= capacity) return;
  capacity = entries;
  k_rows.resize(k_rows.extent(0), capacity * nv);
  k_partner.resize(k_partner.extent(0), capacity);
  maxexchange = 2 + capacity * (1 + nv);
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::set_longest_row(int entries)
{
  longest = entries;
}

template <class DeviceType>
typename FixGriddemKokkos<DeviceType>::t_rows FixGriddemKokkos<DeviceType>::rows_on_device()
{
  k_rows.template sync<DeviceType>();
  return k_rows.template view<DeviceType>();
}

template <class DeviceType>
typename FixGriddemKokkos<DeviceType>::t_partners FixGriddemKokkos<DeviceType>::partners_on_device()
{
  k_partner.template sync<DeviceType>();
  return k_partner.template view<DeviceType>();
}

template <class DeviceType>
typename FixGriddemKokkos<DeviceType>::t_count FixGriddemKokkos<DeviceType>::counts_on_device()
{
  k_count.template sync<DeviceType>();
  return k_count.template view<DeviceType>();
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::rows_modified_on_device()
{
  k_rows.template modify<DeviceType>();
  k_partner.template modify<DeviceType>();
  k_count.template modify<DeviceType>();
}

/* a new layout of values per contact: each row keeps its values up to the shorter length */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::set_values(int values)
{
  if (values == nv) return;
  sync_host();
  const int nlocal = atom->nlocal;
  tdual_rows converted("griddem/kk:rows", k_rows.extent(0), capacity * values);
  for (int i = 0; i < nlocal; i++)
    for (int e = 0; e < k_count.h_view(i); e++)
      for (int k = 0; k < values; k++)
        converted.h_view(i, e * values + k) = k < nv ? k_rows.h_view(i, e * nv + k) : 0.0;
  k_rows = converted;
  nv = values;
  modify_host();
  maxexchange = 2 + capacity * (1 + nv);
}

template <class DeviceType>
const double *FixGriddemKokkos<DeviceType>::find_history(int i, double partner) const
{
  auto self = const_cast<FixGriddemKokkos<DeviceType> *>(this);
  self->sync_host();
  for (int e = 0; e < k_count.h_view(i); e++)
    if ((double) k_partner.h_view(i, e) == partner) {
      for (int k = 0; k < nv; k++) found[k] = k_rows.h_view(i, e * nv + k);
      return found;
    }
  return nullptr;
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::set_arrays(int i)
{
  sync_host();
  k_count.h_view(i) = 0;
  modify_host();
}

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::copy_arrays(int i, int j, int /*delflag*/)
{
  sync_host();
  k_count.h_view(j) = k_count.h_view(i);
  for (int e = 0; e < k_count.h_view(i); e++) k_partner.h_view(j, e) = k_partner.h_view(i, e);
  for (int k = 0; k < k_count.h_view(i) * nv; k++) k_rows.h_view(j, k) = k_rows.h_view(i, k);
  modify_host();
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::pack_exchange(int i, double *buf)
{
  sync_host();
  const int n = k_count.h_view(i);
  buf[0] = n;
  for (int e = 0, m = 1; e < n; e++) {
    buf[m++] = (double) k_partner.h_view(i, e);
    for (int k = 0; k < nv; k++) buf[m++] = k_rows.h_view(i, e * nv + k);
  }
  return 1 + n * (1 + nv);
}

/* a message's entries beyond the capacity make room for themselves (restart files and other
   processes may hold longer rows); values are converted from `values` per contact */

template <class DeviceType> int FixGriddemKokkos<DeviceType>::put_row(int i, const double *message)
{
  const int count = static_cast<int>(message[0]);
  sync_host();
  if (count > capacity) {
    reserve_entries(count);
    sync_host();
  }
  k_count.h_view(i) = count;
  for (int e = 0, m = 1; e < count; e++) {
    k_partner.h_view(i, e) = (tagint) message[m++];
    for (int k = 0; k < nv; k++) k_rows.h_view(i, e * nv + k) = message[m++];
  }
  modify_host();
  longest = MAX(longest, count);
  return 1 + count * (1 + nv);
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::unpack_exchange(int nlocal, double *buf)
{
  return put_row(nlocal, buf);
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::pack_restart(int i, double *buf)
{
  buf[1] = nv;    // as fix griddem: record length, values per contact, row message
  buf[0] = 2 + pack_exchange(i, buf + 2);
  return static_cast<int>(buf[0]);
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  const double *record = &extra[nlocal][m];
  const int record_values = static_cast<int>(record[1]);
  if (record_values != nv) set_values(record_values);
  put_row(nlocal, record + 2);
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::size_restart(int nlocal)
{
  sync_host();
  return 3 + k_count.h_view(nlocal) * (1 + nv);
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::maxsize_restart()
{
  int mine = 3 + longest * (1 + nv), most;
  MPI_Allreduce(&mine, &most, 1, MPI_INT, MPI_MAX, world);
  return most;
}

template <class DeviceType> double FixGriddemKokkos<DeviceType>::memory_usage()
{
  return (double) k_count.extent(0) *
      ((double) capacity * (nv * sizeof(double) + sizeof(tagint)) + sizeof(int));
}

/* ---------------------------------------------------------------------- */

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::sort_kokkos(Kokkos::BinSort<KeyViewType, BinOp> &Sorter)
{
  // LAMMPS sorts atoms on its device
  k_rows.sync_device();
  k_partner.sync_device();
  k_count.sync_device();
  Sorter.sort(LMPDeviceType(), k_rows.d_view);
  Sorter.sort(LMPDeviceType(), k_partner.d_view);
  Sorter.sort(LMPDeviceType(), k_count.d_view);
  k_rows.modify_device();
  k_partner.modify_device();
  k_count.modify_device();
}

/* Exchange on the device, in CommKokkos's layout: nsend offsets (as integer bits), then the
   messages; the slot of each sent atom is refilled from copylist */

template <class DeviceType>
int FixGriddemKokkos<DeviceType>::pack_exchange_kokkos(const int &nsend,
                                                       DAT::tdual_xfloat_2d &k_buf,
                                                       DAT::tdual_int_1d k_sendlist,
                                                       DAT::tdual_int_1d k_copylist,
                                                       ExecutionSpace /*space*/)
{
  k_rows.template sync<DeviceType>();
  k_partner.template sync<DeviceType>();
  k_count.template sync<DeviceType>();
  k_buf.template sync<DeviceType>();
  k_sendlist.template sync<DeviceType>();
  k_copylist.template sync<DeviceType>();
  auto rows = k_rows.template view<DeviceType>();
  auto partner = k_partner.template view<DeviceType>();
  auto count = k_count.template view<DeviceType>();
  auto sendlist = k_sendlist.template view<DeviceType>();
  auto copylist = k_copylist.template view<DeviceType>();
  typename ArrayTypes<DeviceType>::t_xfloat_1d_um buf(k_buf.template view<DeviceType>().data(),
                                                      k_buf.extent(0) * k_buf.extent(1));
  const int nvalues = nv;

  int total = 0;
  Kokkos::parallel_scan(
      "griddem/kk:pack_exchange", Kokkos::RangePolicy<DeviceType>(0, nsend),
      KOKKOS_LAMBDA(const int s, int &offset, const bool final) {
        const int i = sendlist(s);
        const int n = count(i);
        if (final) {
          int m = nsend + offset;
          buf(s) = d_ubuf(m).d;
          buf(m++) = n;
          for (int e = 0; e < n; e++) {
            buf(m++) = (double) partner(i, e);
            for (int k = 0; k < nvalues; k++) buf(m++) = rows(i, e * nvalues + k);
          }
        }
        offset += 1 + n * (1 + nvalues);
      },
      total);
  // refill the sent slots only after every message is packed: a copy source may be sent too
  Kokkos::parallel_for(
      "griddem/kk:fill_sent", Kokkos::RangePolicy<DeviceType>(0, nsend),
      KOKKOS_LAMBDA(const int s) {
        const int i = sendlist(s), j = copylist(s);
        if (j < 0) return;
        const int n = count(j);
        count(i) = n;
        for (int e = 0; e < n; e++) partner(i, e) = partner(j, e);
        for (int k = 0; k < n * nvalues; k++) rows(i, k) = rows(j, k);
      });
  k_rows.template modify<DeviceType>();
  k_partner.template modify<DeviceType>();
  k_count.template modify<DeviceType>();
  return nsend + total;
}

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::unpack_exchange_kokkos(DAT::tdual_xfloat_2d &k_buf,
                                                          DAT::tdual_int_1d &k_indices, int nrecv,
                                                          int nrecv1, int nextrarecv1,
                                                          ExecutionSpace /*space*/)
{
  k_buf.template sync<DeviceType>();
  k_indices.template sync<DeviceType>();
  typename ArrayTypes<DeviceType>::t_xfloat_1d_um buf(k_buf.template view<DeviceType>().data(),
                                                      k_buf.extent(0) * k_buf.extent(1));
  auto indices = k_indices.template view<DeviceType>();
  const int nvalues = nv;

  // rows longer than the capacity (from a process whose rows grew further) make room first
  int most = 0;
  Kokkos::parallel_reduce(
      "griddem/kk:exchange_longest", Kokkos::RangePolicy<DeviceType>(0, nrecv),
      KOKKOS_LAMBDA(const int r, int &longest_row) {
        int m = (int) d_ubuf(buf(r)).i;
        if (r >= nrecv1) m = nextrarecv1 + (int) d_ubuf(buf(nextrarecv1 + r - nrecv1)).i;
        const int n = (int) buf(m);
        if (n > longest_row) longest_row = n;
      },
      Kokkos::Max<int>(most));
  k_rows.template sync<DeviceType>();
  k_partner.template sync<DeviceType>();
  k_count.template sync<DeviceType>();
  if (most > capacity) reserve_entries(most);
  longest = MAX(longest, most);
  auto rows = k_rows.template view<DeviceType>();
  auto partner = k_partner.template view<DeviceType>();
  auto count = k_count.template view<DeviceType>();

  Kokkos::parallel_for(
      "griddem/kk:unpack_exchange", Kokkos::RangePolicy<DeviceType>(0, nrecv),
      KOKKOS_LAMBDA(const int r) {
        const int i = indices(r);
        if (i < 0) return;
        int m = (int) d_ubuf(buf(r)).i;
        if (r >= nrecv1) m = nextrarecv1 + (int) d_ubuf(buf(nextrarecv1 + r - nrecv1)).i;
        const int n = (int) buf(m++);
        count(i) = n;
        for (int e = 0; e < n; e++) {
          partner(i, e) = (tagint) buf(m++);
          for (int k = 0; k < nvalues; k++) rows(i, e * nvalues + k) = buf(m++);
        }
      });
  k_rows.template modify<DeviceType>();
  k_partner.template modify<DeviceType>();
  k_count.template modify<DeviceType>();
}

namespace LAMMPS_NS {
template class FixGriddemKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixGriddemKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
