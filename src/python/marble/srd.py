"""Stochastic rotation dynamics (SRD / MPCD) solvent and stick colloids (doc/srd.md).

::

    import marble, marble.srd
    system = marble.System(box_l=[16] * 3, time_step=0.025)
    system.srd = marble.srd.SRDFluid(types=[0], cell_size=1.0, tau=0.1, angle=90, kT=1.0,
                                     seed=42, shift=True, rule="srd")
    marble.srd.add_fluid(system, density=5, type=0, kT=1.0, seed=1)
    col = marble.srd.add_colloid(system, pos=[8, 8, 8], radius=2.0, mass=125.0, type=1)
    system.non_bonded_inter[1, 0].srd_boundary.set_params(radius=2.0, rule="stochastic")
    system.integrator.run(1000)

The SRD particles are kept by the SRD fluid itself (not in ``system.part``):
they have no pair interactions and stream ballistically once per MD step; the
collision happens every ``tau`` (a multiple of ``time_step``). Positions and
velocities: ``system.srd.pos``, ``system.srd.v`` (numpy copies; ``v`` can be
set). Checkpoints (pickling the System) carry the fluid and continue bit for
bit; MPI and H5MD work as for DPD (doc/srd.md).

Theory (reference.md section 6; Kikuchi et al. 2003, Ihle et al. 2004,
Padding et al. 2005 = seed 003): :func:`eta_kin`, :func:`eta_col`,
:func:`eta`, :func:`D_f`, :func:`schmidt`, :func:`enskog_friction`.
"""
import numpy as np

from . import _marble
from .code_features import assert_features

_PARAMS = ("types", "cell_size", "tau", "angle", "kT", "mass", "seed", "shift", "rule",
           "thermostat", "conserve_angular", "wall_axis", "wall_rule", "wall_velocity_lo",
           "wall_velocity_hi", "wall_positions")


class SRDFluid:
    """The SRD solvent: parameters of the collision step.

    Parameters
    ----------
    tau : float > 0
        Collision interval, an integer multiple of ``system.time_step``.
    seed : int >= 0
        Seed of the counter-based noise (grid shift, axes, thermostat, walls).
    types : list of int
        The SRD particle types (checked: no pair interaction, no MD particle).
    cell_size : float > 0 (1.0)
        Collision cell size a0; must divide the box.
    angle : float in [0, 180] degrees (90)
        Rotation angle alpha (rule ``srd``).
    kT : float >= 0 (1.0)
        Temperature of the Andersen rule, the thermostat and stochastic boundaries.
    mass : float > 0 (1.0)
        Mass of an SRD particle.
    shift : bool (True)
        Random grid shift in [-a0/2, a0/2)^3 (Galilean invariance; keep it on
        at mean free paths below ~a0/2).
    rule : "srd" | "at"
        Rotation about a random axis, or the Andersen thermostatted rule.
    thermostat : "none" | "mbs"
        Cell-level Maxwell-Boltzmann scaling after each rotation.
    conserve_angular : bool (False)
        AT+a (angular-momentum conserving Andersen rule); needs rule="at".
    wall_axis : 0, 1, 2 or None
        Channel walls: planes at x[wall_axis] = 0 and = L confine the SRD
        particles (collision cells are not wrapped across them).
    wall_rule : "stochastic" | "bounce_back" | "slip"
    wall_velocity_lo, wall_velocity_hi : 3-vectors tangential to the walls
        Wall velocities (Couette flow).
    wall_positions : (lo, hi), optional
        Positions of the two walls along ``wall_axis`` (default: the box
        faces 0 and L), 0 <= lo, hi <= L, hi - lo >= cell_size; the SRD
        particles live between them (``add_fluid`` fills the channel).
    """

    def __init__(self, **kwargs):
        assert_features("SRD")
        unknown = set(kwargs) - set(_PARAMS)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)} for SRDFluid "
                             f"(allowed: {', '.join(_PARAMS)})")
        self._kw = dict(kwargs)
        self._system = None

    def _attach(self, system):
        system._core.srd_create(self._kw)
        self._system = system

    def get_params(self):
        if self._system is None:
            return dict(self._kw)
        return self._system._core.srd_get_params()

    @property
    def n(self):
        """Number of SRD particles (on all MPI ranks)."""
        return self._system._core.srd_n() if self._system is not None else 0

    def __len__(self):
        return self.n

    @property
    def pos(self):
        """Folded positions (N, 3) of the SRD particles, in their stored order
        (the order of ``ids``; on several MPI ranks every rank's particles in
        rank order: match by ``ids``). Setting takes the same order. Collective."""
        return self._system._core.srd_pos()

    @pos.setter
    def pos(self, x):
        self._system._core.srd_set_pos(np.asarray(x, dtype=float))

    @property
    def v(self):
        """Velocities (N, 3), in the order of ``pos`` and ``ids``. Collective."""
        return self._system._core.srd_v()

    @v.setter
    def v(self, x):
        self._system._core.srd_set_v(np.asarray(x, dtype=float))

    @property
    def ids(self):
        """Ids of the SRD particles, in the order of ``pos``. Collective."""
        return np.asarray(self._system._core.srd_ids())

    @property
    def type(self):
        """Types of the SRD particles, in the order of ``pos``. Collective."""
        return np.asarray(self._system._core.srd_types())

    @property
    def n_collisions(self):
        return self._system._core.srd_n_collisions()

    @property
    def acceleration(self):
        """Uniform acceleration of every SRD particle (e.g. -F/(N m) for the drag method)."""
        return self._accel

    @acceleration.setter
    def acceleration(self, a):
        self._system._core.srd_set_acceleration(np.asarray(a, dtype=float))
        self._accel = np.asarray(a, dtype=float)

    _accel = np.zeros(3)

    def _restore(self, state):
        """Checkpoint restore (System.__setstate__)."""
        self._system._core.srd_set_state(state)
        self._accel = np.asarray(state["drive"][4], dtype=float)

    def collide(self):
        """One collision now (for tests; run() collides every tau by itself)."""
        self._system._core.srd_collide()

    def momentum_to_walls(self):
        """Total momentum handed to the lower and upper wall so far."""
        return self._system._core.srd_wall_momentum()

    def momentum_to_colloids(self):
        """Total momentum handed to the colloids by the boundary rules so far."""
        return self._system._core.srd_momentum_to_colloids()


