# labels: python
"""SRD collision step (reference.md section 6, doc/srd.md): exact per-cell
conservation (checked in numpy on the unshifted grid, independently of the
core's sort), loop-order independence of the counter-based noise, relaxation
to a Maxwellian, the cell thermostat, and bad input (ValueError, nothing
changed)."""
import pickle

import numpy as np
import pytest
from scipy import stats

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("SRD"), reason="missing feature SRD")

if marble.has_features("SRD"):
    import marble.srd as srd


def make(L=6.0, density=5, dt=0.1, seed=3, **kw):
    s = marble.System(box_l=[L] * 3, time_step=dt)
    args = dict(types=[0], cell_size=1.0, tau=0.1, angle=130, kT=1.0, seed=seed)
    args.update(kw)
    s.srd = srd.SRDFluid(**args)
    srd.add_fluid(s, density=density, type=0, kT=1.0, seed=seed + 100)
    return s


def by_id(s):
    o = np.argsort(s.srd.ids)
    return s.srd.pos[o], s.srd.v[o]


def cell_sums(pos, v, L):
    """Per-cell momentum, kinetic energy and angular momentum about the cell
    centre of mass, on the unshifted grid of unit cells."""
    n = int(L)
    c = np.floor(pos).astype(int) % n
    g = (c[:, 0] * n + c[:, 1]) * n + c[:, 2]
    P = np.stack([np.bincount(g, v[:, d], n ** 3) for d in range(3)], axis=1)
    E = np.bincount(g, 0.5 * np.sum(v * v, axis=1), n ** 3)
    return g, P, E


def test_per_cell_conservation_srd_rule():
    for rule, kw in (("srd", {}), ("at", {}), ("at", {"conserve_angular": True})):
        s = make(shift=False, rule=rule, **kw)
        x0, v0 = by_id(s)
        g, P0, E0 = cell_sums(x0, v0, 6)
        s.srd.collide()
        x1, v1 = by_id(s)
        assert np.array_equal(x0, x1)
        _, P1, _E1 = cell_sums(x1, v1, 6)
        assert not np.allclose(v0, v1)
        scale = np.sqrt(np.sum(v0 ** 2) / len(v0))
        assert np.max(np.abs(P1 - P0)) < 1e-13 * scale * 20
        if rule == "srd":
            assert np.max(np.abs(_E1 - E0) / np.maximum(E0, 1e-300)) < 1e-13
        if kw.get("conserve_angular"):
            # angular momentum about the cell's centre of mass
            for cell in np.unique(g)[:50]:
                m = g == cell
                r = x0[m] - x0[m].mean(axis=0)
                L0 = np.sum(np.cross(r, v0[m]), axis=0)
                L1 = np.sum(np.cross(r, v1[m]), axis=0)
                assert np.allclose(L0, L1, atol=1e-12)


def test_shifted_collision_conserves_totals_and_energy_drift():
    s = make(L=8.0, angle=90)
    x, v = by_id(s)
    P0 = v.sum(axis=0)
    E0 = 0.5 * np.sum(v * v)
    s.integrator.run(100)  # 100 collisions (dt = tau), grid shift on
    assert s.srd.n_collisions == 100
    _, v = by_id(s)
    assert np.allclose(v.sum(axis=0), P0, atol=1e-10)
    drift = abs(0.5 * np.sum(v * v) - E0) / E0 / 100
    assert drift < 1e-10


def test_loop_order_independent():
    """The same states stored in reversed order collide to the same states
    (rule srd: axes keyed by cell, shift by collision), and two identical
    set-ups give bit-identical trajectories."""
    a = make(L=5.0)
    b = make(L=5.0)
    order = np.arange(a.srd.n)[::-1]
    b.srd.pos = a.srd.pos[order]
    b.srd.v = a.srd.v[order]
    a.integrator.run(10)
    b.integrator.run(10)

    def states(s):
        x, v = s.srd.pos, s.srd.v
        o = np.lexsort(x.T)
        return x[o], v[o]
    xa, va = states(a)
    xb, vb = states(b)
    assert np.allclose(xa, xb, rtol=0, atol=1e-12)
    assert np.allclose(va, vb, rtol=0, atol=1e-12)
    d = make(L=5.0)
    d.integrator.run(10)
    assert np.array_equal(by_id(a)[1], by_id(d)[1])


