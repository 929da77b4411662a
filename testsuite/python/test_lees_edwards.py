"""Lees-Edwards boundary conditions (marble.lees_edwards, doc/lees-edwards.md).

(1) Kinematics: particles crossing the shear plane get the position jump
    -/+ pos_offset(t) and the velocity jump -/+ shear_velocity along the shear
    direction (read before and after the list rebuild that folds them); the
    forces, energy and virial of a soft pair potential over a random
    configuration equal an independent numpy sum over the Lees-Edwards
    minimum images, also after steps that move the images between rebuilds;
    the DPD friction of a pair across the plane sees the shear velocity jump.
(2) The sheared DPD fluid (viscosity) is test_lees_edwards_viscosity.py (long).
(3) Bad input and unsupported combinations are refused with clear errors.
"""
import pickle

import numpy as np
import pytest

import marble
import marble.lees_edwards as le

# the soft potential these tests use for a list range and for forces to compare
needs_hat = pytest.mark.skipif(not marble.has_features("HAT"), reason="needs the HAT feature")


def le_mi(d, L, off, s=0, n=1):
    """Lees-Edwards minimum image of d = a - b (image of b nearest to a)."""
    d = np.array(d, dtype=float)
    k = np.round(d[..., n] / L[n])
    d[..., n] -= k * L[n]
    d[..., s] -= k * off
    for i in range(3):
        if i != n:
            d[..., i] -= L[i] * np.round(d[..., i] / L[i])
    return d


# --- (1) kinematics ---------------------------------------------------------

@needs_hat
def test_crossing_jumps():
    L = np.array([5.0, 6.0, 7.0])
    s = marble.System(box_l=L)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    s.non_bonded_inter[1, 1].hat.set_params(F_max=1.0, cutoff=1.0)  # a list range; type 0 feels nothing
    up = s.part.add(pos=[2.0, 5.9, 3.0], v=[0.2, 1.0, 0.0])
    down = s.part.add(pos=[3.0, 0.05, 1.0], v=[0.0, -1.0, 0.3])
    proto = le.LinearShear(initial_pos_offset=1.3, shear_velocity=0.5, time_0=0.0)
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y", protocol=proto)
    assert s.lees_edwards.shear_direction == "x" and s.lees_edwards.shear_plane_normal == "y"
    assert s.lees_edwards.pos_offset == pytest.approx(1.3)
    assert s.lees_edwards.shear_velocity == pytest.approx(0.5)
    s.integrator.run(0)
    seen_rebuild = set()
    for n_steps in (15, 45):  # 15: crossed, not yet folded by a rebuild; 60: folded
        r0 = s._core.n_rebuilds()
        s.integrator.run(n_steps)
        seen_rebuild.add(s._core.n_rebuilds() > r0)
        t = s.time
        off = 1.3 + 0.5 * t
        assert s.lees_edwards.pos_offset == pytest.approx(off, abs=1e-12)
        exp_up = np.array([(2.0 + 0.2 * t - off) % L[0], 5.9 + t - L[1], 3.0])
        exp_down = np.array([(3.0 + off) % L[0], 0.05 - t + L[1], 1.0 + 0.3 * t])
        np.testing.assert_allclose(up.pos_folded, exp_up, atol=1e-9)
        np.testing.assert_allclose(down.pos_folded, exp_down, atol=1e-9)
        np.testing.assert_allclose(up.v, [0.2 - 0.5, 1.0, 0.0], atol=1e-12)
        np.testing.assert_allclose(down.v, [0.5, -1.0, 0.3], atol=1e-12)
    assert seen_rebuild == {False, True}  # both the pending-fold and the folded state were read
    # switching off keeps the particles where they are
    s.lees_edwards.protocol = None
    assert s.lees_edwards.protocol is None and s.lees_edwards.shear_direction is None
    assert s.lees_edwards.pos_offset == 0.0


