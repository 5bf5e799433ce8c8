/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem.
   Holds the grid options, the per-atom contact history (which migrates with its atom between
   processes and is written to restart files) and the grid diagnostics as a global vector.
------------------------------------------------------------------------- */

#include "fix_griddem.h"

#include "atom.h"
#include "error.h"
#include "griddem_grid.h"
#include "griddem_contact.h"
#include "griddem_sweep.h"
#include "memory.h"

#include <cstring>
#include <utility>
#include <mpi.h>

using namespace LAMMPS_NS;
using namespace FixConst;

FixGriddem::FixGriddem(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), cell_mode(GRIDDEM_CELL_EXACT), cell_edge(0.0), slots(24), hist(),
    row_of(nullptr), stats()
{
  int iarg = 3;
  while (iarg < narg) {
    if (strcmp(arg[iarg], "cell") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem cell", error);
      if (strcmp(arg[iarg + 1], "exact") == 0)
        cell_mode = GRIDDEM_CELL_EXACT;
      else if (strcmp(arg[iarg + 1], "multi") == 0)
        cell_mode = GRIDDEM_CELL_MULTI;
      else {
        cell_mode = GRIDDEM_CELL_FIXED;
        cell_edge = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
        if (cell_edge <= 0.0)
          error->all(FLERR, "Fix griddem cell must be exact, multi or a positive edge, not {}",
                     arg[iarg + 1]);
      }
      iarg += 2;
    } else if (strcmp(arg[iarg], "contacts") == 0) {
      if (iarg + 2 > narg) utils::missing_cmd_args(FLERR, "fix griddem contacts", error);
      slots = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (slots < 0 || slots > 10000)
        error->all(FLERR, "Fix griddem contacts must be between 0 and 10000, not {}", slots);
      iarg += 2;
    } else
      error->all(FLERR, "Unknown fix griddem keyword: {}", arg[iarg]);
  }
  griddem_history_init(&hist, 3, slots);
  // most values one atom's row adds to an exchange message, so Comm sizes its buffers for it
  maxexchange = 1 + slots * GRIDDEM_HISTORY_ENTRY(GRIDDEM_MAX_HISTORY);

  vector_flag = 1;
  size_vector = 7;
  global_freq = 1;
  extvector = 0;
  restart_peratom = 1;
  create_attribute = 1;    // atoms made later (create_atoms, fix pour) start with no contacts

  grow_arrays(atom->nmax);
  atom->add_callback(Atom::GROW);
  atom->add_callback(Atom::RESTART);
  for (int i = 0; i < atom->nmax; i++) row_of[i] = -1;
}

FixGriddem::~FixGriddem()
{
  atom->delete_callback(id, Atom::GROW);
  atom->delete_callback(id, Atom::RESTART);
  memory->destroy(row_of);
  griddem_history_free(&hist);
}

int FixGriddem::setmask()
{
  return 0;
}

void FixGriddem::grow_arrays(int nmax)
{
  memory->grow(row_of, nmax, "griddem:row_of");
}

void FixGriddem::adopt_rows(int nslot, const int *order, int nlocal)
{
  for (int s = 0; s < nslot; s++)
    if (order[s] < nlocal) row_of[order[s]] = s;
}

void FixGriddem::add_row(int i, int count, const double *entries, int values)
{
  row_of[i] = griddem_history_add_row(&hist, count, entries, values);
  if (row_of[i] < 0) error->one(FLERR, "Fix griddem: out of memory for the contact history of atom {}", atom->tag[i]);
}

void FixGriddem::set_values(int nv)
{
  if (griddem_history_set_values(&hist, nv) != 0)
    error->one(FLERR, "Fix griddem: out of memory converting the contact history to {} values per contact", nv);
}

void FixGriddem::set_arrays(int i)
{
  row_of[i] = -1;
}

// copies move only the row index; exchange and restart carry the row: count, then
// (tag, values) per contact

void FixGriddem::copy_arrays(int i, int j, int /*delflag*/)
{
  row_of[j] = row_of[i];
}

