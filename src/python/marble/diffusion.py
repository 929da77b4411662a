"""Measuring (colloid) diffusion: Green-Kubo, MSD fits, blocking error bars and
the constant-force drag measurement (reference.md section 5, doc/analysis.md).

Every estimator returns its value together with an error bar computed from the
data itself; ``D, D_err = green_kubo(...)`` unpacks the two, the other fields
are attributes of the result.
"""
import warnings

import numpy as np

from .code_features import assert_features


class Result:
    """Value, error and details of an estimate; unpacks as (value, error)."""

    def __init__(self, value, error, **details):
        self.value = value
        self.error = error
        self.__dict__.update(details)

    def __iter__(self):
        return iter((self.value, self.error))

    def __repr__(self):
        return f"{type(self).__name__}({self.value:.6g} +/- {self.error:.2g})"


class BlockingResult(Result):
    """mean, error and plateau (block size at which the error estimate levels
    off, None if it never does); unpacks as (mean, error, plateau)."""

    @property
    def mean(self):
        """The mean (same as ``value``)."""
        return self.value

    def __iter__(self):
        return iter((self.value, self.error, self.plateau))


def blocking(x, min_blocks=16):
    """Mean of a correlated time series and its standard error by blocking
    (Flyvbjerg, Petersen, J. Chem. Phys. 91, 461 (1989)).

    Level l averages neighbouring pairs l times (block size 2^l); its error
    estimate is s_l = std(blocks)/sqrt(n_l) with uncertainty s_l/sqrt(2 (n_l - 1)).
    Only levels with >= min_blocks blocks are used. The plateau is the first
    level, followed by at least two more, that no later level exceeds by more
    than twice that later level's uncertainty; its s_l is the error. If no level qualifies
    the series is too short for its correlation time: ``converged`` is False,
    the error is the largest s_l (a lower bound) and a RuntimeWarning is issued.

    Returns a BlockingResult: mean, error, plateau (block size or None), and
    the arrays block_sizes, errors, error_errors per level, converged.
    """
    x = np.asarray(x, dtype=float).ravel()
    if x.size < 2 * min_blocks or min_blocks < 2:
        raise ValueError(f"blocking needs at least 2 * min_blocks = {2 * min_blocks} values "
                         f"(min_blocks >= 2), got {x.size}")
    if not np.all(np.isfinite(x)):
        raise ValueError("blocking: the series contains non-finite values")
    sizes, errs, derrs = [], [], []
    y, size = x, 1
    while y.size >= min_blocks:
        n = y.size
        s = float(np.std(y, ddof=1) / np.sqrt(n))
        sizes.append(size)
        errs.append(s)
        derrs.append(s / np.sqrt(2.0 * (n - 1)))
        m = n // 2
        y = 0.5 * (y[:2 * m:2] + y[1:2 * m:2])
        size *= 2
    errs, derrs = np.array(errs), np.array(derrs)
    plateau_level = None
    for level in range(len(errs) - 2):
        later = slice(level + 1, None)
        if np.all(errs[later] - errs[level] <= 2.0 * derrs[later]):
            plateau_level = level
            break
    converged = plateau_level is not None
    if converged:
        error = float(errs[plateau_level])
    else:
        error = float(np.max(errs))
        warnings.warn("blocking: no plateau in the error estimate; the series is too short "
                      "for its correlation time (the error is a lower bound)", RuntimeWarning,
                      stacklevel=2)
    return BlockingResult(float(np.mean(x)), error,
                          plateau=sizes[plateau_level] if converged else None,
                          converged=converged, block_sizes=np.array(sizes), errors=errs,
                          error_errors=derrs)


def _window_mask(t, window, name):
    if window is None or len(window) != 2 or not window[0] < window[1]:
        raise ValueError(f"parameter 'window' must be (t_min, t_max) with t_min < t_max, "
                         f"got {window}")
    mask = (t >= window[0]) & (t <= window[1])
    if not np.any(mask):
        raise ValueError(f"{name}: no lag time inside window {window}")
    return mask


def _as_runs(t, y, name):
    t = np.asarray(t, dtype=float).ravel()
    y = np.asarray(y, dtype=float)
    if y.ndim >= 2 and y.shape[-1] == 1 and y.shape[-2] == t.size:
        y = y[..., 0]  # Correlator scalar_product results: (n_lags, 1)
    if y.ndim == 1:
        y = y[None, :]
    if y.ndim != 2 or y.shape[1] != t.size:
        raise ValueError(f"{name}: values must have shape (n_lags,) or (n_runs, n_lags) "
                         f"matching lag_times ({t.size}), got {np.shape(y)}")
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{name}: lag_times must increase")
    return t, y