def _attach(system, fluid):
    """``system.srd = fluid`` (None removes the fluid and its particles)."""
    if fluid is None:
        system._core.srd_remove()
        system.__dict__["_srd"] = None
        return
    if not isinstance(fluid, SRDFluid):
        raise ValueError("system.srd must be a marble.srd.SRDFluid or None")
    fluid._attach(system)
    system.__dict__["_srd"] = fluid


def colloid_volume(system, type=0):
    """Total volume ``sum 4/3 pi a^3`` of the colloids present whose type has
    an SRD boundary (``boundary(system, c, type)``) for SRD ``type``
    (overlaps between colloids and with walls are not subtracted)."""
    types, counts = np.unique(np.asarray(system.part.all().type, dtype=int), return_counts=True)
    radii = [boundary(system, int(c), type).get_params().get("radius", 0.0) for c in types]
    return float(np.sum(counts * 4.0 / 3.0 * np.pi * np.asarray(radii, dtype=float) ** 3))


def add_fluid(system, density, type=0, kT=1.0, seed=0, n=None, volume="box"):
    """Add ``density * volume`` (or ``n``) SRD particles of ``type``: uniform
    positions outside the colloids (between the walls, if any), Maxwellian velocities at ``kT`` with zero
    total momentum. Returns the number added.

    ``volume``: ``"box"`` (default) counts the whole box (the channel between
    the walls, if any), so the colloids' displaced particles raise the density
    of the free volume; ``"free"`` subtracts the volume of the colloids already
    added (``colloid_volume``), so the free volume holds ``density`` exactly:
    add the colloids first (colloids added later still displace particles)."""
    if getattr(system, "_srd", None) is None:
        raise RuntimeError("no SRD fluid: set system.srd = marble.srd.SRDFluid(...) first")
    if volume not in ("box", "free"):
        raise ValueError(f"parameter 'volume' must be 'box' or 'free', got {volume!r}")
    if n is None:
        density = float(density)
        if not np.isfinite(density) or density < 0:
            raise ValueError(f"parameter 'density' must be a finite number >= 0, got {density}")
        vol = float(np.prod(system.box_l))
        par = system._core.srd_get_params()
        if "wall_positions" in par:  # the channel between the walls
            lo, hi = par["wall_positions"]
            vol *= (hi - lo) / system.box_l[par["wall_axis"]]
        if volume == "free":
            vol -= colloid_volume(system, type)
            if vol <= 0:
                raise ValueError("parameter 'volume': the colloids fill the box, no free volume left")
        n = int(round(density * vol))
    system._core.srd_add_particles(n, type, kT, seed)
    return n


