# labels: python long
"""A stick colloid (a = 2, M = 125, I = (2/5) M a^2) in the SRD fluid of
seed 003 (gamma = 5, alpha = 90 deg, tau = 0.1, L = 16): equipartition of V
and Omega within 3 % + 3 sigma; short-time friction, the initial decay rate
of the VACF / rotational VACF (one lag, error by a jackknife over 16 blocks),
within 5 % + 3 sigma of the kinetic theory of the rule: the `rough` rule
against seed 003's Enskog eqs. (5), (6) (zeta_V = 1.370, zeta_Omega = 0.761;
with the pair's effective masses 1.364, 0.746), the `stochastic` rule against
diffuse (Epstein) reflection (1.473, 1.306); the friction at the shortest lag
from the one-step velocity changes within 2 % + 3 sigma of the same values
at the free-volume density and the fluid's temperature (8 seeds: 0.994-0.999 +/-
0.002-0.005 of them; doc/srd.md "Short-time friction"). The slip rule exerts no
torque; total momentum is conserved by every rule; SRD particles are never
left inside. A light colloid (M = 20) is at kT with the default pair coupling
and ~20 % too warm with seed 003's literal rule; also in a walled channel
(bounce events with wall bounces)."""
import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("SRD", "ROTATION", "MASS"),
                                reason="missing feature SRD, ROTATION or MASS")

if marble.has_features("SRD"):
    import marble.srd as srd
    import marble.observables as obs
    import marble.accumulators as acc
    from marble.viscosity import block_average

L, A, M, DT = 16.0, 2.0, 125.0, 0.025
I = 0.4 * M * A ** 2


def make(rule, seed=8):
    s = marble.System(box_l=[L] * 3, time_step=DT)
    s.cell_system.skin = 0.5
    s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=1.0, seed=seed)
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=seed + 1)
    c = srd.add_colloid(s, pos=[L / 2] * 3, radius=A, mass=M, type=1, rule=rule)
    return s, c


def total_momentum(s, c):
    return s.srd.v.sum(axis=0) + M * np.asarray(c.v)


def min_dist(s, c):
    d = s.srd.pos - np.asarray(c.pos) % L
    d -= L * np.round(d / L)
    return np.min(np.linalg.norm(d, axis=1))


@pytest.mark.parametrize("rule", ["stochastic", "rough"])
def test_equipartition_and_short_time_friction(rule):
    s, c = make(rule)
    s.integrator.run(int(20 / DT))
    tv = acc.TimeSeries(obs=obs.ParticleVelocities(ids=[c.id], system=s), delta_N=1)
    tw = acc.TimeSeries(obs=obs.ParticleAngularVelocities(ids=[c.id], system=s), delta_N=1)
    s.auto_update_accumulators.add(tv)
    s.auto_update_accumulators.add(tw)
    s.integrator.run(int(600 / DT))
    V = np.array(tv.time_series()).reshape(-1, 3)
    W = np.array(tw.time_series()).reshape(-1, 3)
    theory = srd.kinetic_friction(A, M, 5.0, rule)
    # the one-step estimate is precise enough to see the fluid's actual state:
    # add_colloid moved the particles inside it to the free volume (density
    # 5 L^3 / (L^3 - 4 pi a^3 / 3), +0.8 %), and the temperature of the
    # unthermostatted fluid is that of its initial draw (+/- 0.6 % per seed)
    kT_f = float(np.mean(s.srd.v ** 2))
    rho_free = 5.0 * L ** 3 / (L ** 3 - 4.0 / 3.0 * np.pi * A ** 3)
    theory_free = srd.kinetic_friction(A, M, rho_free, rule, kT=kT_f)
    for k, (X, m) in enumerate(((V, M), (W, I))):
        e, err = block_average((m * X ** 2).mean(axis=1), min_blocks=16)
        z, zerr = srd.short_time_friction(X, DT)  # one lag: the initial rate
        z1, z1err = srd.one_step_friction(X, DT, m, kT=kT_f)
        print(f"{rule} {'VW'[k]}: <m x^2> = {e:.4f} +/- {err:.4f}, zeta = {z:.4f} +/- {zerr:.4f} "
              f"(theory {theory[k]:.4f}, Enskog {srd.enskog_friction(A, M, 5.0)[k]:.4f}), "
              f"one step {z1:.4f} +/- {z1err:.4f} (theory {theory_free[k]:.4f}, kT {kT_f:.4f})")
        assert abs(e - 1.0) < 0.03 + 3 * err
        # 8 seeds (doc/srd.md, "Short-time friction"): the one-lag rate is
        # 0.985-1.009 (+/- 0.008-0.017) of the kinetic value; the 8-lag fit
        # of the earlier versions measured the RVACF's mean decay over 0.2 t0,
        # 0.925 +/- 0.015 of it for the stochastic rule (memory of the fluid
        # next to the surface), hence its 10 % band then
        assert abs(z - theory[k]) < 0.05 * theory[k] + 3 * zerr
        # one step: 0.994-0.999 +/- 0.002-0.005 of theory_free over 8 seeds (scatter
        # between seeds 0.6-0.9 %, jackknife errors 0.5-0.9 %); 2 % covers
        # the 0.1-0.6 % offset and the O((zeta dt)^2) terms the exponential
        # inversion leaves; a 5 % error of a rule's friction fails it
        assert abs(z1 - theory_free[k]) < 0.02 * theory_free[k] + 3 * z1err
        if rule == "stochastic" and k == 1:
            # seed 003's Enskog value does not describe its own stochastic rule
            assert abs(z - srd.enskog_friction(A, M, 5.0)[1]) > 5 * zerr


