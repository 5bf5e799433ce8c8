/* ----------------------------------------------------------------------
   GRIDDEM package: fix griddem, the CPU store (fix_griddem.h). Copies within a process move
   only the row index; exchange and restart carry the row as a message (FixGriddem, fix_griddem_face.h).
------------------------------------------------------------------------- */

#include "fix_griddem.h"

#include "atom.h"
#include "error.h"
#include "memory.h"
#include "griddem_contact.h"

#include <algorithm>

using namespace LAMMPS_NS;

FixGriddemCPU::FixGriddemCPU(LAMMPS *lmp, int narg, char **arg) :
    FixGriddem(lmp, narg, arg), row_of(nullptr), reserved(0), parity_types(0), most_contacts(0)
{
  griddem_history_init(&rows, 3);
  update_maxexchange();
  grow_arrays(atom->nmax);
  for (int i = 0; i < atom->nmax; i++) row_of[i] = -1;
}

FixGriddemCPU::~FixGriddemCPU()
{
  leave();    // while the rows are still here
  memory->destroy(row_of);
  griddem_history_free(&rows);
}

/* storage for `contacts` per atom up front, so the first steps do not grow it piecemeal */

void FixGriddemCPU::init()
{
  FixGriddem::init();
  const int contacts = options.contacts;
  if (reserved || contacts == 0) return;
  const int n = atom->nlocal;
  if (griddem_history_reserve(&rows, n, (long) n * contacts) != 0)
    error->one(FLERR, "Fix griddem: out of memory reserving {} contacts for each of {} atoms", contacts, n);
  reserved = 1;
}

// before atoms migrate: the rows complete, as their messages travel

int FixGriddemCPU::setmask()
{
  return FixGriddem::setmask() | FixConst::PRE_EXCHANGE | FixConst::MIN_PRE_EXCHANGE;
}

void FixGriddemCPU::grow_arrays(int nmax)
{
  memory->grow(row_of, nmax, "griddem:row_of");
}

void FixGriddemCPU::copy_arrays(int i, int j, int /*delflag*/)
{
  row_of[j] = row_of[i];
}

void FixGriddemCPU::set_arrays(int i)
{
  row_of[i] = -1;
}

double FixGriddemCPU::memory_usage()
{
  return (double) atom->nmax * sizeof(int) + griddem_history_memory(&rows);
}

void FixGriddemCPU::set_values(int values)
{
  if (griddem_history_set_values(&rows, values) != 0)
    error->one(FLERR, "Fix griddem: out of memory converting the contact history to {} values per contact", values);
  update_maxexchange();
}

const double *FixGriddemCPU::find_history(int i, int64_t partner)
{
  complete();
  return griddem_history_find(&rows, row_of[i], partner);
}

int FixGriddemCPU::get_message(int i, double *message)
{
  complete();
  return griddem_history_get_message(&rows, row_of[i], message);
}

int FixGriddemCPU::message_length(int i)
{
  complete();
  return griddem_history_message_length(&rows, row_of[i]);
}

int FixGriddemCPU::longest_message()
{
  complete();
  return griddem_history_longest_message(&rows);
}

void FixGriddemCPU::put_message(int i, const double *message)
{
  row_of[i] = griddem_history_put_message(&rows, message, rows.values);
  if (row_of[i] < 0)
    error->one(FLERR, "Fix griddem: out of memory for the contact history of atom {}", atom->tag[i]);
  update_maxexchange();
}

void FixGriddemCPU::commit_step(const griddem_model &law, int most)
{
  const int n = law.ntypes + 1;
  parity.resize((size_t) n * n * GRIDDEM_MAX_HISTORY);
  for (int k = 0; k < n * n; k++)
    for (int v = 0; v < GRIDDEM_MAX_HISTORY; v++) parity[(size_t) k * GRIDDEM_MAX_HISTORY + v] = law.pair[k].parity[v];
  parity_types = law.ntypes;
  most_contacts = most;
  update_maxexchange();
}

void FixGriddemCPU::complete()
{
  if (!rows.one_sided) return;
  if (griddem_history_mirror(&rows, atom->nlocal, row_of, atom->tag, sizeof(tagint), atom->type, parity_types,
                             parity.data()) != 0)
    error->one(FLERR, "Fix griddem: out of memory completing the contact history of {} atoms", atom->nlocal);
  update_maxexchange();
}

// the longest row sizes exchange messages: where the rows are one-sided, the most contacts of one
// atom bounds the row each will have

void FixGriddemCPU::update_maxexchange()
{
  const int longest = rows.one_sided ? std::max(rows.max_count, most_contacts) : rows.max_count;
  maxexchange = GRIDDEM_ROW_MESSAGE_LENGTH(exchange_room(longest), rows.values);
}