def boundary(system, c, s):
    """``system.non_bonded_inter[c, s].srd_boundary``: the boundary of colloid
    type ``c`` for SRD type ``s`` (``set_params(radius=, rule=)`` with rule
    ``stochastic``, ``bounce_back``, ``slip`` or ``rough``)."""
    return system.non_bonded_inter[c, s].srd_boundary


def add_colloid(system, pos, radius=2.0, mass=None, type=1, srd_types=(0,), rule="stochastic",
                v=(0.0, 0.0, 0.0), density=5.0, coupling="pair"):
    """Add one SRD colloid (a rotating MD particle, I = (2/5) M a^2) and its
    boundary for each SRD type. Default mass: neutrally buoyant,
    M = density (4/3) pi a^3 (seed 003 uses M = (2.5 a)^3: pass mass=125 for
    its a = 2 colloid). SRD particles inside are moved to random free places (also before every run).
    ``coupling``: "pair" (default: the rule acts on the relative velocity of
    the pair particle/colloid with their effective masses; the bounces of a
    step are found at the crossing times of the relative motion and applied
    in time order, each impulse at once; detailed balance for any M), or, for
    comparison only, "fixed_surface" / "seed003" (doc/srd.md)."""
    assert_features("SRD", "ROTATION", "MASS")
    if mass is None:
        mass = density * 4.0 / 3.0 * np.pi * radius ** 3
    for s in srd_types:
        boundary(system, type, s).set_params(radius=radius, rule=rule, coupling=coupling)
    p = system.part.add(pos=pos, v=v, type=type, mass=mass, rotation=[True] * 3,
                        rinertia=[0.4 * mass * radius ** 2] * 3)
    if getattr(system, "_srd", None) is not None:
        system._core.srd_move_out()
    return p


# --- reverse Poiseuille viscosity of the SRD fluid ------------------------

def reverse_poiseuille(system, g, time, equilibration=None, n_bins=None, n_blocks=10,
                       flow_dir=0, grad_dir=2, margin=1.0, sample_every=10):
    """Viscosity of the SRD fluid from a reverse Poiseuille flow (see
    marble.viscosity.reverse_poiseuille: the same fit, the force is applied by
    the SRD streaming step). Returns a marble.viscosity.PoiseuilleResult."""
    from .viscosity import PoiseuilleResult, _fit_matrix, block_average
    core = system._core
    dt = system.time_step
    L = float(system.box_l[grad_dir])
    if n_bins is None:
        n_bins = 2 * int(round(L))
    N = core.srd_n()
    n = N / np.prod(system.box_l)
    rho = n * system.srd.get_params()["mass"]
    if equilibration is None:
        equilibration = 8.0 * rho * L ** 2 / (4.0 * np.pi ** 2 * 2.0)  # 8 decay times at eta >= 2
    edges = np.linspace(0.0, L, n_bins + 1)
    z = 0.5 * (edges[1:] + edges[:-1])
    used, A, Ap = _fit_matrix(z, L, margin)
    steps_per_block = max(1, int(round(time / n_blocks / dt / sample_every)))
    core.srd_set_drive(flow_dir, grad_dir, g)
    try:
        system.integrator.run(int(round(equilibration / dt)))
        etas, series, profs = [], [], []
        for _ in range(n_blocks):
            vs = np.zeros(n_bins)
            cs = np.zeros(n_bins)
            for _ in range(steps_per_block):
                system.integrator.run(sample_every)
                a, b = core.srd_profile(flow_dir, grad_dir, n_bins)
                prof = np.asarray(a) / np.maximum(np.asarray(b), 1)
                coef = Ap @ prof[used]
                series.append(-n * g / (2.0 * coef[4]))
                vs += np.asarray(a)
                cs += np.asarray(b)
            prof = vs / np.maximum(cs, 1)
            profs.append(prof)
            coef = Ap @ prof[used]
            etas.append(-n * g / (2.0 * coef[4]))
    finally:
        core.srd_set_drive(flow_dir, grad_dir, 0.0)
    profs = np.array(profs)
    mean_prof = profs.mean(axis=0)
    coef = Ap @ mean_prof[used]
    eta = -n * g / (2.0 * coef[4])
    # error of 1/curvature from the scatter of the block curvatures
    curv = np.array([(Ap @ p[used])[4] for p in profs])
    c_mean, c_err = block_average(curv, min_blocks=min(8, len(curv)))
    eta_err = abs(eta) * c_err / abs(c_mean)
    fit = np.full(n_bins, np.nan)
    fit[used] = A @ coef
    return PoiseuilleResult(eta=eta, eta_err=eta_err, eta_blocks=np.array(etas), z=z,
                            v=mean_prof, v_err=profs.std(axis=0, ddof=1) / np.sqrt(len(profs)),
                            fit=fit, g=g, n=n, kT=None, v_max=float(np.nanmax(np.abs(fit))))


