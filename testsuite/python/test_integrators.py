# labels: python
"""Integrators: velocity Verlet (free flight, external force and torque, fixed
coordinates), steepest descent, and blow-ups that must stop with an error
naming the step and the particle, leaving a usable system."""
import numpy as np
import pytest

import marble
from unittest_decorators import skipIfMissingFeatures


def test_free_flight_and_run_zero():
    s = marble.System(box_l=[10.0] * 3, time_step=0.01)
    v = np.array([[0.3, -0.2, 0.1], [-1.0, 0.5, 2.0]])
    x0 = np.array([[1.0, 2.0, 3.0], [5.0, 5.0, 5.0]])
    s.part.add(pos=x0, v=v)
    s.integrator.set_vv()
    assert s.integrator.get_state()["name"] == "VelocityVerlet"
    assert s.integrator.run(200) == 200
    np.testing.assert_allclose(s.part.all().pos, x0 + 2.0 * v, atol=1e-12)
    np.testing.assert_allclose(s.part.all().v, v, atol=0)
    s.integrator.run(0)
    assert s.step == 200
    np.testing.assert_allclose(s.part.all().pos, x0 + 2.0 * v, atol=1e-12)


def test_run_without_time_step_raises():
    s = marble.System(box_l=[10.0] * 3)
    s.part.add(pos=[1, 1, 1])
    with pytest.raises(RuntimeError, match="time_step"):
        s.integrator.run(1)
    assert s.step == 0


@skipIfMissingFeatures("EXTERNAL_FORCE", "MASS")
def test_ext_force_gives_constant_acceleration():
    s = marble.System(box_l=[10.0] * 3, time_step=0.005)
    F = np.array([0.4, -0.2, 1.0])
    m = 2.5
    p = s.part.add(pos=[5.0, 5.0, 5.0], ext_force=F, mass=m)
    s.integrator.run(400)  # t = 2
    t = 2.0
    np.testing.assert_allclose(p.v, F * t / m, rtol=1e-12)
    np.testing.assert_allclose(p.pos, 5.0 + 0.5 * F * t ** 2 / m, rtol=1e-12)
    np.testing.assert_allclose(p.f, F, rtol=0)


@skipIfMissingFeatures("EXTERNAL_FORCE", "ROTATION")
def test_ext_torque_gives_constant_angular_acceleration():
    s = marble.System(box_l=[10.0] * 3, time_step=0.01)
    tau = np.array([0.5, 0.0, -1.5])
    inertia = 4.0
    p = s.part.add(pos=[1, 1, 1], rotation=[True] * 3, rinertia=[inertia] * 3, ext_torque=tau)
    q = s.part.add(pos=[2, 2, 2], rotation=[False] * 3, ext_torque=tau)  # does not rotate
    s.integrator.run(300)  # t = 3
    np.testing.assert_allclose(p.omega_lab, tau * 3.0 / inertia, rtol=1e-12)
    np.testing.assert_array_equal(q.omega_lab, [0.0, 0.0, 0.0])
    e = s.analysis.energy()
    assert e["kinetic_rotational"] == pytest.approx(
        0.5 * inertia * np.sum((tau * 3.0 / inertia) ** 2), rel=1e-12)


@skipIfMissingFeatures("EXTERNAL_FORCE")
def test_fix_keeps_coordinates():
    s = marble.System(box_l=[10.0] * 3, time_step=0.01)
    p = s.part.add(pos=[3.0, 3.0, 3.0], v=[1.0, 1.0, 1.0], ext_force=[1.0, 2.0, 3.0],
                   fix=[True, False, True])
    s.integrator.run(100)  # t = 1
    pos = p.pos
    assert pos[0] == 3.0 and pos[2] == 3.0
    assert pos[1] == pytest.approx(3.0 + 1.0 + 0.5 * 2.0)
    assert p.v[0] == 0.0 and p.v[2] == 0.0
    assert p.v[1] == pytest.approx(3.0)


def _random_positions(n, L, rng):
    return rng.uniform(0, L, size=(n, 3))