def test_maxwellian_after_50_collisions():
    s = make(L=10.0, angle=90, seed=11)
    n = s.srd.n
    rng = np.random.default_rng(5)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    v = np.sqrt(3.0) * u  # every speed sqrt(3 kT/m): far from Maxwellian
    v -= v.mean(axis=0)
    s.srd.v = v
    s.integrator.run(50)
    vx = s.srd.v.ravel()
    # Kolmogorov-Smirnov against N(0, kT/m) (the 3 components of a particle
    # are nearly independent; the test has margin: p > 1e-3)
    p = stats.kstest(vx, "norm").pvalue
    assert p > 1e-3, p
    # the initial shell fails the same test
    assert stats.kstest(v.ravel(), "norm").pvalue < 1e-10


def test_mbs_thermostat():
    s = make(L=8.0, angle=130, thermostat="mbs", seed=7)
    s.srd.v = 2.0 * s.srd.v  # kT = 4
    s.integrator.run(60)
    T = []
    for _ in range(40):
        s.integrator.run(5)
        v = s.srd.v
        T.append(np.mean(np.sum((v - v.mean(axis=0)) ** 2, axis=1)) / 3)
    T = np.array(T)
    err = T.std(ddof=1) / np.sqrt(len(T))
    # relative kinetic energy per cell has 3(n-1) dof: the mean over all
    # particles is kT (1 - <1/n>-ish); compare with the exact expectation
    n = s.srd.n
    assert abs(T.mean() - 1.0) < 0.02 + 4 * err


def test_bad_input_changes_nothing():
    s = marble.System(box_l=[6.0] * 3, time_step=0.03)
    with pytest.raises(ValueError, match="tau"):
        s.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1)
    assert s.srd is None and not s._core.srd_active()
    s.time_step = 0.05
    with pytest.raises(ValueError, match="cell_size"):
        s.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1, cell_size=0.7)
    with pytest.raises(ValueError, match="angle"):
        s.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1, angle=-10)
    with pytest.raises(ValueError, match="rule"):
        s.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1, rule="xyz")
    with pytest.raises(ValueError, match="unknown"):
        srd.SRDFluid(types=[0], tau=0.1, seed=1, foo=2)
    assert not s._core.srd_active()
    s.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1)
    with pytest.raises(ValueError, match="density"):
        srd.add_fluid(s, density=-1, type=0)
    assert s.srd.n == 0
    srd.add_fluid(s, density=2, type=0, seed=1)
    n = s.srd.n
    with pytest.raises(ValueError, match="radius"):
        srd.boundary(s, 1, 0).set_params(radius=-1.0)
    with pytest.raises(ValueError, match="rule"):
        srd.boundary(s, 1, 0).set_params(radius=1.0, rule="sticky")
    assert srd.boundary(s, 1, 0).get_params() == {}
    # an SRD type with a pair interaction
    if marble.has_features("LENNARD_JONES"):
        s2 = marble.System(box_l=[6.0] * 3, time_step=0.05)
        s2.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=1.12, shift="auto")
        with pytest.raises(ValueError, match="pair interaction"):
            s2.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1)
        assert s2.srd is None
    # MD particles of an SRD type
    s3 = marble.System(box_l=[6.0] * 3, time_step=0.05)
    s3.part.add(pos=[1, 1, 1], type=0)
    with pytest.raises(ValueError, match="MD particles"):
        s3.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1)
    # a time step changed later: a RuntimeError at run naming the cause
    s.time_step = 0.03
    with pytest.raises(RuntimeError, match="tau"):
        s.integrator.run(1)
    assert s.srd.n == n
    s.time_step = 0.05
    # a pair interaction set on the SRD type after the fluid was created
    if marble.has_features("LENNARD_JONES"):
        s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=1.12, shift="auto")
        with pytest.raises(RuntimeError, match="pair interaction"):
            s.integrator.run(1)
        s.non_bonded_inter[0, 0].lennard_jones.deactivate()
    assert s.srd.n_collisions == 0
    s.integrator.run(4)
    assert s.srd.n_collisions == 2


