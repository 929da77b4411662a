"""The marble coupling inside the Shardlow sweep (marble/Colloids.cpp,
shardlow_marble_sweep; doc/marble.md "Under Shardlow").

(a) exactness at kT = 0: after one step of a bead next to a rotating colloid (no
    other force), the bead's and the colloid's velocities and the colloid's spin
    are those of the exact Ornstein-Uhlenbeck decay of the contact velocity's
    normal and tangential parts, with their own reduced masses (an independent
    calculation here), for the three couplings; a fixed colloid acts as
    infinitely heavy.
(b) fluctuation-dissipation at a step where the explicit coupling is refused
    (gamma dt / m = 2 on a bead): the colloid's translational and rotational
    kinetic temperatures equal kT within 3 sigma of their blocking errors;
    total momentum is conserved with the noise on.
(c) velocity Verlet keeps the explicit coupling (the sweep is Shardlow's only).
"""
import math

import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("MARBLE", "DPD", "ROTATION"),
                                reason="needs MARBLE, DPD, ROTATION")

R, M, I = 2.0, 30.0, 40.0


def pair_scene(coupling, gamma=20.0, dt=0.05, fixed=False, kT=0.0, h=0.3):
    """One colloid at the centre (mass M, inertia I, spin (0, 0, 0.01)) and one bead
    at gap h along x with velocity (3e-3, 2e-3, -1e-3); Shardlow, thermostat kT."""
    s = marble.System(box_l=[10.0] * 3)
    s.time_step = dt
    s.cell_system.skin = 0.4
    c = s.part.add(pos=[5.0, 5.0, 5.0], type=1, mass=M, rinertia=[I] * 3, rotation=[True] * 3,
                   omega_lab=[0.0, 0.0, 0.01], v=[1e-3, 0.0, 0.0])
    if fixed:
        c.fix = [True] * 3
    b = s.part.add(pos=[5.0 + R + h, 5.0, 5.0], type=0, v=[3e-3, 2e-3, -1e-3])
    s.non_bonded_inter[1, 0].marble.set_params(radius=R, gamma=gamma, r_cut=1.0, coupling=coupling)
    s.thermostat.set_dpd(kT=kT, seed=3)
    s.integrator.set_shardlow()
    return s, c, b


def exact_update(coupling, gamma, dt, xb, xc, vb, vc, om, inv_M, inv_I):
    """The expected impulse on the bead: each part of u = v_b - (v_c + om x R n) decays
    by exp(-gamma w^2 dt / mu) with 1/mu = 1 + 1/M (normal), 1 + 1/M + R^2/I (tangential)."""
    d = xb - xc
    r = np.linalg.norm(d)
    n = d / r
    w = 1.0 - (r - R) / 1.0
    u = vb - (vc + np.cross(om, R * n))
    un = np.dot(n, u) * n
    ut = u - un
    J = np.zeros(3)
    if coupling != "transverse":
        imu = 1.0 + inv_M
        J += (math.exp(-gamma * w * w * dt * imu) - 1.0) * un / imu
    if coupling != "dpd":
        imu = 1.0 + inv_M + R * R * inv_I
        J += (math.exp(-gamma * w * w * dt * imu) - 1.0) * ut / imu
    return J, R * n


@pytest.mark.parametrize("coupling", ["tunable_slip", "transverse", "dpd"])
@pytest.mark.parametrize("fixed", [False, True])
def test_exact_pair_update(coupling, fixed):
    s, c, b = pair_scene(coupling, fixed=fixed)
    if fixed:
        c.v = [0.0, 0.0, 0.0]
    vb0, vc0, om0 = np.array(b.v), np.array(c.v), np.array(c.omega_lab)
    s.integrator.run(1)
    # no force acts before the sweep: the drift used the old velocities, the sweep the new positions
    xb, xc = np.array(b.pos), np.array(c.pos)
    np.testing.assert_allclose(xb, np.array([5.0 + R + 0.3, 5.0, 5.0]) + vb0 * 0.05, rtol=0, atol=1e-14)
    inv_M, inv_I = (0.0, 0.0) if fixed else (1.0 / M, 1.0 / I)
    J, rA = exact_update(coupling, 20.0, 0.05, xb, xc, vb0, vc0, om0, inv_M, inv_I)
    assert np.linalg.norm(J) > 1e-4  # a strong friction: the test can fail
    np.testing.assert_allclose(b.v, vb0 + J, rtol=0, atol=1e-15)
    np.testing.assert_allclose(c.v, vc0 - J * inv_M, rtol=0, atol=1e-15)
    # the colloid's spin by the torque rA x (-J); a fixed colloid keeps its spin
    np.testing.assert_allclose(c.omega_lab, om0 + inv_I * np.cross(rA, -J), rtol=0, atol=1e-15)
    if not fixed:  # the sweep conserves linear momentum
        np.testing.assert_allclose(np.array(b.v) + M * np.array(c.v), vb0 + M * vc0, rtol=0, atol=1e-15)


