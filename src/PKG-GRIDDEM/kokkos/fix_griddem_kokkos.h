/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package, Kokkos: fix griddem/kk, the contact history of the griddem kk pair styles.

   Each owned atom owns one row of `capacity` entries: the partners' tags in one array, their
   history values in another (tags are integers: half the bytes of the doubles the row messages
   of fix griddem carry them in), plus its entry count. The pair's sweep reads and rewrites
   an atom's row in place from that atom's own thread (no atomics). Rows travel with their atoms
   on the device (sort_kokkos, pack/unpack_exchange_kokkos) and on the host (copy_arrays,
   exchange, restart) through DualViews. The capacity grows with the most contacts of one atom;
   contacts a row cannot take in a step wait in a spill buffer that is appended once the rows
   have grown (GriddemKKSpill), so no atom has a fixed limit.

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

#include "fix_griddem.h"
#include "kokkos_base.h"
#include "griddem_contact.h"
#include "kokkos_type.h"

namespace LAMMPS_NS {

template <class DeviceType> class FixGriddemKokkos : public FixGriddem, public KokkosBase {
 public:
  typedef DeviceType device_type;
  // on LAMMPS's device whatever DeviceType is, as DAT's DualViews: atoms are sorted there. Laid
  // out as that device lays out 2D arrays: on a GPU (LayoutLeft) the threads of neighbouring
  // atoms, each reading its own row, read one column together (coalesced); on a CPU
  // (LayoutRight) each row is contiguous for its thread's cache
  typedef typename LMPDeviceType::execution_space::array_layout rows_layout;
  typedef Kokkos::DualView<double **, rows_layout, LMPDeviceType> tdual_rows;
  typedef Kokkos::DualView<tagint **, rows_layout, LMPDeviceType> tdual_partners;
  typedef DAT::tdual_int_1d tdual_count;
  typedef Kokkos::View<double **, rows_layout, DeviceType> t_rows;
  typedef Kokkos::View<tagint **, rows_layout, DeviceType> t_partners;
  typedef Kokkos::View<int *, DeviceType> t_count;

  FixGriddemKokkos(class LAMMPS *, int, char **);
  ~FixGriddemKokkos() override;
  void post_constructor() override;
  void init() override;

  void grow_arrays(int) override;
  void copy_arrays(int, int, int) override;
  void set_arrays(int) override;
  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double memory_usage() override;

  void sort_kokkos(Kokkos::BinSort<KeyViewType, BinOp> &Sorter) override;
  int pack_exchange_kokkos(const int &nsend, DAT::tdual_xfloat_2d &k_buf,
                           DAT::tdual_int_1d k_sendlist, DAT::tdual_int_1d k_copylist,
                           ExecutionSpace space) override;
  void unpack_exchange_kokkos(DAT::tdual_xfloat_2d &k_buf, DAT::tdual_int_1d &k_indices, int nrecv,
                              int nrecv1, int nextrarecv1, ExecutionSpace space) override;

  void set_values(int values) override;
  const double *find_history(int i, double partner) const override;

  // for the pair style: the rows on its device, made current there, and room for `entries`
  // contacts in every row (rows keep their entries)
  t_rows rows_on_device();
  t_partners partners_on_device();
  t_count counts_on_device();
  void rows_modified_on_device();
  void reserve_entries(int entries);
  int entry_capacity() const { return capacity; }
  int values_per_contact() const { return nv; }
  // after a step: the most entries in one row, which sizes exchange messages
  void set_longest_row(int entries);

 private:
  tdual_rows k_rows;            // [nmax][capacity * nv] history values, entry after entry
  tdual_partners k_partner;    // [nmax][capacity] partner tags
  tdual_count k_count;         // [nmax] entries in use
  mutable double found[GRIDDEM_MAX_HISTORY];    // find_history's copy: a row's values need not be contiguous
  int capacity;           // entries per row
  int nv;                 // history values per contact
  int longest;            // most entries of one row after the last step
  void sync_host();
  void modify_host();
  // store a row message as atom i's row; returns its length
  int put_row(int i, const double *message);
};

}    // namespace LAMMPS_NS

#endif
#endif