def green_kubo(lag_times, vacf, window, dim=3, n_particles=1, tail_amplitude=None):
    """D = (1/dim) Int_0^t C_v(t') dt' (trapezoid on the given, possibly
    multiple-tau, lag grid), averaged over the plateau window (t_min, t_max).

    vacf: C_v(t) = <v(0).v(t)> summed over the dim components (a scalar_product
    Correlator of ParticleVelocities); divided by n_particles when the
    observable holds several particles. Shape (n_lags,) or (n_runs, n_lags).
    tail_amplitude: optional per-component A with C(t) -> A t^-3/2 beyond the
    data (theory.vacf_tail_amplitude); adds 2 A/sqrt(t) to the running integral.

    Error: with several independent runs, the standard error of the per-run
    plateau values; with one run, the spread (std) of the running integral in
    the window -- a rough estimate, prefer independent runs.
    Returns Result (D, D_err) with running (n_runs, n_lags), lag_times, method.
    """
    t, C = _as_runs(lag_times, vacf, "green_kubo")
    mask = _window_mask(t, window, "green_kubo")
    upto = t <= window[1]
    if not np.all(np.isfinite(C[:, upto])):
        raise ValueError("green_kubo: the VACF has non-finite values (lags without samples?) "
                         "up to the end of the window")
    C = C / (dim * n_particles)
    running = np.full_like(C, np.nan)
    Cu, tu = C[:, upto], t[upto]
    steps = np.cumsum(0.5 * (Cu[:, 1:] + Cu[:, :-1]) * np.diff(tu), axis=1)
    # a grid that does not start at t = 0: rectangle rule on [0, t_0]
    start = t[0] * C[:, :1] if t[0] > 0 else 0.0
    running[:, upto] = np.concatenate([np.zeros((C.shape[0], 1)), steps], axis=1) + start
    if tail_amplitude is not None:
        tpos = np.where(t > 0, t, 1.0)
        running = running + np.where(t > 0, 2.0 * tail_amplitude / np.sqrt(tpos), 0.0)
    plateau = running[:, mask].mean(axis=1)
    if C.shape[0] > 1:
        D = float(plateau.mean())
        err = float(plateau.std(ddof=1) / np.sqrt(C.shape[0]))
        method = "independent runs"
    else:
        D = float(plateau[0])
        err = float(running[0, mask].std(ddof=1)) if mask.sum() > 1 else np.nan
        method = "plateau spread"
    return Result(D, err, running=running, lag_times=t, plateau_values=plateau, method=method)


def msd_fit(lag_times, msd, window, dim=3, msd_err=None):
    """Fit MSD(t) = a + 2 dim D t in the window (t_min, t_max).

    msd: summed over the dim components (e.g. a square_distance_componentwise
    Correlator of ParticlePositions summed over its last axis), shape (n_lags,)
    or (n_runs, n_lags). Error: standard error over independent runs; with one
    run, from msd_err (weighted least squares) if given, else from the fit
    residuals (an underestimate: MSD points are strongly correlated).
    Returns Result (D, D_err) with intercept, lag_times, fit, method.
    """
    t, y = _as_runs(lag_times, msd, "msd_fit")
    mask = _window_mask(t, window, "msd_fit")
    if mask.sum() < 2:
        raise ValueError("msd_fit: need at least 2 lag times in the window")
    if not np.all(np.isfinite(y[:, mask])):
        raise ValueError("msd_fit: the MSD has non-finite values in the window")
    tw = t[mask]
    A = np.stack([np.ones_like(tw), 2.0 * dim * tw], axis=1)
    coef = np.linalg.lstsq(A, y[:, mask].T, rcond=None)[0]  # (2, n_runs)
    intercepts, Ds = coef[0], coef[1]
    if y.shape[0] > 1:
        D = float(Ds.mean())
        err = float(Ds.std(ddof=1) / np.sqrt(y.shape[0]))
        method = "independent runs"
        intercept = float(intercepts.mean())
    else:
        D, intercept = float(Ds[0]), float(intercepts[0])
        if msd_err is not None:
            e = np.asarray(msd_err, dtype=float).ravel()[mask]
            W = A / e[:, None]
            cw = np.linalg.lstsq(W, y[0, mask] / e, rcond=None)[0]
            D, intercept = float(cw[1]), float(cw[0])
            err = float(np.sqrt(np.linalg.inv(W.T @ W)[1, 1]))
            method = "weighted fit"
        else:
            if mask.sum() < 3:
                raise ValueError("msd_fit: need >= 3 points in the window for a residual error")
            res = y[0, mask] - A @ coef[:, 0]
            s2 = float(res @ res) / (mask.sum() - 2)
            err = float(np.sqrt(s2 * np.linalg.inv(A.T @ A)[1, 1]))
            method = "fit residuals"
    return Result(D, err, intercept=intercept, lag_times=t, fit=intercept + 2 * dim * D * t,
                  method=method)


