/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: fix griddem/kk, the contact history of the griddem kk pair styles.

   Compressed rows in the layout of the CPU store (griddem_history.h): a pool of entries (partner tags in one array, their history
   values in another) and, per atom, the first entry of its row and the row's length. So memory
   follows the contacts present, not the most contacts of one atom times the atoms (a chute has
   ~0.5 contacts per atom and up to ~10 for one; a large sphere among small ones, hundreds).
   There are two pools: the pair's sweep reads the rows of the last step from one and writes each
   atom's new row into the other, from that atom's own thread (no atomics), at a place laid out
   from the length of the atom's contact list of the step (pair_griddem_kokkos.h). Rows travel
   with their atoms on the device (sort_kokkos moves the row heads; pack/unpack_exchange_kokkos)
   and on the host (copy_arrays, exchange, restart) through DualViews; a received row is appended
   to the pool, and the next sweep compacts it.

   The style is renamed "griddem" once made, so that restart files written on a CPU or a GPU
   are read by either, and the pair styles find it as fix griddem.
------------------------------------------------------------------------- */

#ifdef FIX_CLASS
// clang-format off
FixStyle(griddem/kk,FixGriddemKokkos<LMPDeviceType>);
FixStyle(griddem/kk/device,FixGriddemKokkos<LMPDeviceType>);
FixStyle(griddem/kk/host,FixGriddemKokkos<LMPHostType>);
// clang-format on
#else

#ifndef LMP_FIX_GRIDDEM_KOKKOS_H
#define LMP_FIX_GRIDDEM_KOKKOS_H

#include "fix_griddem_face.h"
#include "kokkos_base.h"
#include "griddem_contact.h"
#include "kokkos_type.h"

namespace LAMMPS_NS {

template <class DeviceType> class FixGriddemKokkos : public FixGriddem, public KokkosBase {
 public:
  typedef DeviceType device_type;
  // on LAMMPS's device whatever DeviceType is, as DAT's DualViews: atoms are sorted there
  typedef Kokkos::DualView<int64_t *, LMPDeviceType> tdual_partners;
  typedef Kokkos::DualView<double *, LMPDeviceType> tdual_values;
  typedef DAT::tdual_int_1d tdual_index;
  typedef Kokkos::View<int64_t *, DeviceType> t_partners;
  typedef Kokkos::View<double *, DeviceType> t_values;
  typedef Kokkos::View<int *, DeviceType> t_index;

  FixGriddemKokkos(class LAMMPS *, int, char **);
  ~FixGriddemKokkos() override;
  void post_constructor() override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  double memory_usage() override;

  void sort_kokkos(Kokkos::BinSort<KeyViewType, BinOp> &Sorter) override;
  int pack_exchange_kokkos(const int &nsend, DAT::tdual_xfloat_2d &k_buf,
                           DAT::tdual_int_1d k_sendlist, DAT::tdual_int_1d k_copylist,
                           ExecutionSpace space) override;
  void unpack_exchange_kokkos(DAT::tdual_xfloat_2d &k_buf, DAT::tdual_int_1d &k_indices, int nrecv,
                              int nrecv1, int nextrarecv1, ExecutionSpace space) override;

  int history_values() const override { return nv; }
  void set_values(int values) override;
  const double *find_history(int i, int64_t partner) override;
  int get_message(int i, double *message) override;
  int message_length(int i) override;
  int longest_message() override;
  void put_message(int i, const double *message) override;

  // For the pair's sweep, on its device: the rows of the last step (read), and the rows the
  // sweep writes (first_out, count_out), in room for at least `entries` that `reserve_out`
  // makes (out_room: how many); `commit` makes the written rows, `entries` in all, current.
  struct Rows {
    t_partners partner, partner_out;
    t_values value, value_out;
    t_index first, count, first_out, count_out;
  };
  Rows rows_on_device();
  void reserve_out(long entries);
  long out_room() const;
  void commit(long entries, int longest_row);

 private:
  tdual_partners k_partner[2];    // the pools; [cur]: the current rows
  tdual_values k_value[2];        // values of entry e: [e * nv, (e + 1) * nv)
  tdual_index k_first[2];         // [nmax] first entry of each atom's row
  tdual_index k_count[2];         // [nmax] entries in it
  int cur;          // the pool and row heads of the current rows
  long used;        // entries of pool cur in use (rows, and holes left by atoms that left)
  int nv;           // history values per contact
  int longest;      // most entries of one row
  double found[GRIDDEM_MAX_HISTORY];    // find_history's copy
  // make the current rows' arrays current on the host / mark them written there; heads only:
  // first and count alone (a row moved or emptied leaves the pool as it is, so the pool is not
  // copied to the other side for it)
  void sync_host();
  void modify_host();
  void sync_heads_host();
  void modify_heads_host();
  // make pool p's arrays current on DeviceType / mark them written there
  void sync_here(int p);
  void modify_here(int p);
  template <class F> void each_head(int p, F f)
  {
    f(k_first[p]);
    f(k_count[p]);
  }
  template <class F> void each_array(int p, F f)
  {
    f(k_partner[p]);
    f(k_value[p]);
    each_head(p, f);
  }
  // room for `entries` in pool p, its first `keep` entries kept
  void reserve_pool(int p, long entries, long keep);
  void update_maxexchange();
};

}    // namespace LAMMPS_NS

#endif
#endif
