# labels: python
"""Langevin / Brownian thermostat API (doc/thermostats.md): parameter checks
naming the parameter and its range, get_state, turn_off, per-particle gamma,
the integrator/thermostat combinations that are refused, checkpoints, and the
noise keying (same numbers whatever the order of the particles)."""
import pickle

import numpy as np
import pytest

import marble


def make(n=10, L=8.0, dt=0.01, seed=1):
    s = marble.System(box_l=[L, L, L])
    s.time_step = dt
    s.cell_system.skin = 0.5
    rng = np.random.default_rng(seed)
    s.part.add(pos=rng.uniform(0, L, (n, 3)), v=rng.normal(size=(n, 3)))
    return s


@pytest.mark.parametrize("call", ["set_langevin", "set_brownian"])
def test_parameter_errors_name_parameter_and_range(call):
    s = make()
    setter = getattr(s.thermostat, call)
    with pytest.raises(ValueError, match="'kT'.*\\[0, inf"):
        setter(kT=-1.0, gamma=1.0, seed=1)
    with pytest.raises(ValueError, match="'gamma'"):
        setter(kT=1.0, gamma=-1.0, seed=1)
    with pytest.raises(ValueError, match="'gamma_rotation'"):
        setter(kT=1.0, gamma=1.0, gamma_rotation=float("nan"), seed=1)
    with pytest.raises(ValueError, match="'seed'.*required"):
        setter(kT=1.0, gamma=1.0)
    with pytest.raises(ValueError, match="'seed'.*>= 0"):
        setter(kT=1.0, gamma=1.0, seed=-3)
    with pytest.raises(ValueError, match="'kT' is required"):
        setter(gamma=1.0, seed=1)
    with pytest.raises(ValueError, match="unknown parameter"):
        setter(kT=1.0, gamma=1.0, seed=1, gama=2.0)
    assert s.thermostat.get_state() == []  # nothing changed by a refused call


def test_brownian_gamma_must_be_positive():
    s = make()
    with pytest.raises(ValueError, match="'gamma'.*\\(0, inf"):
        s.thermostat.set_brownian(kT=1.0, gamma=0.0, seed=1)
    s.thermostat.set_langevin(kT=1.0, gamma=0.0, seed=1)  # Langevin: gamma = 0 allowed


def test_get_state_and_turn_off():
    s = make()
    s.thermostat.set_langevin(kT=1.5, gamma=2.0, seed=42)
    (st,) = s.thermostat.get_state()
    assert st["type"] == "LANGEVIN" and st["kT"] == 1.5 and st["gamma"] == 2.0
    assert st["gamma_rotation"] == 2.0  # defaults to gamma
    assert st["seed"] == 42 and st["philox_counter"] == 0
    s.integrator.run(5)
    assert s.thermostat.langevin.philox_counter == 5
    s.thermostat.set_langevin(kT=1.0, gamma=2.0, gamma_rotation=0.5)  # keeps seed
    assert s.thermostat.langevin.seed == 42 and s.thermostat.langevin.gamma_rotation == 0.5
    s.thermostat.turn_off()
    assert s.thermostat.get_state() == []
    assert not s.thermostat.langevin.active
    v0 = s.part.all().v.copy()
    s.integrator.run(3)  # no friction, no noise, no forces: velocities unchanged
    np.testing.assert_array_equal(s.part.all().v, v0)
    s.thermostat.set_brownian(kT=1.0, gamma=3.0, seed=5)
    assert [d["type"] for d in s.thermostat.get_state()] == ["BROWNIAN"]


@pytest.mark.skipif(not marble.has_features("DPD"), reason="needs DPD")
def test_langevin_combines_with_dpd():
    s = make()
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=0, gamma=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=3)
    s.thermostat.set_langevin(kT=1.0, gamma=1.0, seed=4)
    assert {d["type"] for d in s.thermostat.get_state()} == {"DPD", "LANGEVIN"}
    s.integrator.run(10)
    s.thermostat.turn_off()
    assert s.thermostat.get_state() == []