def _id_list(system, items, name):
    ids = []
    for p in np.atleast_1d(np.asarray(items, dtype=object)):
        pid = p.id if hasattr(p, "id") else p
        if isinstance(pid, (bool, np.bool_)) or int(pid) != pid:
            raise ValueError(f"parameter '{name}' must be particles or particle ids")
        ids.append(int(pid))
    if not ids:
        raise ValueError(f"parameter '{name}' is empty")
    for pid in ids:
        if not system.part.exists(pid):
            raise IndexError(f"parameter '{name}': particle {pid} does not exist")
    return ids


def measure_drag(system, colloids, force, steps, solvent=None, equilibration_steps=0,
                 delta_N=10, kT=1.0, min_blocks=16, restore=True):
    """Friction of colloid(s) from a constant force (reference.md section 5).

    Sets ext_force = force on every colloid and -N_c force / N_s on every solvent
    particle (zero net force: the box does not accelerate), integrates
    ``equilibration_steps``, then ``steps`` more, sampling every ``delta_N``
    steps the mean colloid velocity relative to the solvent's centre-of-mass
    velocity, projected on the force. Blocking gives v and its error;
    zeta = ``|F|``/v and D = kT/zeta (in the periodic box: compare with
    theory.diffusion_coefficient at this L). The previous ext_force values are
    restored afterwards (restore=False keeps the drive on).

    colloids: particle handles or ids; solvent: ids (default: every other particle).
    Returns Result (zeta, zeta_err) with D, D_err, v, v_err, blocking, v_parallel,
    times, force.
    """
    assert_features("EXTERNAL_FORCE")
    from .accumulators import TimeSeries
    from .observables import ComVelocity, ParticleVelocities

    F = np.asarray(force, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)) or not np.linalg.norm(F) > 0:
        raise ValueError(f"parameter 'force' must be a finite, non-zero 3-vector, got {force}")
    for name, val, lo in (("steps", steps, 1), ("equilibration_steps", equilibration_steps, 0),
                          ("delta_N", delta_N, 1)):
        if isinstance(val, bool) or int(val) != val or val < lo:
            raise ValueError(f"parameter '{name}' must be an integer >= {lo}, got {val}")
    if int(steps) // int(delta_N) < 2 * min_blocks:
        raise ValueError(f"steps/delta_N = {int(steps) // int(delta_N)} samples, blocking needs "
                         f">= {2 * min_blocks}")
    c_ids = _id_list(system, colloids, "colloids")
    if solvent is None:
        s_ids = sorted(set(int(i) for i in system.part.all().id) - set(c_ids))
    else:
        s_ids = _id_list(system, solvent, "solvent")
    if set(c_ids) & set(s_ids):
        raise ValueError("parameters 'colloids' and 'solvent' overlap")
    if not s_ids:
        raise ValueError("no solvent particles to take the counter force")
    cs, ss = system.part.by_ids(c_ids), system.part.by_ids(s_ids)
    old_c, old_s = np.array(cs.ext_force), np.array(ss.ext_force)
    cs.ext_force = F
    ss.ext_force = -len(c_ids) * F / len(s_ids)
    try:
        if equilibration_steps:
            system.integrator.run(int(equilibration_steps))
        tc = TimeSeries(obs=ParticleVelocities(ids=c_ids, system=system), delta_N=int(delta_N))
        tsol = TimeSeries(obs=ComVelocity(ids=s_ids, system=system), delta_N=int(delta_N))
        system.auto_update_accumulators.add(tc)
        system.auto_update_accumulators.add(tsol)
        t0 = system.time
        try:
            system.integrator.run(int(steps))
        finally:
            system.auto_update_accumulators.remove(tc)
            system.auto_update_accumulators.remove(tsol)
    finally:
        if restore:
            cs.ext_force = old_c
            ss.ext_force = old_s
    v_rel = tc.time_series().mean(axis=1) - tsol.time_series()
    e = F / np.linalg.norm(F)
    v_par = v_rel @ e
    blk = blocking(v_par, min_blocks=min_blocks)
    Fn = float(np.linalg.norm(F))
    v, v_err = blk.mean, blk.error
    if not v > 0:
        warnings.warn(f"measure_drag: the colloid does not move along the force (v = {v:.3g} "
                      f"+/- {v_err:.2g}); use a larger force or a longer run", RuntimeWarning,
                      stacklevel=2)
    zeta = Fn / v
    zeta_err = Fn * v_err / v ** 2
    dt = system.time_step * int(delta_N)
    return Result(zeta, abs(zeta_err), D=kT * v / Fn, D_err=kT * v_err / Fn, v=v, v_err=v_err,
                  blocking=blk, v_parallel=v_par, times=t0 + dt * np.arange(1, v_par.size + 1),
                  force=F)
