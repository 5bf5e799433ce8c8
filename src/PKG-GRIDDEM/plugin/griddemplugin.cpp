/* ----------------------------------------------------------------------
   GRIDDEM as a LAMMPS plugin: "plugin load griddemplugin.so" registers the package's pair, fix and
   compute styles (and, when built with KOKKOS, their kk, kk/device and kk/host variants) with a
   LAMMPS built with the PLUGIN and GRANULAR packages.

   The styles registered are exactly those LAMMPS would compile in: griddem_plugin_styles.h, written
   at configure time, includes every package header that declares a style, and each header's
   PairStyle/FixStyle/ComputeStyle line is expanded here into one registration, as LAMMPS's
   force.cpp and modify.cpp expand style_*.h.
------------------------------------------------------------------------- */

#include "compute.h"
#include "error.h"
#include "fix.h"
#include "lammps.h"
#include "lammpsplugin.h"
#include "library.h"
#include "pair.h"
#include "version.h"

#include "griddem_plugin_styles.h"

#include <cstring>
#include <mpi.h>
#include <string>

using namespace LAMMPS_NS;

namespace {

template <class T> Pair *make_pair(LAMMPS *lmp)
{
  return new T(lmp);
}

template <class T> Fix *make_fix(LAMMPS *lmp, int narg, char **arg)
{
  return new T(lmp, narg, arg);
}

template <class T> Compute *make_compute(LAMMPS *lmp, int narg, char **arg)
{
  return new T(lmp, narg, arg);
}

/* The plugin shares LAMMPS's classes, so it must come from the same LAMMPS version, integer sizes
   and MPI library (or STUBS) as the host; a mismatch would corrupt memory, so it is refused (MPI
   libraries are told apart as far as the size of their MPI_Comm allows). */
void check_host(LAMMPS *lmp)
{
  if (strcmp(lmp->version, LAMMPS_VERSION) != 0)
    lmp->error->all(FLERR, "GRIDDEM plugin was compiled for LAMMPS {}, not {}: rebuild it against "
                    "this LAMMPS's source", LAMMPS_VERSION, lmp->version);
  const int host_sizes[3] = {lammps_extract_setting(lmp, "tagint"),
                             lammps_extract_setting(lmp, "bigint"),
                             lammps_extract_setting(lmp, "imageint")};
  if (host_sizes[0] != (int) sizeof(tagint) || host_sizes[1] != (int) sizeof(bigint) ||
      host_sizes[2] != (int) sizeof(imageint))
    lmp->error->all(FLERR, "GRIDDEM plugin was compiled with {}-byte tagint, {}-byte bigint and "
                    "{}-byte imageint, this LAMMPS has {}, {} and {} (LAMMPS_SIZES): rebuild it "
                    "with this LAMMPS's LAMMPS_SIZES", sizeof(tagint), sizeof(bigint),
                    sizeof(imageint), host_sizes[0], host_sizes[1], host_sizes[2]);
#ifdef MPI_STUBS
  const int plugin_comm = 0;
#else
  const int plugin_comm = (int) sizeof(MPI_Comm);
#endif
  // the host's answer is 0 for the STUBS, else its sizeof(MPI_Comm) (4 for MPICH, 8 for Open MPI)
  const int host_comm = lammps_config_has_mpi_support();
  if (host_comm != plugin_comm) {
    auto mpi = [](int comm) {
      return comm ? "with an MPI whose MPI_Comm has " + std::to_string(comm) + " bytes"
                  : std::string("with the MPI STUBS");
    };
    lmp->error->all(FLERR, "GRIDDEM plugin was compiled {}, this LAMMPS {}: rebuild it with this "
                    "LAMMPS's BUILD_MPI and MPI library", mpi(plugin_comm), mpi(host_comm));
  }
}

}    // namespace

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  check_host((LAMMPS *) lmp);
  auto register_style = (lammpsplugin_regfunc) regfunc;
  lammpsplugin_t plugin;
  plugin.version = LAMMPS_VERSION;
  plugin.author = "the GRIDDEM developers";
  plugin.handle = handle;

  plugin.style = "pair";
#define PAIR_CLASS
#define PairStyle(key, Class)                                               \
  plugin.name = #key;                                                       \
  plugin.info = "GRIDDEM pair style " #key;                                 \
  plugin.creator.v1 = (lammpsplugin_factory1 *) &make_pair<Class>;          \
  (*register_style)(&plugin, lmp);
#include "griddem_plugin_styles.h"
#undef PairStyle
#undef PAIR_CLASS

  plugin.style = "fix";
#define FIX_CLASS
#define FixStyle(key, Class)                                                \
  plugin.name = #key;                                                       \
  plugin.info = "GRIDDEM fix style " #key;                                  \
  plugin.creator.v2 = (lammpsplugin_factory2 *) &make_fix<Class>;           \
  (*register_style)(&plugin, lmp);
#include "griddem_plugin_styles.h"
#undef FixStyle
#undef FIX_CLASS

  plugin.style = "compute";
#define COMPUTE_CLASS
#define ComputeStyle(key, Class)                                            \
  plugin.name = #key;                                                       \
  plugin.info = "GRIDDEM compute style " #key;                              \
  plugin.creator.v2 = (lammpsplugin_factory2 *) &make_compute<Class>;       \
  (*register_style)(&plugin, lmp);
#include "griddem_plugin_styles.h"
#undef ComputeStyle
#undef COMPUTE_CLASS
}