def test_per_particle_gamma_readback_and_validation():
    s = make()
    p = s.part.by_id(3)
    assert p.gamma == -1.0  # -1: the thermostat's gamma
    p.gamma = 2.5
    assert p.gamma == 2.5
    s.part.all().gamma = 0.5
    np.testing.assert_array_equal(s.part.all().gamma, 0.5)
    with pytest.raises(ValueError, match="'gamma'.*>= 0"):
        p.gamma = -2.0
    assert p.gamma == 0.5
    q = s.part.add(pos=[1, 1, 1], gamma=3.0)
    assert q.gamma == 3.0
    if marble.has_features("ROTATION"):
        q.gamma_rot = 1.25
        assert q.gamma_rot == 1.25
        assert "gamma_rot" in q.to_dict()
    else:
        with pytest.raises(marble.FeaturesError):
            q.gamma_rot = 1.0


def test_friction_only_force_is_minus_gamma_v():
    """kT = 0: the Langevin force is -gamma v (the per-particle value where set)."""
    s = make(n=4)
    s.part.by_id(1).gamma = 3.0
    s.thermostat.set_langevin(kT=0.0, gamma=0.5, seed=1)
    s.integrator.run(0)
    parts = s.part.all()
    gam = np.array([0.5, 3.0, 0.5, 0.5])[:, None]
    np.testing.assert_allclose(parts.f, -gam * parts.v, rtol=1e-14, atol=1e-14)


def test_noise_variance_and_keying():
    """The force of one step: variance 2 gamma kT / dt per component (uniform
    noise, 24 gamma kT / dt * 1/12), independent of the particles' order."""
    n = 4000
    s = make(n=n, L=20.0)
    s.part.all().v = np.zeros((n, 3))
    s.thermostat.set_langevin(kT=2.0, gamma=1.5, seed=9)
    s.integrator.run(0)
    f = s.part.all().f
    var = f.var()
    expected = 2 * 1.5 * 2.0 / s.time_step
    # relative error of a variance of a uniform: sqrt((9/5 - 1) / (3 n))
    assert abs(var / expected - 1) < 3 * np.sqrt(0.8 / (3 * n))
    # the same ids added in another order: the same force on each id
    s2 = marble.System(box_l=[20.0] * 3)
    s2.time_step = s.time_step
    s2.cell_system.skin = 0.5
    order = np.random.default_rng(0).permutation(n)
    pos = s.part.all().pos
    s2.part.add(id=order, pos=pos[order])
    s2.thermostat.set_langevin(kT=2.0, gamma=1.5, seed=9)
    s2.integrator.run(0)
    np.testing.assert_array_equal(s2.part.by_ids(range(n)).f, f)


def test_unstable_friction_refused():
    s = make()
    s.thermostat.set_langevin(kT=1.0, gamma=1.0, seed=1)
    s.part.by_id(2).gamma = 250.0  # gamma dt / m = 2.5
    with pytest.raises(RuntimeError, match="particle 2.*>= 2.*reduce time_step"):
        s.integrator.run(1)


def test_brownian_combinations_refused():
    s = make()
    s.integrator.set_brownian_dynamics()
    assert s.integrator.get_state()["name"] == "BrownianDynamics"
    with pytest.raises(RuntimeError, match="requires the BD thermostat"):
        s.integrator.run(1)
    s.thermostat.set_brownian(kT=1.0, gamma=2.0, seed=1)
    s.thermostat.set_langevin(kT=1.0, gamma=2.0, seed=1)
    with pytest.raises(RuntimeError, match="cannot be combined with the Langevin"):
        s.integrator.run(1)
    s.thermostat.turn_off()
    s.thermostat.set_brownian(kT=1.0, gamma=2.0)
    s.integrator.run(2)
    s.integrator.set_vv()
    with pytest.raises(RuntimeError, match="Brownian thermostat works only with"):
        s.integrator.run(1)


@pytest.mark.skipif(not marble.has_features("DPD"), reason="needs DPD")
def test_brownian_with_dpd_refused():
    s = make()
    s.integrator.set_brownian_dynamics()
    s.thermostat.set_brownian(kT=1.0, gamma=2.0, seed=1)
    s.thermostat.set_dpd(kT=1.0, seed=1)
    with pytest.raises(RuntimeError, match="cannot be combined with the DPD"):
        s.integrator.run(1)


