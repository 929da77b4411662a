"""Flow fields: the time-averaged solvent velocity and number density on a grid
(doc/flow-fields.md).

    from marble.flow import FlowField
    ff = FlowField(system, grid=(24, 24, 24), types=[0], co_moving=colloid.id)
    ff.sample_run(n_samples=1000, every=10)   # integrate 10 steps, sample, 1000 times
    ff.velocity      # (nx, ny, nz, 3), NaN in cells no particle ever visited
    ff.density       # (nx, ny, nz) number density
    ff.write_vtk("flow.vtk")                  # ParaView: legacy VTK structured points

The grid covers the whole box or a sub-box ``lower``..``upper``. With
``co_moving=pid`` the grid moves with particle ``pid`` (a colloid): positions are
taken relative to its centre (minimum image, so ``lower`` defaults to -L/2) and
velocities relative to its velocity. Each sample bins the selected particles
with ``numpy.bincount`` (a few ms for 1e5 particles); the average of a cell is
(sum of velocities) / (number of particles seen), so a cell is weighted by its
occupancy and an empty cell is NaN, never 0. With ``block_size=n`` the samples
are also grouped in blocks of n and ``velocity_error`` is the standard error of
the block means (choose blocks longer than the flow's correlation time).

The module also gives the Stokes flow of a sphere dragged by a force, unbounded
(Stokes 1851; Basset 1888 for a Navier slip length) and in a periodic box
(``periodic_stokes_velocity``), for comparison.
"""
import numpy as np

__all__ = ["FlowField", "axis_profile", "write_vtk", "read_vtk", "stokes_velocity",
           "periodic_stokes_velocity"]


def _vec3(name, x):
    a = np.asarray(x, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"parameter '{name}' must be a finite 3-vector, got {x!r}")
    return a