@pytest.mark.parametrize("rule", ["stochastic", "rough", "bounce_back", "slip"])
def test_momentum_and_no_overlap(rule):
    s, c = make(rule, seed=21)
    c.v = [0.05, -0.02, 0.01]
    c.omega_lab = [0.01, 0.02, -0.03]
    assert min_dist(s, c) >= A  # moved out at insertion
    P0 = total_momentum(s, c)
    W0 = np.array(c.omega_lab)
    for _ in range(5):
        s.integrator.run(40)
        assert min_dist(s, c) >= A - 1e-12
    assert np.allclose(total_momentum(s, c), P0, rtol=0, atol=1e-9)
    if rule == "slip":
        # no torque: the impulse of a specular reflection is along the normal
        assert np.max(np.abs(np.array(c.omega_lab) - W0)) < 1e-13
    else:
        assert not np.allclose(np.array(c.omega_lab), W0)


def test_light_colloid_temperature():
    """doc/srd.md "Finite colloid mass": a = 1.5, M = 20, L = 10. The pair
    coupling (reduced-mass rule, bounces in the order of their crossing times
    within the step) keeps <M V^2>/3kT and <I Omega^2>/3kT at 1 within
    3 % + 3 sigma at dt = 0.025 and at the large dt = 0.05 (where detection
    after the step had +7 %); seed 003's literal rule (infinitely heavy
    surface, impulses at the end of the step) runs warm by more than 5 sigma
    (measured +24 % at dt = 0.05)."""
    a, M, Lb = 1.5, 20.0, 10.0
    I1 = 0.4 * M * a ** 2
    res = {}
    for coupling, dt, T in (("pair", 0.025, 600), ("pair", 0.05, 1600), ("seed003", 0.05, 300)):
        s = marble.System(box_l=[Lb] * 3, time_step=dt)
        s.cell_system.skin = 0.5
        s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=1.0, seed=5, thermostat="mbs")
        srd.add_fluid(s, density=5, type=0, kT=1.0, seed=6)
        c = srd.add_colloid(s, pos=[Lb / 2] * 3, radius=a, mass=M, type=1, coupling=coupling)
        s.integrator.run(int(20 / dt))
        every = int(round(0.25 / dt))
        tv = acc.TimeSeries(obs=obs.ParticleVelocities(ids=[c.id], system=s), delta_N=every)
        tw = acc.TimeSeries(obs=obs.ParticleAngularVelocities(ids=[c.id], system=s), delta_N=every)
        s.auto_update_accumulators.add(tv)
        s.auto_update_accumulators.add(tw)
        s.integrator.run(int(T / dt))
        V = np.array(tv.time_series()).reshape(-1, 3)
        W = np.array(tw.time_series()).reshape(-1, 3)
        res[coupling, dt] = (block_average((M * V ** 2).mean(axis=1), min_blocks=16),
                             block_average((I1 * W ** 2).mean(axis=1), min_blocks=16))
        print(coupling, dt, res[coupling, dt])
    for dt in (0.025, 0.05):
        for e, err in res["pair", dt]:
            assert abs(e - 1.0) < 0.03 + 3 * err
    # and tighter: detection after the step (the previous versions) gave
    # 1.072 +/- 0.014 for <M V^2>/3kT here, > 5 sigma outside this bound
    e, err = res["pair", 0.05][0]
    assert abs(e - 1.0) < 4 * err
    for e, err in res["seed003", 0.05]:
        assert e - 1.0 > 5 * err


