# labels: python
"""cell_system.list_check (doc/benchmarks.md, "The Verlet list's life"): with
"pairs" a Verlet list outlives the half-skin mark until a pair may be missing
from it. The forces it gives are those of a list built afresh at the current
positions, at every step of a run in which it was kept longer than the
half-skin rule would keep it (under velocity Verlet and under Shardlow, whose
sweep reads the same list); where the test does not apply it falls back to
the half-skin rule; bad values are refused."""
import pickle

import numpy as np
import pytest

import marble

needs_hat = pytest.mark.skipif(not marble.has_features("HAT"), reason="needs HAT")
needs_hat_dpd = pytest.mark.skipif(not marble.has_features("HAT", "DPD"), reason="needs HAT, DPD")
needs_marble_dpd = pytest.mark.skipif(not marble.has_features("MARBLE", "DPD"), reason="needs MARBLE, DPD")
# fluid(shardlow=False) needs HAT, fluid(shardlow=True) HAT and DPD
VV_AND_SHARDLOW = [pytest.param(False, marks=needs_hat, id="vv"),
                   pytest.param(True, marks=needs_hat_dpd, id="shardlow")]


def fluid(check, L=7.0, seed=3, shardlow=False):
    """A soft-sphere (hat, a = 25) fluid at rho = 3, kT about 1; the box is
    more than 3 pair ranges wide (the pair test applies). NVE, or with
    @p shardlow Groot-Warren water (DPD gamma = 4.5, kT = 1) under Shardlow at
    dt = 0.04 and skin 0.3, where the half-skin rule rebuilds at every step."""
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.04 if shardlow else 0.01
    s.cell_system.skin = 0.3 if shardlow else 0.4
    s.cell_system.list_check = check
    n = int(round(3 * L**3))
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    if shardlow:
        s.thermostat.set_dpd(kT=1.0, seed=seed)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.integrator.set_shardlow()
    s.integrator.run(30)
    return s


def copy_forces(s, fresh, keys=("f",)):
    """The arrays @p keys after a force pass on a copy of @p s (a checkpoint
    rebuilds its lists at their build's positions: the same lists), with
    @p fresh its lists built afresh at the current positions instead."""
    c = pickle.loads(pickle.dumps(s))
    if fresh:
        c.cell_system.skin = s.cell_system.skin
    c.integrator.run(0)
    return [np.array(getattr(c.part.all(), k)) for k in keys]


def kept_and_fresh_forces(s, steps):
    """Run @p s step by step; after each step its forces must be those of a
    list built afresh at the current positions. Returns the rebuilds."""
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    fmax = 0.0
    for _ in range(steps):
        s.integrator.run(1)
        f = np.array(s.part.all().f)
        np.testing.assert_allclose(copy_forces(s, fresh=True)[0], f, rtol=0, atol=1e-11)
        fmax = max(fmax, float(np.abs(f).max()))
    assert fmax > 1.0  # (the forces are not trivially zero)
    return s.cell_system.get_state()["verlet_rebuilds"] - r0


def rebuilds_of(s, steps):
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    s.integrator.run(steps)
    return s.cell_system.get_state()["verlet_rebuilds"] - r0


@needs_hat
def test_kept_lists_give_the_forces_of_fresh_lists():
    s = fluid("pairs")
    assert s.cell_system.get_state()["pair_test_applies"]
    kept = kept_and_fresh_forces(s, 40)
    # the same 40 steps under the half-skin rule rebuild more often: the
    # lists above were kept past half the skin
    h = fluid("half_skin")
    half = rebuilds_of(h, 40)
    assert kept < 0.85 * half, (kept, half)
    # NVE from the same start: both runs keep its total energy
    e_pairs, e_half = s.analysis.energy()["total"], h.analysis.energy()["total"]
    assert abs(e_pairs - e_half) < 1e-6 * abs(e_half), (e_pairs, e_half)