def test_brownian_step_by_hand():
    """kT = 0: one BD step is x += F dt / gamma, v = F / gamma (here F = ext_force)."""
    if not marble.has_features("EXTERNAL_FORCE"):
        pytest.skip("needs EXTERNAL_FORCE")
    s = make(n=3)
    s.part.all().ext_force = [[1.0, 0.0, -2.0]] * 3
    s.part.by_id(1).gamma = 4.0
    s.integrator.set_brownian_dynamics()
    s.thermostat.set_brownian(kT=0.0, gamma=2.0, seed=1)
    x0 = s.part.all().pos.copy()
    s.integrator.run(1)
    gam = np.array([2.0, 4.0, 2.0])[:, None]
    F = np.array([1.0, 0.0, -2.0])
    np.testing.assert_allclose(s.part.all().pos - x0, F * s.time_step / gam, atol=1e-14)
    np.testing.assert_allclose(s.part.all().v, F / gam, atol=1e-14)


@pytest.mark.parametrize("mode", ["langevin", "brownian"])
def test_checkpoint_restart_bit_exact(mode):
    """A pickled System (the core's checkpoint blob) continues bit for bit:
    thermostat parameters, seed, counter and per-particle gamma are stored."""
    s = make(n=30)
    s.part.by_id(4).gamma = 2.0
    if mode == "langevin":
        s.thermostat.set_langevin(kT=1.2, gamma=0.8, seed=11)
    else:
        s.integrator.set_brownian_dynamics()
        s.thermostat.set_brownian(kT=1.2, gamma=0.8, seed=11)
        s.time_step = 0.001
    s.integrator.run(20)
    restored = pickle.loads(pickle.dumps(s))
    s.integrator.run(20)
    st = {d["type"]: d for d in restored.thermostat.get_state()}
    assert st[mode.upper()]["philox_counter"] == 20 and st[mode.upper()]["seed"] == 11
    assert st[mode.upper()]["gamma"] == 0.8
    assert restored.part.by_id(4).gamma == 2.0
    assert restored.integrator.get_state()["name"] == s.integrator.get_state()["name"]
    restored.integrator.run(20)
    np.testing.assert_array_equal(restored.part.all().pos, s.part.all().pos)
    np.testing.assert_array_equal(restored.part.all().v, s.part.all().v)


def test_scheme_at_large_gamma_dt():
    """The scheme's own statistics at a = gamma dt / m = 0.5 (doc/thermostats.md):
    on-step velocities have exactly <v_d^2> = kT / m, and the velocity
    autocorrelation at lag k steps is (1 - a/2)(1 - a)^(k-1) (0.75, 0.375,
    0.1875), far from exp(-a k); ideal gas, error from 20 blocks of particles."""
    n, kT, a, dt = 2000, 1.3, 0.5, 0.01
    s = make(n=n, L=30.0, dt=dt, seed=3)
    s.part.all().v = np.random.default_rng(4).normal(scale=np.sqrt(kT), size=(n, 3))
    s.thermostat.set_langevin(kT=kT, gamma=a / dt, seed=8)
    s.integrator.run(50)
    parts = s.part.all()
    v = []
    for _ in range(400):
        s.integrator.run(1)
        v.append(parts.v)
    v = np.array(v)                                    # step, particle, 3
    blocks = np.array_split(np.arange(n), 20)

    def stat(per_particle):
        b = np.array([per_particle[i].mean() for i in blocks])
        return b.mean(), b.std(ddof=1) / np.sqrt(len(blocks))
    m, e = stat((v**2).mean(axis=(0, 2)))
    assert abs(m - kT) < 3 * e, (m, e)
    c0 = (v * v).sum(axis=2).mean(axis=0)
    for k in (1, 2, 3):
        ck = (v[k:] * v[:-k]).sum(axis=2).mean(axis=0)
        r = np.array([ck[i].mean() / c0[i].mean() for i in blocks])
        m, e = r.mean(), r.std(ddof=1) / np.sqrt(len(blocks))
        expect = (1 - a / 2) * (1 - a) ** (k - 1)
        assert abs(m - expect) < 3 * e, (k, m, e, expect)
        assert abs(m - np.exp(-a * k)) > 5 * e  # the continuum value is clearly not it
