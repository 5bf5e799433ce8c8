/* ----------------------------------------------------------------------
   GRIDDEM package: what every fix griddem is (fix_griddem_face.h): its options, the grid diagnostics,
   and the per-atom contact history as row messages through the store's face, so that exchange
   and restart files are one format whichever store holds the rows.
------------------------------------------------------------------------- */

#include "fix_griddem_face.h"

#include "griddem_search.h"

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "pair.h"
#include "update.h"

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <utility>
#include <mpi.h>

using namespace LAMMPS_NS;
using namespace FixConst;

GriddemPairLink *LAMMPS_NS::griddem_pair_link(Pair *pair)
{
  int dim;
  return pair ? static_cast<GriddemPairLink *>(pair->extract("griddem", dim)) : nullptr;
}

// the value word names among the choices, or -1
static int choice(const char *word, std::initializer_list<std::pair<const char *, int>> choices)
{
  for (const auto &c : choices)
    if (strcmp(word, c.first) == 0) return c.second;
  return -1;
}

FixGriddem::FixGriddem(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), options(parse_options(narg, arg)), made_by_pair(0), tracking(0), image_axes(0)
{
  vector_flag = 1;
  size_vector = 8;
  global_freq = 1;
  extvector = 0;
  restart_peratom = 1;
  create_attribute = 0;        // from track_atoms() on, atoms made (create_atoms, fix pour) start with no contacts
  maxexchange_dynamic = 1;     // an atom's row is as long as its contacts: sized after each step
  comm_forward = 1;            // periodic_images()

  // Modify replaces a fix of the same ID in place: it deletes the old one and leaves its slot
  // empty while it makes the new one
  int in_place = 0;
  for (int k = 0; k < modify->nfix; k++) in_place |= modify->fix[k] == nullptr;
  if (auto pair = griddem_pair_link(force->pair)) pair->fix_made(this, in_place);
}

GriddemFixOptions FixGriddem::parse_options(int narg, char **arg)
{
  GriddemFixOptions o;
  o.cell_mode = GRIDDEM_CELL_AUTO;
  o.cell_edge = 0.0;
  o.contacts = 6;
  o.precision = GRIDDEM_PRECISION_DOUBLE;
  o.search = GRIDDEM_SEARCH_AUTO;
  o.kernel = GRIDDEM_KERNEL_AUTO;
  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "cell") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem cell", error);
      o.cell_mode = choice(arg[iarg + 1], {{"auto", GRIDDEM_CELL_AUTO}, {"exact", GRIDDEM_CELL_EXACT},
                                           {"multi", GRIDDEM_CELL_MULTI}, {"classes", GRIDDEM_CELL_CLASSES}});
      if (o.cell_mode < 0) {
        o.cell_mode = GRIDDEM_CELL_FIXED;
        o.cell_edge = utils::is_double(arg[iarg + 1]) ? utils::numeric(FLERR, arg[iarg + 1], false, lmp) : -1.0;
        if (!(o.cell_edge > 0.0))
          error->all(FLERR, "Fix griddem cell must be auto, exact, multi, classes or a positive edge, not {}",
                     arg[iarg + 1]);
      }
      iarg += 2;
    } else if (strcmp(arg[iarg], "contacts") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem contacts", error);
      o.contacts = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (o.contacts < 0 || o.contacts > 10000)
        error->all(FLERR, "Fix griddem contacts must be between 0 and 10000, not {}", o.contacts);
      iarg += 2;
    } else if (strcmp(arg[iarg], "precision") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem precision", error);
      o.precision = choice(arg[iarg + 1], {{"double", GRIDDEM_PRECISION_DOUBLE}, {"single", GRIDDEM_PRECISION_SINGLE}});
      if (o.precision < 0) error->all(FLERR, "Fix griddem precision must be single or double, not {}", arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "search") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem search", error);
      o.search = choice(arg[iarg + 1], {{"auto", GRIDDEM_SEARCH_AUTO}, {"thread", GRIDDEM_SEARCH_THREAD},
                                        {"team", GRIDDEM_SEARCH_TEAM}});
      if (o.search < 0) error->all(FLERR, "Fix griddem search must be auto, thread or team, not {}", arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "kernel") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem kernel", error);
      o.kernel = choice(arg[iarg + 1], {{"auto", GRIDDEM_KERNEL_AUTO}, {"scalar", GRIDDEM_KERNEL_SCALAR},
                                        {"avx2", GRIDDEM_KERNEL_AVX2}, {"avx512", GRIDDEM_KERNEL_AVX512}});
      if (o.kernel < 0)
        error->all(FLERR, "Fix griddem kernel must be auto, scalar, avx2 or avx512, not {}", arg[iarg + 1]);
      iarg += 2;
    } else
      error->all(FLERR, "Unknown fix griddem keyword: {}", arg[iarg]);
  }
  return o;
}

