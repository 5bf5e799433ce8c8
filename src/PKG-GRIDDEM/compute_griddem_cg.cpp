/* ----------------------------------------------------------------------
   GRIDDEM package: compute griddem/cg.
   Each atom of the group carries channels (mass, solid volume, momentum, m v v, its share of the
   virial, 1, its contacts) to the Nx x Ny x Nz grid points at the cell centres with cloud-in-cell
   weights (griddem_cg.h); Grid3d sums ghost points into their owners; each channel is convolved
   with the truncated Gaussian by LAMMPS's FFT3d on a grid zero-padded along non-periodic axes
   (a kernel whose truncation radius is below every grid spacing reaches no other point: the
   channels are then left as assigned, without transforms);
   the fields are ratios and differences of the smoothed channels per grid point.
------------------------------------------------------------------------- */

#include "compute_griddem_cg.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "fix_griddem_rom.h"
#include "force.h"
#include "grid3d.h"
#include "griddem_cg.h"
#include "math_const.h"
#include "memory.h"
#include "modify.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"

#if defined(__has_include)
#if __has_include("fft3d_wrap.h")
#define GRIDDEM_CG_HAVE_FFT
#include "fft3d_wrap.h"
#include "remap_wrap.h"
#endif
#endif

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace {

enum Value { SOLID, DENSITY, VX, VY, VZ, PXX, PYY, PZZ, PXY, PXZ, PYZ, TEMPERATURE, COORDINATION, NVALUES };
const char *const VALUE_NAMES[] = {"solid", "density", "vx", "vy", "vz", "pxx", "pyy", "pzz",
                                   "pxy", "pxz", "pyz", "temperature", "coordination"};

// per-atom quantities carried to the grid; tensors in LAMMPS's order xx yy zz xy xz yz
enum Channel { MASS, VOLUME, PX, PY, PZ, MVV, VIRIAL = MVV + 6, ONE = VIRIAL + 6, CONTACTS, NCHANNELS };

// the channels a value is made of
std::vector<int> channels_of(int value)
{
  std::vector<int> kinetic = {MASS, PX, PY, PZ, MVV, MVV + 1, MVV + 2, MVV + 3, MVV + 4, MVV + 5};
  switch (value) {
    case SOLID: return {VOLUME};
    case DENSITY: return {MASS};
    case VX: case VY: case VZ: return {MASS, PX, PY, PZ};
    case TEMPERATURE: return {MASS, PX, PY, PZ, MVV, MVV + 1, MVV + 2};    // the trace only
    case COORDINATION: return {ONE, CONTACTS};
    default:    // a stress component: kinetic part and contact part
      for (int k = 0; k < 6; k++) kinetic.push_back(VIRIAL + k);
      return kinetic;
  }
}

// Grid3d's reverse communication (ghost-point sums) calls back a KSpace, Pair or Fix, not a
// Compute; this Fix, never added to the input's fixes, packs and unpacks the channel brick.
class GhostSum : public Fix {
 public:
  GhostSum(LAMMPS *lmp, char **arg) : Fix(lmp, 3, arg) {}
  int setmask() override { return 0; }
  double *data = nullptr;    // the brick's first value, nper values per grid point
  int nper = 0;
  void pack_reverse_grid(int, void *vbuf, int n, int *list) override
  {
    auto buf = (double *) vbuf;
    for (int i = 0, k = 0; i < n; i++)
      for (int c = 0; c < nper; c++) buf[k++] = data[(long) list[i] * nper + c];
  }
  void unpack_reverse_grid(int, void *vbuf, int n, int *list) override
  {
    auto buf = (double *) vbuf;
    for (int i = 0, k = 0; i < n; i++)
      for (int c = 0; c < nper; c++) data[(long) list[i] * nper + c] += buf[k++];
  }
};

// px x py processes for an nx x ny plane, the squarest pieces (PPPM's procs2grid2d)
void procs2grid2d(int nprocs, int nx, int ny, int &px, int &py)
{
  int best = 2 * (nx + ny) + 2, bestarea = 0;
  px = 1, py = nprocs;
  for (int ipx = 1; ipx <= nprocs; ipx++) {
    if (nprocs % ipx) continue;
    const int ipy = nprocs / ipx;
    const int boxx = (nx + ipx - 1) / ipx, boxy = (ny + ipy - 1) / ipy;
    if (boxx + boxy < best || (boxx + boxy == best && boxx * boxy > bestarea)) {
      best = boxx + boxy, bestarea = boxx * boxy, px = ipx, py = ipy;
    }
  }
}

}    // namespace

