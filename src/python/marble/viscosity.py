"""Measuring the shear viscosity of a particle fluid (doc/dpd.md, "Viscosity").

``reverse_poiseuille`` drives a periodic Poiseuille flow: a body force +g along
``flow_dir`` on every particle in the lower half of the box (along ``grad_dir``)
and -g in the upper half (Backer, Lowe, Hoefsloot, Iedema, J. Chem. Phys. 122,
154503 (2005)). Each half carries a parabola

    eta d^2 v / dz^2 = -n g     =>     v(z) = a + b z - (n g / (2 eta)) z^2,

(n: number density of the forced particles). The two halves are fitted together
with one curvature; eta's error bar comes from the scatter of the fits of
independent time blocks. ``block_average`` is the usual blocking analysis
(Flyvbjerg, Petersen, J. Chem. Phys. 91, 461 (1989)).
"""
import numbers

import numpy as np

from .code_features import has_features
from ._marble import FeaturesError


def block_average(x, min_blocks=16):
    """Mean of the time series ``x`` and its standard error from blocking.

    The series is halved (neighbouring values averaged) repeatedly; the error
    estimate of each level is sigma/sqrt(n_blocks - 1). Returns (mean, error),
    taking the largest estimate over the levels that keep >= ``min_blocks``
    blocks (the plateau for a series much longer than its correlation time).
    """
    x = np.asarray(x, dtype=float).ravel()
    if x.size < 2:
        raise ValueError("block_average needs at least 2 values")
    mean = float(np.mean(x))
    best = float(np.std(x, ddof=1) / np.sqrt(x.size))
    y = x
    while y.size // 2 >= min_blocks:
        n = y.size // 2
        y = 0.5 * (y[:2 * n:2] + y[1:2 * n:2])
        best = max(best, float(np.std(y, ddof=1) / np.sqrt(n)))
    return mean, best