@pytest.mark.skipif(not marble.has_features("SRD", "ROTATION", "MASS"), reason="missing ROTATION or MASS")
@pytest.mark.parametrize("walls", [False, True])
def test_add_fluid_at_free_volume_density(walls):
    """volume="free": the colloids added first are subtracted, so the free
    volume holds the density exactly (counted here from the particles outside
    the spheres, independently of the volume sum); "box" overfills it by the
    displaced particles; a bad value changes nothing."""
    L, rho, radii = 12.0, 5.0, {1: 2.0, 2: 1.5}
    counts = {}
    for volume in ("box", "free"):
        s = marble.System(box_l=[L] * 3, time_step=0.1)
        kw = dict(wall_axis=2, wall_positions=(1.0, 11.0)) if walls else {}
        s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=1.0, seed=5, **kw)
        centres = {1: [[3.0, 3.0, 6.0]], 2: [[8.0, 8.0, 4.0], [8.0, 3.0, 8.0]]}
        for t, cs in centres.items():
            for c in cs:
                srd.add_colloid(s, pos=c, radius=radii[t], type=t)
        if volume == "free":
            with pytest.raises(ValueError, match="volume"):
                srd.add_fluid(s, density=rho, type=0, volume="shell")
            assert s.srd.n == 0
        n = srd.add_fluid(s, density=rho, type=0, seed=6, volume=volume)
        assert s.srd.n == n
        inside = 0
        for t, cs in centres.items():
            for c in cs:
                d = s.srd.pos - np.asarray(c)
                d -= L * np.round(d / L)
                inside += np.sum(np.linalg.norm(d, axis=1) < radii[t])
        assert inside == 0
        counts[volume] = n
    height = 10.0 if walls else L
    v_free = L * L * height - 4.0 / 3.0 * np.pi * (2.0 ** 3 + 2 * 1.5 ** 3)
    assert counts["free"] == round(rho * v_free)
    assert counts["box"] == round(rho * L * L * height)


def test_theory_numbers():
    assert abs(srd.eta(5, 90, 0.1) - 2.496) < 5e-4
    assert abs(srd.eta(5, 130, 0.1) - 3.961) < 5e-4
    assert abs(srd.nu_kin(5, 90, 0.1) - 0.0540) < 5e-5
    assert abs(srd.nu_col(5, 90, 0.1) - 0.4452) < 5e-5
    zv, zo = srd.enskog_friction(2.0, 125.0, 5.0)
    assert abs(zv - 1.370) < 5e-4 and abs(zo - 0.761) < 5e-4
    assert abs(zv / zo - 9 / 5) < 1e-12
    assert abs(srd.D_f(5, 90, 0.1) - 0.137) < 5e-4
    assert abs(srd.schmidt(5, 90, 0.1) - 3.6) < 0.05


@pytest.mark.skipif(not marble.has_features("ROTATION", "MASS"), reason="needs ROTATION, MASS")
def test_checkpoint_bit_exact_continuation():
    """A pickled system (fluid, colloid, boundary, thermostat, drive) continues
    bit for bit."""
    s = make(L=8.0, dt=0.025, thermostat="mbs")
    s.cell_system.skin = 0.5
    c = srd.add_colloid(s, pos=[4.0, 4.0, 4.0], radius=1.5, mass=50.0, type=1, rule="stochastic")
    c.ext_force = [0.5, 0.0, 0.0]
    s.srd.acceleration = [-0.5 / s.srd.n, 0.0, 0.0]
    s.integrator.run(22)
    blob = pickle.dumps(s)
    s.integrator.run(30)
    r = pickle.loads(blob)
    assert r.srd.n_collisions == 5 and r.srd.get_params()["thermostat"] == "mbs"
    assert np.array_equal(r.srd.acceleration, s.srd.acceleration)
    assert srd.boundary(r, 1, 0).get_params() == srd.boundary(s, 1, 0).get_params()
    r.integrator.run(30)
    assert np.array_equal(r.srd.pos, s.srd.pos) and np.array_equal(r.srd.v, s.srd.v)
    assert np.array_equal(r.srd.ids, s.srd.ids)
    rc = r.part.by_id(c.id)
    assert np.array_equal(rc.v, c.v) and np.array_equal(rc.omega_lab, c.omega_lab)
    assert np.array_equal(rc.pos, c.pos)


