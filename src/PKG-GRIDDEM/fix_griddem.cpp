/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem.
   Owns the grid engine: its options, the per-atom contact history (which migrates with its atom
   between processes and is written to restart files) and the grid diagnostics as a global
   vector. History rows grow with the contacts: no atom has a fixed limit.
------------------------------------------------------------------------- */

#include "fix_griddem.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "pair_griddem.h"

#include <cstring>
#include <mpi.h>

using namespace LAMMPS_NS;
using namespace FixConst;

GriddemPairLink *LAMMPS_NS::griddem_pair_link(Pair *pair)
{
  int dim;
  return pair ? static_cast<GriddemPairLink *>(pair->extract("griddem", dim)) : nullptr;
}

FixGriddem::FixGriddem(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), kokkos_history(0), cell_mode(GRIDDEM_CELL_AUTO), cell_edge(0.0), contacts(6), precision(GRIDDEM_PRECISION_DOUBLE), search(GRIDDEM_SEARCH_AUTO), made_by_pair(0),
    stats_current(0), engine(), row_of(nullptr), reserved(0)
{
  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "cell") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem cell", error);
      if (strcmp(arg[iarg + 1], "auto") == 0)
        cell_mode = GRIDDEM_CELL_AUTO;
      else if (strcmp(arg[iarg + 1], "exact") == 0)
        cell_mode = GRIDDEM_CELL_EXACT;
      else if (strcmp(arg[iarg + 1], "multi") == 0)
        cell_mode = GRIDDEM_CELL_MULTI;
      else if (strcmp(arg[iarg + 1], "classes") == 0)
        cell_mode = GRIDDEM_CELL_CLASSES;
      else {
        cell_mode = GRIDDEM_CELL_FIXED;
        cell_edge = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
        if (cell_edge <= 0.0)
          error->all(FLERR, "Fix griddem cell must be auto, exact, multi, classes or a positive edge, not {}",
                     arg[iarg + 1]);
      }
      iarg += 2;
    } else if (strcmp(arg[iarg], "contacts") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem contacts", error);
      contacts = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (contacts < 0 || contacts > 10000)
        error->all(FLERR, "Fix griddem contacts must be between 0 and 10000, not {}", contacts);
      iarg += 2;
    } else if (strcmp(arg[iarg], "precision") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem precision", error);
      if (strcmp(arg[iarg + 1], "double") == 0)
        precision = GRIDDEM_PRECISION_DOUBLE;
      else if (strcmp(arg[iarg + 1], "single") == 0)
        precision = GRIDDEM_PRECISION_SINGLE;
      else
        error->all(FLERR, "Fix griddem precision must be single or double, not {}", arg[iarg + 1]);
      iarg += 2;
    } else if (strcmp(arg[iarg], "search") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem search", error);
      if (strcmp(arg[iarg + 1], "auto") == 0)
        search = GRIDDEM_SEARCH_AUTO;
      else if (strcmp(arg[iarg + 1], "thread") == 0)
        search = GRIDDEM_SEARCH_THREAD;
      else if (strcmp(arg[iarg + 1], "team") == 0)
        search = GRIDDEM_SEARCH_TEAM;
      else
        error->all(FLERR, "Fix griddem search must be auto, thread or team, not {}", arg[iarg + 1]);
      iarg += 2;
    } else
      error->all(FLERR, "Unknown fix griddem keyword: {}", arg[iarg]);
  }
  griddem_engine_init(&engine, 3);

  vector_flag = 1;
  size_vector = 7;
  global_freq = 1;
  extvector = 0;
  restart_peratom = 1;
  create_attribute = 1;        // atoms made later (create_atoms, fix pour) start with no contacts
  maxexchange_dynamic = 1;     // an atom's row is as long as its contacts: sized after each step
  maxexchange = griddem_engine_max_row_length(&engine);

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nmax; i++) row_of[i] = -1;

  // Modify replaces a fix of the same ID in place: it deletes the old one and leaves its slot
  // empty while it makes the new one
  int in_place = 0;
  for (int k = 0; k < modify->nfix; k++) in_place |= modify->fix[k] == nullptr;
  if (auto pair = griddem_pair_link(force->pair)) pair->fix_made(this, in_place);
}

FixGriddem::~FixGriddem()
{
  leave();
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(row_of);
  griddem_engine_free(&engine);
}

int FixGriddem::setmask()
{
  return 0;
}

/* storage for `contacts` per atom up front, so the first steps do not grow it piecemeal */

void FixGriddem::init()
{
  if (reserved || contacts == 0) return;
  if (griddem_engine_reserve(&engine, atom->nlocal, contacts) != 0)
    error->one(FLERR, "Fix griddem: out of memory reserving {} contacts for each of {} atoms", contacts, atom->nlocal);
  reserved = 1;
}

void FixGriddem::grow_arrays(int nmax)
{
  memory->grow(row_of, nmax, "griddem:row_of");
}

int FixGriddem::run_step(griddem_step &step, griddem_sweep_result &result, int &coarsened)
{
  step.row_of = row_of;
  const int fault = griddem_engine_step(&engine, &step, &result, &coarsened);
  stats_current = 1;
  maxexchange = griddem_engine_max_row_length(&engine);
  return fault;
}

