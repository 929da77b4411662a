# labels: python
"""The dissipative parts of analysis.pressure_tensor() (doc/dpd.md): 'dpd'
(DPD pair friction + noise of the main list and the colloid pairs) and
'marble' (the marble surface coupling), each (1/V) sum d (x) F, against an
independent numpy computation at kT = 0 (friction only, every pair by
minimum image); 'total' stays kinetic + non_bonded; with noise, the main-list
part equals dpd_stress_split()['total']."""
import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("DPD"), reason="missing feature DPD")


def mi(d, L):
    return d - L * np.round(d / L)


def dpd_friction_virial(pos, v, L, gamma, r_cut, types=None, pair_types=None):
    """sum_{i<j} d_ij (x) F_ij, F_ij = -gamma w^2 (e.v_ij) e, w = 1 - r/r_cut."""
    W = np.zeros((3, 3))
    n = len(pos)
    for i in range(n):
        for j in range(i + 1, n):
            if pair_types is not None and (types[i], types[j]) not in pair_types:
                continue
            d = mi(pos[i] - pos[j], L)
            r = np.linalg.norm(d)
            if r >= r_cut:
                continue
            e = d / r
            w = 1.0 - r / r_cut
            W += np.outer(d, -gamma * w * w * np.dot(e, v[i] - v[j]) * e)
    return W


def fluid(L=5.0, n=300, kT=0.0, seed=3):
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    rng = np.random.default_rng(seed)
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    s.thermostat.set_dpd(kT=kT, seed=5)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.0, k=1, r_cut=1.0)
    return s


def test_dpd_friction_virial_vs_numpy():
    s = fluid()
    s.integrator.run(0)
    p = s.analysis.pressure_tensor()
    parts = s.part.all()
    want = dpd_friction_virial(parts.pos, parts.v, 5.0, 4.0, 1.0) / 125.0
    np.testing.assert_allclose(p["dpd"], want, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(p["total"], p["kinetic"] + p["non_bonded"], rtol=0, atol=0)
    assert np.max(np.abs(want)) > 0.01  # the check is not vacuous


def test_dpd_part_with_noise_is_the_dpd_stress():
    s = fluid(kT=1.0)
    s.integrator.run(10)
    p = s.analysis.pressure_tensor()
    np.testing.assert_allclose(p["dpd"], s.analysis.dpd_stress_split()["total"], rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(p["marble"], np.zeros((3, 3)))


@pytest.mark.skipif(not marble.has_features("MARBLE"), reason="missing feature MARBLE")
@pytest.mark.parametrize("coupling", ["tunable_slip", "transverse", "dpd"])
def test_marble_and_colloid_dpd_virial_vs_numpy(coupling):
    L, R, g_m, g_d = 8.0, 1.5, 3.0, 2.0
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    s.thermostat.set_dpd(kT=0.0, seed=11)
    rng = np.random.default_rng(8)
    col = s.part.add(pos=[1.0, 4.0, 4.0], v=[0.1, -0.2, 0.3], omega_lab=[0.4, 0.1, -0.3], type=1,
                     mass=50.0, rinertia=20.0, rotation=True)
    beads = s.part.add(pos=rng.random((400, 3)) * L, v=rng.normal(size=(400, 3)), type=0)
    s.non_bonded_inter[1, 0].marble.set_params(radius=R, gamma=g_m, r_cut=1.0, coupling=coupling)
    # a DPD pair interaction of the colloid with the beads (served by the colloid pair list)
    s.non_bonded_inter[1, 0].dpd.set_params(weight_function=1, gamma=g_d, k=1, r_cut=2.5)
    s.integrator.run(0)
    p = s.analysis.pressure_tensor()
    c, om, vc = col.pos, col.omega_lab, col.v
    W_m, W_d = np.zeros((3, 3)), np.zeros((3, 3))
    for x, v in zip(beads.pos, beads.v):
        d = mi(x - c, L)
        r = np.linalg.norm(d)
        n = d / r
        h = r - R
        if h < 1.0:
            w = 1.0 - max(h, 0.0)
            u = v - (vc + np.cross(om, R * n))
            f = {"tunable_slip": -g_m * w * w * u,
                 "transverse": -g_m * w * w * (u - np.dot(n, u) * n),
                 "dpd": -g_m * w * w * np.dot(n, u) * n}[coupling]
            W_m += np.outer(d, f)
        if r < 2.5:
            w = 1.0 - r / 2.5
            W_d += np.outer(d, -g_d * w * w * np.dot(n, v - vc) * n)
    V = L ** 3
    assert np.max(np.abs(W_m)) > 1e-3 and np.max(np.abs(W_d)) > 1e-3
    np.testing.assert_allclose(p["marble"], W_m / V, rtol=1e-10, atol=1e-14)
    # no bead-bead DPD: 'dpd' is the colloid pairs' part alone
    np.testing.assert_allclose(p["dpd"], W_d / V, rtol=1e-10, atol=1e-14)
