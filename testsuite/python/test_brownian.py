# labels: python long
"""Brownian dynamics statistics on an ideal gas (doc/thermostats.md): the
mean squared displacement MSD(t) = 6 D t with D = kT / gamma (global gamma and
a per-particle gamma), the drift velocity F / gamma under a constant external
force (EXTERNAL_FORCE), the kinetic temperature of the Maxwell velocities and,
with ROTATION, of omega. The scheme is exact for free particles (Gaussian
increments), so the tolerance is 3 sigma of the run's own error, from 20
independent blocks of particles."""
import numpy as np
import pytest

import marble
from stat_helpers import block_mean_err

KT, GAMMA, DT, STEPS = 1.2, 2.0, 0.01, 1000
N, N_BLOCKS = 5000, 20
TIMES = [100, 250, 500, 1000]  # steps


@pytest.fixture(scope="module")
def run():
    rng = np.random.default_rng(5)
    L = 40.0
    s = marble.System(box_l=[L, L, L])
    s.time_step = DT
    s.cell_system.skin = 2.0  # ideal gas: no pairs; a BD step may move ~0.5
    extra = {}
    if marble.has_features("ROTATION"):
        extra = dict(rotation=True, rinertia=1.5)
    a = s.part.add(pos=rng.uniform(0, L, (N, 3)), **extra)          # global gamma
    b = s.part.add(pos=rng.uniform(0, L, (N, 3)), gamma=0.5)        # per-particle gamma
    c = None
    if marble.has_features("EXTERNAL_FORCE"):
        c = s.part.add(pos=rng.uniform(0, L, (N, 3)), ext_force=[0.6, 0.0, -0.3])
    s.integrator.set_brownian_dynamics()
    s.thermostat.set_brownian(kT=KT, gamma=GAMMA, gamma_rotation=3.0, seed=78)
    x0 = {k: p.pos.copy() for k, p in (("a", a), ("b", b), ("c", c)) if p is not None}
    disp, vel, omg = {}, [], []
    done = 0
    for t in TIMES:
        s.integrator.run(t - done)
        done = t
        disp[t] = {k: p.pos - x0[k] for k, p in (("a", a), ("b", b), ("c", c)) if p is not None}
        vel.append(a.v)
        if extra:
            omg.append(a.omega_lab)
    return dict(disp=disp, v=np.array(vel), w=np.array(omg) if extra else None)


@pytest.mark.parametrize("group,gamma", [("a", GAMMA), ("b", 0.5)])
def test_msd_6Dt(run, group, gamma):
    D = KT / gamma
    for t in TIMES:
        dx = run["disp"][t][group]
        mean, err = block_mean_err((dx**2).sum(axis=1), N_BLOCKS)
        theory = 6 * D * t * DT
        print(f"gamma {gamma}: t = {t * DT:.2f}: MSD = {mean:.4f} +- {err:.4f}, 6Dt = {theory:.4f}; "
              f"D = {mean / (6 * t * DT):.4f} +- {err / (6 * t * DT):.4f} (kT/gamma = {D})")
        assert abs(mean - theory) < 3 * err


@pytest.mark.skipif(not marble.has_features("EXTERNAL_FORCE"), reason="needs EXTERNAL_FORCE")
def test_drift_velocity(run):
    F = np.array([0.6, 0.0, -0.3])
    for t in TIMES:
        dx = run["disp"][t]["c"]
        mean, err = block_mean_err(dx.T, N_BLOCKS)
        drift = F / GAMMA * t * DT
        print(f"t = {t * DT:.2f}: mean displacement {mean} +- {err}, F t / gamma = {drift}")
        assert np.all(np.abs(mean - drift) < 3 * err)
        # the spread around the drift is still 2 D t per component
        var, verr = block_mean_err(((dx - drift) ** 2).T, N_BLOCKS)
        assert np.all(np.abs(var - 2 * KT / GAMMA * t * DT) < 3 * verr)


def test_maxwell_velocities(run):
    v = run["v"]  # samples, particle, 3 (F = 0: v is the Maxwell part only)
    mean, err = block_mean_err((v**2).mean(axis=0).T, N_BLOCKS)
    print(f"<v_d^2> = {mean} +- {err} (kT/m = {KT})")
    assert np.all(np.abs(mean - KT) < 3 * err)


@pytest.mark.skipif(not marble.has_features("ROTATION"), reason="needs ROTATION")
def test_rotation_kT(run):
    w = run["w"]
    mean, err = block_mean_err((1.5 * w**2).mean(axis=0).T, N_BLOCKS)
    print(f"<I omega_d^2> = {mean} +- {err} (kT = {KT})")
    assert np.all(np.abs(mean - KT) < 3 * err)