class FlowField:
    """Time-averaged velocity and number density of particles on a regular grid.

    Parameters
    ----------
    system : marble.System
    grid : (nx, ny, nz) ints >= 1, the number of cells along each axis.
    types : particle types to include (default: every type; the co-moving
        particle itself is always left out). The selection is made at the first
        sample and redone whenever the number of particles changes.
    co_moving : id (or ParticleHandle) of the particle whose frame is used:
        positions relative to its centre (minimum image), velocities minus its
        velocity. None (default): the lab frame.
    lower, upper : corners of the sampled region (3-vectors; box coordinates in
        the lab frame, coordinates relative to the centre with ``co_moving``).
        Default: the whole box, [0, L) or [-L/2, L/2) with ``co_moving``.
        ``upper - lower`` must be > 0 and <= L along each axis.
    block_size : group the samples into blocks of this many for
        ``velocity_error`` (None: no error estimate).
    """

    def __init__(self, system, grid, types=None, co_moving=None, lower=None, upper=None,
                 block_size=None):
        self._system = system
        g = np.asarray(grid)
        if g.shape != (3,) or g.dtype.kind not in "iu" or np.any(g < 1):
            raise ValueError(f"parameter 'grid' must be three integers >= 1, got {grid!r}")
        self.grid = tuple(int(n) for n in g)
        if co_moving is not None and not isinstance(co_moving, (int, np.integer)):
            co_moving = getattr(co_moving, "id", co_moving)
        if co_moving is not None:
            if isinstance(co_moving, bool) or not isinstance(co_moving, (int, np.integer)) \
                    or not system.part.exists(int(co_moving)):
                raise ValueError(f"parameter 'co_moving' must be the id of an existing particle, "
                                 f"got {co_moving!r}")
            co_moving = int(co_moving)
        self.co_moving = co_moving
        self.types = None if types is None else [int(t) for t in np.atleast_1d(types)]
        L = np.asarray(system.box_l, dtype=float)
        self._L = L
        default_lower = -0.5 * L if co_moving is not None else np.zeros(3)
        self.lower = default_lower if lower is None else _vec3("lower", lower)
        self.upper = self.lower + L if upper is None else _vec3("upper", upper)
        ext = self.upper - self.lower
        if np.any(ext <= 0) or np.any(ext > L * (1 + 1e-12)):
            raise ValueError(f"parameters 'lower', 'upper': upper - lower must be > 0 and <= box_l "
                             f"along each axis, got {ext}")
        self.cell_size = ext / np.asarray(self.grid)
        if block_size is not None and (isinstance(block_size, bool) or int(block_size) != block_size
                                       or block_size < 1):
            raise ValueError(f"parameter 'block_size' must be an integer >= 1 or None, "
                             f"got {block_size!r}")
        self.block_size = None if block_size is None else int(block_size)
        self._ids = self._idl = None
        self._n_part = -1
        self.reset()

    # -- sampling ------------------------------------------------------
    def reset(self):
        """Forget all samples."""
        n = int(np.prod(self.grid))
        self._counts = np.zeros(n)
        self._vsum = np.zeros((n, 3))
        self.n_samples = 0
        self._blocks = []          # (counts, vsum, frame velocity) of finished blocks
        self._bc = np.zeros(n)     # current block
        self._bv = np.zeros((n, 3))
        self._bn = 0
        self._bf = np.zeros(3)
        self._frame_v = np.zeros(3)
        self._last_frame_v = np.zeros(3)

    def _selected_ids(self):
        core = self._system._core
        n = core.n_part()
        if self._ids is None or n != self._n_part:
            ids = np.asarray(core.particle_ids(), dtype=int)
            if self.types is not None and len(ids):
                t = np.asarray(core.get_property("type", list(ids)))
                ids = ids[np.isin(t, self.types)]
            if self.co_moving is not None:
                ids = ids[ids != self.co_moving]
            self._ids, self._idl, self._n_part = ids, ids.tolist(), n
        return self._ids

    def _bin(self):
        core = self._system._core
        ids = self._selected_ids()
        n = int(np.prod(self.grid))
        if len(ids) == 0:
            return np.zeros(n), np.zeros((n, 3))
        idl = self._idl
        pos = np.asarray(core.get_property("pos_folded", idl), dtype=float)
        vel = np.asarray(core.get_property("v", idl), dtype=float)
        origin = self.lower.copy()
        if self.co_moving is not None:
            c = core.get_property("pos_folded", [self.co_moving])[0]
            vc = core.get_property("v", [self.co_moving])[0]
            origin += c
            vel = vel - vc
            self._last_frame_v = np.asarray(vc, dtype=float)
        rel = np.mod(pos - origin, self._L)          # minimum image / periodic folding
        idx = np.floor(rel / self.cell_size).astype(np.int64)
        ok = np.all(idx < np.asarray(self.grid), axis=1)
        idx, vel = idx[ok], vel[ok]
        nx, ny, nz = self.grid
        flat = (idx[:, 0] * ny + idx[:, 1]) * nz + idx[:, 2]
        counts = np.bincount(flat, minlength=n).astype(float)
        vsum = np.stack([np.bincount(flat, weights=vel[:, d], minlength=n) for d in range(3)],
                        axis=1)
        return counts, vsum

    def sample(self):
        """Add one sample of the current state."""
        self._last_frame_v = np.zeros(3)
        counts, vsum = self._bin()
        self._frame_v += self._last_frame_v
        self._counts += counts
        self._vsum += vsum
        self.n_samples += 1
        if self.block_size is not None:
            self._bc += counts
            self._bv += vsum
            self._bf += self._last_frame_v
            self._bn += 1
            if self._bn == self.block_size:
                self._blocks.append((self._bc, self._bv, self._bf / self._bn))
                self._bc = np.zeros_like(self._bc)
                self._bv = np.zeros_like(self._bv)
                self._bf = np.zeros(3)
                self._bn = 0

    def sample_run(self, n_samples, every):
        """``n_samples`` times: ``system.integrator.run(every)``, then ``sample()``."""
        for name, x in (("n_samples", n_samples), ("every", every)):
            if isinstance(x, bool) or not isinstance(x, (int, np.integer)) or x < 1:
                raise ValueError(f"parameter '{name}' must be an integer >= 1, got {x!r}")
        for _ in range(int(n_samples)):
            self._system.integrator.run(int(every))
            self.sample()
        return self

    # -- results -------------------------------------------------------
    def _shape(self, a):
        return a.reshape(self.grid + a.shape[1:])

    @property
    def counts(self):
        """Number of particle visits per cell, summed over the samples, (nx, ny, nz)."""
        return self._shape(self._counts.copy())

    @property
    def velocity(self):
        """Mean velocity per cell, (nx, ny, nz, 3); NaN where no particle was seen.
        Relative to the co-moving particle's velocity if ``co_moving`` is set."""
        with np.errstate(invalid="ignore", divide="ignore"):
            v = self._vsum / self._counts[:, None]
        v[self._counts == 0] = np.nan
        return self._shape(v)

    @property
    def density(self):
        """Mean number density per cell, (nx, ny, nz); NaN before the first sample."""
        if self.n_samples == 0:
            return np.full(self.grid, np.nan)
        return self._shape(self._counts / (self.n_samples * np.prod(self.cell_size)))

    @property
    def frame_velocity(self):
        """Mean velocity of the co-moving particle over the samples (zeros in the lab frame)."""
        return self._frame_v / max(self.n_samples, 1)

    @property
    def n_blocks(self):
        """Number of finished blocks (``block_size``)."""
        return len(self._blocks)

    @property
    def velocity_error(self):
        """Standard error of the mean velocity per cell from the finished blocks,
        (nx, ny, nz, 3): std of the block means / sqrt(n_blocks). NaN where a block
        saw no particle. Needs ``block_size`` and >= 2 finished blocks."""
        if self.block_size is None:
            raise ValueError("velocity_error needs block_size= (the samples per block)")
        if len(self._blocks) < 2:
            raise ValueError(f"velocity_error needs >= 2 finished blocks of {self.block_size} "
                             f"samples, have {len(self._blocks)}")
        with np.errstate(invalid="ignore", divide="ignore"):
            means = np.stack([v / c[:, None] for c, v, _ in self._blocks])
        err = np.std(means, axis=0, ddof=1) / np.sqrt(len(self._blocks))
        return self._shape(err)

    def block_means(self):
        """Mean velocity per cell in each finished block, (n_blocks, nx, ny, nz, 3) (NaN
        where a block saw no particle), for errors of derived quantities."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.stack([self._shape(v / c[:, None]) for c, v, _ in self._blocks]) \
                if self._blocks else np.empty((0,) + self.grid + (3,))

    def block_counts(self):
        """Particle visits per cell in each finished block, (n_blocks, nx, ny, nz)."""
        return np.stack([self._shape(c) for c, _, _ in self._blocks]) if self._blocks \
            else np.empty((0,) + self.grid)

    @property
    def axes(self):
        """The cell-centre coordinates along x, y and z (three 1D arrays)."""
        return [self.lower[d] + (np.arange(self.grid[d]) + 0.5) * self.cell_size[d]
                for d in range(3)]

    @property
    def cell_centres(self):
        """Cell centres, (nx, ny, nz, 3), in the sampling frame (relative to the
        co-moving particle's centre if set)."""
        return np.stack(np.meshgrid(*self.axes, indexing="ij"), axis=-1)

    def write_vtk(self, path):
        """Write ``velocity`` (vector), ``density`` and ``counts`` as point data on
        the cell centres, a legacy VTK STRUCTURED_POINTS file that ParaView and
        meshio read. Empty cells are written as NaN."""
        write_vtk(path, self.lower + 0.5 * self.cell_size, self.cell_size,
                  {"velocity": self.velocity, "density": self.density,
                   "counts": self.counts})

    def __repr__(self):
        return (f"FlowField(grid={self.grid}, lower={self.lower.tolist()}, "
                f"upper={self.upper.tolist()}, co_moving={self.co_moving}, "
                f"n_samples={self.n_samples})")


def axis_profile(ff, r_edges, axis=0, half_width=None, theory=None, lab=False):
    """Velocity component along ``axis`` on that axis through the grid's origin
    (the colloid's centre with ``co_moving``), binned in the distance ``r = abs(x_axis)``
    (both sides pooled, as the Stokes flow is symmetric) over the cells whose other
    two coordinates are within ``half_width`` (default: half a cell, i.e. the cells
    on the axis). Cells are weighted by their particle counts.

    Returns a dict with ``r`` (count-weighted mean distance per bin), ``u`` (mean
    velocity), ``err`` (standard error over the blocks, NaN without block_size),
    ``counts`` and, if ``theory`` (an (nx, ny, nz, 3) field on ``ff.cell_centres``)
    is given, ``theory``: that field averaged over the same cells with the same
    weights. ``lab=True`` adds the co-moving particle's mean velocity (per block for
    the error, so its fluctuation is included): the lab-frame velocity."""
    if axis not in (0, 1, 2):
        raise ValueError(f"parameter 'axis' must be 0, 1 or 2, got {axis!r}")
    x = ff.cell_centres
    others = [d for d in range(3) if d != axis]
    hw = 0.5 * np.max(ff.cell_size[others]) * 1.001 if half_width is None else half_width
    near = np.all(np.abs(x[..., others]) <= hw, axis=-1)
    edges = np.asarray(r_edges, dtype=float)
    rr = np.abs(x[..., axis])
    grp = np.digitize(rr, edges) - 1
    grp[~near | (rr >= edges[-1])] = -1
    nb = len(edges) - 1
    grp_flat = grp.reshape(-1)
    sel = grp_flat >= 0

    def reduce(counts, vsum):
        c = np.bincount(grp_flat[sel], weights=counts[sel], minlength=nb)
        v = np.bincount(grp_flat[sel], weights=vsum[sel, axis], minlength=nb)
        with np.errstate(invalid="ignore", divide="ignore"):
            return v / c, c

    u, c = reduce(ff._counts, ff._vsum)
    if lab:
        u = u + ff.frame_velocity[axis]
    with np.errstate(invalid="ignore", divide="ignore"):
        r = np.bincount(grp_flat[sel], weights=(ff._counts * rr.reshape(-1))[sel], minlength=nb) / c
    out = {"r": r, "u": u, "counts": c, "err": np.full(nb, np.nan)}
    if len(ff._blocks) >= 2:
        bm = np.array([reduce(bc, bv)[0] + (bf[axis] if lab else 0.0)
                       for bc, bv, bf in ff._blocks])
        out["err"] = np.std(bm, axis=0, ddof=1) / np.sqrt(len(bm))
    if theory is not None:
        t = np.asarray(theory, dtype=float).reshape(-1, 3)
        out["theory"] = reduce(ff._counts, t * ff._counts[:, None])[0]
    return out


def write_vtk(path, origin, spacing, fields):
    """Write fields on a regular grid as legacy VTK (binary STRUCTURED_POINTS).

    ``fields``: name -> array of shape (nx, ny, nz) (scalar) or (nx, ny, nz, 3)
    (vector), all with the same (nx, ny, nz); ``origin`` is the first point,
    ``spacing`` the distance between points."""
    shapes = {np.shape(a)[:3] for a in fields.values()}
    if len(shapes) != 1:
        raise ValueError("parameter 'fields': all arrays need the same grid shape")
    nx, ny, nz = shapes.pop()
    o, s = _vec3("origin", origin), _vec3("spacing", spacing)
    with open(path, "wb") as f:
        f.write(b"# vtk DataFile Version 3.0\nmarble flow field\nBINARY\n"
                b"DATASET STRUCTURED_POINTS\n")
        f.write(f"DIMENSIONS {nx} {ny} {nz}\nORIGIN {o[0]!r} {o[1]!r} {o[2]!r}\n"
                f"SPACING {s[0]!r} {s[1]!r} {s[2]!r}\nPOINT_DATA {nx * ny * nz}\n".encode())
        for name, a in fields.items():
            a = np.asarray(a, dtype=float)
            if a.ndim == 4:
                f.write(f"VECTORS {name} double\n".encode())
                data = a.transpose(2, 1, 0, 3)    # x varies fastest
            else:
                f.write(f"SCALARS {name} double 1\nLOOKUP_TABLE default\n".encode())
                data = a.transpose(2, 1, 0)
            f.write(np.ascontiguousarray(data, dtype=">f8").tobytes())
            f.write(b"\n")


def read_vtk(path):
    """Read a file written by ``write_vtk``: returns (origin, spacing, fields) with
    fields as (nx, ny, nz[, 3]) arrays."""
    fields = {}
    with open(path, "rb") as f:
        def line():
            return f.readline().decode().strip()
        for _ in range(4):
            line()
        dims = [int(x) for x in line().split()[1:]]
        origin = np.array([float(x) for x in line().split()[1:]])
        spacing = np.array([float(x) for x in line().split()[1:]])
        n = int(line().split()[1])
        while True:
            head = line()
            if not head:
                break
            kind, name = head.split()[:2]
            ncomp = 3 if kind == "VECTORS" else 1
            if kind == "SCALARS":
                line()  # LOOKUP_TABLE
            data = np.frombuffer(f.read(8 * n * ncomp), dtype=">f8").astype(float)
            f.readline()
            nx, ny, nz = dims
            if ncomp == 3:
                fields[name] = data.reshape(nz, ny, nx, 3).transpose(2, 1, 0, 3)
            else:
                fields[name] = data.reshape(nz, ny, nx).transpose(2, 1, 0)
    return origin, spacing, fields


# -- Stokes flow past a sphere ---------------------------------------------
def _basset_coefficients(R, b):
    """A, B of u = A (I + n n)/r . U + B (I - 3 n n)/r^3 . U for a sphere of radius R
    and Navier slip length b moving with U in fluid at rest (Stokes 1851: b = 0,
    A = 3R/4, B = R^3/4; Basset 1888: A = (3R/4)(1 + 2b/R)/(1 + 3b/R),
    B = (R^3/4)/(1 + 3b/R); b = inf: A = R/2, B = 0)."""
    if not (R > 0):
        raise ValueError(f"parameter 'R' must be > 0, got {R}")
    if np.isinf(b):
        return R / 2.0, 0.0
    if not (b >= 0):
        raise ValueError(f"parameter 'b' (slip length) must be >= 0 or inf, got {b}")
    lam = b / R
    return 0.75 * R * (1 + 2 * lam) / (1 + 3 * lam), 0.25 * R ** 3 / (1 + 3 * lam)


def stokes_velocity(points, U, R, b=0.0):
    """Velocity at ``points`` (..., 3; relative to the sphere's centre) of the fluid
    around a sphere of radius R moving with velocity U through an unbounded fluid
    at rest (lab frame; Stokes 1851 for b = 0, Basset 1888 for slip length b).
    Inside the sphere (r < R) the sphere's velocity U is returned for b = 0 and
    NaN otherwise."""
    x = np.asarray(points, dtype=float)
    U = _vec3("U", U)
    A, B = _basset_coefficients(R, b)
    r = np.linalg.norm(x, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        n = x / r[..., None]
        nU = np.sum(n * U, axis=-1)[..., None]
        u = A * (U + n * nU) / r[..., None] + B * (U - 3 * n * nU) / r[..., None] ** 3
    u[r < R] = U if b == 0 else np.nan
    return u


def periodic_stokes_velocity(points, F, eta, R, L, b=0.0, n_grid=None, sigma=0.25,
                             fluid_counter_force=True):
    """Stokes flow of a sphere dragged by force F in a periodic cubic box of side L,
    in the frame where the box's mean velocity is zero (zero total momentum for a
    neutrally buoyant sphere; Hasimoto 1959).

    The counter force -F is spread uniformly: with ``fluid_counter_force=True``
    (default) over the fluid only, as a drag run with -F/N on every solvent bead
    does, which is the same as a uniform density over the whole box (the Fourier
    sum below) plus a force F L^3/(L^3 - 4 pi R^3/3) on the sphere; False: over the
    whole box, sphere included (the sphere force is F).

    The sphere is represented by a force F on a spherical shell of radius a,
    smoothed by a Gaussian of width ``sigma``: outside it (r > a + 4 sigma) its flow
    is exactly a Stokeslet plus a source doublet, and a and sigma are chosen so that
    their ratio is Stokes' (b = 0) or Basset's (slip length b):
    a^2/6 + sigma^2/2 = B/(2A) = (R^2/6)/(1 + 2b/R). The periodic sum
    u(x) = (1/(eta L^3)) sum_{k != 0} g(k) (I - k k/k^2) F / k^2 exp(i k.x), with
    g(k) = sin(k a)/(k a) exp(-k^2 sigma^2/2), is done by FFT on an n_grid^3 grid and
    interpolated (cubic splines) to ``points`` (..., 3; relative to the centre). Valid
    outside the sphere; corrections from the images' flow gradients across the
    sphere are O((R/L)^3)."""
    from scipy import ndimage
    F = _vec3("F", F)
    if not (eta > 0 and R > 0 and L > 0):
        raise ValueError("parameters 'eta', 'R', 'L' must be > 0")
    A, B = _basset_coefficients(R, b)
    if fluid_counter_force:
        F = F * L ** 3 / (L ** 3 - 4.0 / 3.0 * np.pi * R ** 3)
    if not (sigma > 0 and sigma < R / 4):
        raise ValueError(f"parameter 'sigma' must be in (0, R/4), got {sigma}")
    # perfect slip (B = 0): a = 0, the Gaussian's own doublet sigma^2/2 remains (relative
    # error ~ sigma^2/r^2 of the doublet-free field)
    a = np.sqrt(max(3.0 * (B / A - sigma ** 2), 0.0))
    if n_grid is None:   # resolve k up to ~4.5/sigma
        n_grid = int(2 * np.ceil(4.5 / sigma * L / (2 * np.pi)))
        n_grid += n_grid % 2
    k1 = 2 * np.pi * np.fft.fftfreq(n_grid, d=L / n_grid)
    kz = 2 * np.pi * np.fft.rfftfreq(n_grid, d=L / n_grid)
    KX, KY, KZ = np.meshgrid(k1, k1, kz, indexing="ij")
    k2 = KX ** 2 + KY ** 2 + KZ ** 2
    k = np.sqrt(k2)
    with np.errstate(invalid="ignore", divide="ignore"):
        g = np.where(k > 0, np.sinc(k * a / np.pi), 1.0) * np.exp(-0.5 * k2 * sigma ** 2)
        kF = (KX * F[0] + KY * F[1] + KZ * F[2]) / k2
        pref = np.where(k2 > 0, g / (eta * k2), 0.0)
    pts = np.asarray(points, dtype=float)
    flat = pts.reshape(-1, 3)
    coords = (np.mod(flat, L) / (L / n_grid)).T
    out = np.empty_like(flat)
    for d, Kd in enumerate((KX, KY, KZ)):
        uk = np.where(k2 > 0, pref * (F[d] - Kd * kF), 0.0)
        ud = np.fft.irfftn(uk, s=(n_grid,) * 3) * n_grid ** 3 / L ** 3
        out[:, d] = ndimage.map_coordinates(ud, coords, order=3, mode="grid-wrap")
    return out.reshape(pts.shape)
