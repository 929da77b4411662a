"""RESPA substeps for the stiff colloid pair forces (integrator.set_vv(substeps=n),
set_shardlow(substeps=n); integrators/integrate.cpp run_md_respa, doc/speed-accuracy.md).

(a) NVE accuracy: a marble's LJ wall with a soft-repulsive solvent, thermostat off:
    the total-energy fluctuation at dt with n substeps is much smaller than plain
    velocity Verlet at dt and close to plain velocity Verlet at dt/n.
(b) no fast forces (no colloid): substeps = n follows substeps = 1 to round-off.
(c) momentum conservation with the DPD noise (Shardlow + marble coupling).
(d) bad input, get_state, checkpoints, continuation bit for bit, refusals.
"""
import pickle

import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("MARBLE", "DPD", "HAT"),
                                reason="needs MARBLE, DPD, HAT")


def marble_scene(seed=3, L=8.0, R=2.0, dt=0.02, thermostat=False, hat=True, colloid=True):
    """A marble of radius R (LJ wall, add_marble defaults) in a solvent of density 3,
    with a soft repulsion (hat, F_max = 5) between the beads if @p hat; kT = 1 velocities."""
    from marble.colloids import add_marble
    s = marble.System(box_l=[L] * 3)
    s.time_step = dt
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    n = int(3 * L ** 3)
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)), type=0)
    if hat:
        s.non_bonded_inter[0, 0].hat.set_params(F_max=5.0, cutoff=1.0)
    if thermostat:
        s.thermostat.set_dpd(kT=1.0, seed=seed)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    if colloid:
        add_marble(s, pos=[L / 2] * 3, radius=R, gamma=5.0)
    return s


def energy_fluctuation(dt, substeps, hat, colloid=True, seed=3):
    """NVE (no thermostat): std of the total energy per particle over 4 tau, sampled
    every 0.04 tau, after relaxing the overlaps of the random start at dt = 0.002."""
    s = marble_scene(seed=seed, dt=0.002, hat=hat, colloid=colloid)
    s.integrator.run(500)
    p = s.part.all()
    p.v = np.random.default_rng(seed + 1).normal(size=(len(p), 3))
    s.time_step = dt
    s.integrator.set_vv(substeps=substeps)
    every = int(round(0.04 / dt))
    e = []
    for _ in range(100):
        s.integrator.run(every)
        e.append(s.analysis.energy()["total"])
    return np.std(e) / len(p)


def test_nve_wall_only_respa_is_vv_at_h():
    """Ideal-gas solvent + the marble's WCA wall: the wall is the only force, so RESPA
    at dt = 0.04 with 4 substeps is velocity Verlet at h = 0.01 (the same arithmetic
    up to round-off): its energy fluctuation equals VV(0.01)'s to 5 % and is > 10x
    below VV(0.04)'s (measured 1.13e-5, 1.13e-5 and 2.4e-4)."""
    vv_big = energy_fluctuation(0.04, 1, hat=False)
    respa = energy_fluctuation(0.04, 4, hat=False)
    vv_small = energy_fluctuation(0.01, 1, hat=False)
    print(f"wall only: VV 0.04 {vv_big:.3e}, RESPA 0.04/4 {respa:.3e}, VV 0.01 {vv_small:.3e}")
    assert respa < 0.1 * vv_big
    assert abs(respa / vv_small - 1.0) < 0.05


def test_nve_with_slow_force():
    """With a soft solvent repulsion (hat, F_max = 5: the slow part, at the outer step),
    RESPA's error is the slow force's: its fluctuation is within 2x of that of the
    same solvent without the marble under VV at 0.04 (measured 3.1e-4 vs 4.1e-4),
    and < 0.25x of VV at 0.04 with the marble (7.6e-3)."""
    vv_big = energy_fluctuation(0.04, 1, hat=True)
    respa = energy_fluctuation(0.04, 4, hat=True)
    slow_only = energy_fluctuation(0.04, 1, hat=True, colloid=False)
    print(f"with hat: VV 0.04 {vv_big:.3e}, RESPA 0.04/4 {respa:.3e}, solvent alone VV 0.04 "
          f"{slow_only:.3e}")
    assert respa < 0.25 * vv_big
    assert 0.5 * slow_only < respa < 2.0 * slow_only


