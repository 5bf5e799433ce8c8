"""2D incompressible granular flow with a pressure- and rate-dependent mu(I) viscosity and a VOF free
surface (NumPy/SciPy), after Lagree, Staron & Popinet (JFM 2011): grains and a light, weakly viscous
"air" share one velocity field; c is the grain volume fraction of a cell (VOF colour).

    rho Du/Dt = -grad p + div(2 eta D) + rho g,   div u = 0,   dc/dt + div(u c) = 0,
    rho = c rho_g + (1 - c) rho_air,   eta = c eta_g + (1 - c) eta_air,
    eta_g = min(mu(I) p / |gdot|, eta_max),   I = d |gdot| / sqrt(p / rho_s),
    |gdot| = sqrt(2 D:D) (= the shear rate in simple shear), p clipped at 0.

rho_g = phi rho_s is the bulk density of the (incompressible) grain phase. Units: grain diameter d,
particle density rho_s, gravity g.

Grid: MAC (staggered), square cells of side h; u on x-faces, v on y-faces, p and c at centres, the
shear rate du/dy + dv/dx and its viscosity at cell corners (nodes). Boundaries: no slip at the base
(y = 0), free slip at the top and at the side walls (x = 0 is the column's symmetry plane), the
side x = nx h open to air at rest instead (a given pressure, no viscous stress), or periodic in x
(the inclined-layer check).

Step (first order in time): semi-Lagrangian advection of the velocity; the viscous step implicit
with the viscosity of the previous state (a symmetric positive definite sparse solve: the force is
minus the gradient of the dissipation, K = 2 Exx^T W_c Exx + 2 Eyy^T W_c Eyy + Gxy^T W_n Gxy);
with the pressure of the previous step (incremental pressure correction: a hydrostatic state
passes the viscous step unchanged, so the normal viscous stresses leave p alone), then the
projection of the increment, div(grad dp / rho) = div u* / dt; the colour
advected in flux form (MUSCL, van Leer limiter, unsplit), so the grain volume sum(c) h^2 is conserved
to round-off in a closed box. The pressure (hydrostatic included) is the p of the rheology at the
next step.

Why NumPy with one C kernel: both linear systems are banded once the unknowns are ordered along the
box's longer side (bandwidth about twice the shorter side); their Cholesky factorization and solves,
most of a step's time, are band_cholesky.c (O(n b^2); 4-6x faster than LAPACK's dpbtrf with the
reference BLAS of a plain Debian system), the rest of a step is a few dozen vectorised NumPy
operations (see the README for the measured times)."""
import ctypes
import functools
import math
import os

import numpy as np
import scipy.sparse as sp
from scipy.ndimage import map_coordinates
from scipy.sparse.linalg import splu

HERE = os.path.dirname(os.path.abspath(__file__))


@functools.lru_cache(maxsize=None)
def band_cholesky():
    """band_cholesky.c (built by ./tools/build as build/libgriddem_band_cholesky.so; another path in
    GRIDDEM_BAND_CHOLESKY), loaded once."""
    path = os.environ.get("GRIDDEM_BAND_CHOLESKY", os.path.join(HERE, "..", "..", "build", "libgriddem_band_cholesky.so"))
    if not os.path.exists(path):
        raise FileNotFoundError("%s not found: build it with ./tools/build (or set GRIDDEM_BAND_CHOLESKY)" % path)
    lib = ctypes.CDLL(path)
    band = np.ctypeslib.ndpointer(np.float64, flags="C_CONTIGUOUS")
    lib.band_cholesky.argtypes = [ctypes.c_int, ctypes.c_int, band]
    lib.band_cholesky.restype = ctypes.c_int
    lib.band_solve.argtypes = [ctypes.c_int, ctypes.c_int, band, band]
    lib.band_solve.restype = None
    return lib