FixGriddem::~FixGriddem()
{
  if (!tracking) return;
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
}

int FixGriddem::setmask()
{
  return 0;
}

void FixGriddem::track_atoms()
{
  if (tracking) return;
  tracking = create_attribute = 1;
  grow_arrays(atom->nmax);
  for (int i = 0; i < atom->nmax; i++) set_arrays(i);
  // Atom::add_callback registers the fix in the first empty slot of Modify's list (the one a fix
  // replaced in place fills while it is constructed), else the next one: this fix's own slot is
  // emptied for the two calls
  const int slot = modify->find_fix(id);
  modify->fix[slot] = nullptr;
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  modify->fix[slot] = this;
}

void FixGriddem::init()
{
  track_atoms();
  follow_renumbering();
}

/* each row with contacts carries its atom's ID, for follow_renumbering: the row messages travel
   with the atoms through whatever happens between runs (deletions, migration, restart files) */

void FixGriddem::post_run()
{
  if (history_values() < 1) return;
  std::vector<double> message;
  for (int i = 0; i < atom->nlocal; i++) {
    if (message_length(i) <= 1) continue;
    message.resize(message_length(i) + GRIDDEM_HISTORY_ENTRY(history_values()));
    own_message(i, message.data());
    put_message(i, message.data());
  }
}

/* delete_atoms (compress yes, its default) and reset_atoms id give the atoms new IDs, and the
   rows key partners by the old ones: each key takes its partner's new ID, by the pairs (old ID,
   new ID) of every atom whose row holds its old one (a partner's does: the rows of a run's end
   hold each contact from both sides); a key whose partner is gone is dropped, so that no atom
   given its number inherits the contact. The pairs meet the keys that ask for them at the
   process old ID % nprocs (LAMMPS's rendezvous, as reset_atoms id and the special lists find
   atoms), so no process holds more than its own rows' partners. Each row then holds its atom's
   new ID: reset_atoms id runs an init of its own before it renumbers. */

namespace {
// a datum of the rendezvous: an atom's old and new ID (new >= 1), or a process's question for
// an old ID (new 0: asked; -1 in the answer: the atom is gone)
struct RenumberDatum {
  int64_t old_id, new_id;
  int proc;
};
}    // namespace

int FixGriddem::renumbering_answers(int n, char *in, int &flag, int *&procs, char *&out, void *ptr)
{
  auto *fix = (FixGriddem *) ptr;
  auto *datum = (RenumberDatum *) in;
  std::vector<std::pair<int64_t, int64_t>> known;
  int nasked = 0;
  for (int k = 0; k < n; k++) {
    if (datum[k].new_id > 0) known.emplace_back(datum[k].old_id, datum[k].new_id);
    else nasked++;
  }
  std::sort(known.begin(), known.end());
  fix->memory->create(procs, nasked, "griddem:renumbering_procs");
  auto *answer = (RenumberDatum *) fix->memory->smalloc((bigint) nasked * sizeof(RenumberDatum) + 1,
                                                        "griddem:renumbering_answers");
  int m = 0;
  for (int k = 0; k < n; k++) {
    if (datum[k].new_id > 0) continue;
    auto at = std::lower_bound(known.begin(), known.end(), std::make_pair(datum[k].old_id, (int64_t) 0));
    const bool found = at != known.end() && at->first == datum[k].old_id;
    answer[m] = {datum[k].old_id, found ? at->second : -1, datum[k].proc};
    procs[m++] = datum[k].proc;
  }
  flag = 2;
  out = (char *) answer;
  return nasked;
}