@needs_hat
@pytest.mark.skipif(not marble.has_features("DPD"), reason="needs the DPD feature")
def test_net_normal_momentum_drifts_the_mean_flow():
    """A net momentum P_y normal to the shear plane (conserved) carries mass
    across the plane, and every crossing changes v_x by the shear velocity:
    P_x(T) - P_x(0) = -v_s (P_y T - sum m dy_folded) / L_y exactly (the net
    crossings), i.e. the mean flow drifts as -rate V_y T; the bias this puts
    into a sheared suspension's kinetic stress is doc/suspensions.md 7k."""
    L = np.array([5.0, 5.0, 5.0])
    s = marble.System(box_l=L)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(3)
    n = 375
    v = rng.normal(0.0, 1.0, (n, 3))
    v -= v.mean(axis=0)
    v[:, 1] += 0.4  # V_y = 0.4
    s.part.add(pos=rng.uniform(0, 1, (n, 3)) * L, v=v)
    s.non_bonded_inter[0, 0].hat.set_params(F_max=10.0, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=5)
    v_s = 0.3
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                           protocol=le.LinearShear(shear_velocity=v_s, time_0=0.0))
    p = s.part.all()
    P0, y0 = np.asarray(p.v).sum(axis=0), np.asarray(p.pos_folded)[:, 1]
    T = 20.0
    s.integrator.run(int(round(T / s.time_step)))
    P1, y1 = np.asarray(p.v).sum(axis=0), np.asarray(p.pos_folded)[:, 1]
    assert P1[1] == pytest.approx(P0[1], abs=1e-9)  # P_y conserved
    crossings = (P0[1] * T - np.sum(y1 - y0)) / L[1]
    assert abs(crossings - round(crossings)) < 1e-6  # an integer: the bookkeeping is exact
    assert crossings > 20  # the drift did cross (V_y T / L_y = 1.6 per particle)
    assert P1[0] - P0[0] == pytest.approx(-v_s * crossings, abs=1e-8)
    # the mean flow moved by about -rate V_y T = -0.48 (the rest: the folded positions' change)
    assert (P1[0] - P0[0]) / n == pytest.approx(-(v_s / L[1]) * 0.4 * T, abs=0.1)


def test_oscillatory_state():
    s = marble.System(box_l=[4.0, 4.0, 4.0])
    s.time = 0.7
    s.lees_edwards.set_boundary_conditions(
        shear_direction="z", shear_plane_normal="x",
        protocol=le.OscillatoryShear(initial_pos_offset=0.1, amplitude=0.3, omega=2.0, time_0=0.2))
    assert s.lees_edwards.pos_offset == pytest.approx(0.1 + 0.3 * np.sin(2.0 * 0.5))
    assert s.lees_edwards.shear_velocity == pytest.approx(0.3 * 2.0 * np.cos(2.0 * 0.5))
    p = s.lees_edwards.protocol
    assert isinstance(p, le.OscillatoryShear) and p.omega == 2.0 and p.amplitude == 0.3


def soft_scene(offset, shear_velocity=0.0, n=80, seed=5, L=(5.0, 6.0, 7.0), s_dir="x", n_dir="y"):
    rng = np.random.default_rng(seed)
    L = np.array(L)
    s = marble.System(box_l=L)
    s.time_step = 0.005
    s.cell_system.skin = 0.3
    s.part.add(pos=rng.uniform(0, 1, (n, 3)) * L, v=rng.normal(0, 0.5, (n, 3)))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=3.0, cutoff=1.4)
    s.lees_edwards.set_boundary_conditions(
        shear_direction=s_dir, shear_plane_normal=n_dir,
        protocol=le.LinearShear(initial_pos_offset=offset, shear_velocity=shear_velocity))
    return s


def numpy_hat(s, F_max=3.0, rc=1.4, s_dir=0, n_dir=1):
    """Forces, energy and virial of the hat potential over the LE minimum images."""
    L = np.asarray(s.box_l, dtype=float)
    x = np.asarray(s.part.all().pos_folded, dtype=float)
    off = s.lees_edwards.pos_offset
    d = le_mi(x[:, None, :] - x[None, :, :], L, off, s_dir, n_dir)
    r = np.linalg.norm(d, axis=2)
    np.fill_diagonal(r, np.inf)
    with np.errstate(invalid="ignore", divide="ignore"):
        w = np.where(r < rc, F_max * (1 - r / rc) / r, 0.0)  # F/r
    f = (w[:, :, None] * d).sum(axis=1)
    u = 0.5 * np.where(r < rc, 0.5 * F_max * rc * (1 - r / rc) ** 2, 0.0).sum()
    vir = 0.5 * np.einsum("ij,ija,ijb->ab", w, d, d) / np.prod(L)
    return f, u, vir


@needs_hat
@pytest.mark.parametrize("offset,axes", [(1.3, ("x", "y")), (101.77, ("x", "y")),
                                         (-2.45, ("z", "x")), (0.6, ("y", "z"))])