# --- theory (reference.md section 6) --------------------------------------

def _gam(density):
    return density - 1.0 + np.exp(-density)


def nu_kin(density, angle_deg, tau, kT=1.0, m=1.0):
    """Kinetic kinematic viscosity (Kikuchi et al. 2003)."""
    a = np.radians(angle_deg)
    return kT * tau / (2.0 * m) * (5.0 * density / (_gam(density) * (2.0 - np.cos(a) - np.cos(2 * a))) - 1.0)


def nu_col(density, angle_deg, tau, a0=1.0):
    """Collisional kinematic viscosity."""
    a = np.radians(angle_deg)
    return a0 ** 2 / (18.0 * tau) * (_gam(density) / density) * (1.0 - np.cos(a))


def eta_kin(density, angle_deg, tau, kT=1.0, m=1.0, a0=1.0):
    return density * m / a0 ** 3 * nu_kin(density, angle_deg, tau, kT, m)


def eta_col(density, angle_deg, tau, m=1.0, a0=1.0):
    return density * m / a0 ** 3 * nu_col(density, angle_deg, tau, a0)


def eta(density, angle_deg, tau, kT=1.0, m=1.0, a0=1.0):
    """Shear viscosity eta = gamma m / a0^3 (nu_kin + nu_col); gamma = 5,
    alpha = 90 deg, tau = 0.1 gives 2.496; alpha = 130 deg gives 3.961."""
    return eta_kin(density, angle_deg, tau, kT, m, a0) + eta_col(density, angle_deg, tau, m, a0)


def D_f(density, angle_deg, tau, kT=1.0, m=1.0):
    """Self-diffusion coefficient of an SRD particle (Ripoll et al. 2005):
    D = (kT tau / 2m) [3 gamma / ((gamma - 1 + e^-gamma)(1 - cos a)) - 1]."""
    a = np.radians(angle_deg)
    return kT * tau / (2.0 * m) * (3.0 * density / (_gam(density) * (1.0 - np.cos(a))) - 1.0)


def schmidt(density, angle_deg, tau, kT=1.0, m=1.0, a0=1.0):
    """Sc = nu / D_f (3.6 for Padding's gamma = 5, 90 deg, tau = 0.1)."""
    nu = nu_kin(density, angle_deg, tau, kT, m) + nu_col(density, angle_deg, tau, a0)
    return nu / D_f(density, angle_deg, tau, kT, m)


def enskog_friction(radius, M, density, kT=1.0, m=1.0, chi=0.4):
    """Enskog friction rates (seed 003 eqs. 5, 6): returns (zeta_V, zeta_Omega)
    in 1/time; a = 2, M = 125, gamma = 5: (1.370, 0.761)."""
    base = 8.0 / 3.0 * np.sqrt(2.0 * np.pi * kT * m * M / (m + M)) / M * density * radius ** 2
    return base * (1.0 + 2.0 * chi) / (1.0 + chi), base / (1.0 + chi)