def test_no_coupling_beyond_the_shell():
    s, c, b = pair_scene("tunable_slip", h=1.05)
    vb0 = np.array(b.v)
    s.integrator.run(1)
    np.testing.assert_array_equal(b.v, vb0)


def test_velocity_verlet_keeps_the_explicit_coupling():
    """Under velocity Verlet the coupling is an explicit force: after one step the
    bead's velocity is not the exact OU update (the two differ at this gamma dt)."""
    s, c, b = pair_scene("tunable_slip", gamma=20.0, dt=0.02)
    vb0, vc0, om0 = np.array(b.v), np.array(c.v), np.array(c.omega_lab)
    s.integrator.set_vv()
    s.integrator.run(1)
    J, _ = exact_update("tunable_slip", 20.0, 0.02, np.array(b.pos), np.array(c.pos), vb0, vc0, om0,
                        1.0 / M, 1.0 / I)
    dv = np.array(b.v) - vb0
    assert np.linalg.norm(dv) > 1e-5
    assert np.linalg.norm(dv - J) > 1e-3 * np.linalg.norm(J)


def block_mean_err(x, nblocks=20):
    x = np.asarray(x)
    n = len(x) // nblocks * nblocks
    b = x[:n].reshape(nblocks, -1).mean(axis=1)
    return float(b.mean()), float(b.std(ddof=1) / math.sqrt(nblocks))


def test_equipartition_at_large_gamma_dt():
    """A marble (R = 1.5) in a DPD solvent (rho = 3, gamma = 4.5, no conservative
    forces but the wall) with marble gamma = 50 at dt = 0.04: nu = gamma dt / m = 2
    on the beads (velocity Verlet refuses this). The colloid's <M v^2>/3 within 3
    sigma of kT (1 - M/M_total) = 0.958 (the total momentum is fixed at zero, which
    takes the colloid's share M/M_total of one kT per axis: doc/suspensions.md 7c; the
    test compared with kT = 1 until session 15, whose round-off-level change of the
    Shardlow trajectories moved this seed's value to 0.945(17), 3.2 sigma below 1 and
    0.8 below 0.958) and <I w^2>/3 within 3 sigma of kT = 1 (the box does not conserve
    angular momentum), both within 6 % (the FDT of the exact update: an explicit
    coupling at this nu is far off); momentum conserved."""
    from marble.colloids import add_marble
    L, dt = 7.0, 0.04
    s = marble.System(box_l=[L] * 3)
    s.time_step = dt
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(11)
    n = int(3 * L ** 3)
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)), type=0)
    s.thermostat.set_dpd(kT=1.0, seed=11)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
    col = add_marble(s, pos=[L / 2] * 3, radius=1.5, gamma=50.0)
    s.integrator.set_vv()
    with pytest.raises(RuntimeError, match="explicit friction too stiff"):
        s.integrator.run(1)
    s.integrator.set_shardlow()
    p = s.part.all()
    m = np.asarray(p.mass)
    p.v = np.asarray(p.v) - np.sum(m[:, None] * np.asarray(p.v), axis=0) / m.sum()
    s.integrator.run(250)
    P0 = np.sum(m[:, None] * np.asarray(p.v), axis=0)
    Mc, Ic = float(col.mass), float(np.asarray(col.rinertia)[0])
    kt, kr = [], []
    for _ in range(3000):
        s.integrator.run(4)
        kt.append(Mc * np.dot(col.v, col.v) / 3.0)
        w = np.asarray(col.omega_lab)
        kr.append(Ic * np.dot(w, w) / 3.0)
    P1 = np.sum(m[:, None] * np.asarray(p.v), axis=0)
    np.testing.assert_allclose(P1, P0, rtol=0, atol=1e-9 * n)
    share = Mc / float(np.sum(m))
    for name, x, want in (("translation", kt, 1.0 - share), ("rotation", kr, 1.0)):
        mean, err = block_mean_err(x)
        assert abs(mean - want) < max(3 * err, 1e-3), f"{name}: {mean} +- {err}, expected {want}"
        assert err < 0.03, f"{name}: error {err} too large for the test to mean anything"