@needs_hat_dpd
def test_shardlow_keeps_lists_that_have_every_pair():
    """Shardlow (substeps 1, no colloids): its sweep reads the Verlet list the
    forces read, so a kept list must hold every pair in range at every step.
    At dt = 0.04 and skin 0.3 the half-skin rule rebuilds at (almost) every
    step; the pair test keeps about every list for a second step."""
    s = fluid("pairs", shardlow=True)
    assert s.cell_system.get_state()["pair_test_applies"]
    kept = kept_and_fresh_forces(s, 30)
    h = fluid("half_skin", shardlow=True)
    half = rebuilds_of(h, 30)
    assert kept < 0.75 * half, (kept, half)

    # the sweep on kept lists thermalises as on fresh ones: the kinetic kT
    # (1029 beads, 600 steps) of the two runs agrees within their errors
    # (both carry the same dt error of the conservative force's VV part)
    def kinetic_kt(sys_):
        sys_.integrator.run(50)
        kts = []
        for _ in range(60):
            sys_.integrator.run(10)
            v = np.array(sys_.part.all().v)
            kts.append(float(np.mean(np.sum(v * v, axis=1))) / 3.0)
        b = np.array(kts).reshape(6, 10).mean(axis=1)
        return float(b.mean()), float(b.std(ddof=1) / np.sqrt(len(b)))

    (m1, e1), (m2, e2) = kinetic_kt(s), kinetic_kt(h)
    assert max(e1, e2) < 0.01, (e1, e2)  # (so the test can fail)
    assert abs(m1 - m2) < 4 * np.hypot(e1, e2), (m1, e1, m2, e2)
    assert abs(m1 - 1.0) < 0.05, m1  # (the VV part's dt error at a = 25, dt = 0.04: ~2 %)


@pytest.mark.parametrize("integrator,substeps,dt,skin", [("vv", 1, 0.01, 0.3), ("shardlow", 1, 0.04, 0.3),
                                                         ("shardlow", 3, 0.06, 0.45)])
@needs_marble_dpd
def test_marble_scenes_keep_lists_that_have_every_pair(integrator, substeps, dt, skin):
    """A marble in the paper solvent (marble.colloid_runs.make_system; with 3
    RESPA substeps: Fig. 4's integrator at its dt), at skins where the
    half-skin rule rebuilds every 1-3 steps: the Verlet list and the
    colloid pair list built with it are kept past the half-skin mark while
    the pair test and the colloid list's criterion (d_max + d_colloid < skin)
    allow. After every step the forces and torques (the DPD pairs', the
    marble coupling's and its wall's) on the kept lists (a copy of the system
    whose lists are rebuilt at their build's positions, as a restart does)
    equal those on lists built afresh, and the lists are rebuilt less often
    than under the half-skin rule."""
    from marble.colloid_runs import make_system

    def scene(check):
        s, _, _ = make_system(7.0, 1.5, 2.0, 5, integrator=integrator, dt=dt, substeps=substeps, warmup=0.0,
                              skin=skin)
        s.cell_system.list_check = check
        s.integrator.run(20)
        return s

    s = scene("pairs")
    assert s.cell_system.get_state()["pair_test_applies"]
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    for _ in range(40):
        s.integrator.run(1)
        # the forces at the current velocities (the step's own were computed
        # at the half-step ones), on the kept lists and on fresh ones
        keys = ("f", "torque_lab")
        for key, got, want in zip(keys, copy_forces(s, False, keys), copy_forces(s, True, keys)):
            np.testing.assert_allclose(want, got, rtol=0, atol=1e-9, err_msg=key)
    kept = s.cell_system.get_state()["verlet_rebuilds"] - r0
    half = rebuilds_of(scene("half_skin"), 40)
    assert kept < 0.9 * half, (kept, half)


@needs_marble_dpd
def test_a_bead_closing_on_a_marble_is_found():
    """The colloid pair list's criterion: a marble (R = 1.5, coupling range
    R + r_cut = 2.5) moving 0.45 skins in one step and a bead 1.1 skins
    beyond that range flying at it by 0.75 skins: the pair comes into range
    without having been listed. The Verlet list's own hot-warm search cannot
    see it (the pair is farther apart than that list's cutoff), so only
    d_max + d_colloid >= skin can: one rebuild, and the forces of fresh
    lists."""
    from marble.colloid_runs import make_system
    skin, dt = 0.3, 0.01
    s, colloid, solvent = make_system(7.0, 1.5, 2.0, 5, integrator="vv", dt=dt, warmup=0.0, skin=skin)
    s.integrator.run(20)
    parts = s.part.all()
    parts.v = np.zeros((len(parts), 3))
    c = s.part.by_id(int(colloid.id))
    bead = s.part.by_id(int(np.asarray(solvent.id)[0]))  # moved to range + 1.1 skins on the +x side
    bead.pos = np.array(c.pos) + [2.5 + 1.1 * skin, 0.0, 0.0]
    c.v = [0.45 * skin / dt, 0.0, 0.0]
    bead.v = [-0.75 * skin / dt, 0.0, 0.0]
    s.cell_system.skin = skin  # lists built at these positions
    s.integrator.run(0)
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    s.integrator.run(1)
    d = np.linalg.norm(np.array(bead.pos) - np.array(c.pos))
    assert 2.4 < d < 2.5, d  # (in the coupling's range now)
    assert s.cell_system.get_state()["verlet_rebuilds"] == r0 + 1
    np.testing.assert_allclose(copy_forces(s, True)[0], copy_forces(s, False)[0], rtol=0, atol=1e-9)