def kinetic_friction(radius, M, density, rule="stochastic", kT=1.0, m=1.0, chi=0.4, coupling="pair"):
    """Short-time (kinetic, uncorrelated-collision) friction rates (zeta_V,
    zeta_Omega) of a sphere for each boundary rule (doc/srd.md, "Finite
    colloid mass"). With the specular (Epstein) rate
    z0 = (8/3) sqrt(2 pi kT mu_n) gamma a^2 / M, mu_n = m M/(m+M), and
    q = mu_t/mu_n, 1/mu_t = 1/m + (1 + 1/chi)/M (``coupling="pair"``, the
    default rule; q = 1 for the infinitely heavy surface of ``"seed003"`` /
    ``"fixed_surface"``):
    slip: (z0, 0); rough (tangential reversal fraction K = chi/(1+chi), seed
    003's Enskog eqs. 5, 6 for q = 1): (z0 (1 + K q), z0 K q/chi);
    bounce_back (K = 1): (z0 (1 + q), z0 q/chi); stochastic (diffuse
    re-emission): (z0 (1/2 + pi/8 + q/2), z0 q/(2 chi)).
    a = 2, M = 125, gamma = 5, stochastic, pair: (1.473, 1.306)."""
    if coupling not in ("pair", "fixed_surface", "seed003"):
        raise ValueError(f"parameter 'coupling' must be one of 'pair', 'fixed_surface', 'seed003', got {coupling!r}")
    mu_n = m * M / (m + M)
    z0 = 8.0 / 3.0 * np.sqrt(2.0 * np.pi * kT * mu_n) / M * density * radius ** 2
    q = 1.0
    if coupling == "pair":
        q = 1.0 / (1.0 / m + (1.0 + 1.0 / chi) / M) / mu_n
    if rule == "slip":
        return z0, 0.0
    if rule == "rough":
        K = chi / (1.0 + chi)
        return z0 * (1.0 + K * q), z0 * K * q / chi
    if rule == "bounce_back":
        return z0 * (1.0 + q), z0 * q / chi
    if rule == "stochastic":
        return z0 * (0.5 + np.pi / 8.0 + 0.5 * q), z0 * q / (2.0 * chi)
    raise ValueError(f"parameter 'rule' must be one of 'stochastic', 'bounce_back', 'slip', 'rough', got {rule!r}")


def short_time_friction(X, dt, n_lags=1, n_blocks=16, order=1):
    """Initial decay rate of the autocorrelation of the (n, 3) series X
    sampled every dt: least-squares slope of -ln C(t)/C(0) over the first
    n_lags lags, C(t) averaged over the whole series; returns (rate, error).
    With ``order=2`` a quadratic in t is fitted instead and its slope at
    t = 0 returned.

    The default, one lag (-ln(C(dt)/C(0))/dt), is the initial rate: the
    rotational VACF of an SRD colloid is not exponential over the first
    0.1-0.4 t0 (the fluid next to the surface, correlated with the colloid by
    earlier bounces, lowers the friction as t grows), so a fit over a window
    of width T returns a rate that falls with T (stochastic rule, a = 2,
    M = 125: 1.005, 0.991, 0.968, 0.925, 0.855 of the kinetic value for
    T = 0.025, 0.05, 0.1, 0.2, 0.4 t0, 8 seeds; doc/srd.md "Short-time
    friction"). The default was 8 lags before 2026-12-01. Sample every MD
    step for the kinetic (uncorrelated-collision) value.

    The error is the jackknife over ``n_blocks`` contiguous blocks (the rate
    from C(t) of all blocks but one, for each block left out). It replaces
    the mean of per-block rates with their standard error (before 2026-12-01),
    a ratio estimator that is biased at short blocks and whose error, from 8
    blocks, scattered by a third and underestimated the scatter between
    seeds."""
    X = np.asarray(X, dtype=float)
    if int(n_lags) != n_lags or n_lags < 1:
        raise ValueError(f"parameter 'n_lags' must be an integer >= 1, got {n_lags!r}")
    n_lags = int(n_lags)
    if order not in (1, 2) or n_lags < order:
        raise ValueError(f"parameter 'order' must be 1 or 2 and at most n_lags = {n_lags}, got {order!r}")
    if X.ndim != 2 or len(X) < n_blocks * (n_lags + 2):
        raise ValueError(f"parameter 'X' must be an (n, 3) series with n >= n_blocks * (n_lags + 2) "
                         f"= {n_blocks * (n_lags + 2)}, got shape {X.shape}")
    nb = len(X) // n_blocks
    lag = np.arange(n_lags + 1) * dt
    # per-block sums of x(t).x(t+k) over the pairs that start in the block
    # (a pair may reach into the next block: no pair is lost between blocks)
    n_used = nb * n_blocks
    sums = np.empty((n_blocks, n_lags + 1))
    counts = np.empty((n_blocks, n_lags + 1))
    for k in range(n_lags + 1):
        prod = np.sum(X[:len(X) - k] * X[k:], axis=1)
        prod = prod[:n_used] if len(prod) >= n_used else np.concatenate(
            [prod, np.full(n_used - len(prod), np.nan)])
        prod = prod.reshape(n_blocks, nb)
        sums[:, k] = np.nansum(prod, axis=1)
        counts[:, k] = np.sum(~np.isnan(prod), axis=1)

    def rate(sel):
        c = sums[sel].sum(axis=0) / counts[sel].sum(axis=0)
        return -np.polyfit(lag, np.log(c / c[0]), order)[-2]

    all_blocks = np.ones(n_blocks, dtype=bool)
    jack = []
    for b in range(n_blocks):
        sel = all_blocks.copy()
        sel[b] = False
        jack.append(rate(sel))
    return float(rate(all_blocks)), _jackknife_error(jack)