class PoiseuilleResult:
    """Result of :func:`reverse_poiseuille`.

    Attributes: ``eta``, ``eta_err`` (standard error from a blocking analysis of
    the time series of the fitted curvature), ``eta_blocks`` (one fit per block), ``z`` (bin centres), ``v`` and ``v_err``
    (mass-weighted mean flow velocity per bin and its standard error),
    ``fit`` (the fitted profile at ``z``, NaN in excluded bins), ``g``, ``n``
    (number density of the forced particles), ``kT`` (mean kinetic temperature
    in the frame of the local flow) and ``v_max`` (largest fitted velocity).
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def __repr__(self):
        return f"PoiseuilleResult(eta={self.eta:.4f} +/- {self.eta_err:.4f})"


def _fit_matrix(z, L, margin):
    """Joint least-squares fit of both halves: in half k, v = a_k + b_k zc +- c zc^2
    (zc measured from the half's centre, + in the lower and - in the upper half,
    one shared curvature c). Bins closer than ``margin`` to a plane where the force
    changes sign are left out. Returns (used bins, design matrix, pseudo-inverse)."""
    h = 0.5 * L
    rows, used = [], []
    for k, (lo, hi) in enumerate(((0.0, h), (h, L))):
        sign = 1.0 if k == 0 else -1.0
        for i in np.flatnonzero((z > lo + margin) & (z < hi - margin)):
            zc = z[i] - 0.5 * (lo + hi)
            row = np.zeros(5)
            row[2 * k], row[2 * k + 1], row[4] = 1.0, zc, sign * zc**2
            rows.append(row)
            used.append(i)
    A = np.array(rows)
    return np.array(used), A, np.linalg.pinv(A)


def reverse_poiseuille(system, g, time, equilibration=None, n_bins=None, n_blocks=10,
                       flow_dir=0, grad_dir=2, margin=1.0, update_every=5, sample_every=10,
                       particles=None, progress=None, mass_proportional=False):
    """Measure the shear viscosity from a reverse (periodic) Poiseuille flow.

    Parameters
    ----------
    system : marble.System
        The fluid, with its interactions and thermostat set and equilibrated;
        ``time_step`` set. Needs EXTERNAL_FORCE. The particles' ``ext_force``
        is overwritten during the run and restored afterwards.
    g : float > 0
        Body force per particle. Choose it so that the largest flow velocity
        n g L^2 / (32 eta) stays well below the thermal velocity (~0.3-0.6 kT/m):
        larger g gives a smaller error bar but shear-rate effects.
    time : float > 0
        Production time (simulation time units), split into ``n_blocks`` blocks.
        Each block should be longer than the decay time of the slowest shear mode,
        rho L^2 / (4 pi^2 eta).
    equilibration : float >= 0, optional
        Time with the force on before sampling (default: 3 rho L^2/(4 pi^2 eta)
        with eta = 1 and rho the mass density, i.e. a few decay times).
    n_bins : int, optional
        Bins along ``grad_dir`` (even; default: 2 per unit length, rounded to even).
    margin : float >= 0
        Bins closer than this to a plane where the force changes sign are not
        fitted (the stress of a DPD fluid is non-local over r_cut; default 1).
    update_every : int
        Steps between re-assignments of the force sign from the particle
        positions (a particle moves ~update_every * dt * v_thermal meanwhile).
    sample_every : int
        Steps between velocity samples.
    particles : ParticleSlice, optional
        The forced and sampled particles (default: all).
    progress : callable, optional
        Called as progress(fraction_done) after each block.
    mass_proportional : bool
        False (default): the same force ±g on every particle. True: particle
        i gets ±g m_i / <m> (<m> the mean mass of the forced particles), i.e.
        the same body acceleration for all, as a pressure gradient gives the
        colloids of a suspension whose mass density equals the solvent's
        (doc/suspensions.md). The force density is n g in both cases, so eta
        follows from the same formula. With equal masses both are the same.

    Returns
    -------
    PoiseuilleResult
    """
    if not has_features("EXTERNAL_FORCE"):
        raise FeaturesError("missing feature EXTERNAL_FORCE (needed by reverse_poiseuille)")
    g = float(g)
    if not np.isfinite(g) or g <= 0.0:
        raise ValueError(f"parameter 'g' must be a finite number > 0, got {g}")
    if flow_dir not in (0, 1, 2) or grad_dir not in (0, 1, 2) or flow_dir == grad_dir:
        raise ValueError("parameters 'flow_dir' and 'grad_dir' must be different axes in {0, 1, 2}")
    dt = system.time_step
    if not dt > 0.0:
        raise ValueError("system.time_step must be set")
    for name, val in (("update_every", update_every), ("sample_every", sample_every),
                      ("n_blocks", n_blocks)):
        if int(val) != val or val < 1:
            raise ValueError(f"parameter '{name}' must be an integer >= 1, got {val}")
    if n_blocks < 2:
        raise ValueError("parameter 'n_blocks' must be >= 2 (the error bar needs blocks)")
    box = np.asarray(system.box_l, dtype=float)
    L = box[grad_dir]
    if n_bins is None:
        n_bins = 2 * int(round(L))
        n_bins += n_bins % 2
    if n_bins < 4 or n_bins % 2:
        raise ValueError(f"parameter 'n_bins' must be an even integer >= 4, got {n_bins}")
    if not 0.0 <= margin < L / 4:
        raise ValueError(f"parameter 'margin' must be in [0, L/4), got {margin}")
    parts = system.part.all() if particles is None else particles
    N = len(parts)
    if N == 0:
        raise ValueError("no particles")
    mass = np.asarray(parts.mass, dtype=float) if has_features("MASS") else np.ones(N)
    V = float(np.prod(box))
    n = N / V
    rho = np.sum(mass) / V
    if equilibration is None:
        equilibration = 3.0 * rho * L**2 / (4.0 * np.pi**2)
    steps_per_block = int(round(time / n_blocks / dt / sample_every)) * sample_every
    if steps_per_block < sample_every:
        raise ValueError("parameter 'time' is too short for n_blocks blocks of samples")

    saved_force = np.array(parts.ext_force, dtype=float)
    half = 0.5 * L
    edges = np.linspace(0.0, L, n_bins + 1)
    z_centres = 0.5 * (edges[1:] + edges[:-1])

    def apply_force():
        z = np.mod(parts.pos[:, grad_dir], L)
        f = saved_force.copy()
        sg = np.where(z < half, g, -g)
        # zero net force (the halves hold slightly different particle numbers): a
        # uniform correction that does not change the curvature but stops the
        # centre of mass from random-walking
        if mass_proportional:  # the same acceleration for all (and its correction)
            acc = sg / np.mean(mass)
            acc -= np.sum(mass * acc) / np.sum(mass)
            f[:, flow_dir] += mass * acc
        else:
            f[:, flow_dir] += sg - np.mean(sg)
        parts.ext_force = f

    def run(steps, sample, acc):
        done = 0
        next_sample = sample_every
        while done < steps:
            chunk = min(update_every, steps - done, next_sample - done if sample else steps)
            apply_force()
            system.integrator.run(chunk)
            done += chunk
            if sample and done == next_sample:
                z = np.mod(parts.pos[:, grad_dir], L)
                v = parts.v
                b = np.minimum((z / L * n_bins).astype(int), n_bins - 1)
                m_bin = np.bincount(b, mass, n_bins)
                acc["v"].append(np.bincount(b, mass * v[:, flow_dir], n_bins)
                                / np.maximum(m_bin, 1e-300))
                acc["m"] += m_bin
                acc["ekin"] += np.sum(mass * np.sum(v * v, axis=1))
                next_sample += sample_every

    try:
        run(int(round(equilibration / dt)), False, None)
        blocks = []
        for k in range(n_blocks):
            acc = dict(v=[], m=np.zeros(n_bins), ekin=0.0)
            run(steps_per_block, True, acc)
            acc["v"] = np.array(acc["v"])
            blocks.append(acc)
            if progress is not None:
                progress((k + 1) / n_blocks)
    finally:
        parts.ext_force = saved_force

    # The curvature is linear in the profile: c_t = w . v_t for every sample t,
    # and its error comes from blocking the series c_t.
    used, A, pinv = _fit_matrix(z_centres, L, margin)
    curv_series = np.concatenate([b["v"][:, used] @ pinv[4] for b in blocks])
    curv, curv_err = block_average(curv_series)
    eta = -n * g / (2.0 * curv)
    eta_err = abs(eta) * curv_err / abs(curv)
    prof = np.array([b["v"].mean(axis=0) for b in blocks])
    eta_blocks = -n * g / (2.0 * (prof[:, used] @ pinv[4]))
    v_mean = prof.mean(axis=0)
    v_err = np.std(prof, axis=0, ddof=1) / np.sqrt(n_blocks)
    fit = np.full(n_bins, np.nan)
    fit[used] = A @ (pinv @ v_mean[used])
    n_samp = sum(len(b["v"]) for b in blocks)
    ekin = sum(b["ekin"] for b in blocks) / n_samp
    m_bin = sum(b["m"] for b in blocks) / n_samp
    kT = (ekin - np.sum(m_bin * v_mean**2)) / (3.0 * N)  # in the frame of the flow
    return PoiseuilleResult(eta=float(eta), eta_err=eta_err, eta_blocks=eta_blocks,
                            z=z_centres, v=v_mean, v_err=v_err, fit=fit, g=g, n=n,
                            kT=float(kT), v_max=float(np.nanmax(np.abs(fit))),
                            time=steps_per_block * n_blocks * dt)


class ShearResult:
    """Result of :func:`lees_edwards_viscosity`.

    Attributes: ``eta``, ``eta_err`` (-<P_sn>/rate and its blocking error),
    ``rate``, ``slope``, ``slope_err``, ``chi2``, ``dof`` (weighted straight-line
    fit of the mass-weighted mean flow ``v`` +/- ``v_err`` against the bin centres
    ``y`` along the normal: the realised shear rate and how linear the profile
    is; ``chi2`` is NaN when a bin has no error bar), ``kT``, ``kT_err``
    (kinetic temperature of the velocities relative to the imposed linear flow,
    3 (N - 1) degrees of freedom), ``p_sn`` (the sampled symmetric shear
    stress, one value per sample), ``n_samples`` and ``sample_time`` (time
    between samples).
    """

    def __init__(self, **kw):
        self.__dict__.update(kw)

    def __repr__(self):
        return (f"ShearResult(eta={self.eta:.4f} +/- {self.eta_err:.4f}, slope={self.slope:.5f} "
                f"+/- {self.slope_err:.5f} (rate {self.rate}), kT={self.kT:.4f})")


def _integer(name, value, lowest):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < lowest:
        raise ValueError(f"parameter '{name}' must be an integer >= {lowest}, got {value!r}")
    return int(value)


def lees_edwards_viscosity(system, rate, time, equilibration=10.0, sample_every=10, n_bins=8,
                           shear_direction="x", shear_plane_normal="y", linear_start=True,
                           zero_momentum=True, min_blocks=8):
    """Shear viscosity in uniform simple shear under Lees-Edwards boundary
    conditions (doc/lees-edwards.md): eta = -<P_sn>/rate.

    Switches on ``marble.lees_edwards.LinearShear`` with the shear velocity
    ``rate * L_n`` from the current time (velocity along ``shear_direction`` s,
    gradient along ``shear_plane_normal`` n), then:

    1. ``zero_momentum``: removes the **mass-weighted** mean velocity
       (``system.galilei.galilei_transform()``). A net momentum along n carries
       the material across the shear plane and biases eta by +M V_n^2 t / V,
       growing with the run; with particles of different masses an unweighted
       mean leaves one (doc/suspensions.md section 7k).
    2. ``linear_start``: adds the steady profile rate (r_n - L_n/2) to the
       velocities along s, so the flow need not build up by diffusion
       (~rho L_n^2/(pi^2 eta)).
    3. runs ``equilibration`` time units, then ``time`` time units, sampling
       every ``sample_every`` steps: the symmetric shear stress
       (P_sn + P_ns)/2 of ``pressure_tensor()``'s 'total' + 'dpd' parts (kinetic,
       every pair kernel's virial including lubrication and surface friction,
       and the DPD pair stress), the mass-weighted flow profile in ``n_bins``
       bins along n, and the kinetic temperature in the frame of the imposed
       flow.

    Errors by blocking (:func:`block_average` with ``min_blocks``). The
    boundary conditions stay on afterwards (``system.lees_edwards.protocol =
    None`` switches them off). Bad input raises ValueError naming the
    parameter before anything changes. Returns a :class:`ShearResult`.

    For a suspension's relative viscosity measure eta_0 of the pure solvent
    the same way (same box, integrator, time step and rate) and divide.
    """
    from .lees_edwards import LinearShear, _axis, _finite
    rate = _finite("rate", rate)
    if rate == 0:
        raise ValueError("parameter 'rate' must be nonzero, got 0.0")
    time = _finite("time", time)
    if time <= 0:
        raise ValueError(f"parameter 'time' must be > 0, got {time!r}")
    equilibration = _finite("equilibration", equilibration)
    if equilibration < 0:
        raise ValueError(f"parameter 'equilibration' must be >= 0, got {equilibration!r}")
    sample_every = _integer("sample_every", sample_every, 1)
    n_bins = _integer("n_bins", n_bins, 3)
    min_blocks = _integer("min_blocks", min_blocks, 2)
    s_ax = _axis("shear_direction", shear_direction)
    n_ax = _axis("shear_plane_normal", shear_plane_normal)
    if s_ax == n_ax:
        raise ValueError("parameters 'shear_direction' and 'shear_plane_normal' must be different "
                         f"axes, got {shear_direction!r} for both")
    dt = float(system.time_step)
    if not dt > 0:
        raise ValueError("system.time_step must be set")
    n_samples = max(2, int(round(time / (sample_every * dt))))
    parts = system.part.all()
    if len(parts) < 2:
        raise ValueError("lees_edwards_viscosity needs at least 2 particles")
    L = np.asarray(system.box_l, dtype=float)
    system.lees_edwards.set_boundary_conditions(
        shear_direction=s_ax, shear_plane_normal=n_ax,
        protocol=LinearShear(shear_velocity=rate * L[n_ax], time_0=system.time))
    if zero_momentum:
        system.galilei.galilei_transform()
    if linear_start:
        v = np.asarray(parts.v)
        v[:, s_ax] += rate * (np.asarray(parts.pos_folded)[:, n_ax] - 0.5 * L[n_ax])
        parts.v = v
    system.integrator.run(int(round(equilibration / dt)))
    m = np.asarray(parts.mass, dtype=float) if has_features("MASS") else np.ones(len(parts))
    edges = np.linspace(0, L[n_ax], n_bins + 1)
    pxy, prof, kts = [], [], []
    for _ in range(n_samples):
        system.integrator.run(sample_every)
        p = system.analysis.pressure_tensor()
        pt = p["total"] + p["dpd"]
        pxy.append(0.5 * (pt[s_ax, n_ax] + pt[n_ax, s_ax]))
        y = np.asarray(parts.pos_folded)[:, n_ax]
        vel = np.asarray(parts.v)
        idx = np.clip(np.digitize(y, edges) - 1, 0, n_bins - 1)
        mass_bin = np.bincount(idx, m, n_bins)
        prof.append(np.bincount(idx, m * vel[:, s_ax], n_bins) / np.maximum(mass_bin, 1e-300))
        c = vel.copy()
        c[:, s_ax] -= rate * y
        c -= (m[:, None] * c).sum(axis=0) / m.sum()
        kts.append((m[:, None] * c ** 2).sum() / (3 * (len(m) - 1)))
    mp, mp_err = block_average(pxy, min_blocks=min_blocks)
    kt, kt_err = block_average(kts, min_blocks=min_blocks)
    prof = np.array(prof)
    yc = 0.5 * (edges[1:] + edges[:-1])
    means, errs = zip(*(block_average(prof[:, k], min_blocks=min_blocks) for k in range(n_bins)))
    means, errs = np.array(means), np.array(errs)
    weighted = bool(np.all(errs > 0))
    w = 1.0 / errs if weighted else np.ones(n_bins)
    A = np.vstack([yc, np.ones_like(yc)]).T * w[:, None]
    coef, *_ = np.linalg.lstsq(A, means * w, rcond=None)
    chi2 = float((((means - (coef[0] * yc + coef[1])) * w) ** 2).sum())
    cov = np.linalg.inv(A.T @ A)
    if not weighted:  # the scatter about the line sets the error
        cov *= chi2 / max(n_bins - 2, 1)
        chi2 = float("nan")
    return ShearResult(eta=float(-mp / rate), eta_err=float(mp_err / abs(rate)), rate=rate,
                       slope=float(coef[0]), slope_err=float(np.sqrt(cov[0, 0])), chi2=chi2,
                       dof=n_bins - 2, kT=float(kt), kT_err=float(kt_err), y=yc, v=means, v_err=errs,
                       p_sn=np.asarray(pxy), n_samples=n_samples, sample_time=sample_every * dt)
