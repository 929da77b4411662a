# labels: python
"""Marble colloid coupling (reference.md section 3): analytic forces and
torques at kT = 0 for the three couplings, reaction and torque sign, momentum
conservation, excluded volume, neighbour search, bad input."""
import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("MARBLE"), reason="missing feature MARBLE")

R = 2.0
GAMMA = 3.0


def expected(coupling, d, v_bead, v_col, omega, radius=R, gamma=GAMMA, r_cut=1.0, k=1.0, wf=1):
    """Force on the bead and torque on the colloid, written independently of the engine."""
    dist = np.linalg.norm(d)
    n = d / dist
    h = dist - radius
    if h >= r_cut:
        return np.zeros(3), np.zeros(3)
    w = 1.0 if wf == 0 else 1.0 - (max(h, 0.0) / r_cut) ** k
    u = v_bead - (v_col + np.cross(omega, radius * n))
    if coupling == "tunable_slip":
        f = -gamma * w * w * u
    elif coupling == "transverse":
        f = -gamma * w * w * (u - np.dot(n, u) * n)
    else:
        f = -gamma * w * w * np.dot(n, u) * n
    return f, np.cross(radius * n, -f)


def make(coupling, bead_pos, col_pos=(1.0, 5.0, 5.0), L=10.0, **kw):
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    s.thermostat.set_dpd(kT=0.0, seed=11)
    col = s.part.add(pos=col_pos, v=[0.1, -0.2, 0.3], omega_lab=[0.4, 0.1, -0.3], type=1,
                     mass=50.0, rinertia=20.0, rotation=True)
    bead = s.part.add(pos=bead_pos, v=[0.5, 0.2, -0.1], type=0)
    params = dict(radius=R, gamma=GAMMA, r_cut=1.0, coupling=coupling)
    params.update(kw)
    s.non_bonded_inter[1, 0].marble.set_params(**params)
    return s, col, bead


@pytest.mark.parametrize("coupling", ["tunable_slip", "transverse", "dpd"])
@pytest.mark.parametrize("bead_pos", [
    (9.3, 5.6, 4.5),   # outside the surface, across the periodic x boundary
    (1.5, 6.1, 5.8),   # inside the sphere (h < 0: full weight)
    (2.0, 3.7, 6.2),   # outside, h ~ 0.4
    (1.0, 5.0, 8.5),   # beyond r_cut: no force
])
def test_analytic_force_and_torque(coupling, bead_pos):
    s, col, bead = make(coupling, bead_pos)
    s.integrator.run(0)
    d = s.distance_vec(col, bead)
    f, tau = expected(coupling, d, bead.v, col.v, col.omega_lab)
    scale = max(1.0, np.abs(f).max())
    np.testing.assert_allclose(bead.f, f, atol=1e-12 * scale, rtol=0)
    np.testing.assert_array_equal(col.f, -bead.f)  # reaction, exactly
    np.testing.assert_allclose(col.torque_lab, tau, atol=1e-12 * scale * R, rtol=0)


@pytest.mark.parametrize("kw", [dict(k=2.0), dict(weight_function=0), dict(r_cut=1.5, k=0.5)])
def test_weight_functions(kw):
    s, col, bead = make("tunable_slip", (2.0, 3.9, 6.1), **kw)
    s.integrator.run(0)
    d = s.distance_vec(col, bead)
    f, tau = expected("tunable_slip", d, bead.v, col.v, col.omega_lab,
                      r_cut=kw.get("r_cut", 1.0), k=kw.get("k", 1.0),
                      wf=kw.get("weight_function", 1))
    np.testing.assert_allclose(bead.f, f, atol=1e-12, rtol=0)
    np.testing.assert_allclose(col.torque_lab, tau, atol=1e-12, rtol=0)


def test_torque_sign_spins_colloid_with_the_flow():
    # A bead above the colloid (+y) moving along +x drags the surface along +x:
    # the colloid must spin up with omega_z < 0 (surface velocity omega x R n = +x).
    s, col, bead = make("tunable_slip", (1.0, 7.5, 5.0))
    col.v = [0, 0, 0]
    col.omega_lab = [0, 0, 0]
    bead.v = [1.0, 0, 0]
    s.integrator.run(0)
    assert bead.f[0] < 0
    assert col.torque_lab[2] < 0
    s.thermostat.turn_off()  # no friction: check that the analytic formula agrees on the sign
    f, tau = expected("tunable_slip", s.distance_vec(col, bead), bead.v, col.v, col.omega_lab)
    assert tau[2] < 0