void FixGriddem::follow_renumbering()
{
  const int nlocal = atom->nlocal, values = history_values(), nprocs = comm->nprocs;
  std::vector<RenumberDatum> send;
  int renumbered = 0, any = 0;
  for (int i = 0; i < nlocal && values >= 1; i++) {
    const double *own = find_history(i, GRIDDEM_OWN_KEY);
    if (!own) continue;
    const auto before = (int64_t) own[0], now = (int64_t) atom->tag[i];
    send.push_back({before, now, comm->me});
    renumbered |= before != now;
  }
  MPI_Allreduce(&renumbered, &any, 1, MPI_INT, MPI_MAX, world);
  if (!any) return;

  // the old IDs this process's rows name, once each
  std::vector<int64_t> asked;
  std::vector<double> message;
  for (int i = 0; i < nlocal; i++) {
    if (message_length(i) <= 1) continue;
    message.resize(message_length(i));
    get_message(i, message.data());
    const size_t at = asked.size();
    asked.resize(at + (size_t) message[0]);
    asked.resize(at + griddem_message_partners(message.data(), values, asked.data() + at));
  }
  std::sort(asked.begin(), asked.end());
  asked.erase(std::unique(asked.begin(), asked.end()), asked.end());
  for (const int64_t id : asked) send.push_back({id, 0, comm->me});

  std::vector<int> procs(send.size());
  for (size_t k = 0; k < send.size(); k++) procs[k] = (int) (send[k].old_id % nprocs);
  char *buf = nullptr;
  const int nanswer = comm->rendezvous(1, (int) send.size(), (char *) send.data(), sizeof(RenumberDatum), 0,
                                       procs.data(), renumbering_answers, 0, buf, sizeof(RenumberDatum),
                                       (void *) this);
  const auto *answer = (const RenumberDatum *) buf;
  std::vector<std::pair<int64_t, int64_t>> pairs;
  for (int k = 0; k < nanswer; k++)
    if (answer[k].new_id > 0) pairs.emplace_back(answer[k].old_id, answer[k].new_id);
  memory->sfree(buf);
  std::sort(pairs.begin(), pairs.end());
  std::vector<int64_t> old_tag(pairs.size()), new_tag(pairs.size());
  for (size_t k = 0; k < pairs.size(); k++) old_tag[k] = pairs[k].first, new_tag[k] = pairs[k].second;
  for (int i = 0; i < nlocal; i++) {
    if (message_length(i) <= 1) continue;
    message.resize(message_length(i) + GRIDDEM_HISTORY_ENTRY(values));
    own_message(i, message.data());
    griddem_message_renumber(message.data(), values, old_tag.data(), new_tag.data(), (long) pairs.size());
    put_message(i, message.data());
  }
}

void FixGriddem::leave()
{
  auto pair = force ? griddem_pair_link(force->pair) : nullptr;
  if (pair) pair->fix_leaving(this);
}

void FixGriddem::put_history(int i, const double *record)
{
  track_atoms();
  set_values(griddem_restart_values(record));
  put_message(i, griddem_restart_message(record));
}

void FixGriddem::drop_history()
{
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);
}

/* An owned atom's image is minus its image flags (griddem_history.h); its keys hold partner IDs
   below 2^GRIDDEM_KEY_TAG_BITS, with the image above. */

const int *FixGriddem::periodic_images(int axes)
{
  const int nlocal = atom->nlocal;
  image_codes.resize(nlocal + atom->nghost);
  image_axes = axes;
  const imageint *image = atom->image;
  const tagint *tag = atom->tag;
  const bigint tag_limit = (bigint) 1 << GRIDDEM_KEY_TAG_BITS;
  for (int i = 0; i < nlocal; i++) {
    if ((bigint) tag[i] >= tag_limit)
      error->one(FLERR, "Fix {}: atom ID {} is {} or more, too large for the contact history of a box "
                 "narrower than twice the contact distance, which keys contacts by atom ID and periodic image",
                 id, tag[i], tag_limit);
    const int m[3] = {-(int) ((image[i] & IMGMASK) - IMGMAX), -(int) ((image[i] >> IMGBITS & IMGMASK) - IMGMAX),
                      -(int) ((image[i] >> IMG2BITS) - IMGMAX)};
    image_codes[i] = griddem_image_code(m, axes);
  }
  comm->forward_comm(this);
  return image_codes.data();
}

// a ghost's image: its source's plus the periodic shift (along the box vectors, triclinic too)

int FixGriddem::pack_forward_comm(int n, int *list, double *buf, int pbc_flag, int *pbc)
{
  const int none[3] = {0, 0, 0};
  const int *shift = pbc_flag ? pbc : none;
  for (int k = 0; k < n; k++) buf[k] = griddem_image_shifted(image_codes[list[k]], shift, image_axes);
  return n;
}

void FixGriddem::unpack_forward_comm(int n, int first, double *buf)
{
  for (int k = 0; k < n; k++) image_codes[first + k] = (int) buf[k];
}

// exchange and restart carry the row as a message

/* LAMMPS's CommKokkos (in every Kokkos run, classic exchange too) grows its send buffer by its
   factor 1.5 each time a fix's maxexchange grows (its grow_send_kokkos applies the factor where
   CommBrick's does not), so a maxexchange that followed the longest row one contact at a time
   grew that buffer geometrically (to 388 MB for 16,250 hot polydisperse atoms) */
int FixGriddem::exchange_room(int longest_row)
{
  int room = 1;
  while (room < longest_row) room *= 2;
  return room;
}

int FixGriddem::pack_exchange(int i, double *buf)
{
  return get_message(i, buf);
}

int FixGriddem::unpack_exchange(int nlocal, double *buf)
{
  put_message(nlocal, buf);
  return message_length(nlocal);
}

int FixGriddem::pack_restart(int i, double *buf)
{
  // the values per contact go with the row, so a run with other sub-models can read it
  // with the atom's own ID, so that the rows of a file read and renumbered before a run
  // (delete_atoms) follow the new IDs
  return griddem_restart_frame(buf, history_values(), own_message(i, buf + GRIDDEM_RESTART_HEADER));
}