ComputeGriddemCg::ComputeGriddemCg(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nslot(0), contact_grid(), contact_bins(), grid3d(nullptr), ghost_sum(nullptr),
    channels(nullptr), gc_buf1(nullptr), gc_buf2(nullptr), fft(nullptr), to_fft(nullptr),
    from_fft(nullptr), nmax(0), virial(nullptr)
{
#ifndef GRIDDEM_CG_HAVE_FFT
  error->all(FLERR, "Compute griddem/cg requires the KSPACE package (its FFT3d and Remap)");
#elif FFT_PRECISION == 1
  error->all(FLERR, "Compute griddem/cg requires double-precision FFTs (LAMMPS built with FFT_SINGLE)");
#endif
  if (narg < 8) utils::missing_cmd_args(FLERR, "compute griddem/cg", error);
  if (!domain->box_exist) error->all(FLERR, "Compute griddem/cg command before simulation box is defined");
  if (domain->dimension != 3) error->all(FLERR, "Compute griddem/cg requires a 3d simulation");
  if (domain->triclinic) error->all(FLERR, "Compute griddem/cg does not support triclinic boxes");
  for (int d = 0; d < 3; d++) {
    ngrid[d] = utils::inumeric(FLERR, arg[3 + d], false, lmp);
    if (ngrid[d] < 1)
      error->all(FLERR, "Compute griddem/cg: grid count N{} must be at least 1, not {}", "xyz"[d],
                 arg[3 + d]);
  }
  width = utils::numeric(FLERR, arg[6], false, lmp);
  if (width <= 0.0) error->all(FLERR, "Compute griddem/cg: kernel width W must be > 0, not {}", arg[6]);

  slot.assign(NCHANNELS, -1);
  for (int iarg = 7; iarg < narg; iarg++) {
    int v = 0;
    while (v < NVALUES && strcmp(arg[iarg], VALUE_NAMES[v]) != 0) v++;
    if (v == NVALUES)
      error->all(FLERR, "Compute griddem/cg: unknown value {} (solid density vx vy vz pxx pyy pzz "
                 "pxy pxz pyz temperature coordination)", arg[iarg]);
    values.push_back(v);
    for (int c : channels_of(v)) slot[c] = 1;
  }
  for (int c = 0; c < NCHANNELS; c++)
    if (slot[c] >= 0) slot[c] = nslot++, carried.push_back(c);
  if ((slot[VOLUME] >= 0 || slot[CONTACTS] >= 0) && !atom->radius_flag)
    error->all(FLERR, "Compute griddem/cg: solid and coordination require atom attribute radius");
  if (slot[VIRIAL] >= 0) {
    // the contact stress is each atom's per-atom virial: the same pair-by-pair tallies LAMMPS sums
    // into compute pressure's virial, so the stress field integrates to that tensor to rounding
    // (a re-evaluation by pair->single() would see contact history already advanced this step)
    pressatomflag = 1;
    comm_reverse = 6;
  }
  if (slot[CONTACTS] >= 0) comm_forward = 3;    // the ghosts' positions (count_contacts)
  // the steps it is invoked on, as LAMMPS's dumps and thermo announce them: the per-atom virial is
  // tallied there, and fix griddem/rom brings the atoms it holds back for them
  timeflag = 1;

  pergrid_flag = 1;
  std::string names[3] = {"griddem_cg_ghost_sum", "all", "griddem/cg/ghost_sum"};
  char *fixarg[3] = {&names[0][0], &names[1][0], &names[2][0]};
  ghost_sum = new GhostSum(lmp, fixarg);
  allocate_grid();
}

ComputeGriddemCg::~ComputeGriddemCg()
{
  deallocate_grid();
  delete ghost_sum;
  memory->destroy(virial);
  griddem_bins_free(&contact_bins);
}

void ComputeGriddemCg::init()
{
  if (domain->triclinic) error->all(FLERR, "Compute griddem/cg does not support triclinic boxes (the box became one)");
  // the pair style's cutoff is what makes the ghost atoms hold every touching partner
  if (slot[CONTACTS] >= 0 && !force->pair)
    error->all(FLERR, "Compute griddem/cg: coordination requires a pair style");
  if (slot[VIRIAL] >= 0 && !force->pair)
    error->all(FLERR, "Compute griddem/cg: stress values require a pair style");
  averages.clear();
  if (slot[VIRIAL] >= 0) averages = modify->get_fix_by_style("^ave/grid");
}

void ComputeGriddemCg::allocate_grid()
{
  grid3d = new Grid3d(lmp, world, ngrid[0], ngrid[1], ngrid[2]);
  // an owned atom lies at most half a skin outside its subdomain between reneighborings; its
  // cloud-in-cell points are floor(u) and floor(u) + 1 with u = (x - boxlo) / h - 1/2
  grid3d->set_distance(0.5 * neighbor->skin);
  grid3d->set_shift_atom(-0.5, -0.5);
  grid3d->set_stencil_atom(0, 1);
  grid3d->setup_grid(lo_in[0], hi_in[0], lo_in[1], hi_in[1], lo_in[2], hi_in[2], lo_out[0],
                     hi_out[0], lo_out[1], hi_out[1], lo_out[2], hi_out[2]);
  int nbuf1, nbuf2;
  grid3d->setup_comm(nbuf1, nbuf2);
  memory->create(gc_buf1, (bigint) nslot * nbuf1, "griddem/cg:gc_buf1");
  memory->create(gc_buf2, (bigint) nslot * nbuf2, "griddem/cg:gc_buf2");
  memory->create4d_offset_last(channels, lo_out[2], hi_out[2], lo_out[1], hi_out[1], lo_out[0],
                               hi_out[0], nslot, "griddem/cg:channels");
  fields.assign(values.size(), nullptr);
  for (auto &field : fields)
    memory->create3d_offset(field, lo_out[2], hi_out[2], lo_out[1], hi_out[1], lo_out[0],
                            hi_out[0], "griddem/cg:field");
  const long nowned = (long) (hi_in[0] - lo_in[0] + 1) * (hi_in[1] - lo_in[1] + 1) * (hi_in[2] - lo_in[2] + 1);
  owned.assign(nowned, 0.0);
  smoothed.assign(nowned * nslot, 0.0);
  fftsize[0] = fftsize[1] = fftsize[2] = 0;
}

void ComputeGriddemCg::deallocate_grid()
{
  destroy_fft();
  delete grid3d;
  grid3d = nullptr;
  memory->destroy(gc_buf1);
  memory->destroy(gc_buf2);
  memory->destroy4d_offset_last(channels, lo_out[2], lo_out[1], lo_out[0]);
  for (auto &field : fields) memory->destroy3d_offset(field, lo_out[2], lo_out[1], lo_out[0]);
  fields.clear();
}

void ComputeGriddemCg::reset_grid()
{
  deallocate_grid();
  allocate_grid();
}

/* FFT grid of size[3] points in x pencils (as PPPM); owned points are remapped in and out. */
void ComputeGriddemCg::make_fft(const int size[3])
{
#ifdef GRIDDEM_CG_HAVE_FFT
  destroy_fft();
  for (int d = 0; d < 3; d++) fftsize[d] = size[d];
  int npy, npz;
  procs2grid2d(comm->nprocs, size[1], size[2], npy, npz);
  const int me_y = comm->me % npy, me_z = comm->me / npy;
  fft_lo[0] = 0, fft_hi[0] = size[0] - 1;
  fft_lo[1] = me_y * size[1] / npy, fft_hi[1] = (me_y + 1) * size[1] / npy - 1;
  fft_lo[2] = me_z * size[2] / npz, fft_hi[2] = (me_z + 1) * size[2] / npz - 1;
  int nbuf;
  fft = new FFT3d(lmp, world, size[0], size[1], size[2], fft_lo[0], fft_hi[0], fft_lo[1], fft_hi[1],
                  fft_lo[2], fft_hi[2], fft_lo[0], fft_hi[0], fft_lo[1], fft_hi[1], fft_lo[2],
                  fft_hi[2], 1, 0, &nbuf, 0);
  to_fft = new Remap(lmp, world, lo_in[0], hi_in[0], lo_in[1], hi_in[1], lo_in[2], hi_in[2],
                     fft_lo[0], fft_hi[0], fft_lo[1], fft_hi[1], fft_lo[2], fft_hi[2], 1, 0, 1,
                     FFT_PRECISION, 0);
  from_fft = new Remap(lmp, world, fft_lo[0], fft_hi[0], fft_lo[1], fft_hi[1], fft_lo[2], fft_hi[2],
                       lo_in[0], hi_in[0], lo_in[1], hi_in[1], lo_in[2], hi_in[2], 1, 0, 1,
                       FFT_PRECISION, 0);
  const long nfft = (long) (fft_hi[0] - fft_lo[0] + 1) * (fft_hi[1] - fft_lo[1] + 1) *
      (fft_hi[2] - fft_lo[2] + 1);
  fft_real.assign(nfft, 0.0);
  work.assign(2 * nfft, 0.0);
  kernel_hat.assign(2 * nfft, 0.0);
  kernel_h[0] = kernel_h[1] = kernel_h[2] = 0.0;    // transformed again for this grid
#else
  (void) size;
#endif
}

void ComputeGriddemCg::destroy_fft()
{
#ifdef GRIDDEM_CG_HAVE_FFT
  delete fft;
  delete to_fft;
  delete from_fft;
#endif
  fft = nullptr, to_fft = from_fft = nullptr;
}

/* The kernel's transform, on the FFT grid with the spacings h. */
void ComputeGriddemCg::transform_kernel(const double h[3])
{
#ifdef GRIDDEM_CG_HAVE_FFT
  int reach[3];
  for (int d = 0; d < 3; d++)
    reach[d] = domain->periodicity[d] ? GRIDDEM_CG_PERIODIC : fftsize[d] - ngrid[d];
  griddem_cg_kernel_brick(fftsize, reach, fft_lo, fft_hi, h, width, fft_real.data());
  for (size_t n = 0; n < fft_real.size(); n++) kernel_hat[2 * n] = fft_real[n], kernel_hat[2 * n + 1] = 0.0;
  fft->compute(kernel_hat.data(), kernel_hat.data(), FFT3d::FORWARD);
  for (int d = 0; d < 3; d++) kernel_h[d] = h[d];
#else
  (void) h;
#endif
}

/* Smooth channel slot s: owned points -> (by_kernel: FFT grid (padding zero) -> product with the
   kernel's transform -> back (FFT3d scales the backward transform by 1/points)) -> smoothed. */
void ComputeGriddemCg::smooth(int s, bool by_kernel)
{
#ifdef GRIDDEM_CG_HAVE_FFT
  long n = 0;
  for (int iz = lo_in[2]; iz <= hi_in[2]; iz++)
    for (int iy = lo_in[1]; iy <= hi_in[1]; iy++)
      for (int ix = lo_in[0]; ix <= hi_in[0]; ix++) owned[n++] = channels[iz][iy][ix][s];
  if (by_kernel) convolve();
  for (size_t c = 0; c < owned.size(); c++) smoothed[c * nslot + s] = owned[c];
#else
  (void) s, (void) by_kernel;
#endif
}

/* owned, convolved with the kernel in place */
void ComputeGriddemCg::convolve()
{
#ifdef GRIDDEM_CG_HAVE_FFT
  std::fill(fft_real.begin(), fft_real.end(), 0.0);
  to_fft->perform(owned.data(), fft_real.data(), nullptr);
  const size_t nfft = fft_real.size();
  for (size_t i = 0; i < nfft; i++) work[2 * i] = fft_real[i], work[2 * i + 1] = 0.0;
  fft->compute(work.data(), work.data(), FFT3d::FORWARD);
  for (size_t i = 0; i < nfft; i++) {
    const double re = work[2 * i], im = work[2 * i + 1];
    const double kre = kernel_hat[2 * i], kim = kernel_hat[2 * i + 1];
    work[2 * i] = re * kre - im * kim;
    work[2 * i + 1] = re * kim + im * kre;
  }
  fft->compute(work.data(), work.data(), FFT3d::BACKWARD);
  for (size_t i = 0; i < nfft; i++) fft_real[i] = work[2 * i];
  from_fft->perform(fft_real.data(), owned.data(), nullptr);
#endif
}

/* Fix ave/grid (LAMMPS 4Feb2025) in grid mode tells the computes with invocation times only its
   first sample step (when made, and after a minimize), never the later ones, so the per-atom virial
   would not be tallied on them. Its samples fall on multiples of its nevery (its nfreq is a multiple
   of nevery) and its windows end on multiples of nfreq: within a window ask for the next multiple
   of nevery; at a window's end for every multiple of nevery up to nfreq ahead, as the fix keeps
   nrepeat, hence where the next window starts, to itself (a per-atom virial on steps between
   windows that nothing reads, where nrepeat x nevery < nfreq). Asked for in descending order, each
   step lands at the end of the compute's list of steps (Compute::addstep keeps it sorted). */
void ComputeGriddemCg::ask_for_virial()
{
  const bigint now = update->ntimestep;
  for (Fix *average : averages) {
    const bigint every = average->nevery, nfreq = average->pergrid_freq;
    const bigint last = now % nfreq ? (now / every + 1) * every : now + nfreq;
    for (bigint step = last; step > now; step -= every) addstep(step);
  }
}

/* Per-atom virial of the pair style and of fixes that add to the virial (as compute stress/atom);
   with newton, ghost atoms' shares go back to their owners. */
void ComputeGriddemCg::gather_virial()
{
  if (update->vflag_atom != update->ntimestep)
    error->all(FLERR, "Compute griddem/cg: per-atom virial was not tallied on step {} (stress "
               "values are available on output steps only)", update->ntimestep);
  const int nall = atom->nlocal + atom->nghost;
  if (nall > nmax) {
    nmax = atom->nmax;
    memory->destroy(virial);
    memory->create(virial, nmax, 6, "griddem/cg:virial");
  }
  const int ntally = force->newton ? nall : atom->nlocal;
  for (int i = 0; i < ntally; i++)
    for (int k = 0; k < 6; k++) virial[i][k] = 0.0;
  if (force->pair && force->pair->vatom)
    for (int i = 0; i < ntally; i++)
      for (int k = 0; k < 6; k++) virial[i][k] += force->pair->vatom[i][k];
  for (auto &ifix : modify->get_fix_list())
    if (ifix->virial_peratom_flag && ifix->thermo_virial && ifix->vatom)
      for (int i = 0; i < atom->nlocal; i++)
        for (int k = 0; k < 6; k++) virial[i][k] += ifix->vatom[i][k];
  if (force->newton) comm->reverse_comm(this);
}

/* an owned atom's position as its ghost's, shifted by the periodic images crossed (the box is
   orthogonal) */
int ComputeGriddemCg::pack_forward_comm(int n, int *list_, double *buf, int pbc_flag, int *pbc)
{
  const double shift[3] = {pbc_flag ? pbc[0] * domain->xprd : 0.0, pbc_flag ? pbc[1] * domain->yprd : 0.0,
                           pbc_flag ? pbc[2] * domain->zprd : 0.0};
  int m = 0;
  for (int i = 0; i < n; i++)
    for (int d = 0; d < 3; d++) buf[m++] = atom->x[list_[i]][d] + shift[d];
  return m;
}

void ComputeGriddemCg::unpack_forward_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int d = 0; d < 3; d++) atom->x[i][d] = buf[m++];
}