def test_forces_energy_virial_match_numpy(offset, axes):
    ax = {"x": 0, "y": 1, "z": 2}
    s = soft_scene(offset, shear_velocity=0.8, s_dir=axes[0], n_dir=axes[1])
    sd, nd = ax[axes[0]], ax[axes[1]]
    for n_steps in (0, 7, 40):  # 7: images moved by the offset without a rebuild
        s.integrator.run(n_steps)
        f, u, vir = numpy_hat(s, s_dir=sd, n_dir=nd)
        np.testing.assert_allclose(s.part.all().f, f, atol=1e-10)
        assert s.analysis.energy()["non_bonded"] == pytest.approx(u, abs=1e-10)
        np.testing.assert_allclose(s.analysis.pressure_tensor()["non_bonded"], vir, atol=1e-12)
    # the pair distance of the API
    p0, p1 = s.part.by_id(0), s.part.by_id(1)
    d = le_mi(np.asarray(p1.pos_folded) - np.asarray(p0.pos_folded), np.asarray(s.box_l),
              s.lees_edwards.pos_offset, sd, nd)
    np.testing.assert_allclose(s.distance_vec(p0, p1), d, atol=1e-12)


@needs_hat
def test_offset_drift_rebuilds_lists():
    """Particles held fixed, images moving 0.03 per step (shear velocity 6):
    only the offset drift can trigger the list rebuilds (every ~10 steps for
    skin 0.3); a list check without it would miss the pairs that the moving
    images bring into range."""
    s = soft_scene(0.2, shear_velocity=6.0)
    s.part.all().fix = [[True, True, True]] * len(s.part.all())
    s.integrator.run(0)
    r0 = s._core.n_rebuilds()
    for n_steps in (7, 40, 40):
        s.integrator.run(n_steps)
        f, u, vir = numpy_hat(s)
        np.testing.assert_allclose(s.part.all().f, f, atol=1e-10)
    assert s._core.n_rebuilds() - r0 >= 6


@needs_hat
def test_range_beyond_the_normal_box_length():
    """A box thinner along the normal (1.2) than the pair range (2 + skin): the
    lists hold images shifted by two box lengths along the normal, which move
    by twice the offset change; the list check must count that (with the
    single drift the forces were off by up to 0.04 F_max in the steps before a
    rebuild). Every step's forces equal a numpy sum over all images."""
    rng = np.random.default_rng(1)
    L = np.array([6.0, 1.2, 5.0])
    s = marble.System(box_l=L)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    n, rc, fm = 50, 2.0, 1e-9  # (F_max tiny: the particles barely move)
    s.part.add(pos=rng.uniform(0, 1, (n, 3)) * L, v=np.zeros((n, 3)))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=fm, cutoff=rc)
    s.lees_edwards.set_boundary_conditions(
        shear_direction="x", shear_plane_normal="y",
        protocol=le.LinearShear(initial_pos_offset=0.3, shear_velocity=4.0))
    worst = 0.0
    for _ in range(30):
        s.integrator.run(1)
        x = np.asarray(s.part.all().pos_folded)
        off = s.lees_edwards.pos_offset
        f = np.zeros((n, 3))
        for k in range(-3, 4):
            for m in range(-2, 3):
                for l in range(-1, 2):
                    d = x[:, None, :] - (x[None, :, :] + [k * off + m * L[0], k * L[1], l * L[2]])
                    r = np.linalg.norm(d, axis=2)
                    if k == 0 and m == 0 and l == 0:
                        np.fill_diagonal(r, np.inf)
                    with np.errstate(invalid="ignore"):  # (r = inf on the diagonal)
                        w = np.where(r < rc, fm * (1 - r / rc) / r, 0.0)
                    f += (w[:, :, None] * d).sum(axis=1)
        worst = max(worst, float(np.abs(np.asarray(s.part.all().f) - f).max() / fm))
    assert worst < 1e-9, worst