def test_no_fast_forces_same_trajectory():
    """Without a colloid there are no fast forces: n substeps of x += h v equal
    x += dt v to round-off (VV and Shardlow, with DPD noise and a soft repulsion)."""
    for kind in ("vv", "shardlow"):
        out = []
        for n in (1, 3):
            s = marble.System(box_l=[6.0] * 3)
            s.time_step = 0.02
            s.cell_system.skin = 0.4
            rng = np.random.default_rng(7)
            s.part.add(pos=rng.random((648, 3)) * 6.0, v=rng.normal(size=(648, 3)))
            s.non_bonded_inter[0, 0].hat.set_params(F_max=5.0, cutoff=1.0)
            s.thermostat.set_dpd(kT=1.0, seed=7)
            s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
            getattr(s.integrator, "set_" + kind)(substeps=n)
            s.integrator.run(40)
            p = s.part.all()
            out.append((np.asarray(p.pos), np.asarray(p.v)))
        assert np.max(np.abs(out[0][0] - out[1][0])) < 1e-9, kind
        assert np.max(np.abs(out[0][1] - out[1][1])) < 1e-9, kind


def test_momentum_conserved_with_noise():
    """Shardlow with 3 substeps, DPD noise and the marble coupling's friction and
    noise: the total momentum stays at its start value to 1e-12 relative to sum |m v|."""
    s = marble_scene(thermostat=True, dt=0.03)
    s.integrator.set_shardlow(substeps=3)
    s.integrator.run(20)
    p0 = np.asarray(s.analysis.linear_momentum())
    s.integrator.run(200)
    p = s.part.all()
    scale = np.sum(np.asarray(p.mass)[:, None] * np.abs(np.asarray(p.v)))
    drift = np.max(np.abs(np.asarray(s.analysis.linear_momentum()) - p0))
    assert drift < 1e-12 * scale, (drift, scale)


def test_continuation_and_checkpoint_bit_for_bit():
    """run(30) == run(12) + run(18); a pickled System keeps substeps and continues bit for bit."""
    a = marble_scene(thermostat=True, dt=0.03)
    b = marble_scene(thermostat=True, dt=0.03)
    for s in (a, b):
        s.integrator.set_shardlow(substeps=2)
    a.integrator.run(30)
    b.integrator.run(12)
    c = pickle.loads(pickle.dumps(b))
    assert c.integrator.get_state() == {"name": "Shardlow", "substeps": 2}
    b.integrator.run(18)
    c.integrator.run(18)
    for k in ("pos", "v", "f", "omega_lab"):
        ref = np.asarray(getattr(a.part.all(), k)).tobytes()
        assert np.asarray(getattr(b.part.all(), k)).tobytes() == ref, k
        assert np.asarray(getattr(c.part.all(), k)).tobytes() == ref, k


def test_forces_are_total():
    """particle.f after a RESPA step holds all forces (slow + fast), as with substeps = 1:
    run(0) recomputes them to round-off."""
    s = marble_scene(thermostat=False, dt=0.02)
    s.integrator.set_vv(substeps=3)
    s.integrator.run(20)
    f = np.asarray(s.part.all().f)
    s.integrator.run(0)
    f0 = np.asarray(s.part.all().f)
    assert np.max(np.abs(f - f0)) < 1e-9 * np.max(np.abs(f0))


@pytest.mark.parametrize("bad", [0, -1, 101, 2.5, "2", None, True])
def test_bad_substeps(bad):
    s = marble.System(box_l=[4.0] * 3)
    for setter in (s.integrator.set_vv, s.integrator.set_shardlow):
        with pytest.raises(ValueError, match="substeps"):
            setter(substeps=bad)
    with pytest.raises(ValueError, match=r"\[1, 100\]"):
        s.integrator.set_vv(substeps=0)


def test_state_and_reset():
    s = marble.System(box_l=[4.0] * 3)
    assert s.integrator.get_state() == {"name": "VelocityVerlet", "substeps": 1}
    s.integrator.set_vv(substeps=4)
    assert s.integrator.get_state() == {"name": "VelocityVerlet", "substeps": 4}
    s.integrator.set_dpd_vv()
    s.integrator.set_shardlow()
    assert s.integrator.get_state() == {"name": "Shardlow", "substeps": 1}
    s.integrator.set_shardlow(substeps=3.0)  # an integral float is an integer
    assert s.integrator.get_state()["substeps"] == 3
    blob = s._core.get_checkpoint_state()
    s2 = marble.System(box_l=[5.0] * 3)
    s2._core.set_checkpoint_state(blob)
    assert s2.integrator.get_state() == {"name": "Shardlow", "substeps": 3}


def test_lees_edwards_refused():
    import marble.lees_edwards as le
    s = marble.System(box_l=[6.0] * 3)
    s.time_step = 0.01
    s.part.add(pos=np.random.default_rng(1).random((50, 3)) * 6.0)
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                           protocol=le.LinearShear(shear_velocity=0.1))
    s.integrator.set_vv(substeps=2)
    with pytest.raises(RuntimeError, match="substeps = 2.*Lees-Edwards"):
        s.integrator.run(1)
    s.integrator.set_vv()
    s.integrator.run(1)