class GramSystem:
    """The symmetric positive definite matrices A(w) = sum_m E_m^T diag(w_m) E_m of the solver, for
    fixed sparse E_m and weights w_m that change every step (viscosities, densities, masses). With a
    band order of the unknowns (x-major on the grid, bandwidth about 2 ny), every entry of A in
    the lower band storage of band_cholesky.c is a fixed linear combination of the weights: that map
    is built once, so assembling A is one sparse matrix-vector product, and band_cholesky.c factors it
    (O(n b^2)). Without an order (periodic x, whose wrap couples the first and last columns) A is
    assembled as a sparse matrix and factored by SuperLU with a symmetric ordering."""

    def __init__(self, blocks, order=None):
        self.blocks = [sp.csr_matrix(E) for E in blocks]
        self.n = self.blocks[0].shape[1]
        self.order = order
        if order is None:
            return
        inv = np.empty_like(order)
        inv[order] = np.arange(self.n)
        pairs, offset = [], 0
        for E in self.blocks:
            E.sum_duplicates()
            counts = np.diff(E.indptr)
            width = int(counts.max())
            cols = -np.ones((E.shape[0], width), int)
            vals = np.zeros((E.shape[0], width))
            slot = np.arange(E.nnz) - np.repeat(E.indptr[:-1], counts)
            rows = np.repeat(np.arange(E.shape[0]), counts)
            cols[rows, slot], vals[rows, slot] = inv[E.indices], E.data
            for a in range(width):
                for b in range(width):
                    r, c = cols[:, a], cols[:, b]
                    keep = (r >= 0) & (c >= 0) & (r <= c)
                    k = np.nonzero(keep)[0]
                    pairs.append((r[k], c[k], vals[k, a] * vals[k, b], k + offset))
            offset += E.shape[0]
        r, c, v, w = (np.concatenate(x) for x in zip(*pairs))
        self.bw = int((c - r).max())
        # A(c, r), r <= c, in the lower band of band_cholesky.c; only the band's structural nonzeros
        # (about a tenth of its slots) are rows of the map
        self.slots, slot = np.unique(r * (self.bw + 1) + c - r, return_inverse=True)
        self.assemble = sp.csr_matrix((v, (slot, w)), shape=(self.slots.size, offset))

    def factor(self, weights):
        """A solver x = A(weights)^-1 b; weights: one array per block, in the blocks' order."""
        if self.order is None:
            A = sum(E.T @ sp.diags(w) @ E for E, w in zip(self.blocks, weights))
            lu = splu(A.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                      options=dict(SymmetricMode=True))
            return lu.solve
        ab = np.zeros((self.bw + 1) * self.n)
        ab[self.slots] = self.assemble @ np.concatenate(weights)
        failed = band_cholesky().band_cholesky(self.n, self.bw, ab)
        if failed:
            raise np.linalg.LinAlgError("band_cholesky: pivot %d of %d not positive" % (failed, self.n))
        order = self.order

        def solve(b):
            y = np.ascontiguousarray(b[order], dtype=float)
            band_cholesky().band_solve(self.n, self.bw, ab, y)
            x = np.empty(self.n)
            x[order] = y
            return x
        return solve


class HeldMu:
    """mu(I) from a curve defined on I <= I_max: above I_max the value at I_max is held, never an
    extrapolation (the callers report how many grain cells were held: MuIFlow.grain_inertial_numbers)."""

    def __init__(self, mu, I_max):
        self.mu, self.I_max = mu, I_max

    def __call__(self, I):
        I = np.asarray(I, float)
        return self.mu(np.minimum(I, self.I_max))