@skipIfMissingFeatures("LENNARD_JONES")
def test_steepest_descent_removes_overlaps():
    rng = np.random.default_rng(42)
    L = 6.0
    s = marble.System(box_l=[L] * 3, time_step=0.005)
    s.part.add(pos=_random_positions(150, L, rng))
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=2 ** (1 / 6),
                                                      shift="auto")
    assert s.analysis.min_dist() < 0.5  # a random configuration overlaps
    # the plain MD run blows up
    with pytest.raises(RuntimeError):
        s.integrator.run(10)
    s.integrator.set_steepest_descent(f_max=5.0, gamma=0.01, max_displacement=0.05)
    state = s.integrator.get_state()
    assert state == dict(name="SteepestDescent", f_max=5.0, gamma=0.01, max_displacement=0.05)
    e_before = s.analysis.energy()["non_bonded"]
    n = s.integrator.run(2000)
    assert 0 < n < 2000  # converged before the limit
    assert s.analysis.energy()["non_bonded"] < 1e-3 * e_before
    assert s.analysis.min_dist() > 0.85
    s.integrator.run(0)
    assert np.max(np.linalg.norm(s.part.all().f, axis=1)) < 5.0
    # now MD runs
    s.integrator.set_vv()
    s.integrator.run(100)
    assert np.all(np.isfinite(s.part.all().pos))


@skipIfMissingFeatures("LENNARD_JONES", "EXTERNAL_FORCE")
def test_steepest_descent_respects_fix_and_max_displacement():
    s = marble.System(box_l=[10.0] * 3, time_step=0.01)
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=2.5)
    a = s.part.add(pos=[5.0, 5.0, 5.0], fix=[True] * 3)
    b = s.part.add(pos=[5.8, 5.0, 5.0])
    s.integrator.set_steepest_descent(f_max=1e-6, gamma=0.01, max_displacement=0.01)
    assert s.integrator.run(1) == 1
    np.testing.assert_array_equal(a.pos, [5.0, 5.0, 5.0])
    np.testing.assert_allclose(b.pos, [5.81, 5.0, 5.0], rtol=1e-14)  # clipped step
    n = s.integrator.run(1000)
    assert n < 1000
    np.testing.assert_array_equal(a.pos, [5.0, 5.0, 5.0])
    assert b.pos[0] - 5.0 == pytest.approx(2 ** (1 / 6), abs=1e-6)  # LJ minimum


def _state(s):
    parts = s.part.all()
    return parts.id.copy(), parts.pos.copy(), parts.v.copy(), s.step, s.time


