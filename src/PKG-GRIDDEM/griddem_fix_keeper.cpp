/* ----------------------------------------------------------------------
   GRIDDEM package: which fix griddem holds a griddem pair style's history (griddem_fix_keeper.h).
------------------------------------------------------------------------- */

#include "griddem_fix_keeper.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix_griddem_face.h"
#include "force.h"
#include "modify.h"

#include <unordered_map>

using namespace LAMMPS_NS;

static const char AUTO_FIX_ID[] = "GRIDDEM";

GriddemFixKeeper::GriddemFixKeeper(LAMMPS *lmp) : Pointers(lmp), chosen(nullptr), heir(nullptr) {}

void GriddemFixKeeper::release()
{
  chosen = nullptr;    // nothing to keep for a successor
  forget_parked();
  for (auto f : modify->get_fix_by_style("^griddem$")) {
    auto history = dynamic_cast<FixGriddem *>(f);
    if (history->made_by_pair)
      modify->delete_fix(history->id);
    else
      history->drop_history();
  }
}

void GriddemFixKeeper::make_default(const std::string &style, int kokkosable, int track_contacts, int remake)
{
  auto existing = dynamic_cast<FixGriddem *>(modify->get_fix_by_id(AUTO_FIX_ID));
  if (existing && existing->made_by_pair &&
      (remake || (track_contacts && (existing->options.contacts == 0 || existing->kokkosable != kokkosable))))
    modify->delete_fix(AUTO_FIX_ID);    // made for a style that keeps no history, or elsewhere
  else if (!modify->get_fix_by_style("^griddem$").empty())
    return;
  auto made = dynamic_cast<FixGriddem *>(
      modify->add_fix(fmt::format("{} all {}{}", AUTO_FIX_ID, style, track_contacts ? "" : " contacts 0"), 0));
  made->made_by_pair = 1;
}

void GriddemFixKeeper::fix_made(FixGriddem *made, int in_place)
{
  if (in_place && !parked_id.empty() && parked_id == made->id)
    heir = made;
  else    // a fix griddem made afresh: the history of one deleted before is dropped
    forget_parked();
}

void GriddemFixKeeper::fix_leaving(FixGriddem *leaving)
{
  if (leaving == heir) forget_parked();
  if (leaving != chosen) return;
  park(*leaving);
  chosen = nullptr;
}

void GriddemFixKeeper::forget_parked()
{
  heir = nullptr;
  parked_id.clear();
  parked.clear();
}

void GriddemFixKeeper::park(FixGriddem &from)
{
  parked.clear();
  parked_id = from.id;
  std::vector<double> record;
  for (int i = 0; i < atom->nlocal; i++) {
    record.resize(from.size_restart(i));
    from.pack_restart(i, record.data());
    if (record[2] == 0.0) continue;    // no contacts
    parked.push_back((double) atom->tag[i]);
    parked.insert(parked.end(), record.begin(), record.end());
  }
}

/* each atom takes its parked row; atoms no longer on this process lose theirs, with a warning */

void GriddemFixKeeper::unpark(FixGriddem &to)
{
  std::unordered_map<tagint, size_t> record_of;
  for (size_t m = 0; m < parked.size(); m += 1 + (size_t) parked[m + 1])
    record_of[(tagint) parked[m]] = m + 1;
  for (int i = 0; i < atom->nlocal; i++) {
    auto found = record_of.find(atom->tag[i]);
    if (found == record_of.end()) continue;
    to.put_history(i, &parked[found->second]);
    record_of.erase(found);
  }
  bigint lost = record_of.size(), lost_all = 0;
  MPI_Allreduce(&lost, &lost_all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  if (lost_all && comm->me == 0)
    error->warning(FLERR, "Pair style {}: fix {} takes the contact history of the fix it replaced, but {} atoms with contacts moved to another process or were deleted in between and lose theirs",
                   force->pair_style, to.id, lost_all);
  forget_parked();
}

FixGriddem *GriddemFixKeeper::choose(const std::string &style, int kokkosable, int track_contacts)
{
  auto fixes = modify->get_fix_by_style("^griddem$");
  if (fixes.size() > 1) {
    Fix *old = nullptr;
    for (auto f : fixes)
      if (f == chosen) old = f;
    for (auto f : fixes)
      if (!old && dynamic_cast<FixGriddem *>(f)->made_by_pair) old = f;
    std::vector<Fix *> others;
    for (auto f : fixes)
      if (f != old) others.push_back(f);
    if (old && old == chosen && others.size() == 1) {
      park(*chosen);
      heir = dynamic_cast<FixGriddem *>(others.front());
      chosen = nullptr;
      if (comm->me == 0)
        utils::logmesg(lmp, "Fix {} replaces fix {} and takes its contact history\n", heir->id, old->id);
    }
    if (old && old != chosen) {
      modify->delete_fix(old->id);
      fixes = others;
    }
  }
  if (fixes.size() > 1)
    error->all(FLERR, "Only one fix griddem may be defined (fixes {} and {}); one defined after a run replaces the one that ran",
               fixes[0]->id, fixes[1]->id);
  auto next = fixes.empty() ? nullptr : dynamic_cast<FixGriddem *>(fixes.front());
  if (!next || next->made_by_pair) {
    // until the first run after read_restart its per-atom data waits in atom->extra: the fix
    // made before the atoms were read is made again to take its history from there
    make_default(style, kokkosable, track_contacts,
                 next && next != chosen && atom->nextra_store > 0 && !next->restart_reset);
    next = dynamic_cast<FixGriddem *>(modify->get_fix_by_id(AUTO_FIX_ID));
  }
  if (heir == next) unpark(*next);
  // Modify gives a fix the restart file's per-atom data only under the ID that wrote it
  if (atom->nextra_store > 0 && !next->restart_reset && comm->me == 0)
    error->warning(FLERR, "Pair style {}: the restart file holds no contact history of fix {}, so its contacts start without one; if a fix griddem of another ID wrote it, define that fix again after read_restart",
                   force->pair_style, next->id);
  chosen = next;
  return chosen;
}