@pytest.mark.parametrize("shardlow", VV_AND_SHARDLOW)
def test_a_pair_closing_in_one_step_is_found(shardlow):
    """Two particles a little more than the pair range apart at the list's
    build, flying at each other so that each moves between half a skin and a
    skin in one step: the pair is then within the cutoff but not in the list.
    Nothing else moves half a skin (the fluid starts at rest), so only the
    pair test's hot-warm search can find it: the list must be rebuilt and the
    forces must be those of a fresh list."""
    s = fluid("pairs", shardlow=shardlow)
    skin, dt = s.cell_system.skin, s.time_step
    parts = s.part.all()
    parts.v = np.zeros((len(parts), 3))
    if shardlow:
        s.thermostat.set_dpd(kT=0.0, seed=1)  # (no noise: nothing else gets hot)
    gap = 1.0 + 1.15 * skin  # apart by more than the range 1 + skin
    speed = 0.6 * skin / dt  # each moves 0.6 skins: both hot, the pair closes by 1.2 skins
    x0 = np.array([1.5, 2.5, 3.5])
    a, b = s.part.by_id(0), s.part.by_id(1)
    a.pos, a.v = x0, [speed, 0.0, 0.0]
    b.pos, b.v = x0 + [gap, 0.0, 0.0], [-speed, 0.0, 0.0]
    s.cell_system.skin = skin  # a list built at these positions
    s.integrator.run(0)
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    s.integrator.run(1)
    d = np.linalg.norm(np.array(s.part.by_id(0).pos) - np.array(s.part.by_id(1).pos))
    assert d < 1.0, d  # (the pair is in range now)
    assert s.cell_system.get_state()["verlet_rebuilds"] == r0 + 1  # found: rebuilt
    np.testing.assert_allclose(copy_forces(s, fresh=True)[0], np.array(s.part.all().f), rtol=0, atol=1e-11)


@needs_hat_dpd
def test_where_the_pair_test_does_not_apply():
    # a box under 3 pair ranges: the half-skin rule
    s = fluid("pairs", L=4.0)
    assert not s.cell_system.get_state()["pair_test_applies"]
    # Brownian dynamics keeps the half-skin rule
    s = fluid("pairs", shardlow=True)
    assert s.cell_system.get_state()["pair_test_applies"]
    s.integrator.set_shardlow(substeps=2)
    assert s.cell_system.get_state()["pair_test_applies"]
    s.integrator.set_brownian_dynamics()
    assert not s.cell_system.get_state()["pair_test_applies"]
    s.integrator.set_vv()
    assert s.cell_system.get_state()["pair_test_applies"]
    s.cell_system.list_check = "half_skin"
    assert not s.cell_system.get_state()["pair_test_applies"]


def test_bad_values_are_refused():
    s = marble.System(box_l=[8.0] * 3)
    assert s.cell_system.list_check == "pairs"
    for bad in ("exact", "", None, 0, True):
        with pytest.raises(ValueError, match="list_check"):
            s.cell_system.list_check = bad
        assert s.cell_system.list_check == "pairs"
    s.cell_system.list_check = "half_skin"
    assert s.cell_system.get_state()["list_check"] == "half_skin"


@pytest.mark.parametrize("shardlow", VV_AND_SHARDLOW)
def test_restart_continues_bit_for_bit(shardlow):
    """A checkpoint (pickle) taken at any step of a list's life, past the
    half-skin mark included, continues bit for bit: the test's decisions
    depend only on the saved positions and those at the list's build (and
    Shardlow's sweep, whose order is the list's, reads the list rebuilt at
    the build's positions)."""
    s = fluid("pairs", shardlow=shardlow)
    copies = []
    for _ in range(8):  # more than one list's life
        copies.append(pickle.dumps(s))
        s.integrator.run(1)
    s.integrator.run(30)
    want = {k: np.array(getattr(s.part.all(), k)) for k in ("id", "pos", "v", "f")}
    for k, blob in enumerate(copies):
        c = pickle.loads(blob)
        for _ in range(8 - k):
            c.integrator.run(1)
        c.integrator.run(30)
        for key, ref in want.items():
            assert np.array(getattr(c.part.all(), key)).tobytes() == ref.tobytes(), (k, key)