class GrainFields:
    """The colour c and pressure p of nx x ny cells of side h, and what follows from them alone.
    phi: packing fraction of the grain phase (bulk density rho_g = phi rho_s); the air's density is
    air_density rho_g."""

    def __init__(self, nx, ny, h, phi, gravity=(0.0, -1.0), rho_s=1.0, air_density=0.01):
        self.nx, self.ny, self.h = nx, ny, h
        self.rho_s, self.rho_g, self.rho_air = rho_s, phi * rho_s, air_density * phi * rho_s
        self.gx, self.gy = gravity
        self.c = np.zeros((nx, ny))
        self.p = np.zeros((nx, ny))
        self.t = 0.0

    def set_column(self, L0, H0):
        """c = the covered fraction of each cell by the rectangle [0, L0] x [0, H0]; hydrostatic p."""
        h = self.h
        xs = np.clip((L0 - np.arange(self.nx) * h) / h, 0, 1)
        ys = np.clip((H0 - np.arange(self.ny) * h) / h, 0, 1)
        self.c = np.outer(xs, ys)
        self.p = self.hydrostatic()

    def set_layer(self, H):
        ys = np.clip((H - np.arange(self.ny) * self.h) / self.h, 0, 1)
        self.c = np.tile(ys, (self.nx, 1))
        self.p = self.hydrostatic()

    def density(self):
        return self.c * self.rho_g + (1 - self.c) * self.rho_air

    def hydrostatic(self):
        """p of each cell: the weight (g_y) of the column above its centre."""
        w = self.density() * self.h * (-self.gy)
        above = np.cumsum(w[:, ::-1], axis=1)[:, ::-1]
        return above - 0.5 * w

    def thickness(self):
        """Grain thickness h(x) of each column of cells: sum of c times h."""
        return self.c.sum(axis=1) * self.h