def test_light_colloid_temperature_walled_channel():
    """doc/srd.md "Channel walls": the light colloid of the test above
    (a = 1.5, M = 20, dt = 0.05) in a channel between stochastic SRD walls
    at z = 0 and 10, kept >~ 1.5 a0 away from them by two WCA walls: the
    bounces are events together with the wall bounces, and <M V^2>/3kT is at
    1 within 4 sigma, both within 3 % + 3 sigma (measured 0.992 +/- 0.010,
    0.999 +/- 0.010; ~20 s). Detection after the step (the previous versions
    in walled channels) gives 1.084 +/- 0.011 here and fails both bounds
    (doc/srd.md: 1.06-1.09 in four runs of bench/srd_colloid_temperature.py
    --walls)."""
    from marble.shapes import Wall
    a, M, Lb, dt, T, gap = 1.5, 20.0, 10.0, 0.05, 2400, 1.5
    s = marble.System(box_l=[Lb] * 3, time_step=dt)
    s.cell_system.skin = 0.5
    s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=1.0, seed=5, thermostat="mbs",
                         wall_axis=2, wall_rule="stochastic")
    srd.add_fluid(s, density=5, type=0, kT=1.0, seed=6)
    c = srd.add_colloid(s, pos=[Lb / 2] * 3, radius=a, mass=M, type=1)
    zc = a + gap - 1.0  # WCA planes: the centre stays beyond ~0.95 of them
    for nrm, dist in (([0, 0, 1], zc), ([0, 0, -1], -(Lb - zc))):
        s.constraints.add(shape=Wall(normal=nrm, dist=dist), particle_type=2)
    s.non_bonded_inter[2, 1].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2 ** (1 / 6), shift="auto")
    s.integrator.run(int(20 / dt))
    every = int(round(0.25 / dt))
    tv = acc.TimeSeries(obs=obs.ParticleVelocities(ids=[c.id], system=s), delta_N=every)
    tw = acc.TimeSeries(obs=obs.ParticleAngularVelocities(ids=[c.id], system=s), delta_N=every)
    tx = acc.TimeSeries(obs=obs.ParticlePositions(ids=[c.id], system=s), delta_N=every)
    for t in (tv, tw, tx):
        s.auto_update_accumulators.add(t)
    s.integrator.run(int(T / dt))
    V = np.array(tv.time_series()).reshape(-1, 3)
    W = np.array(tw.time_series()).reshape(-1, 3)
    z = np.array(tx.time_series()).reshape(-1, 3)[:, 2]
    ev = block_average((M * V ** 2).mean(axis=1), min_blocks=16)
    ew = block_average((0.4 * M * a ** 2 * W ** 2).mean(axis=1), min_blocks=16)
    print("walled channel", ev, ew, "colloid z range", z.min(), z.max())
    # the colloid stayed away from the SRD walls, and it moved across the channel
    assert z.min() - a > 1.0 and Lb - z.max() - a > 1.0 and z.max() - z.min() > 1.0
    for e, err in (ev, ew):
        assert abs(e - 1.0) < 0.03 + 3 * err
    assert abs(ev[0] - 1.0) < 4 * ev[1]
