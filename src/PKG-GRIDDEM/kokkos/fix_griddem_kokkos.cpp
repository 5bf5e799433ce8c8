/* ----------------------------------------------------------------------
   GRIDDEM package, Kokkos: fix griddem/kk (fix_griddem_kokkos.h).
   A row message, as fix griddem's: count, then (partner tag, values) per contact.
------------------------------------------------------------------------- */

#include "fix_griddem_kokkos.h"

#include "griddem_kk_launch.h"

#include "atom_kokkos.h"
#include "atom_masks.h"
#include "error.h"
#include "memory_kokkos.h"

#include <climits>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;

/* A pool's entries are written before they are read (a row names those it holds): its arrays are
   allocated without the fill a View gets by default, on the device and in the host mirror alike,
   so that a pool that grows on a GPU costs the host neither a pass over its mirror nor the
   mirror's memory until something reads it there */
template <class Pool> static Pool pool_array(const char *label, long n)
{
  return Pool(Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)), n);
}

template <class DeviceType>
FixGriddemKokkos<DeviceType>::FixGriddemKokkos(LAMMPS *lmp, int narg, char **arg) :
    FixGriddem(lmp, narg, arg), cur(0), used(0), nv(0), longest(0)
{
  kokkosable = 1;
  exchange_comm_device = sort_device = 1;
  atomKK = (AtomKokkos *) atom;
  execution_space = ExecutionSpaceFromDevice<DeviceType>::space;
  datamask_read = datamask_modify = EMPTY_MASK;

  for (int p = 0; p < 2; p++) {
    k_partner[p] = pool_array<tdual_partners>("griddem/kk:partner", 0);
    k_value[p] = pool_array<tdual_values>("griddem/kk:value", 0);
  }
  grow_arrays(atom->nmax);    // rows start empty (Views are zero-filled)
  update_maxexchange();
}

template <class DeviceType> FixGriddemKokkos<DeviceType>::~FixGriddemKokkos()
{
  if (copymode) return;
  leave();    // while the rows are still here
}