@pytest.mark.skipif(not marble.has_features("ROTATION", "MASS"), reason="needs ROTATION, MASS")
@pytest.mark.parametrize("walls", [False, True])
@pytest.mark.parametrize("rule", ["bounce_back", "slip"])
def test_pair_coupling_conserves_energy(rule, walls):
    """The deterministic rules act on the pair (particle, colloid) with its
    effective masses (coupling "pair", doc/srd.md "Finite colloid mass"): the
    total kinetic energy (fluid, colloid V and Omega) is conserved to
    round-off through streaming and collisions (rule srd, no thermostat). In
    the frame of an infinitely heavy surface ("seed003") the colloid's recoil
    adds energy at every bounce. Also in a channel between slip walls at rest,
    the colloid 0.3 from the lower one (wall bounces as events)."""
    drift = {}
    for coupling in ("pair", "seed003"):
        s = make(L=8.0, dt=0.025, **(dict(wall_axis=2, wall_rule="slip") if walls else {}))
        s.cell_system.skin = 0.5
        c = srd.add_colloid(s, pos=[4.0, 4.0, 1.8 if walls else 4.0], radius=1.5, mass=10.0, type=1, rule=rule,
                            v=(0.3, -0.1, 0.2), coupling=coupling)
        c.omega_lab = [0.2, -0.3, 0.1]
        I = 0.4 * 10.0 * 1.5 ** 2

        def energy():
            return (0.5 * np.sum(s.srd.v ** 2) + 0.5 * 10.0 * np.sum(np.asarray(c.v) ** 2)
                    + 0.5 * I * np.sum(np.asarray(c.omega_lab) ** 2))
        E0 = energy()
        s.integrator.run(200)
        assert np.abs(s.srd.momentum_to_colloids()).max() > 1.0  # the colloid was hit
        drift[coupling] = abs(energy() - E0) / E0
    print(drift)
    assert drift["pair"] < 1e-12, drift
    assert drift["seed003"] > 1e-6, drift


def _slip_flight(x, v, t, centre, a):
    """Specular flight of a point between the plane z = 0 and a fixed sphere
    (numpy, independent of the core): returns the position and velocity after
    time t and the times of the wall and sphere hits, in their order."""
    x, v, hits = np.array(x, float), np.array(v, float), []
    t_now = 0.0
    while True:
        tw = -x[2] / v[2] if v[2] < 0 else np.inf
        d = x - centre
        b, c = d @ v, d @ d - a * a
        disc = b * b - (v @ v) * c
        ts = (-b - np.sqrt(disc)) / (v @ v) if b < 0 and disc > 0 else np.inf
        t_hit = min(tw, ts)
        if t_now + t_hit > t:
            return x + (t - t_now) * v, v, hits
        x, t_now = x + t_hit * v, t_now + t_hit
        nrm = np.array([0.0, 0.0, 1.0]) if tw < ts else (x - centre) / a
        v = v - 2 * (v @ nrm) * nrm
        hits.append(("wall" if tw < ts else "sphere", t_now))


def _one_particle_step(s, x0, v0):
    """Put SRD particle 0 at x0 with velocity v0 and the others at rest, parked
    on a line at (7.5, 7.5, 6-7) out of the way; run one step; return that
    particle's position and velocity."""
    n = len(s.srd.ids)
    pos = np.tile([7.5, 7.5, 6.0], (n, 1)) + np.linspace(0, 1, n)[:, None] * [0, 0, 1]
    vel = np.zeros((n, 3))
    pos[0], vel[0] = x0, v0
    s.srd.pos, s.srd.v = pos, vel
    pid = s.srd.ids[0]
    s.integrator.run(1)
    k = int(np.flatnonzero(s.srd.ids == pid)[0])
    return s.srd.pos[k], s.srd.v[k]

@pytest.mark.skipif(not marble.has_features("ROTATION", "MASS"), reason="needs ROTATION, MASS")
@pytest.mark.parametrize("reverse", [False, True])
def test_walled_channel_bounces_in_time_order(reverse):
    """A walled channel with a colloid (coupling pair, doc/srd.md "Channel
    walls"): a particle that hits a slip wall and then a (very heavy) slip
    colloid within one MD step, or the colloid and then the wall (the
    time-reversed path), is reflected at both in the order of the hits and
    ends where the exact specular flight (numpy) puts it. Detection after the
    step (the previous versions in walled channels) found it inside the
    colloid and put it elsewhere (0.30 and 7.7 away in the two cases)."""
    dt, a, centre = 0.1, 1.5, np.array([4.0, 4.0, 1.6])
    x0, v0 = np.array([2.3, 4.0, 0.3]), np.array([10.0, 0.0, -10.0])
    x1, v1, hits = _slip_flight(x0, v0, dt, centre, a)
    assert [h[0] for h in hits] == ["wall", "sphere"] and hits[1][1] < dt
    if reverse:  # the time-reversed path: sphere first, then the wall
        x0, v0, x1, v1 = x1, -v1, x0, -v0
    s = make(L=8.0, dt=dt, tau=1.0, wall_axis=2, wall_rule="slip")
    s.cell_system.skin = 0.5
    c = srd.add_colloid(s, pos=list(centre), radius=a, mass=1e9, type=1, rule="slip")
    x, v = _one_particle_step(s, x0, v0)
    np.testing.assert_allclose(x, x1, atol=1e-6)
    np.testing.assert_allclose(v, v1, atol=1e-6)
    assert np.abs(np.asarray(c.v)).max() < 1e-6