def test_dpd_coupling_exerts_no_torque():
    s, col, bead = make("dpd", (2.0, 3.7, 6.2))
    s.integrator.run(0)
    assert np.abs(bead.f).max() > 1e-3
    np.testing.assert_allclose(col.torque_lab, 0.0, atol=1e-13)


def fluid_with_colloids(coupling, n_col=2, L=8.0, seed=5, masses=True):
    from marble.colloids import add_marble
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    n = int(3 * L ** 3)
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)), type=0,
               mass=rng.uniform(0.5, 2.0, n) if masses else 1.0)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    cols = [add_marble(s, pos=[L * 0.25, L * 0.3, L * 0.5], radius=1.5, gamma=5.0,
                       coupling=coupling)]
    if n_col > 1:
        cols.append(add_marble(s, pos=[L * 0.75, L * 0.8, L * 0.1], radius=1.5, gamma=5.0,
                               coupling=coupling))
    return s, cols


@pytest.mark.parametrize("coupling", ["tunable_slip", "transverse", "dpd"])
def test_momentum_conservation(coupling):
    s, cols = fluid_with_colloids(coupling)
    p0 = s.analysis.linear_momentum()
    s.integrator.run(200)
    p1 = s.analysis.linear_momentum()
    total_mass = np.sum(s.part.all().mass)
    np.testing.assert_allclose(p1, p0, atol=1e-12 * total_mass, rtol=0)


def test_colloid_pairs_found_across_boundaries_without_enlarging_cells():
    # The colloid's neighbour list equals a brute-force search, and the solvent's
    # Verlet range is not enlarged by the colloid (R + r_cut = 2.5 >> 1).
    s, cols = fluid_with_colloids("tunable_slip", n_col=1, L=8.0)
    col = cols[0]
    col.pos = [0.3, 7.9, 4.0]  # near a corner: the sphere wraps around
    s.integrator.run(0)
    assert s.cell_system.get_state()["max_cut"] == pytest.approx(1.0)
    solvent = s.part.select(type=0)
    d = solvent.pos_folded - col.pos_folded
    d -= s.box_l * np.round(d / s.box_l)
    r = np.linalg.norm(d, axis=1)
    # the engine's force on a bead is non-zero iff it is within R + r_cut (kT=0 check)
    s.thermostat.set_dpd(kT=0.0)
    s.non_bonded_inter[0, 0].dpd.deactivate()
    s.non_bonded_inter[1, 0].lennard_jones.deactivate()
    col.v = [0.5, 0.0, 0.0]
    s.integrator.run(0)
    f = np.linalg.norm(solvent.f, axis=1)
    inside = r < 1.5 + 1.0
    assert inside.sum() > 50
    assert np.all(f[inside & (r < 2.4)] > 0)
    assert np.all(f[~inside] == 0)


def test_excluded_volume_keeps_solvent_out():
    s, cols = fluid_with_colloids("tunable_slip", n_col=1, L=8.0, masses=False)
    s.integrator.run(1000)
    col = cols[0]
    solvent = s.part.select(type=0)
    d = solvent.pos_folded - col.pos_folded
    d -= s.box_l * np.round(d / s.box_l)
    assert np.linalg.norm(d, axis=1).min() > 1.5 - 0.5
    assert abs(s.analysis.kinetic_temperature(types=[0]) - 1.0) < 0.05


def test_add_marble_defaults():
    s, cols = fluid_with_colloids("tunable_slip", n_col=1, L=8.0, masses=False)
    col = cols[0]
    M = 3.0 * 4.0 / 3.0 * np.pi * 1.5 ** 3  # rho = 3 before insertion
    assert col.mass == pytest.approx(M)
    np.testing.assert_allclose(col.rinertia, 0.4 * M * 1.5 ** 2)
    assert np.all(col.rotation)
    lj = s.non_bonded_inter[1, 0].lennard_jones.get_params()
    assert lj["offset"] == pytest.approx(0.5)
    assert lj["cutoff"] == pytest.approx(2 ** (1 / 6))
    assert s.non_bonded_inter[1, 0].marble.get_params()["coupling"] == "tunable_slip"


def test_energy_and_pressure_include_colloid_pairs():
    s = marble.System(box_l=[10.0] * 3)
    s.time_step = 0.01
    col = s.part.add(pos=[5, 5, 5], type=1, rotation=True, mass=10, rinertia=1)
    b = s.part.add(pos=[5, 5, 7.05], type=0)
    s.non_bonded_inter[1, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=2 ** (1 / 6),
                                                      shift="auto", offset=1.0)
    s.non_bonded_inter[1, 0].marble.set_params(radius=2.0, gamma=1.0)
    rr = 2.05 - 1.0
    e_lj = 4 * (rr ** -12 - rr ** -6 + 0.25)
    assert s.analysis.energy()["non_bonded"] == pytest.approx(e_lj, rel=1e-12)
    s.integrator.run(0)
    fz = 4 * (12 * rr ** -13 - 6 * rr ** -7)
    np.testing.assert_allclose(b.f, [0, 0, fz], rtol=1e-12)
    pzz = s.analysis.pressure_tensor()["non_bonded"][2, 2]
    assert pzz == pytest.approx(2.05 * fz / 1000.0, rel=1e-12)