int ComputeGriddemCg::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int k = 0; k < 6; k++) buf[m++] = virial[i][k];
  return m;
}

void ComputeGriddemCg::unpack_reverse_comm(int n, int *list_, double *buf)
{
  int m = 0;
  for (int i = 0; i < n; i++)
    for (int k = 0; k < 6; k++) virial[list_[i]][k] += buf[m++];
}

/* Touching neighbours (overlap > 0) of each owned atom among the owned and ghost atoms. */
void ComputeGriddemCg::count_contacts()
{
  // the ghosts where their atoms are now: a fix that moves atoms at the end of a step (fix
  // deform's remap) leaves them where the step's communication put them (this compute's own
  // communication: it reads and writes the host's positions whatever the atom style's back end)
  comm->forward_comm(this);
  const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
  contacts.assign(nlocal, 0.0);
  if (nall && griddem_cg_contacts(nlocal, nall, atom->x[0], atom->radius, contacts.data(), &contact_grid,
                                  &contact_bins) != 0)
    error->one(FLERR, "Compute griddem/cg: no memory for the grid of {} atoms that finds their contacts", nall);
}

void ComputeGriddemCg::compute_pergrid()
{
  invoked_pergrid = update->ntimestep;
  // fix griddem/rom's stored atoms are deposited where they are held where it can give them (one
  // process) and the values need nothing but their own quantities; else it brings them back for
  // the steps this compute can be invoked on (announced ones, fix ave/grid's): on any other step
  // the fields would miss them. Looked up here, not at init: a fix unfixed since is gone
  std::vector<double> held;    // FixGriddemRom::FIELD_VALUES per stored atom of the group
  for (Fix *fix : modify->get_fix_by_style("^griddem/rom$")) {
    auto rom = dynamic_cast<FixGriddemRom *>(fix);
    if (!rom) continue;
    int dim = 0;
    const auto *nheld = (const double *) rom->extract("stored_atoms", dim);
    if (!nheld || *nheld == 0.0) continue;
    if (!reads_store() || !rom->fields_in_place())
      error->all(FLERR, "Compute griddem/cg: invoked at step {}, which was not announced to it, while fix {} holds {} "
                 "atoms out of LAMMPS (its keyword store); use store no",
                 update->ntimestep, rom->id, (bigint) *nheld);
    rom->stored_for_fields(groupbit, held);
  }
  if (slot[VIRIAL] >= 0) {
    ask_for_virial();
    gather_virial();
  }
  if (slot[CONTACTS] >= 0) count_contacts();

  const double *boxlo = domain->boxlo, *prd = domain->prd;
  const int *periodic = domain->periodicity;
  double h[3];
  int size[3];
  for (int d = 0; d < 3; d++) {
    h[d] = prd[d] / ngrid[d];
    size[d] = griddem_cg_fft_size(ngrid[d], periodic[d], width, h[d]);
  }
  const bool by_kernel = griddem_cg_cutoff(width) >= std::min({h[0], h[1], h[2]});
  if (by_kernel && (size[0] != fftsize[0] || size[1] != fftsize[1] || size[2] != fftsize[2])) make_fft(size);
  if (by_kernel && (h[0] != kernel_h[0] || h[1] != kernel_h[1] || h[2] != kernel_h[2])) transform_kernel(h);

  // assign
  double *first = &channels[lo_out[2]][lo_out[1]][lo_out[0]][0];
  const long nbrick = (long) (hi_out[0] - lo_out[0] + 1) * (hi_out[1] - lo_out[1] + 1) *
      (hi_out[2] - lo_out[2] + 1) * nslot;
  std::fill(first, first + nbrick, 0.0);
  double local_totals[3] = {0.0, 0.0, 0.0};    // mass, atoms, solid volume of the group here
  double value[NCHANNELS];                      // the atom's carried channels, in slot order
  const int a[6] = {0, 1, 2, 0, 0, 1}, b[6] = {0, 1, 2, 1, 2, 2};
  // one atom (LAMMPS's i, or -1 for a stored one: no virial, no contacts) to the grid
  auto assign = [&](int i, const double *x, const double *v, double m, double radius) {
    const double volume = slot[VOLUME] >= 0 ? 4.0 / 3.0 * MathConst::MY_PI * pow(radius, 3) : 0.0;
    local_totals[0] += m, local_totals[1] += 1.0, local_totals[2] += volume;
    for (int s = 0; s < nslot; s++) {
      const int c = carried[s];
      value[s] = c == MASS       ? m
          : c == VOLUME          ? volume
          : c <= PZ              ? m * v[c - PX]
          : c < VIRIAL           ? m * v[a[c - MVV]] * v[b[c - MVV]]
          : c < ONE              ? virial[i][c - VIRIAL]
          : c == ONE             ? 1.0
                                 : contacts[i];
    }
    int index[3][2];
    double weight[3][2];
    for (int d = 0; d < 3; d++) griddem_cg_cic(x[d], boxlo[d], h[d], ngrid[d], periodic[d], index[d], weight[d]);
    for (int cz = 0; cz < 2; cz++)
      for (int cy = 0; cy < 2; cy++)
        for (int cx = 0; cx < 2; cx++) {
          double *point = channels[index[2][cz]][index[1][cy]][index[0][cx]];
          const double w = weight[0][cx] * weight[1][cy] * weight[2][cz];
          for (int s = 0; s < nslot; s++) point[s] += w * value[s];
        }
  };
  for (int i = 0; i < atom->nlocal; i++)
    if (atom->mask[i] & groupbit)
      assign(i, atom->x[i], atom->v[i], atom->rmass ? atom->rmass[i] : atom->mass[atom->type[i]],
             atom->radius ? atom->radius[i] : 0.0);
  for (size_t k = 0; k < held.size(); k += FixGriddemRom::FIELD_VALUES)
    assign(-1, &held[k], &held[k + 3], held[k + 6], held[k + 7]);
  auto sum = static_cast<GhostSum *>(ghost_sum);
  sum->data = first;
  sum->nper = nslot;
  grid3d->reverse_comm(Grid3d::FIX, ghost_sum, 0, nslot, sizeof(double), gc_buf1, gc_buf2, MPI_DOUBLE);
  for (int s = 0; s < nslot; s++) smooth(s, by_kernel);

  // fields. FFT rounding leaves about 1e-16 of the peak, of either sign, where the kernel never
  // reached: a smoothed mass, solid volume or atom count below 1e-9 of its mean per grid point is
  // taken as none, so densities there are 0 and ratios over it are not taken (0 too)
  double totals[3];
  MPI_Allreduce(local_totals, totals, 3, MPI_DOUBLE, MPI_SUM, world);
  const double npoints = (double) ngrid[0] * ngrid[1] * ngrid[2];
  const double mass_floor = 1e-9 * totals[0] / npoints, count_floor = 1e-9 * totals[1] / npoints,
               volume_floor = 1e-9 * totals[2] / npoints;
  const double cellvol = prd[0] * prd[1] * prd[2] / npoints;
  long c = 0;
  for (int iz = lo_in[2]; iz <= hi_in[2]; iz++)
    for (int iy = lo_in[1]; iy <= hi_in[1]; iy++)
      for (int ix = lo_in[0]; ix <= hi_in[0]; ix++, c++) {
        auto channel = [&](int ch) { return smoothed[c * nslot + slot[ch]]; };
        const double mass = slot[MASS] >= 0 ? channel(MASS) : 0.0;
        const bool massive = mass > mass_floor;
        for (size_t n = 0; n < values.size(); n++) {
          const int value = values[n];
          double out = 0.0;
          if (value == SOLID) out = channel(VOLUME) > volume_floor ? channel(VOLUME) / cellvol : 0.0;
          else if (value == DENSITY) out = massive ? mass / cellvol : 0.0;
          else if (value >= VX && value <= VZ) out = massive ? channel(PX + value - VX) / mass : 0.0;
          else if (value >= PXX && value <= PYZ) {
            // kinetic: sum m (v - V)(v - V) phi = sum m v v phi - (sum m v phi)(sum m v phi) / (sum m phi)
            const int k = value - PXX, a[6] = {0, 1, 2, 0, 0, 1}, b[6] = {0, 1, 2, 1, 2, 2};
            const double mean_flow = massive ? channel(PX + a[k]) * channel(PX + b[k]) / mass : 0.0;
            out = (channel(VIRIAL + k) + channel(MVV + k) - mean_flow) / cellvol;
          } else if (value == TEMPERATURE && massive) {
            double fluctuation = 0.0;
            for (int d = 0; d < 3; d++)
              fluctuation += channel(MVV + d) - channel(PX + d) * channel(PX + d) / mass;
            // >= 0 exactly for a kernel >= 0 (Cauchy-Schwarz); rounding alone makes it negative
            out = std::max(fluctuation / (3.0 * mass), 0.0);
          } else if (value == COORDINATION && channel(ONE) > count_floor)
            out = std::max(channel(CONTACTS) / channel(ONE), 0.0);
          fields[n][iz][iy][ix] = out;
        }
      }
}

