# labels: python long
"""Langevin thermostat statistics on an ideal gas (doc/thermostats.md).

Groups of non-interacting particles: (A) global gamma, m = 1, rotating with
rinertia 2 (ROTATION); (B) m = 3 (MASS); (C) per-particle gamma = 2.5. Checked
against theory, each within 3 sigma of the run's own error:
  - kT from <m v_d^2> per component and per group, and from <I omega_d^2>;
  - the velocity autocorrelation C(t) / C(0) = exp(-gamma t / m) at several t
    (and the angular one exp(-gamma_rot t / I)).
The particles are independent, so the error bars come from independent blocks
of particles (20 blocks), not from a correlated time series. The scheme's own
error is stated and added to the tolerance: on-step velocities of a free
particle have exactly kT; the VACF of the discrete scheme is
(1 - a/2)(1 - a)^(k-1) with a = gamma dt / m (relative deviation from the
exponential ~ a/2 = 0.6 % at most here).
"""
import numpy as np
import pytest

import marble
from stat_helpers import block_mean_err

KT, GAMMA, GAMMA_ROT, DT = 1.5, 1.0, 1.5, 0.005
N_GROUP, N_BLOCKS = 1000, 20
EVERY, N_SAMPLES, WARMUP = 10, 3000, 1000   # samples every 0.05; 150 time units
LAGS = [10, 20, 30, 40]                     # in samples: t = 0.5, 1, 1.5, 2 (C: /5)


@pytest.fixture(scope="module")
def run():
    rng = np.random.default_rng(12)
    L = 20.0
    s = marble.System(box_l=[L, L, L])
    s.time_step = DT
    s.cell_system.skin = 0.5
    groups = {}
    mass = {"A": 1.0, "B": 3.0 if marble.has_features("MASS") else 1.0, "C": 1.0}
    for g in "ABC":
        extra = {}
        if g == "B" and marble.has_features("MASS"):
            extra["mass"] = mass["B"]
        if g == "C":
            extra["gamma"] = 2.5
        if g == "A" and marble.has_features("ROTATION"):
            extra.update(rotation=True, rinertia=2.0,
                         omega_lab=rng.normal(scale=np.sqrt(KT / 2.0), size=(N_GROUP, 3)))
        p = s.part.add(pos=rng.uniform(0, L, (N_GROUP, 3)),
                       v=rng.normal(scale=np.sqrt(KT / mass[g]), size=(N_GROUP, 3)), **extra)
        groups[g] = p.id
    s.thermostat.set_langevin(kT=KT, gamma=GAMMA, gamma_rotation=GAMMA_ROT, seed=2025)
    s.integrator.run(WARMUP)
    parts = s.part.all()
    ids = parts.id
    v = np.empty((N_SAMPLES, len(ids), 3))
    w = np.empty_like(v) if marble.has_features("ROTATION") else None
    for t in range(N_SAMPLES):
        s.integrator.run(EVERY)
        v[t] = parts.v
        if w is not None:
            w[t] = parts.omega_lab
    index = {pid: k for k, pid in enumerate(ids)}
    sel = {g: np.array([index[i] for i in groups[g]]) for g in groups}
    return dict(v=v, w=w, sel=sel, mass=mass)


def gammas():
    return {"A": GAMMA, "B": GAMMA, "C": 2.5}


@pytest.mark.parametrize("g", "ABC")
def test_kT_per_component(run, g):
    m = run["mass"][g]
    x = m * run["v"][:, run["sel"][g], :] ** 2       # time, particle, component
    mean, err = block_mean_err(x.mean(axis=0).T, N_BLOCKS)      # component, particle -> per component
    print(f"group {g}: kT per component {mean} +- {err}")
    for d in range(3):
        assert abs(mean[d] - KT) < 3 * err[d], (g, d, mean[d], err[d])


@pytest.mark.skipif(not marble.has_features("ROTATION"), reason="needs ROTATION")
def test_kT_rotation(run):
    x = 2.0 * run["w"][:, run["sel"]["A"], :] ** 2
    mean, err = block_mean_err(x.mean(axis=0).T, N_BLOCKS)
    print(f"rotation: kT per component {mean} +- {err}")
    for d in range(3):
        assert abs(mean[d] - KT) < 3 * err[d]


def discrete_vacf(a, k):
    """VACF of the scheme (friction on the half-step velocity) at lag k steps."""
    return (1 - a / 2) * (1 - a) ** (k - 1)


def check_decay(x, rate, lags, label):
    blocks = np.array_split(np.arange(x.shape[1]), N_BLOCKS)
    c0 = (x * x).sum(axis=2).mean(axis=0)                          # per particle
    ts = np.array([lag * EVERY * DT for lag in lags])
    ratios = []                                                    # block, lag
    for lag, t in zip(lags, ts):
        prod = (x[lag:] * x[:-lag]).sum(axis=2).mean(axis=0)       # per particle
        # ratio estimator per block of particles
        r = np.array([prod[b].mean() / c0[b].mean() for b in blocks])
        ratios.append(r)
        mean, err = r.mean(), r.std(ddof=1) / np.sqrt(N_BLOCKS)
        exact = np.exp(-rate * t)
        scheme = discrete_vacf(rate * DT, lag * EVERY)
        print(f"{label}: t = {t:.2f}: C/C0 = {mean:.4f} +- {err:.4f}, exp = {exact:.4f}, "
              f"scheme = {scheme:.4f}")
        assert abs(mean - exact) < 3 * err + abs(scheme - exact), (label, t, mean, err, exact)
    ratios = np.array(ratios).T

    # decay rate: least squares of log C = -rate t per block (the lags of one
    # block are correlated, so the error comes from the spread over blocks)
    def fit(c):
        return -np.sum(ts * np.log(c), axis=-1) / np.sum(ts * ts)
    rates = fit(ratios)
    fit_rate, fit_err = rates.mean(), rates.std(ddof=1) / np.sqrt(N_BLOCKS)
    # the same fit of the scheme's exact values: its O(gamma dt / m) offset
    offset = abs(fit(np.array([discrete_vacf(rate * DT, lag * EVERY) for lag in lags])) - rate)
    print(f"{label}: fitted decay rate {fit_rate:.4f} +- {fit_err:.4f} (theory {rate:.4f}, "
          f"scheme offset {offset:.4f})")
    assert abs(fit_rate - rate) < 3 * fit_err + offset


@pytest.mark.parametrize("g", "ABC")
def test_vacf_exponential(run, g):
    rate = gammas()[g] / run["mass"][g]
    lags = LAGS if g != "C" else [2, 4, 8, 12]
    check_decay(run["v"][:, run["sel"][g], :], rate, lags, f"group {g}")


@pytest.mark.skipif(not marble.has_features("ROTATION"), reason="needs ROTATION")
def test_angular_vacf_exponential(run):
    check_decay(run["w"][:, run["sel"]["A"], :], GAMMA_ROT / 2.0, LAGS, "rotation")