@needs_hat
@pytest.mark.parametrize("large", ["auto", [1], None])
def test_two_types_large_range(large):
    """Big particles (type 1, pair ranges 3.0 among them and 2.0 to the small
    ones) with the two-grid scheme of the cell system (large-range types) or
    without: forces equal the numpy sum over the Lees-Edwards minimum images."""
    rng = np.random.default_rng(8)
    L = np.array([7.0, 8.0, 7.5])
    s = marble.System(box_l=L)
    s.time_step = 0.002
    s.cell_system.skin = 0.3
    n_small, n_big = 150, 8
    s.part.add(pos=rng.uniform(0, 1, (n_small, 3)) * L, v=rng.normal(0, 0.5, (n_small, 3)))
    s.part.add(pos=rng.uniform(0, 1, (n_big, 3)) * L, v=rng.normal(0, 0.2, (n_big, 3)),
               type=[1] * n_big)
    cut = {(0, 0): (2.0, 1.0), (0, 1): (4.0, 2.0), (1, 1): (6.0, 3.0)}  # F_max, cutoff
    for (a, b), (fm, rc) in cut.items():
        s.non_bonded_inter[a, b].hat.set_params(F_max=fm, cutoff=rc)
    s.cell_system.large_range_types = large
    s.lees_edwards.set_boundary_conditions(
        shear_direction="z", shear_plane_normal="y",
        protocol=le.LinearShear(initial_pos_offset=3.1, shear_velocity=-0.9))
    types = np.array([0] * n_small + [1] * n_big)
    fm = np.array([[cut[(min(a, b), max(a, b))][0] for b in (0, 1)] for a in (0, 1)])[types[:, None], types[None, :]]
    rc = np.array([[cut[(min(a, b), max(a, b))][1] for b in (0, 1)] for a in (0, 1)])[types[:, None], types[None, :]]
    for n_steps in (0, 5, 60):
        s.integrator.run(n_steps)
        x = np.asarray(s.part.all().pos_folded, dtype=float)
        d = le_mi(x[:, None, :] - x[None, :, :], L, s.lees_edwards.pos_offset, 2, 1)
        r = np.linalg.norm(d, axis=2)
        np.fill_diagonal(r, np.inf)
        with np.errstate(invalid="ignore", divide="ignore"):
            w = np.where(r < rc, fm * (1 - r / rc) / r, 0.0)
        np.testing.assert_allclose(s.part.all().f, (w[:, :, None] * d).sum(axis=1), atol=1e-9)


def test_dpd_friction_sees_velocity_jump():
    """Two particles at rest on either side of the shear plane: the DPD
    friction (kT = 0) acts on the relative velocity v_a - (v_b + V e_x)."""
    L = np.array([6.0, 6.0, 6.0])
    s = marble.System(box_l=L)
    s.time_step = 0.01
    a = s.part.add(pos=[3.0, 5.8, 3.0], v=[0.0, 0.0, 0.0])
    b = s.part.add(pos=[2.9, 0.1, 3.1], v=[0.0, 0.0, 0.0])
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=0.0, seed=1)
    V, off = 0.7, 0.25
    s.lees_edwards.set_boundary_conditions(
        shear_direction="x", shear_plane_normal="y",
        protocol=le.LinearShear(initial_pos_offset=off, shear_velocity=V))
    s.integrator.run(0, recalc_forces=True)
    d = le_mi(np.asarray(a.pos_folded) - np.asarray(b.pos_folded), L, off)
    r = np.linalg.norm(d)
    e = d / r
    vij = np.zeros(3) - (np.zeros(3) + [V, 0.0, 0.0])
    f = -4.5 * (1 - r) ** 2 * np.dot(e, vij) * e
    np.testing.assert_allclose(a.f, f, atol=1e-12)
    np.testing.assert_allclose(b.f, -f, atol=1e-12)
    assert np.linalg.norm(f) > 0.01