@skipIfMissingFeatures("LENNARD_JONES")
def test_overlap_blow_up_names_step_and_particle_and_recovers():
    s = marble.System(box_l=[8.0] * 3, time_step=0.005)
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=2.5, shift="auto")
    # a lattice with spacing 1.6 (no overlap) ...
    g = np.arange(5) * 1.6 + 0.3
    pos = np.array(np.meshgrid(g, g, g)).reshape(3, -1).T
    s.part.add(pos=pos, v=np.random.default_rng(1).normal(0, 0.5, pos.shape))
    s.integrator.run(50)
    # ... then a particle dropped almost on top of particle 62
    bad = s.part.add(pos=s.part.by_id(62).pos + [0.05, 0.0, 0.0], id=500)
    before = _state(s)
    with pytest.raises(RuntimeError) as err:
        s.integrator.run(100)
    msg = str(err.value)
    assert "step 51" in msg
    assert "particle 62" in msg or "particle 500" in msg
    # nothing moved, the counters did not advance, nothing is NaN
    after = _state(s)
    np.testing.assert_array_equal(after[0], before[0])
    np.testing.assert_allclose(after[1], before[1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(after[2], before[2], rtol=0, atol=1e-12)
    assert after[3:] == before[3:]
    assert np.all(np.isfinite(s.part.all().f))
    e = s.analysis.energy()
    assert np.isfinite(e["total"])
    # running again without fixing the cause fails the same way
    with pytest.raises(RuntimeError, match="step 51"):
        s.integrator.run(1)
    # remove the overlap: the run continues
    bad.remove()
    assert s.integrator.run(100) == 100
    assert s.step == 150
    assert np.all(np.isfinite(s.part.all().pos)) and np.all(np.isfinite(s.part.all().v))


def test_huge_time_step_blow_up_and_recover():
    s = marble.System(box_l=[10.0] * 3, time_step=0.01)
    s.cell_system.skin = 0.4
    p = s.part.add(pos=np.full((4, 3), 2.0) + np.arange(4)[:, None], v=[[0.1, 0, 0]] * 3 + [[2.0, 0, 0]])
    s.integrator.run(10)
    before = _state(s)
    s.time_step = 1.0  # particle 3 would move 2.0 > skin in one step
    with pytest.raises(RuntimeError) as err:
        s.integrator.run(10)
    msg = str(err.value)
    assert "step 11" in msg and "particle 3" in msg
    after = _state(s)
    np.testing.assert_allclose(after[1], before[1], atol=1e-12)
    np.testing.assert_allclose(after[2], before[2], atol=1e-12)
    assert after[3:] == before[3:]
    s.time_step = 0.01
    assert s.integrator.run(10) == 10
    assert s.step == 20
    np.testing.assert_allclose(p.pos[:, 0], before[1][:, 0] + 0.1 * before[2][:, 0], atol=1e-12)


@skipIfMissingFeatures("LENNARD_JONES")
def test_non_finite_force_fails_the_same_way_again():
    """A force that overflows (two particles 1e-30 apart under LJ) stops the run
    with the non-finite force message; the forces are marked invalid, so the
    next run recomputes them and stops with the same message (not a second,
    misleading one about velocities); separated, the particles run on."""
    s = marble.System(box_l=[5.0] * 3, time_step=0.01)
    s.cell_system.skin = 0.3
    s.part.add(pos=[[1.0, 1.0, 1e-30], [1.0, 1.0, 2e-30]])
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5)
    for _ in range(2):
        with pytest.raises(RuntimeError, match="non-finite force on particle 0 at step 0"):
            s.integrator.run(5)
        assert s.step == 0
        assert np.all(np.isfinite(s.part.all().pos)) and np.all(np.isfinite(s.part.all().v))
    s.part.by_id(1).pos = [2.2, 1.0, 0.0]
    assert s.integrator.run(5) == 5
    assert np.all(np.isfinite(s.part.all().f)) and np.all(np.isfinite(s.part.all().v))


@skipIfMissingFeatures("EXTERNAL_FORCE")
def test_no_silent_nan_from_overflowing_force():
    s = marble.System(box_l=[10.0] * 3, time_step=0.01)
    s.part.add(pos=[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]])
    p = s.part.by_id(1)
    p.ext_force = [1e308, 1e308, 0.0]  # finite, but the update overflows
    with pytest.raises(RuntimeError) as err:
        s.integrator.run(5)
    assert "particle 1" in str(err.value) and "step 1" in str(err.value)
    assert np.all(np.isfinite(s.part.all().pos)) and np.all(np.isfinite(s.part.all().v))
    p.ext_force = [0.0, 0.0, 0.0]
    s.integrator.run(5)
    assert s.step == 5
    assert np.all(np.isfinite(s.part.all().pos))


@skipIfMissingFeatures("DPD", "EXTERNAL_FORCE")
def test_setting_ext_force_between_runs_changes_nothing_else():
    """Re-setting ext_force (as reverse Poiseuille does) corrects the stored
    force in place: 200 x (set ext_force, run(1)) is bit-identical to run(200)
    with the same ext_force, and a new ext_force acts from the next half kick
    (momentum gain exactly N F t)."""
    def make():
        rng = np.random.default_rng(3)
        s = marble.System(box_l=[6.0] * 3, time_step=0.04)
        s.cell_system.skin = 0.4
        s.part.add(pos=rng.uniform(0, 6, (648, 3)), v=rng.normal(size=(648, 3)))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=3)
        s.integrator.run(1)
        return s
    a, b = make(), make()
    a.integrator.run(200)
    for _ in range(200):
        b.part.all().ext_force = np.zeros((648, 3))
        b.integrator.run(1)
    np.testing.assert_array_equal(a.part.all().pos, b.part.all().pos)
    np.testing.assert_array_equal(a.part.all().f, b.part.all().f)
    p0 = b.analysis.linear_momentum()
    b.part.all().ext_force = [0.1, 0.0, -0.05]
    b.integrator.run(50)
    np.testing.assert_allclose(b.analysis.linear_momentum() - p0,
                               648 * np.array([0.1, 0.0, -0.05]) * 50 * 0.04, rtol=1e-10, atol=1e-9)