const double *FixGriddem::find_history(int i, double partner) const
{
  return griddem_engine_find(&engine, row_of[i], (tagint) partner);
}

void FixGriddem::leave()
{
  auto pair = force ? griddem_pair_link(force->pair) : nullptr;
  if (pair) pair->fix_leaving(this);
}

void FixGriddem::put_history(int i, const double *record)
{
  set_values(static_cast<int>(record[1]));
  unpack_exchange(i, const_cast<double *>(record + 2));
}

void FixGriddem::drop_history()
{
  for (int i = 0; i < atom->nlocal; i++) set_arrays(i);
  stats_current = 0;
}

void FixGriddem::add_row(int i, const double *message, int values)
{
  row_of[i] = griddem_engine_put_row(&engine, message, values);
  if (row_of[i] < 0)
    error->one(FLERR, "Fix griddem: out of memory for the contact history of atom {}", atom->tag[i]);
  maxexchange = griddem_engine_max_row_length(&engine);
}

void FixGriddem::set_values(int nv)
{
  if (griddem_engine_set_history_values(&engine, nv) != 0)
    error->one(FLERR, "Fix griddem: out of memory converting the contact history to {} values per contact", nv);
  maxexchange = griddem_engine_max_row_length(&engine);
}

void FixGriddem::set_arrays(int i)
{
  row_of[i] = -1;
}

// copies move only the row index; exchange and restart carry the row as a message

void FixGriddem::copy_arrays(int i, int j, int /*delflag*/)
{
  row_of[j] = row_of[i];
}

int FixGriddem::pack_exchange(int i, double *buf)
{
  return griddem_engine_get_row(&engine, row_of[i], buf);
}

int FixGriddem::unpack_exchange(int nlocal, double *buf)
{
  add_row(nlocal, buf, griddem_engine_history_values(&engine));
  return griddem_engine_row_length(&engine, row_of[nlocal]);
}

int FixGriddem::pack_restart(int i, double *buf)
{
  // the values per contact go with the row, so a run with other sub-models can read it
  return griddem_restart_frame(buf, griddem_engine_history_values(&engine),
                               griddem_engine_get_row(&engine, row_of[i], buf + GRIDDEM_RESTART_HEADER));
}

void FixGriddem::unpack_restart(int nlocal, int nth)
{
  const double *record = griddem_restart_record(atom->extra[nlocal], nth);
  // take the file's layout (the pair style, made later, converts it if its sub-models differ)
  const int record_values = griddem_restart_values(record);
  if (record_values != griddem_engine_history_values(&engine)) set_values(record_values);
  add_row(nlocal, griddem_restart_message(record), record_values);
}

int FixGriddem::size_restart(int nlocal)
{
  return GRIDDEM_RESTART_HEADER + griddem_engine_row_length(&engine, row_of[nlocal]);
}

// the longest record of any atom on any process (the file header states one size for all)

int FixGriddem::maxsize_restart()
{
  int mine = GRIDDEM_RESTART_HEADER + griddem_engine_max_row_length(&engine), most;
  MPI_Allreduce(&mine, &most, 1, MPI_INT, MPI_MAX, world);
  return most;
}

double FixGriddem::memory_usage()
{
  return (double) atom->nmax * sizeof(int) + griddem_engine_memory(&engine);
}

/* 1 occupied cells, 2 most centres in one cell, 3 largest displacement per step in cells,
   4 cell edge, 5 contacts (pairs), 6 most contacts of one atom, 7 elastic energy in contacts */

double FixGriddem::compute_vector(int n)
{
  if (!stats_current) {
    const char *pair_style = force->pair_style ? force->pair_style : "none";
    if (!griddem_pair_link(force->pair))
      error->all(FLERR, "Fix {}: its grid values are those of a griddem pair style's step, and pair style {} is not a griddem pair style",
                 id, pair_style);
    error->all(FLERR, "Fix {}: its grid values are those of a griddem pair style's step, and pair style {} has run none with it yet",
               id, pair_style);
  }
  // counted when asked: only the Kokkos styles leave it so, and their pair ran this step (the
  // values are current), so force->pair is the style that can count it
  if ((n == 0 || n == 1) && engine.stats.occupied_cells < 0)
    griddem_pair_link(force->pair)->count_occupancy(engine.stats);
  const griddem_engine_stats &s = engine.stats;
  double value = 0.0, mine = 0.0;
  MPI_Op op = MPI_MAX;
  switch (n) {
    case 0: mine = (double) s.occupied_cells, op = MPI_SUM; break;
    case 1: mine = s.max_occupancy; break;
    case 2: mine = s.max_cells_moved; break;
    case 3: mine = s.cell_edge; break;
    case 4: mine = 0.5 * (double) s.contacts, op = MPI_SUM; break;    // each seen from both atoms
    case 5: mine = s.max_contacts; break;
    case 6: mine = s.elastic_energy, op = MPI_SUM; break;
  }
  MPI_Allreduce(&mine, &value, 1, MPI_DOUBLE, op, world);
  return value;
}