bool ComputeGriddemCg::reads_store() const
{
  return slot[VIRIAL] < 0 && slot[CONTACTS] < 0;
}

int ComputeGriddemCg::get_grid_by_name(const std::string &name, int &dim)
{
  if (name != "grid") return -1;
  dim = 3;
  return 0;
}

void *ComputeGriddemCg::get_grid_by_index(int index)
{
  return index == 0 ? grid3d : nullptr;
}

int ComputeGriddemCg::get_griddata_by_name(int igrid, const std::string &name, int &ncol)
{
  if (igrid != 0) return -1;
  for (size_t n = 0; n < values.size(); n++)
    if (name == VALUE_NAMES[values[n]]) {
      ncol = 0;
      return (int) n;
    }
  return -1;
}

void *ComputeGriddemCg::get_griddata_by_index(int index)
{
  // fix ave/grid (LAMMPS 4Feb2025, grid mode) reads grid data without clearing the computes'
  // invoked flags first, so it would be handed the fields of an earlier step: make them this step's
  if (grid3d && invoked_pergrid != update->ntimestep) compute_pergrid();
  return index >= 0 && index < (int) fields.size() ? fields[index] : nullptr;
}

double ComputeGriddemCg::memory_usage()
{
  const double points = (double) (hi_out[0] - lo_out[0] + 1) * (hi_out[1] - lo_out[1] + 1) *
      (hi_out[2] - lo_out[2] + 1);
  return sizeof(double) *
      (points * (nslot + fields.size()) + smoothed.size() + owned.size() + work.size() +
       kernel_hat.size() + fft_real.size() + 6.0 * nmax + contacts.size()) +
      sizeof(int) * ((double) contact_bins.ncell_cap + contact_bins.n_cap) + sizeof(long) * (double) contact_bins.n_cap;
}