class MuIFlow(GrainFields):
    """nx x ny cells of side h. mu: function of I (arrays). periodic_x: else walls at x = 0, nx h.
    open_pressure (ny values): the side x = nx h is open instead, to air at rest whose pressure at
    each row is open_pressure (a ghost column of cells with that p and no viscous stress; no grains
    cross it, so a caller keeps them away: FollowingBox)."""

    def __init__(self, nx, ny, h, mu, phi, gravity=(0.0, -1.0), periodic_x=False, rho_s=1.0, d=1.0,
                 air_density=0.01, air_viscosity=0.01, eta_max=1e4, open_pressure=None):
        super().__init__(nx, ny, h, phi, gravity, rho_s, air_density)
        self.mu, self.d = mu, d
        self.eta_air, self.eta_max = air_viscosity, eta_max
        self.periodic = periodic_x
        if open_pressure is not None and periodic_x:
            raise ValueError("open_pressure: a periodic box has no side to open")
        if open_pressure is not None and len(open_pressure) != ny:
            raise ValueError("open_pressure: %d values for %d rows" % (len(open_pressure), ny))
        self.open_pressure = None if open_pressure is None else np.asarray(open_pressure, float)
        self._number_unknowns()
        self._operators()
        self.U = np.zeros(self.nu + self.nv)

    # ------------------------------------------------------------ indexing and operators
    def _number_unknowns(self):
        nx, ny = self.nx, self.ny
        uid = -np.ones((nx + 1, ny), int)
        if self.periodic:
            uid[:nx] = np.arange(nx * ny).reshape(nx, ny)
            uid[nx] = uid[0]
        else:
            last = nx + 1 if self.open_pressure is not None else nx
            uid[1:last] = np.arange((last - 1) * ny).reshape(last - 1, ny)
        self.nu = int(uid.max()) + 1
        vid = -np.ones((nx, ny + 1), int)
        vid[:, 1:ny] = self.nu + np.arange(nx * (ny - 1)).reshape(nx, ny - 1)
        self.nv = nx * (ny - 1)
        self.uid, self.vid = uid, vid
        self.nnx = nx if self.periodic else nx + 1            # node columns
        # band orderings of the velocity unknowns and the cells along the longer side (bandwidth about
        # twice the shorter side); none when periodic
        if self.periodic:
            self.order_u = self.order_p = None
            return
        iu, ju = np.nonzero(uid >= 0)
        iv, jv = np.nonzero(vid >= 0)
        if nx >= ny:       # x-major: a column of u faces, then the column of v faces to its right
            key = np.concatenate([2 * iu * (ny + 1) + ju, (2 * iv + 1) * (ny + 1) + jv])
            self.order_p = np.arange(nx * ny)
        else:              # y-major: a row of v faces, then the row of u faces above it
            key = np.concatenate([(2 * ju + 1) * (nx + 1) + iu, 2 * jv * (nx + 1) + iv])
            self.order_p = np.arange(nx * ny).reshape(nx, ny).T.ravel()
        ids = np.concatenate([uid[iu, ju], vid[iv, jv]])
        self.order_u = ids[np.argsort(key, kind="stable")]

    def _matrix(self, entries, nrows, ncols):
        r, c, v = (np.concatenate(x) for x in zip(*entries))
        keep = c >= 0
        return sp.csr_matrix((v[keep], (r[keep], c[keep])), shape=(nrows, ncols))

    def _operators(self):
        nx, ny, h = self.nx, self.ny, self.h
        n = self.nu + self.nv
        I, J = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
        cell = (I * ny + J).ravel()
        ones = np.ones(nx * ny)
        self.Exx = self._matrix([(cell, self.uid[I + 1, J].ravel(), ones / h),
                                 (cell, self.uid[I, J].ravel(), -ones / h)], nx * ny, n)
        self.Eyy = self._matrix([(cell, self.vid[I, J + 1].ravel(), ones / h),
                                 (cell, self.vid[I, J].ravel(), -ones / h)], nx * ny, n)
        self.Div = (self.Exx + self.Eyy).tocsr()
        self.Grad = self.Div.T.tocsr()                          # minus the gradient, at the faces
        # nodes (i, j), j = 0..ny; the shear rate du/dy + dv/dx; rows at side walls and the top stay 0
        nnx = self.nnx
        Ni, Nj = np.meshgrid(np.arange(nnx), np.arange(ny + 1), indexing="ij")
        node = (Ni * (ny + 1) + Nj).ravel()
        Ni, Nj = Ni.ravel(), Nj.ravel()
        ent = []
        sheared = Ni < nx if self.open_pressure is not None else np.ones_like(Ni, bool)   # open side: no shear
        mid = (Nj >= 1) & (Nj <= ny - 1) & sheared
        ent.append((node[mid], self.uid[Ni[mid], Nj[mid]], np.full(mid.sum(), 1 / h)))
        ent.append((node[mid], self.uid[Ni[mid], Nj[mid] - 1], np.full(mid.sum(), -1 / h)))
        base = (Nj == 0) & sheared                              # no slip: ghost u = -u
        ent.append((node[base], self.uid[Ni[base], 0], np.full(base.sum(), 2 / h)))
        inner = (Nj <= ny - 1) & ((Ni >= 1) & (Ni <= nx - 1) if not self.periodic else np.ones_like(Ni, bool))
        left = (Ni[inner] - 1) % nx
        ent.append((node[inner], self.vid[Ni[inner] % nx, Nj[inner]], np.full(inner.sum(), 1 / h)))
        ent.append((node[inner], self.vid[left, Nj[inner]], np.full(inner.sum(), -1 / h)))
        self.Gxy = self._matrix(ent, nnx * (ny + 1), n)
        area = np.full(nnx * (ny + 1), h * h)
        area[Nj == 0] *= 0.5
        self.node_area = area
        # averages: cells -> nodes (plain; and for p, extrapolated to the base), nodes -> cells
        corners = []
        for di, dj in ((-1, -1), (0, -1), (-1, 0), (0, 0)):
            a, b = Ni + di, Nj + dj
            if self.periodic:
                a = a % nx
            corners.append((a, b, (a >= 0) & (a < nx) & (b >= 0) & (b < ny)))
        count = sum(inside.astype(float) for _, _, inside in corners)
        plain, extrap = [], []
        for a, b, inside in corners:
            k = np.nonzero(inside)[0]
            plain.append((k, a[k] * ny + b[k], 1.0 / count[k]))
            mid, base = k[Nj[k] > 0], k[Nj[k] == 0]             # p at the base: linear from the two rows above
            extrap += [(mid, a[mid] * ny + b[mid], 1.0 / count[mid]),
                       (base, a[base] * ny, 1.5 / count[base]), (base, a[base] * ny + 1, -0.5 / count[base])]
        self.C2N = self._matrix(plain, nnx * (ny + 1), nx * ny)
        self.C2N_p = self._matrix(extrap, nnx * (ny + 1), nx * ny)
        ent = []
        for di, dj in ((0, 0), (1, 0), (0, 1), (1, 1)):
            a = (I + di) % nx if self.periodic else I + di
            ent.append((cell, (a * (ny + 1) + J + dj).ravel(), np.full(nx * ny, 0.25)))
        self.N2C = self._matrix(ent, nx * ny, nnx * (ny + 1))
        # cells -> unknown faces (density at faces)
        ent = []
        uI, uJ = np.nonzero(self.uid >= 0)
        if self.periodic:
            keep = uI < nx
            uI, uJ = uI[keep], uJ[keep]
        ent.append((self.uid[uI, uJ], ((uI - 1) % nx) * ny + uJ, np.full(uI.size, 0.5)))
        ent.append((self.uid[uI, uJ], (uI % nx if self.periodic else np.minimum(uI, nx - 1)) * ny + uJ,
                    np.full(uI.size, 0.5)))                     # the open side's face: its cell's density
        vI, vJ = np.nonzero(self.vid >= 0)
        ent.append((self.vid[vI, vJ], vI * ny + vJ - 1, np.full(vI.size, 0.5)))
        ent.append((self.vid[vI, vJ], vI * ny + vJ, np.full(vI.size, 0.5)))
        r, c, v = (np.concatenate(x) for x in zip(*ent))
        self.C2F = sp.csr_matrix((v, (r, c)), shape=(n, nx * ny))
        self.g = np.concatenate([np.full(self.nu, self.gx), np.full(self.nv, self.gy)])
        # pressure gauge: p = 0 in the top-left cell (air); the closed-box Poisson matrix is singular
        # (constants), and a compatible right-hand side sums to 0, so this row fixes p there to 0
        self.gauge = np.zeros(nx * ny)
        if self.open_pressure is None:          # open: dp = 0 in the ghost cells fixes the constant
            self.gauge[ny - 1] = 1.0 / (self.rho_g * h * h)
            self.open_force = 0.0
        else:                                   # -grad p at the open faces takes the ghost cells' p
            self.open_force = np.zeros(n)
            self.open_force[self.uid[nx]] = -h * self.open_pressure
        # viscous step: M/dt + Exx^T W_c Exx + Eyy^T W_c Eyy + Gxy^T W_n Gxy; projection:
        # Div diag(1/rho_f) Div^T + gauge
        self.viscous_system = GramSystem([self.Exx, self.Eyy, self.Gxy, sp.identity(n)], self.order_u)
        self.pressure_system = GramSystem([self.Grad, sp.identity(nx * ny)], self.order_p)

    # ------------------------------------------------------------ fields
    def u_full(self, U=None):
        U = self.U if U is None else U
        ext = np.concatenate([U, [0.0]])
        return ext[self.uid], ext[self.vid]

    def viscosity(self, c, p, gdot):
        p = np.maximum(p, 0.0)
        I = self.d * gdot / np.sqrt(np.maximum(p, 1e-30) / self.rho_s)
        eta_g = np.minimum(self.mu(I) * p / np.maximum(gdot, 1e-30), self.eta_max)
        return c * eta_g + (1 - c) * self.eta_air

    def strain_rates(self, U):
        """|gdot| at cells and nodes, and the node shear rate G = du/dy + dv/dx."""
        exx, eyy, G = self.Exx @ U, self.Eyy @ U, self.Gxy @ U
        normal = 2 * exx ** 2 + 2 * eyy ** 2
        gc = np.sqrt(normal + (self.N2C @ G) ** 2)
        gn = np.sqrt(self.C2N @ normal + G ** 2)
        return gc, gn

    # ------------------------------------------------------------ step
    def advect_velocity(self, dt):
        """Semi-Lagrangian (bilinear) transport of u and v by the current velocity."""
        h, nx, ny = self.h, self.nx, self.ny
        u, v = self.u_full()
        # v at u faces and u at v faces (averages of the four neighbours)
        vpad = np.concatenate([v[-1:], v, v[:1]]) if self.periodic else np.concatenate([v[:1], v, v[-1:]])
        vu = 0.25 * (vpad[:-1, :-1] + vpad[:-1, 1:] + vpad[1:, :-1] + vpad[1:, 1:])
        uv_in = 0.25 * (u[:-1, :-1] + u[:-1, 1:] + u[1:, :-1] + u[1:, 1:])
        uv = np.zeros((nx, ny + 1))
        uv[:, 1:ny] = uv_in
        Iu, Ju = np.meshgrid(np.arange(nx + 1), np.arange(ny), indexing="ij")
        Iv, Jv = np.meshgrid(np.arange(nx), np.arange(ny + 1), indexing="ij")
        xu = Iu - dt * u / h                                   # index coordinates of the foot points
        yu = Ju - dt * vu / h
        xv = Iv - dt * uv / h
        yv = Jv - dt * v / h
        if self.periodic:
            xu = np.mod(xu, nx)
            xv = np.mod(xv - 0.0, nx)
            upad = np.concatenate([u[:nx], u[:1]])
            vwrap = np.concatenate([v, v[:1]])
            un = map_coordinates(upad, [xu, yu], order=1, mode="nearest")
            vn = map_coordinates(vwrap, [xv, yv], order=1, mode="nearest")
        else:
            un = map_coordinates(u, [xu, yu], order=1, mode="nearest")
            vn = map_coordinates(v, [xv, yv], order=1, mode="nearest")
        out = np.empty_like(self.U)
        m = self.uid >= 0
        out[self.uid[m]] = un[m]
        m = self.vid >= 0
        out[self.vid[m]] = vn[m]
        return out

    def advect_colour(self, dt):
        """Flux-form MUSCL transport of c (van Leer limiter, unsplit): sum(c) is conserved exactly
        because every face flux leaves one cell and enters its neighbour, and walls carry none."""
        u, v = self.u_full()
        c = self.c
        nx = self.nx

        def limited(a, b):
            return np.where(a * b > 0, 2 * a * b / np.where(a + b == 0, 1, a + b), 0.0)

        if self.periodic:
            cx = np.concatenate([c[-2:], c, c[:2]])
        else:
            cx = np.concatenate([c[:1], c[:1], c, c[-1:], c[-1:]])
        sx = limited(cx[1:-1] - cx[:-2], cx[2:] - cx[1:-1])    # slopes of cells -1..nx
        nu = u * dt / self.h                                   # faces 0..nx
        left, right = cx[1:-2], cx[2:-1]                       # cells either side of face i
        sl, sr = sx[:-1], sx[1:]
        fx = np.where(nu > 0, left + 0.5 * (1 - nu) * sl, right - 0.5 * (1 + nu) * sr) * nu
        cy = np.concatenate([c[:, :1], c[:, :1], c, c[:, -1:], c[:, -1:]], axis=1)
        sy = limited(cy[:, 1:-1] - cy[:, :-2], cy[:, 2:] - cy[:, 1:-1])
        nv = v * dt / self.h
        fy = np.where(nv > 0, cy[:, 1:-2] + 0.5 * (1 - nv) * sy[:, :-1],
                      cy[:, 2:-1] - 0.5 * (1 + nv) * sy[:, 1:]) * nv
        if self.periodic:
            fx[nx] = fx[0]
        else:
            fx[nx] = 0.0                                       # a wall, or the open side (air only)
        self.c = c - (fx[1:] - fx[:-1]) - (fy[:, 1:] - fy[:, :-1])

    def step(self, dt, passes=2):
        """One step of length dt. The viscosity of the first pass is that of the previous state; each
        further pass (Picard) redoes the step with the viscosity of the last pass's velocity, which
        matters when a static region starts to flow (at rest eta = eta_max: one pass holds a released
        column nearly rigid for a step, and its front lags by a few dt)."""
        nx, ny, h = self.nx, self.ny, self.h
        c = self.c.ravel()
        rho_f = self.C2F @ (c * self.rho_g + (1 - c) * self.rho_air)
        M = rho_f * h * h
        p_node = self.C2N_p @ self.p.ravel()
        c_node = np.clip(self.C2N @ c, 0, 1)
        Uadv = self.advect_velocity(dt)
        force_p = h * h * (self.Grad @ self.p.ravel()) + self.open_force   # -grad p^n times the cell area
        rhs = M * (Uadv / dt + self.g) + force_p
        solve_pressure = self.pressure_system.factor([1.0 / rho_f, self.gauge])
        U = self.U
        for _ in range(passes):
            gc, gn = self.strain_rates(U)
            wc = 2 * self.viscosity(c, self.p.ravel(), gc) * h * h
            wn = self.viscosity(c_node, p_node, gn) * self.node_area
            # each pass factors its system anew: with band_cholesky.c that is cheaper than CG
            # preconditioned with an earlier factorization (13 iterations on average at a = 2, the README)
            Ustar = self.viscous_system.factor([wc, wc, wn, M / dt])(rhs)
            dp = solve_pressure(-(self.Div @ Ustar) / dt)
            U = Ustar + dt * (self.Grad @ dp) / rho_f
        self.U = U
        self.p = self.p + dp.reshape(nx, ny)
        u, v = self.u_full()
        courant = dt / h * max(float(np.max(np.abs(u))), float(np.max(np.abs(v))), 1e-300)
        substeps = max(1, int(math.ceil(courant / 0.4)))      # the MUSCL update is bounded for CFL <= 0.5
        for _ in range(substeps):
            self.advect_colour(dt / substeps)
        self.t += dt

    def stable_dt(self, cfl=1.0, dt_max=0.05):
        """The velocity step: semi-Lagrangian advection and the implicit viscous step are stable for
        any dt, so cfl (the largest velocity's cells per step) is an accuracy choice; the colour takes
        its own substeps (CFL <= 0.4). dt_max 0.05: with 0.1 the lagged viscosity delays the start of a
        collapse (a column of height 8: front at t = 7 is 9.4 with dt 0.1, 11.2 with 0.05 and 0.025)."""
        umax = float(np.max(np.abs(self.U))) if self.U.size else 0.0
        return min(dt_max, cfl * self.h / max(umax, 1e-12))

    # ------------------------------------------------------------ diagnostics
    def grain_inertial_numbers(self):
        """I of the cells that are mostly grains (c > 0.5), at least one grain layer deep
        (p >= rho_g g d: at the free surface p -> 0 and I -> infinity by construction) and shearing
        (|gdot| > 1e-6)."""
        gc, _ = self.strain_rates(self.U)
        c, p = self.c.ravel(), self.p.ravel()
        keep = (c > 0.5) & (p >= self.rho_g * abs(self.gy) * self.d) & (gc > 1e-6)
        return self.d * gc[keep] / np.sqrt(p[keep] / self.rho_s)

    def kinetic_energy(self):
        u, v = self.u_full()
        rho = self.density()
        ke_u = 0.5 * np.sum(0.5 * (rho[:-1] + rho[1:]) * u[1:-1] ** 2) if not self.periodic else \
            0.5 * np.sum(rho * u[:-1] ** 2)
        ke_v = 0.5 * np.sum(0.5 * (rho[:, :-1] + rho[:, 1:]) * v[:, 1:-1] ** 2)
        return (ke_u + ke_v) * self.h ** 2