/* one name for CPU and Kokkos runs, so that restart files match either; here, not in the
   constructor, since Modify names a fix made through a suffix after constructing it */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::post_constructor()
{
  delete[] style;
  style = utils::strdup("griddem");
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::sync_host()
{
  each_array(cur, [](auto &k) { k.sync_host(); });
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::modify_host()
{
  each_array(cur, [](auto &k) { k.modify_host(); });
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::sync_heads_host()
{
  each_head(cur, [](auto &k) { k.sync_host(); });
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::modify_heads_host()
{
  each_head(cur, [](auto &k) { k.modify_host(); });
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::sync_here(int p)
{
  each_array(p, [](auto &k) { k.template sync<DeviceType>(); });
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::modify_here(int p)
{
  each_array(p, [](auto &k) { k.template modify<DeviceType>(); });
}

/* a row's message and its offset in CommKokkos's device layout */
template <class DeviceType> void FixGriddemKokkos<DeviceType>::update_maxexchange()
{
  maxexchange = 1 + GRIDDEM_ROW_MESSAGE_LENGTH(exchange_room(longest), nv);
}

/* DualView::resize keeps the contents of the side modified last and reallocates the other, to
   be synced from it: callers that write on the other side sync again */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::grow_arrays(int nmax)
{
  for (int p = 0; p < 2; p++) {
    if (!k_count[p].d_view.data()) {
      k_first[p] = tdual_index("griddem/kk:first", nmax);
      k_count[p] = tdual_index("griddem/kk:count", nmax);
    } else if (nmax > (int) k_count[p].extent(0)) {
      k_first[p].resize(nmax);
      k_count[p].resize(nmax);
    }
  }
}

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::reserve_pool(int p, long entries, long keep)
{
  if ((long) k_partner[p].extent(0) >= entries && (long) k_value[p].extent(0) >= entries * nv)
    return;
  if (entries > INT_MAX)
    error->one(FLERR, "Fix {}: {} contact history entries on one process, more than an int counts",
               style, entries);
  const long room = MAX(entries, (long) (1.25 * k_partner[p].extent(0)));
  if (keep) {
    k_partner[p].resize(Kokkos::view_alloc(Kokkos::WithoutInitializing), room);
    k_value[p].resize(Kokkos::view_alloc(Kokkos::WithoutInitializing), room * nv);
  } else {    // the old pool freed first: the peak is the new one
    k_partner[p] = tdual_partners();
    k_value[p] = tdual_values();
    k_partner[p] = pool_array<tdual_partners>("griddem/kk:partner", room);
    k_value[p] = pool_array<tdual_values>("griddem/kk:value", room * nv);
  }
}

template <class DeviceType>
typename FixGriddemKokkos<DeviceType>::Rows FixGriddemKokkos<DeviceType>::rows_on_device()
{
  const int out = 1 - cur;
  sync_here(cur);
  Rows rows;
  rows.partner = k_partner[cur].template view<DeviceType>();
  rows.value = k_value[cur].template view<DeviceType>();
  rows.first = k_first[cur].template view<DeviceType>();
  rows.count = k_count[cur].template view<DeviceType>();
  rows.partner_out = k_partner[out].template view<DeviceType>();
  rows.value_out = k_value[out].template view<DeviceType>();
  rows.first_out = k_first[out].template view<DeviceType>();
  rows.count_out = k_count[out].template view<DeviceType>();
  return rows;
}

/* room in the other pool for the rows the sweep writes */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::reserve_out(long entries)
{
  const int out = 1 - cur;
  reserve_pool(out, entries, 0);
  // written on DeviceType from here on, whatever either side held before
  each_array(out, [](auto &k) { k.clear_sync_state(); });
  modify_here(out);
}

template <class DeviceType> long FixGriddemKokkos<DeviceType>::out_room() const
{
  const int out = 1 - cur;
  const long room = (long) k_partner[out].extent(0);
  return nv ? MIN(room, (long) k_value[out].extent(0) / nv) : room;
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::commit(long entries, int longest_row)
{
  cur = 1 - cur;
  used = entries;
  longest = longest_row;
  update_maxexchange();
}

/* a new layout of values per contact: each row keeps its values up to the shorter length */

template <class DeviceType> void FixGriddemKokkos<DeviceType>::set_values(int values)
{
  if (values == nv) return;
  sync_host();
  const int nlocal = atom->nlocal;
  tdual_values converted = pool_array<tdual_values>("griddem/kk:value", k_partner[cur].extent(0) * values);
  for (int i = 0; i < nlocal; i++)
    for (int e = k_first[cur].h_view(i); e < k_first[cur].h_view(i) + k_count[cur].h_view(i); e++)
      for (int k = 0; k < values; k++)
        converted.h_view((long) e * values + k) = k < nv ? k_value[cur].h_view((long) e * nv + k) : 0.0;
  k_value[cur] = converted;
  k_value[1 - cur] = pool_array<tdual_values>("griddem/kk:value", k_partner[1 - cur].extent(0) * values);
  nv = values;
  modify_host();
  update_maxexchange();
}

template <class DeviceType>
const double *FixGriddemKokkos<DeviceType>::find_history(int i, int64_t partner)
{
  sync_host();
  const long e = griddem_history_entry(k_partner[cur].h_view.data(), k_first[cur].h_view(i),
                                       k_count[cur].h_view(i), partner);
  if (e < 0) return nullptr;
  for (int k = 0; k < nv; k++) found[k] = k_value[cur].h_view(e * nv + k);
  return found;
}

template <class DeviceType> void FixGriddemKokkos<DeviceType>::set_arrays(int i)
{
  sync_heads_host();
  k_first[cur].h_view(i) = k_count[cur].h_view(i) = 0;
  modify_heads_host();
}

/* atom j takes atom i's row (i leaves: its entries become a hole until the next sweep) */

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::copy_arrays(int i, int j, int /*delflag*/)
{
  sync_heads_host();
  k_first[cur].h_view(j) = k_first[cur].h_view(i);
  k_count[cur].h_view(j) = k_count[cur].h_view(i);
  modify_heads_host();
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::get_message(int i, double *message)
{
  sync_host();
  const int n = k_count[cur].h_view(i), first = k_first[cur].h_view(i);
  message[0] = n;
  for (int k = 0; k < n; k++)
    griddem_history_get(k_partner[cur].h_view.data(), k_value[cur].h_view.data(), nv, first + k,
                        message + 1 + (long) k * GRIDDEM_HISTORY_ENTRY(nv));
  return GRIDDEM_ROW_MESSAGE_LENGTH(n, nv);
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::message_length(int i)
{
  sync_heads_host();
  return GRIDDEM_ROW_MESSAGE_LENGTH(k_count[cur].h_view(i), nv);
}

template <class DeviceType> int FixGriddemKokkos<DeviceType>::longest_message()
{
  return GRIDDEM_ROW_MESSAGE_LENGTH(longest, nv);
}

/* a received or restarted row is appended to the pool; the next sweep compacts it */

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::put_message(int i, const double *message)
{
  const int count = static_cast<int>(message[0]);
  sync_host();
  reserve_pool(cur, used + count, used);
  sync_host();    // the side a resize did not keep
  k_first[cur].h_view(i) = (int) used;
  k_count[cur].h_view(i) = count;
  for (int e = 0; e < count; e++) {
    const double *entry = message + 1 + (long) e * GRIDDEM_HISTORY_ENTRY(nv);
    griddem_history_put(k_partner[cur].h_view.data(), k_value[cur].h_view.data(), nv, used + e,
                        (int64_t) entry[0], entry + 1);
  }
  used += count;
  modify_host();
  longest = MAX(longest, count);
  update_maxexchange();
}

template <class DeviceType> double FixGriddemKokkos<DeviceType>::memory_usage()
{
  double bytes = 0.0;
  for (int p = 0; p < 2; p++)
    bytes += (double) k_partner[p].extent(0) * sizeof(int64_t) +
        (double) k_value[p].extent(0) * sizeof(double) +
        (double) (k_first[p].extent(0) + k_count[p].extent(0)) * sizeof(int);
  return bytes;
}

/* ---------------------------------------------------------------------- */

/* LAMMPS sorts atoms on its device: the row heads move with them, the pool stays */

template <class DeviceType>
void FixGriddemKokkos<DeviceType>::sort_kokkos(Kokkos::BinSort<KeyViewType, BinOp> &Sorter)
{
  k_first[cur].sync_device();
  k_count[cur].sync_device();
  Sorter.sort(LMPDeviceType(), k_first[cur].d_view);
  Sorter.sort(LMPDeviceType(), k_count[cur].d_view);
  k_first[cur].modify_device();
  k_count[cur].modify_device();
}

/* Exchange on the device, in CommKokkos's layout: nsend offsets (as integer bits), then the
   messages; the slot of each sent atom takes the row of its copylist atom. The buffer is left
   current in the space CommKokkos sends from (space: Host where exchange runs on the host, as
   with MPI that cannot read device memory), as fix spring/self/kk and fix shake/kk leave it. */

template <class DeviceType>
int FixGriddemKokkos<DeviceType>::pack_exchange_kokkos(const int &nsend,
                                                       DAT::tdual_xfloat_2d &k_buf,
                                                       DAT::tdual_int_1d k_sendlist,
                                                       DAT::tdual_int_1d k_copylist,
                                                       ExecutionSpace space)
{
  sync_here(cur);
  k_buf.template sync<DeviceType>();
  k_sendlist.template sync<DeviceType>();
  k_copylist.template sync<DeviceType>();
  auto partner = k_partner[cur].template view<DeviceType>();
  auto value = k_value[cur].template view<DeviceType>();
  auto first = k_first[cur].template view<DeviceType>();
  auto count = k_count[cur].template view<DeviceType>();
  auto sendlist = k_sendlist.template view<DeviceType>();
  auto copylist = k_copylist.template view<DeviceType>();
  typename ArrayTypes<DeviceType>::t_xfloat_1d_um buf(k_buf.template view<DeviceType>().data(),
                                                      k_buf.extent(0) * k_buf.extent(1));
  const int nvalues = nv;

  int total = 0;
  griddem_kk_scan(
      "griddem/kk:pack_exchange", Kokkos::RangePolicy<DeviceType>(0, nsend),
      KOKKOS_LAMBDA(const int s, int &offset, const bool final) {
        const int i = sendlist(s);
        const int n = count(i);
        if (final) {
          int m = nsend + offset;
          buf(s) = d_ubuf(m).d;
          buf(m++) = n;
          for (int e = first(i); e < first(i) + n; e++, m += GRIDDEM_HISTORY_ENTRY(nvalues))
            griddem_history_get(partner.data(), value.data(), nvalues, e, &buf(m));
        }
        offset += GRIDDEM_ROW_MESSAGE_LENGTH(n, nvalues);
      },
      total);
  // refill the sent slots only after every message is packed: a copy source may be sent too
  griddem_kk_for(
      "griddem/kk:fill_sent", Kokkos::RangePolicy<DeviceType>(0, nsend),
      KOKKOS_LAMBDA(const int s) {
        const int i = sendlist(s), j = copylist(s);
        if (j < 0) return;
        first(i) = first(j);
        count(i) = count(j);
      });
  k_first[cur].template modify<DeviceType>();
  k_count[cur].template modify<DeviceType>();
  k_buf.template modify<DeviceType>();
  if (space == Host) k_buf.template sync<LMPHostType>();
  else k_buf.template sync<LMPDeviceType>();
  return nsend + total;
}

/* received rows are appended to the pool; message r starts at exchange_message(buf, r, ...) */

template <class Buffer>
KOKKOS_INLINE_FUNCTION static int exchange_message(const Buffer &buf, int r, int nrecv1,
                                                   int nextrarecv1)
{
  if (r >= nrecv1) return nextrarecv1 + (int) d_ubuf(buf(nextrarecv1 + r - nrecv1)).i;
  return (int) d_ubuf(buf(r)).i;
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

  long entries = 0;
  int most = 0;
  griddem_kk_reduce(
      "griddem/kk:exchange_entries", Kokkos::RangePolicy<DeviceType>(0, nrecv),
      KOKKOS_LAMBDA(const int r, long &sum, int &longest_row) {
        if (indices(r) < 0) return;
        const int n = (int) buf(exchange_message(buf, r, nrecv1, nextrarecv1));
        sum += n;
        if (n > longest_row) longest_row = n;
      },
      entries, Kokkos::Max<int>(most));
  sync_here(cur);
  reserve_pool(cur, used + entries, used);
  sync_here(cur);    // the side a resize did not keep
  auto partner = k_partner[cur].template view<DeviceType>();
  auto value = k_value[cur].template view<DeviceType>();
  auto first = k_first[cur].template view<DeviceType>();
  auto count = k_count[cur].template view<DeviceType>();
  const long base = used;

  griddem_kk_scan(
      "griddem/kk:unpack_exchange", Kokkos::RangePolicy<DeviceType>(0, nrecv),
      KOKKOS_LAMBDA(const int r, long &offset, const bool final) {
        const int i = indices(r);
        if (i < 0) return;
        int m = exchange_message(buf, r, nrecv1, nextrarecv1);
        const int n = (int) buf(m++);
        if (final) {
          const long e0 = base + offset;
          first(i) = (int) e0;
          count(i) = n;
          for (long e = e0; e < e0 + n; e++, m += GRIDDEM_HISTORY_ENTRY(nvalues))
            griddem_history_put(partner.data(), value.data(), nvalues, e, (int64_t) buf(m), &buf(m + 1));
        }
        offset += n;
      });
  used += entries;
  longest = MAX(longest, most);
  update_maxexchange();
  modify_here(cur);
}

namespace LAMMPS_NS {
template class FixGriddemKokkos<LMPDeviceType>;
#ifdef LMP_KOKKOS_GPU
template class FixGriddemKokkos<LMPHostType>;
#endif
}    // namespace LAMMPS_NS