/* An atom's row message with its own ID where it has contacts (griddem_message_with_own_tag;
   room for one more entry than its row): its length */

int FixGriddem::own_message(int i, double *message)
{
  const int length = get_message(i, message);
  if (length <= 1 || history_values() < 1) return length;
  return griddem_message_with_own_tag(message, history_values(), atom->tag[i]);
}

void FixGriddem::unpack_restart(int nlocal, int nth)
{
  track_atoms();
  const double *record = griddem_restart_record(atom->extra[nlocal], nth);
  // take the file's layout (the pair style, made later, converts it if its sub-models differ)
  const int record_values = griddem_restart_values(record);
  if (record_values != history_values()) set_values(record_values);
  put_message(nlocal, griddem_restart_message(record));
}

int FixGriddem::size_restart(int nlocal)
{
  std::vector<double> message(message_length(nlocal) + GRIDDEM_HISTORY_ENTRY(history_values()));
  return GRIDDEM_RESTART_HEADER + own_message(nlocal, message.data());
}

// the longest record of any atom on any process (the file header states one size for all)

int FixGriddem::maxsize_restart()
{
  int mine = GRIDDEM_RESTART_HEADER + longest_message() + GRIDDEM_HISTORY_ENTRY(history_values()), most;
  MPI_Allreduce(&mine, &most, 1, MPI_INT, MPI_MAX, world);
  return most;
}

/* The elastic energy is tallied on the steps LAMMPS tallies energy (Integrate::ev_set: where a
   compute of it is due), as a pair style's is. Its value read on another step is refused; read on
   such a step, it invokes compute thermo_pe as thermo's pe keyword does, so that whoever reads it
   (thermo, dumps, fix print, ave/time, halt) announces its next step to that compute
   (Modify::addstep_compute) and LAMMPS tallies energy there. */

void FixGriddem::request_energy(const griddem_engine_stats &s)
{
  if (!s.energy_tallied)
    error->all(FLERR, "Fix {}: value 7 (the elastic energy) is tallied on the steps LAMMPS tallies energy, "
               "and step {} was not one: read it on a thermo step, through a fix that reads it on its own "
               "steps (print, ave/time, halt), or after run 0", id, update->ntimestep);
  Compute *pe = modify->get_compute_by_id("thermo_pe");
  if (pe && !(pe->invoked_flag & Compute::INVOKED_SCALAR)) {
    pe->compute_scalar();
    pe->invoked_flag |= Compute::INVOKED_SCALAR;
  }
}

/* 1 occupied cells, 2 most centres in one cell, 3 largest displacement per step in cells,
   4 cell edge, 5 contacts (pairs), 6 most contacts of one atom, 7 elastic energy in contacts */

double FixGriddem::compute_vector(int n)
{
  auto pair = griddem_pair_link(force->pair);
  const griddem_engine_stats *stats = pair ? pair->step_stats(this, n == 0 || n == 1) : nullptr;
  if (!stats) {
    const char *pair_style = force->pair_style ? force->pair_style : "none";
    if (!pair)
      error->all(FLERR, "Fix {}: its grid values are those of a griddem pair style's step, and pair style {} is not a griddem pair style",
                 id, pair_style);
    error->all(FLERR, "Fix {}: its grid values are those of a griddem pair style's step, and pair style {} has run none with it yet",
               id, pair_style);
  }
  const griddem_engine_stats &s = *stats;
  double value = 0.0, mine = 0.0;
  MPI_Op op = MPI_MAX;
  switch (n) {
    case 0: mine = (double) s.occupied_cells, op = MPI_SUM; break;
    case 1: mine = s.max_occupancy; break;
    case 2: mine = s.max_cells_moved; break;
    case 3: mine = s.cell_edge; break;
    case 4: mine = 0.5 * (double) s.contacts, op = MPI_SUM; break;    // each seen from both atoms
    case 5: mine = s.max_contacts; break;
    case 6:
      request_energy(s);
      mine = s.elastic_energy, op = MPI_SUM;
      break;
    case 7:    // the candidate kernel the CPU engine runs, by its place after auto in
               // GRIDDEM_KERNEL_NAMES (the kk kernels search with their own: -1)
      mine = -1.0;
      for (int k = GRIDDEM_KERNEL_SCALAR; !kokkosable && k <= GRIDDEM_KERNEL_AVX512; k++)
        if (strcmp(GRIDDEM_KERNEL_NAMES[k], griddem_touching_name()) == 0) mine = k - GRIDDEM_KERNEL_SCALAR;
      break;
  }
  MPI_Allreduce(&mine, &value, 1, MPI_DOUBLE, op, world);
  return value;
}