class FollowingBox(GrainFields):
    """MuIFlow on the part of an nx x ny closed box (walls at x = 0 and nx h, base, top) that the
    grains occupy: the solver runs on the cells [0, mx) x [0, my).
    - Its top, a free-slip wall as the box's, stays margin_min to margin + 2 quantum - 2 rows above
      the highest row with c > threshold, and comes down as the column collapses.
    - With margin_x, its length follows the front too: mx grows (never shrinks) to keep at least
      margin_x columns beyond the last column with c > threshold (margin_x + quantum_x to
      margin_x + 2 quantum_x - 1 after it grows), and until it reaches nx
      its side x = mx h is open to the air at rest beyond (MuIFlow's open_pressure), so the air that
      the front pushes ahead can leave. (A wall there instead squeezes that air: walls 4 or 12 cells
      beyond the front shortened the run-out at a = 3 by 6 % and 1.7 %, the README.)
    Outside the solver's cells the air is at rest (velocity 0) and the cells keep their c (at most
    threshold: a smear that numerical diffusion carries out, frozen, so sum(c) stays conserved to
    round-off) and p.
    Why: a collapse ends as a layer a third of the column's height and starts as a column a fraction
    of the box long, but the banded solves cost O(n b^2) with b about twice the box's shorter side;
    the solver of each size is built once (sizes are multiples of quantum rows and quantum_x columns,
    so a collapse meets a few dozen of them)."""

    def __init__(self, nx, ny, h, mu, phi, margin=8, margin_min=4, quantum=4, threshold=1e-3, margin_x=None,
                 quantum_x=8, **flow_args):
        flow_args.pop("periodic_x", None)
        flow_args.pop("open_pressure", None)
        super().__init__(nx, ny, h, phi, flow_args.get("gravity", (0.0, -1.0)), flow_args.get("rho_s", 1.0),
                         flow_args.get("air_density", 0.01))
        self.mu, self.phi, self.flow_args = mu, phi, flow_args
        self.margin, self.margin_min, self.quantum, self.threshold = margin, margin_min, quantum, threshold
        self.margin_x, self.quantum_x = margin_x, quantum_x
        self.u = np.zeros((nx + 1, ny))
        self.v = np.zeros((nx, ny + 1))
        self.solvers = {}
        self.box = (0 if margin_x is not None else nx, 0)
        self.flow = None

    def _occupied_end(self, axis):
        """One past the last column (axis 1) or row (axis 0) holding a cell with c > threshold; 1 if none."""
        occupied = (self.c > self.threshold).any(axis=axis)
        return int(np.nonzero(occupied)[0].max()) + 1 if occupied.any() else 1

    def _rows(self):
        """The box's height: margin rows above the highest row with c > threshold, rounded up to a
        multiple of quantum (at most ny); the current height is kept while it is at least margin_min
        rows above that row and less than quantum above its new height."""
        last = self._occupied_end(axis=0)
        target = min(self.ny, -(-(last + self.margin) // self.quantum) * self.quantum)
        current = self.box[1]
        return current if last + self.margin_min <= current < target + self.quantum else target

    def _columns(self):
        """The box's length: at least margin_x columns beyond the last column with c > threshold,
        rounded up to a multiple of quantum_x (at most nx); it never shrinks."""
        if self.margin_x is None:
            return self.nx
        last = self._occupied_end(axis=1)
        if last + self.margin_x <= self.box[0]:
            return self.box[0]
        return min(self.nx, -(-(last + self.margin_x + self.quantum_x) // self.quantum_x) * self.quantum_x)

    def enter(self):
        """Pick the box's size and load the fields into its solver."""
        mx, my = self.box = (self._columns(), self._rows())
        if self.box not in self.solvers:
            side = self.p[mx, :my].copy() if mx < self.nx else None     # the air at rest beyond
            self.solvers[self.box] = MuIFlow(mx, my, self.h, self.mu, self.phi, open_pressure=side, **self.flow_args)
        f = self.flow = self.solvers[self.box]
        f.mu, f.t = self.mu, self.t
        f.c, f.p = self.c[:mx, :my].copy(), self.p[:mx, :my].copy()
        m = f.uid >= 0
        f.U[f.uid[m]] = self.u[:mx + 1, :my][m]
        m = f.vid >= 0
        f.U[f.vid[m]] = self.v[:mx, :my + 1][m]

    def set_column(self, L0, H0):
        super().set_column(L0, H0)
        self.enter()

    def step(self, dt, passes=2):
        self.enter()
        f = self.flow
        f.step(dt, passes)
        mx, my = self.box
        self.c[:mx, :my], self.p[:mx, :my] = f.c, f.p
        self.u[:], self.v[:] = 0.0, 0.0
        self.u[:mx + 1, :my], self.v[:mx, :my + 1] = f.u_full()
        self.t = f.t

    def stable_dt(self, cfl=1.0, dt_max=0.05):
        return self.flow.stable_dt(cfl, dt_max)

    def grain_inertial_numbers(self):
        return self.flow.grain_inertial_numbers()

    def kinetic_energy(self):
        return self.flow.kinetic_energy()
