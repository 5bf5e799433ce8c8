/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem.
   Holds the grid options, the per-atom contact history (which migrates with its atom between
   processes and is written to restart files) and the grid diagnostics as a global vector.
------------------------------------------------------------------------- */

#include "fix_griddem.h"

#include "atom.h"
#include "error.h"
#include "griddem_grid.h"
#include "griddem_sweep.h"
#include "memory.h"

#include <cstring>
#include <utility>
#include <mpi.h>

using namespace LAMMPS_NS;
using namespace FixConst;

FixGriddem::FixGriddem(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), cell_mode(GRIDDEM_CELL_EXACT), cell_edge(0.0), slots(24), values(3),
    rows(nullptr), row_of(nullptr), rows_used(0), rows_cap(0), stats(), next(nullptr), next_cap(0)
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
  stride = GRIDDEM_HISTORY_STRIDE(slots, values);

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
  memory->sfree(rows);
  memory->sfree(next);
}

int FixGriddem::setmask()
{
  return 0;
}

void FixGriddem::grow_arrays(int nmax)
{
  memory->grow(row_of, nmax, "griddem:row_of");
}

const double *FixGriddem::row(int i) const
{
  static const double no_contacts = 0.0;
  return row_of[i] >= 0 ? rows + (size_t) row_of[i] * stride : &no_contacts;
}

double *FixGriddem::append_row()
{
  if (rows_used == rows_cap) {
    rows_cap = rows_cap + rows_cap / 2 + 64;
    rows = (double *) memory->srealloc(rows, sizeof(double) * rows_cap * stride, "griddem:rows");
  }
  return rows + (size_t) stride * rows_used++;
}

double *FixGriddem::rows_next(int slots_next)
{
  if (slots_next > next_cap) {
    next_cap = slots_next + slots_next / 4 + 64;
    memory->sfree(next);
    next = (double *) memory->smalloc(sizeof(double) * next_cap * stride, "griddem:next");
  }
  return next;
}

void FixGriddem::adopt_next(int nslot, const int *order, int nlocal)
{
  std::swap(rows, next);
  std::swap(rows_cap, next_cap);
  rows_used = nslot;
  for (int s = 0; s < nslot; s++)
    if (order[s] < nlocal) row_of[order[s]] = s;
}

/* Copy a row written with old_values per contact into one with values per contact: values kept
   up to the shorter length, the rest zero (a sub-model that was not in use starts from zero). */

static void convert_row(const double *from, int old_values, double *to, int values)
{
  const int count = static_cast<int>(from[0]);
  to[0] = count;
  for (int k = 0; k < count; k++) {
    const double *a = from + 1 + (1 + old_values) * k;
    double *b = to + 1 + (1 + values) * k;
    for (int v = 0; v <= values; v++) b[v] = v <= old_values ? a[v] : 0.0;
  }
}

void FixGriddem::set_values(int nv)
{
  if (nv == values) return;
  const int old_values = values, old_stride = stride;
  double *old = rows;
  values = nv;
  stride = GRIDDEM_HISTORY_STRIDE(slots, values);
  rows = nullptr;
  rows_used = rows_cap = 0;
  memory->sfree(next);
  next = nullptr;
  next_cap = 0;
  for (int i = 0; i < atom->nlocal; i++) {
    if (row_of[i] < 0) continue;
    const double *from = old + (size_t) row_of[i] * old_stride;
    row_of[i] = rows_used;
    convert_row(from, old_values, append_row(), values);
  }
  memory->sfree(old);
}

void FixGriddem::set_arrays(int i)
{
  row_of[i] = -1;
}

// copies move only the row index; exchange and restart carry the entries in use:
// count, then (tag, values) per contact

int FixGriddem::used_length(const double *row) const
{
  return 1 + (1 + values) * static_cast<int>(row[0]);
}

void FixGriddem::copy_arrays(int i, int j, int /*delflag*/)
{
  row_of[j] = row_of[i];
}

int FixGriddem::pack_exchange(int i, double *buf)
{
  const int n = used_length(row(i));
  memcpy(buf, row(i), sizeof(double) * n);
  return n;
}

int FixGriddem::unpack_exchange(int nlocal, double *buf)
{
  const int n = used_length(buf);
  row_of[nlocal] = rows_used;
  memcpy(append_row(), buf, sizeof(double) * n);
  return n;
}

int FixGriddem::pack_restart(int i, double *buf)
{
  // buf[0] counts the record including itself, as other fixes read it to skip this record;
  // buf[1] is the number of values per contact, so a run with other sub-models can read it
  const int n = used_length(row(i));
  buf[0] = n + 2;
  buf[1] = values;
  memcpy(buf + 2, row(i), sizeof(double) * n);
  return n + 2;
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
  if (record_values != values) set_values(record_values);
  row_of[nlocal] = rows_used;
  convert_row(record + 2, record_values, append_row(), values);
}

int FixGriddem::size_restart(int nlocal)
{
  return 2 + used_length(row(nlocal));
}

int FixGriddem::maxsize_restart()
{
  return 2 + stride;
}

double FixGriddem::memory_usage()
{
  return (double) atom->nmax * sizeof(int) + (double) (rows_cap + next_cap) * stride * sizeof(double);
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