def test_shardlow_pair_across_plane():
    """Shardlow sweep (kT = 0) of two particles at rest on either side of the
    shear plane: the relative velocity across the plane, v_a - (v_b + V e_x),
    changes along e by the exact OU factor exp(-gamma w^2 dt / mu) - 1, the
    change going to the owners (momentum conserved), nothing across e."""
    L = np.array([6.0, 6.0, 6.0])
    s = marble.System(box_l=L)
    dt, gamma, V, off = 0.01, 4.5, 0.7, 0.25
    s.time_step = dt
    a = s.part.add(pos=[3.0, 5.8, 3.0], v=[0.0, 0.0, 0.0])
    b = s.part.add(pos=[2.9, 0.1, 3.1], v=[0.0, 0.0, 0.0])
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=0.0, seed=1)
    s.integrator.set_shardlow()
    s.lees_edwards.set_boundary_conditions(
        shear_direction="x", shear_plane_normal="y",
        protocol=le.LinearShear(initial_pos_offset=off, shear_velocity=V))
    # at rest, no conservative force: one step moves nothing; the sweep sees
    # the offset of t = dt
    s.integrator.run(1)
    d = le_mi(np.asarray(a.pos_folded) - np.asarray(b.pos_folded), L, off + V * dt)
    r = np.linalg.norm(d)
    e = d / r
    u_rel = np.zeros(3) - (np.zeros(3) + [V, 0.0, 0.0])  # v_a - v_b across the plane
    mu = 0.5
    fac = np.exp(-gamma * (1 - r) ** 2 * dt / mu) - 1.0
    dv_a = mu * fac * np.dot(e, u_rel) * e  # / m_a = 1
    np.testing.assert_allclose(a.v, dv_a, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(b.v, -dv_a, rtol=1e-12, atol=1e-15)
    assert np.linalg.norm(dv_a) > 1e-3
    # further steps (the pair moves and shears apart): each sweep is the exact
    # update with the positions and the offset it sees (zero forces: the sweep
    # reads the drifted positions, the relative velocity of the step's start)
    for _ in range(5):
        va, vb = np.asarray(a.v), np.asarray(b.v)
        s.integrator.run(1)
        d = le_mi(np.asarray(a.pos_folded) - np.asarray(b.pos_folded), L, s.lees_edwards.pos_offset)
        r = np.linalg.norm(d)
        e = d / r
        fac = np.exp(-gamma * (1 - r) ** 2 * dt / mu) - 1.0
        dv_a = mu * fac * np.dot(e, va - vb - [V, 0.0, 0.0]) * e
        np.testing.assert_allclose(np.asarray(a.v) - va, dv_a, rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(np.asarray(b.v) - vb, -dv_a, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(np.asarray(a.v) + np.asarray(b.v), 0.0, atol=1e-14)


@pytest.mark.skipif(not marble.has_features("LUBRICATION", "TRANS_DPD", "ROTATION", "MASS"),
                    reason="needs LUBRICATION, TRANS_DPD, ROTATION, MASS")
def test_shardlow_kernels_across_plane_match_plain_pair():
    """Shardlow sweep (kT = 0) of a pair across the shear plane with DPD,
    lubrication and the stick surface friction (spins): identical to the same
    pair inside a plain periodic box where the partner carries the shear
    velocity jump explicitly (v_b + V e_x), over a few steps."""
    L = np.array([6.0, 6.0, 6.0])
    dt, V, off = 0.01, 0.7, 0.25
    xa, xb = np.array([3.0, 5.8, 3.0]), np.array([2.9, 0.1, 3.1])
    va, vb = np.array([0.1, -0.2, 0.05]), np.array([-0.3, 0.1, 0.2])
    wa, wb = np.array([0.3, 0.0, -0.4]), np.array([0.0, 0.5, 0.1])

    def scene(sheared):
        s = marble.System(box_l=L)
        s.time_step = dt
        if sheared:
            pa, pb = xa, xb
            vb_ = vb
        else:  # b's image across the plane, moved into the box with a
            pa = xa - [0.0, 2.0, 0.0]
            pb = xb + [off, L[1], 0.0] - [0.0, 2.0, 0.0]
            vb_ = vb + [V, 0.0, 0.0]
        a = s.part.add(pos=pa, v=va, type=1, mass=3.0, rotation=[True] * 3, rinertia=[2.0] * 3, omega_lab=wa)
        b = s.part.add(pos=pb, v=vb_, type=0, rotation=[True] * 3, rinertia=[0.7] * 3, omega_lab=wb)
        ia = s.non_bonded_inter[1, 0]
        ia.dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        ia.lubrication.set_params(eta=0.3, a1=0.2, a2=0.2, h_cut=0.8)
        ia.surface_friction.set_params(gamma=30.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=0.0, seed=1)
        s.integrator.set_shardlow()
        if sheared:
            s.lees_edwards.set_boundary_conditions(
                shear_direction="x", shear_plane_normal="y",
                protocol=le.LinearShear(initial_pos_offset=off, shear_velocity=V))
        s.integrator.run(3)
        return a, b

    a1, b1 = scene(True)
    a0, b0 = scene(False)
    np.testing.assert_allclose(a1.v, a0.v, rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(np.asarray(b1.v) + [V, 0.0, 0.0], b0.v, rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(a1.omega_lab, a0.omega_lab, rtol=1e-9, atol=1e-13)
    np.testing.assert_allclose(b1.omega_lab, b0.omega_lab, rtol=1e-9, atol=1e-13)
    assert np.linalg.norm(np.asarray(a1.v) - va) > 1e-2  # the pair did interact
    assert np.linalg.norm(np.asarray(a1.omega_lab) - wa) > 1e-3


@needs_hat
def test_checkpoint_keeps_state():
    s = soft_scene(1.3, shear_velocity=0.8)
    s.integrator.run(10)
    s2 = pickle.loads(pickle.dumps(s))
    assert s2.lees_edwards.protocol == s.lees_edwards.protocol
    assert s2.lees_edwards.pos_offset == s.lees_edwards.pos_offset
    assert s2.lees_edwards.shear_direction == "x"
    s.integrator.run(30)
    s2.integrator.run(30)
    # the lists of the restored system are rebuilt with the current offset:
    # the same physics up to the pair summation order
    np.testing.assert_allclose(s2.part.all().pos, s.part.all().pos, atol=1e-9)
    np.testing.assert_allclose(s2.part.all().v, s.part.all().v, atol=1e-9)


# --- (3) bad input ----------------------------------------------------------

def test_bad_input():
    s = marble.System(box_l=[5.0, 5.0, 5.0])
    bc = s.lees_edwards.set_boundary_conditions
    with pytest.raises(ValueError, match="shear_direction"):
        bc(shear_direction="w", shear_plane_normal="y", protocol=le.LinearShear())
    with pytest.raises(ValueError, match="shear_plane_normal"):
        bc(shear_direction="x", shear_plane_normal=3, protocol=le.LinearShear())
    with pytest.raises(ValueError, match="different axes"):
        bc(shear_direction="x", shear_plane_normal="x", protocol=le.LinearShear())
    with pytest.raises(ValueError, match="protocol"):
        bc(shear_direction="x", shear_plane_normal="y", protocol="linear")
    with pytest.raises(ValueError, match="shear_velocity"):
        le.LinearShear(shear_velocity=float("nan"))
    with pytest.raises(ValueError, match="omega"):
        le.OscillatoryShear(amplitude=1.0, omega="fast")
    with pytest.raises(ValueError, match="set the axes first"):
        s.lees_edwards.protocol = le.LinearShear(shear_velocity=0.1)
    assert s.lees_edwards.protocol is None
    s.periodicity = [True, False, True]
    with pytest.raises(ValueError, match="periodic"):
        bc(shear_direction="x", shear_plane_normal="y", protocol=le.LinearShear())
    s.periodicity = [True, True, True]
    # unsupported integrators are refused at run time, naming the reason
    s.part.add(pos=[1.0, 1.0, 1.0])
    s.time_step = 0.01
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=1.0, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=2)
    bc(shear_direction="x", shear_plane_normal="y", protocol=le.LinearShear(shear_velocity=0.1))
    s.integrator.set_brownian_dynamics()
    with pytest.raises(RuntimeError, match="Lees-Edwards.*Brownian"):
        s.integrator.run(1)
    s.integrator.set_shardlow()  # supported (test_shardlow_pair_across_plane; several ranks: test_lees_edwards_mpi.py)
    s.integrator.run(1)
    s.integrator.set_vv()
    s.integrator.run(1)
    # periodicity switched off after set_boundary_conditions: refused at run time
    s.periodicity = [True, False, True]
    with pytest.raises(RuntimeError, match="Lees-Edwards.*periodic"):
        s.integrator.run(1)


def test_refuses_marble_colloids_and_srd():
    s = marble.System(box_l=[8.0, 8.0, 8.0])
    s.time_step = 0.01
    rng = np.random.default_rng(3)
    s.part.add(pos=rng.uniform(0, 8, (300, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=1.0, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=2)
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                           protocol=le.LinearShear(shear_velocity=0.1))
    s.integrator.run(2)
    if marble.has_features("MARBLE"):
        from marble.colloids import add_marble
        add_marble(s, pos=[4.0, 4.0, 4.0], radius=1.5, gamma=5.0, coupling="dpd")
        with pytest.raises(RuntimeError, match="Lees-Edwards.*marble colloids"):
            s.integrator.run(1)
    if marble.has_features("SRD"):
        from marble import srd
        s2 = marble.System(box_l=[6.0, 6.0, 6.0], time_step=0.1)
        s2.srd = srd.SRDFluid(types=[0], cell_size=1.0, tau=0.1, angle=130, kT=1.0, seed=1)
        srd.add_fluid(s2, density=5, type=0, kT=1.0, seed=5)
        s2.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                                protocol=le.LinearShear(shear_velocity=0.1))
        with pytest.raises(RuntimeError, match="Lees-Edwards.*SRD"):
            s2.integrator.run(1)