@pytest.mark.skipif(not marble.has_features("ROTATION", "MASS"), reason="needs ROTATION, MASS")
@pytest.mark.parametrize("coupling", ["fixed_surface", "seed003"])
@pytest.mark.parametrize("wall_rule", ["slip", "stochastic"])
def test_end_of_step_bounce_respects_walls(coupling, wall_rule):
    """The end-of-step colloid rule (the couplings fixed_surface and seed003,
    and the pair coupling's fallback for a particle the events did not
    foresee; doc/srd.md) puts a particle found inside a colloid onto its
    surface and streams it half a step with the new velocity. Next to a wall
    that half step may cross the wall: the particle must then be reflected by
    the wall rule, not left outside the channel (before: it ended at
    z = -0.05, folded to the far side of the box, z = 7.95). A slip colloid
    0.05 above the lower wall; one particle that enters it from below."""
    dt, a, L = 0.1, 1.5, 8.0
    centre = np.array([4.0, 4.0, 1.55])
    x0, v0 = np.array([3.9, 4.0, 0.02]), np.array([1.0, 0.0, 2.0])
    s = make(L=L, dt=dt, tau=1.0, wall_axis=2, wall_rule=wall_rule)
    s.cell_system.skin = 0.5
    c = srd.add_colloid(s, pos=list(centre), radius=a, mass=1e9, type=1, rule="slip", coupling=coupling)
    x1, v1 = _one_particle_step(s, x0, v0)
    # seed 003's rule in numpy: half a step back, radially onto the surface,
    # specular (slip) about the normal, half a step on: that crosses z = 0
    d = x0 + dt * v0 - centre - 0.5 * dt * v0
    nrm = d / np.linalg.norm(d)
    contact = centre + a * nrm
    vn = v0 - 2 * (v0 @ nrm) * nrm
    assert contact[2] + 0.5 * dt * vn[2] < 0  # the scene does test the wall
    assert 0.0 <= x1[2] < 0.5  # in the channel, near the lower wall
    lo, hi = map(np.asarray, s.srd.momentum_to_walls())
    assert lo[2] < 0 and np.linalg.norm(hi) == 0  # the particle was pushed off the lower wall
    assert v1[2] > 0
    if wall_rule == "slip":  # the exact flight: the rest of the half step mirrored at z = 0
        t_w = -contact[2] / vn[2]
        xw = contact + t_w * vn
        vr = vn * [1, 1, -1]
        np.testing.assert_allclose(x1, xw + (0.5 * dt - t_w) * vr, atol=1e-12)
        np.testing.assert_allclose(v1, vr, atol=1e-12)
        np.testing.assert_allclose(lo, [0, 0, 2 * vn[2]], atol=1e-12)
    # momentum: particle + wall + colloid
    P = v1 + lo + hi + np.asarray(s.srd.momentum_to_colloids())
    np.testing.assert_allclose(P, v0, atol=1e-9)


@pytest.mark.parametrize("rule", ["stochastic", "bounce_back", "slip"])
def test_walls_confine_and_conserve_momentum(rule):
    s = make(L=6.0, wall_axis=1, wall_rule=rule, wall_velocity_lo=[0.3, 0, 0.1],
             wall_velocity_hi=[-0.2, 0, 0])
    P0 = s.srd.v.sum(axis=0)
    s.integrator.run(50)
    y = s.srd.pos[:, 1]
    assert y.min() >= 0 and y.max() < 6.0
    lo, hi = s.srd.momentum_to_walls()
    assert np.linalg.norm(lo) > 0 and np.linalg.norm(hi) > 0
    assert np.allclose(s.srd.v.sum(axis=0) + lo + hi, P0, rtol=0, atol=1e-9)
    with pytest.raises(ValueError, match="tangential"):
        make(L=6.0, wall_axis=1, wall_velocity_lo=[0, 1, 0])
    with pytest.raises(ValueError, match="wall_axis"):
        make(L=6.0, wall_rule="slip")