@pytest.mark.parametrize("kw,msg", [
    (dict(radius=0.0, gamma=1.0), "radius"),
    (dict(radius=-1.0, gamma=1.0), "radius"),
    (dict(radius=float("nan"), gamma=1.0), "radius"),
    (dict(radius=2.0, gamma=-1.0), "gamma"),
    (dict(radius=2.0, gamma=1.0, r_cut=-0.5), "r_cut"),
    (dict(radius=2.0, gamma=1.0, r_cut=0.0), "r_cut"),
    (dict(radius=2.0, gamma=1.0, coupling="sticky"), "coupling"),
    (dict(radius=2.0, gamma=1.0, coupling=3), "coupling"),
    (dict(radius=2.0, gamma=1.0, weight_function=2), "weight_function"),
    (dict(radius=2.0, gamma=1.0, k=0.0), "k"),
    (dict(radius=2.0, gamma=1.0, colour="red"), "colour"),
    (dict(gamma=1.0), "radius"),
    (dict(radius=2.0), "gamma"),
])
def test_bad_parameters(kw, msg):
    s = marble.System(box_l=[10.0] * 3)
    with pytest.raises(ValueError, match=msg):
        s.non_bonded_inter[1, 0].marble.set_params(**kw)
    assert s.non_bonded_inter[1, 0].marble.get_params() == {}


def test_same_type_rejected():
    s = marble.System(box_l=[10.0] * 3)
    with pytest.raises(ValueError, match="differ"):
        s.non_bonded_inter[1, 1].marble.set_params(radius=2.0, gamma=1.0)


def test_non_rotating_colloid_rejected():
    s = marble.System(box_l=[10.0] * 3)
    s.time_step = 0.01
    c = s.part.add(pos=[5, 5, 5], type=1, rotation=False)
    with pytest.raises(ValueError, match="does not rotate"):
        s.non_bonded_inter[1, 0].marble.set_params(radius=2.0, gamma=1.0)
    # the central coupling exerts no torque: allowed
    s.non_bonded_inter[1, 0].marble.set_params(radius=2.0, gamma=1.0, coupling="dpd")
    # a colloid added later without rotation stops the run with a clear error
    s.non_bonded_inter[1, 0].marble.deactivate()
    c.rotation = True
    s.non_bonded_inter[1, 0].marble.set_params(radius=2.0, gamma=1.0)
    s.part.add(pos=[1, 1, 1], type=1, rotation=False)
    with pytest.raises(RuntimeError, match="does not rotate"):
        s.integrator.run(1)


def test_several_colloid_types_and_colloid_colloid_pairs():
    # Two colloids of different types and radii; their mutual LJ (offset) acts
    # across the periodic boundary through the colloid pair list, once.
    s = marble.System(box_l=[12.0] * 3)
    s.time_step = 0.01
    a = s.part.add(pos=[0.5, 6, 6], type=1, rotation=True, mass=20, rinertia=5)
    b = s.part.add(pos=[8.0, 6.5, 6.2], type=2, rotation=True, mass=30, rinertia=9)
    s.part.add(pos=[3.0, 3.0, 3.0], type=0)
    s.non_bonded_inter[1, 0].marble.set_params(radius=1.5, gamma=1.0)
    s.non_bonded_inter[2, 0].marble.set_params(radius=2.5, gamma=2.0)
    s.non_bonded_inter[1, 2].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5,
                                                      shift="auto", offset=3.0)
    s.integrator.run(0)
    d = s.distance_vec(a, b)  # b - a, across the x boundary
    r = np.linalg.norm(d)
    x = r - 3.0
    f_mag = 4 * (12 * x ** -13 - 6 * x ** -7)  # -dV/dr
    np.testing.assert_allclose(b.f, f_mag * d / r, rtol=1e-12)
    np.testing.assert_array_equal(a.f, -b.f)
    e = s.analysis.energy()
    e_lj = 4 * (x ** -12 - x ** -6 + (1 / 2.5) ** 6 - (1 / 2.5) ** 12)
    assert e[("non_bonded", 1, 2)] == pytest.approx(e_lj, rel=1e-12)
    # the solvent's Verlet range is untouched by the colloids
    assert s.cell_system.get_state()["max_cut"] < 1.0 + 1e-12