int FixGriddem::pack_exchange(int i, double *buf)
{
  const int count = griddem_history_count(&hist, row_of[i]);
  const int n = count * GRIDDEM_HISTORY_ENTRY(hist.values);
  buf[0] = count;
  memcpy(buf + 1, griddem_history_row(&hist, row_of[i]), sizeof(double) * n);
  return n + 1;
}

int FixGriddem::unpack_exchange(int nlocal, double *buf)
{
  const int count = static_cast<int>(buf[0]);
  add_row(nlocal, count, buf + 1, hist.values);
  return 1 + count * GRIDDEM_HISTORY_ENTRY(hist.values);
}

int FixGriddem::pack_restart(int i, double *buf)
{
  // buf[0] counts the record including itself, as other fixes read it to skip this record;
  // buf[1] is the number of values per contact, so a run with other sub-models can read it
  const int count = griddem_history_count(&hist, row_of[i]);
  const int n = count * GRIDDEM_HISTORY_ENTRY(hist.values);
  buf[0] = n + 3;
  buf[1] = hist.values;
  buf[2] = count;
  memcpy(buf + 3, griddem_history_row(&hist, row_of[i]), sizeof(double) * n);
  return n + 3;
}

void FixGriddem::unpack_restart(int nlocal, int nth)
{
  double **extra = atom->extra;
  int m = 0;
  for (int i = 0; i < nth; i++) m += static_cast<int>(extra[nlocal][m]);
  const double *record = &extra[nlocal][m];
  const int count = static_cast<int>(record[2]);
  if (count > slots)
    error->one(FLERR, "Fix griddem: atom {} has {} contacts in the restart file, more than contacts {}",
               atom->tag[nlocal], count, slots);
  // take the file's layout (the pair style, made later, converts it if its sub-models differ)
  const int record_values = static_cast<int>(record[1]);
  if (record_values != hist.values) set_values(record_values);
  add_row(nlocal, count, record + 3, record_values);
}

int FixGriddem::size_restart(int nlocal)
{
  return 3 + griddem_history_count(&hist, row_of[nlocal]) * GRIDDEM_HISTORY_ENTRY(hist.values);
}

int FixGriddem::maxsize_restart()
{
  return 3 + slots * GRIDDEM_HISTORY_ENTRY(GRIDDEM_MAX_HISTORY);
}

double FixGriddem::memory_usage()
{
  return (double) atom->nmax * sizeof(int) +
      (double) (hist.rows_cap + hist.next_rows_cap) * sizeof(long) +
      (double) (hist.entries_cap + hist.next_entries_cap) * GRIDDEM_HISTORY_ENTRY(hist.values) * sizeof(double);
}

/* 1 occupied cells, 2 most centres in one cell, 3 largest displacement per step in cells,
   4 cell edge, 5 contacts (pairs), 6 most contacts of one atom, 7 elastic energy in contacts */

double FixGriddem::compute_vector(int n)
{
  double value = 0.0;
  switch (n) {
    case 0: MPI_Allreduce(&stats.occupied_cells, &value, 1, MPI_DOUBLE, MPI_SUM, world); break;
    case 1: MPI_Allreduce(&stats.max_occupancy, &value, 1, MPI_DOUBLE, MPI_MAX, world); break;
    case 2: MPI_Allreduce(&stats.max_cells_moved, &value, 1, MPI_DOUBLE, MPI_MAX, world); break;
    case 3: MPI_Allreduce(&stats.cell_edge, &value, 1, MPI_DOUBLE, MPI_MAX, world); break;
    case 4:
      // each contact is seen from both of its atoms
      MPI_Allreduce(&stats.contacts, &value, 1, MPI_DOUBLE, MPI_SUM, world);
      value *= 0.5;
      break;
    case 5: MPI_Allreduce(&stats.max_contacts, &value, 1, MPI_DOUBLE, MPI_MAX, world); break;
    case 6: MPI_Allreduce(&stats.elastic_energy, &value, 1, MPI_DOUBLE, MPI_SUM, world); break;
  }
  return value;
}