@pytest.mark.skipif(not marble.has_features("ROTATION", "MASS"), reason="needs ROTATION, MASS")
@pytest.mark.parametrize("walls", [False, True])
def test_colloid_search_by_cells_equals_full_search(walls):
    """The colloids find their SRD particles through the collision cells of
    the last collision (doc/srd.md); forgetting that index before every step
    (a full search of all particles) must give the same trajectory, bit for
    bit: two colloids (stick and slip), a drive, optionally stochastic walls."""
    kw = dict(wall_axis=2, wall_rule="stochastic", wall_velocity_lo=[0.3, 0, 0]) if walls else {}
    runs = []
    for full in (False, True):
        s = make(L=8.0, dt=0.025, **kw)
        s.cell_system.skin = 0.5
        a = srd.add_colloid(s, pos=[2.0, 4.0, 4.0], radius=1.5, mass=40.0, type=1, v=(0.4, 0.1, 0))
        b = srd.add_colloid(s, pos=[6.0, 4.0, 4.0], radius=1.2, mass=30.0, type=2, rule="slip",
                            v=(-0.2, 0, 0.3))
        s.srd.acceleration = [0.05, 0.0, 0.0]
        for _ in range(60):
            if full:
                s.srd.v = s.srd.v  # invalidates the cell index: full search this step
            s.integrator.run(1)
        runs.append((s.srd.pos, s.srd.v, np.array(a.v), np.array(a.omega_lab), np.array(b.v),
                     np.array(s.srd.momentum_to_colloids())))
    assert np.abs(runs[0][5]).max() > 0.5  # the colloids were hit
    for x, y in zip(*runs):
        np.testing.assert_array_equal(x, y)


def test_walls_inside_the_box():
    """Walls anywhere along the axis (wall_positions): the particles stay in
    [lo, hi), add_fluid fills the channel at the given density, momentum is
    conserved with the walls' share, the Couette profile follows the walls;
    walls at (0, L) given explicitly change nothing (bit for bit)."""
    lo, hi = 1.5, 6.5
    s = make(L=8.0, dt=0.05, density=0, wall_axis=2, wall_rule="stochastic", wall_positions=(lo, hi),
             wall_velocity_lo=[-0.5, 0, 0], wall_velocity_hi=[0.5, 0, 0])
    assert s.srd.get_params()["wall_positions"] == (lo, hi)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=7)
    assert s.srd.n == int(round(5 * 8 * 8 * (hi - lo)))
    z = s.srd.pos[:, 2]
    assert z.min() >= lo and z.max() < hi
    P0 = s.srd.v.sum(axis=0)
    s.integrator.run(400)
    z = s.srd.pos[:, 2]
    assert z.min() >= lo and z.max() < hi
    wlo, whi = s.srd.momentum_to_walls()
    assert np.allclose(s.srd.v.sum(axis=0) + wlo + whi, P0, rtol=0, atol=1e-8)
    # steady Couette flow: vx rises from the lower to the upper wall
    vx, zs = s.srd.v[:, 0], s.srd.pos[:, 2]
    third = (hi - lo) / 3
    v_low = vx[zs < lo + third].mean()
    v_high = vx[zs >= hi - third].mean()
    assert v_low < -0.15 and v_high > 0.15, (v_low, v_high)
    runs = []
    for extra in ({}, {"wall_positions": (0.0, 6.0)}):
        r = make(L=6.0, wall_axis=1, wall_rule="stochastic", **extra)
        r.integrator.run(20)
        runs.append(by_id(r))
    for x, y in zip(*runs):
        np.testing.assert_array_equal(x, y)
    for bad in ((2.0, 1.0), (-1.0, 4.0), (1.0, 9.0), (1.0, 1.5), (1.0,)):
        with pytest.raises(ValueError, match="wall_positions"):
            make(L=8.0, wall_axis=2, wall_positions=bad)
    with pytest.raises(ValueError, match="wall_positions"):
        make(L=8.0, wall_positions=(1.0, 2.0))


@pytest.mark.parametrize("bad", [2.0e6, -5.0e7])
def test_blow_up_stops_with_runtime_error(bad):
    """The cell sums are exact only for |v| < 2^20 (doc/srd.md, "Exact cell
    sums"): an absurd SRD velocity (the setter already refuses NaN) stops the run with a
    RuntimeError naming the collision, never a silent NaN."""
    s = make()
    v = s.srd.v
    v[7, 1] = bad
    s.srd.v = v
    with pytest.raises(RuntimeError, match="SRD collision"):
        s.integrator.run(1)