def one_step_friction(X, dt, mass, kT=1.0, n_blocks=16):
    """Friction rate at the shortest lag from the one-step changes of the
    (n, 3) series X (a colloid's V with ``mass`` M, or Omega with ``mass`` I)
    sampled every MD step dt: with no external force or torque the change
    dX = X(t + dt) - X(t) is the impulse of the SRD bounces of that step over
    the mass, and stationarity gives <X.dX> = -<dX^2>/2, so
    m <dX_k^2> / (2 kT) = 1 - C(dt)/C(0) per component; solved for the rate as
    for an exponential decay, zeta = -ln(1 - m <dX_k^2>/(2 kT)) / dt. Uses
    equipartition (<m X_k^2> = kT) instead of the measured <X^2>, which makes
    it ~5x more precise than ``short_time_friction`` (the impulses are nearly
    independent from step to step). Returns (rate, error), the error a
    jackknife over ``n_blocks`` contiguous blocks. Measured (a = 2, M = 125
    and 1000, 8 seeds each): 0.994-1.005 (+/- 0.002-0.005) of
    ``kinetic_friction`` at the free-volume density and the fluid's measured
    temperature, for V and Omega, stochastic and rough rules, dt = 0.025 and
    0.0125 (1.005-1.013 at the nominal density 5 and kT = 1; doc/srd.md
    "Short-time friction")."""
    X = np.asarray(X, dtype=float)
    if X.ndim != 2 or len(X) < 2 * n_blocks:
        raise ValueError(f"parameter 'X' must be an (n, d) series with n >= 2 n_blocks = {2 * n_blocks}, "
                         f"got shape {X.shape}")
    if not (dt > 0 and mass > 0 and kT > 0):
        raise ValueError(f"parameters 'dt', 'mass', 'kT' must be > 0, got {dt!r}, {mass!r}, {kT!r}")
    d2 = np.sum((X[1:] - X[:-1]) ** 2, axis=1)
    nb = len(d2) // n_blocks
    sums = d2[:nb * n_blocks].reshape(n_blocks, nb).sum(axis=1)
    dim = X.shape[1]

    def rate(total, count):
        x = mass * total / (count * dim) / (2.0 * kT)
        return -np.log1p(-x) / dt if x < 1 else np.inf

    jack = [rate(sums.sum() - sums[b], nb * (n_blocks - 1)) for b in range(n_blocks)]
    return float(rate(sums.sum(), nb * n_blocks)), _jackknife_error(jack)


def _jackknife_error(jack):
    """Jackknife error from the estimates with one block left out each."""
    jack = np.asarray(jack, dtype=float)
    n = len(jack)
    return float(np.sqrt((n - 1) / n * np.sum((jack - jack.mean()) ** 2)))
