/* -*- c++ -*- ----------------------------------------------------------
   GRIDDEM package: what every fix griddem is (options, the grid diagnostics of its pair style's
   steps, the contact-history store's face); the styles are fix_griddem.h (the CPU store) and kokkos/fix_griddem_kokkos.h.
------------------------------------------------------------------------- */

#ifndef LMP_FIX_GRIDDEM_FACE_H
#define LMP_FIX_GRIDDEM_FACE_H

#include "fix.h"
#include "griddem_engine.h"
#include "griddem_pair_link.h"

#include <vector>

namespace LAMMPS_NS {

enum { GRIDDEM_PRECISION_DOUBLE, GRIDDEM_PRECISION_SINGLE };
// the Kokkos styles' search: a thread per atom reading its candidates from device memory, or a
// team per block of cells with their neighbourhood staged in scratch memory; auto: teams on a GPU
enum { GRIDDEM_SEARCH_AUTO, GRIDDEM_SEARCH_THREAD, GRIDDEM_SEARCH_TEAM };
// the CPU engine's candidate kernel (griddem_search.h), by its name in GRIDDEM_KERNEL_NAMES
enum { GRIDDEM_KERNEL_AUTO, GRIDDEM_KERNEL_SCALAR, GRIDDEM_KERNEL_AVX2, GRIDDEM_KERNEL_AVX512 };
static constexpr const char *GRIDDEM_KERNEL_NAMES[] = {"auto", "scalar", "avx2", "avx512"};


// fix griddem's options, as its keywords set them
struct GriddemFixOptions {
  int cell_mode;        // cell: enum griddem_cell_mode
  double cell_edge;     // cell: the edge of GRIDDEM_CELL_FIXED
  int contacts;         // contacts: expected per atom (initial history storage); 0: no history
  int precision;        // precision: GRIDDEM_PRECISION_*, of the Kokkos styles' sorted particle data
  int search;           // search: GRIDDEM_SEARCH_*, the Kokkos styles' search
  int kernel;           // kernel: GRIDDEM_KERNEL_*, the CPU engine's candidate kernel
};

/* What every fix griddem is: the grid options, the grid diagnostics of its pair style's last step
   (a global vector, which the pair style gives: GriddemPairLink) and the face of the
   contact-history store that the griddem pair styles read and write. The store keeps
   per atom the row of its contacts; rows migrate with their atoms and go into restart files as
   row messages (griddem_history.h), one format for both stores: FixGriddemCPU (fix griddem, a
   griddem_history in host memory, which the CPU styles' engine sweeps; fix_griddem.h) and FixGriddemKokkos (fix
   griddem/kk, pools on the Kokkos device, which the kk kernels sweep). */
class FixGriddem : public Fix {
 public:
  FixGriddem(class LAMMPS *, int, char **);
  ~FixGriddem() override;
  int setmask() override;
  void init() override;
  void post_run() override;

  int pack_exchange(int, double *) override;
  int unpack_exchange(int, double *) override;
  int pack_restart(int, double *) override;
  void unpack_restart(int, int) override;
  int size_restart(int) override;
  int maxsize_restart() override;
  double compute_vector(int) override;

  // the store's face (its rows live on the Kokkos device where the fix is kokkosable: fix
  // griddem/kk, for the kk pair styles)
  virtual int history_values() const = 0;
  // a new layout of values per contact: each stored row keeps its values up to the shorter length
  virtual void set_values(int values) = 0;
  // stored history values of atom i's contact of key partner (griddem_history.h), or nullptr
  virtual const double *find_history(int i, int64_t partner) = 0;
  // atom i's row as a message, returning its length in doubles; the length it has; the longest
  // of any atom of this process
  virtual int get_message(int i, double *message) = 0;
  virtual int message_length(int i) = 0;
  virtual int longest_message() = 0;
  // atom i takes the row of a message with history_values() values per contact
  virtual void put_message(int i, const double *message) = 0;
  // a CPU style's step: the history and each atom's row in it, which the step rewrites (none
  // where the rows live on a Kokkos device, whose styles sweep fix griddem/kk's pools); then
  // commit_step() once the step has written them, with the step's law (whose parity turns a
  // contact's values to its partner's side) and the most contacts of one atom
  virtual griddem_history_rows begin_step() { return griddem_history_rows{nullptr, nullptr}; }
  virtual void commit_step(const griddem_model & /*law*/, int /*most_contacts*/) {}

  // the periodic image code (griddem_image_code) of each owned and ghost atom along the image
  // axes `axes` (bit d: axis d), for the history keys of a box thin along them; the ghosts' by a
  // forward communication, which adds each ghost's periodic shift. Valid until the next call.
  const int *periodic_images(int axes);
  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;

  // entries an exchanged row is given room for, longest_row or more: a power of two
  static int exchange_room(int longest_row);

  // atom i takes the row of a record laid out as pack_restart writes it
  void put_history(int i, const double *record);
  // every atom's row emptied
  void drop_history();

  const GriddemFixOptions options;
  int made_by_pair;     // 1: the pair style's own fix, deleted with the pair style

 protected:
  // tells the pair style this fix goes, while its rows can still be read: called by the
  // destructor of the most derived class
  void leave();

 private:
  // joins Atom's per-atom callbacks, every atom's row empty: at the first init, or as rows come
  // before it (a restart file's, those of the fix this one replaces). Until then the fix holds
  // no row, and LAMMPS's commands that refuse fixes with per-atom data (replicate) run after
  // pair_style as they do after stock's, which makes its history fix at the first run.
  void track_atoms();
  int tracking;    // 1: in Atom's per-atom callbacks (track_atoms)
  // value 7 read: refused unless the step tallied the energy; due again when its reader next reads
  void request_energy(const struct griddem_engine_stats &s);
  // atoms given new IDs between runs (delete_atoms compress yes, reset_atoms id): each row's own
  // ID, written into it at a run's end, tells the keys to renumber at the next init
  void follow_renumbering();
  static int renumbering_answers(int n, char *in, int &flag, int *&procs, char *&out, void *ptr);
  int own_message(int i, double *message);    // atom i's row message with its own ID
  GriddemFixOptions parse_options(int narg, char **arg);
  std::vector<int> image_codes;    // periodic_images()
  int image_axes;                  // of the last periodic_images()
};

}    // namespace LAMMPS_NS

#endif
