# labels: python
"""Analysis against independent numpy computations: energies, pressure
(virial), momentum, minimum distance, and the Galilei helpers."""
import numpy as np
import pytest

import marble
from unittest_decorators import skipIfMissingFeatures

L = 7.0


def random_config(n, rng, dmin=0.8, box=L):
    """n positions (many of them outside the box) with no minimum-image pair closer than dmin."""
    pos = []
    while len(pos) < n:
        x = rng.uniform(0, box, 3)
        if all(np.linalg.norm(mi(x - y, box)) >= dmin for y in pos):
            pos.append(x)
    pos = np.array(pos)
    return pos + box * rng.integers(-3, 4, size=pos.shape)  # unfolded images


def mi(d, box=L):
    return d - box * np.round(d / box)


def pair_vectors(pos, box=L):
    """All i < j minimum-image vectors r_i - r_j (box > 2 cutoff)."""
    i, j = np.triu_indices(len(pos), k=1)
    return i, j, mi(pos[i] - pos[j], box)


LJ = {(0, 0): dict(epsilon=1.0, sigma=1.0, cutoff=2.5, shift="auto"),
      (0, 1): dict(epsilon=0.7, sigma=0.9, cutoff=2.0, shift=0.02, offset=0.1),
      (1, 1): dict(epsilon=1.3, sigma=0.8, cutoff=1.2, shift=0.0)}


def lj_numpy(r, p):
    """Energy and F/r (F = fac d) for arrays of distances."""
    shift = p.get("shift", 0.0)
    if shift == "auto":
        q6c = (p["sigma"] / p["cutoff"]) ** 6
        shift = -(q6c * q6c - q6c)
    ro = r - p.get("offset", 0.0)
    on = ro < p["cutoff"]
    ro = np.where(on, ro, 1.0)
    q6 = (p["sigma"] / ro) ** 6
    e = np.where(on, 4 * p["epsilon"] * (q6 * q6 - q6 + shift), 0.0)
    fac = np.where(on, 24 * p["epsilon"] * (2 * q6 * q6 - q6) / (ro * r), 0.0)
    return e, fac


@pytest.fixture
def lj_system():
    rng = np.random.default_rng(2024)
    s = marble.System(box_l=[L] * 3, time_step=0.001)
    pos = random_config(120, rng)
    types = rng.integers(0, 2, size=len(pos))
    v = rng.normal(size=pos.shape)
    props = dict(pos=pos, v=v, type=types)
    if marble.has_features("MASS"):
        props["mass"] = rng.uniform(0.5, 2.0, size=len(pos))
    s.part.add(**props)
    if marble.has_features("LENNARD_JONES"):
        for (a, b), p in LJ.items():
            s.non_bonded_inter[a, b].lennard_jones.set_params(**p)
    return s


def numpy_nonbonded(s):
    parts = s.part.all()
    pos, types = parts.pos, parts.type
    i, j, d = pair_vectors(pos)
    r = np.linalg.norm(d, axis=1)
    e_pairs = {}
    energy = np.zeros(len(r))
    fac = np.zeros(len(r))
    for (a, b), p in LJ.items():
        sel = ((types[i] == a) & (types[j] == b)) | ((types[i] == b) & (types[j] == a))
        e, f = lj_numpy(r[sel], p)
        energy[sel] = e
        fac[sel] = f
        e_pairs[(a, b)] = e.sum()
    forces = np.zeros_like(pos)
    np.add.at(forces, i, fac[:, None] * d)
    np.add.at(forces, j, -fac[:, None] * d)
    virial = np.einsum("k,ka,kb->ab", fac, d, d)
    return energy.sum(), e_pairs, forces, virial


def masses(s):
    parts = s.part.all()
    return parts.mass if marble.has_features("MASS") else np.ones(len(parts))


def test_kinetic_energy_and_momentum(lj_system):
    s = lj_system
    parts = s.part.all()
    m, v = masses(s), parts.v
    e = s.analysis.energy()
    assert e["kinetic"] == pytest.approx(0.5 * np.sum(m[:, None] * v * v), rel=1e-12)
    np.testing.assert_allclose(s.analysis.linear_momentum(), np.sum(m[:, None] * v, axis=0),
                               rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(s.galilei.system_CMS_velocity(),
                               np.sum(m[:, None] * v, axis=0) / m.sum(), rtol=1e-12, atol=1e-14)
    p = s.analysis.pressure_tensor()
    np.testing.assert_allclose(p["kinetic"], np.einsum("i,ia,ib->ab", m, v, v) / L ** 3,
                               rtol=1e-12)
    assert s.analysis.pressure()["kinetic"] == pytest.approx(
        np.sum(m[:, None] * v * v) / (3 * L ** 3), rel=1e-12)


@skipIfMissingFeatures("LENNARD_JONES")
def test_energy_vs_numpy(lj_system):
    s = lj_system
    e_ref, e_pairs, _, _ = numpy_nonbonded(s)
    e = s.analysis.energy()
    assert abs(e_ref) > 1.0  # the configuration has interacting pairs
    assert e["non_bonded"] == pytest.approx(e_ref, rel=1e-10)
    for (a, b), val in e_pairs.items():
        assert e[("non_bonded", a, b)] == pytest.approx(val, rel=1e-10, abs=1e-12)
    assert e["total"] == pytest.approx(e["kinetic"] + e_ref, rel=1e-10)


@skipIfMissingFeatures("LENNARD_JONES")
def test_forces_and_pressure_vs_numpy(lj_system):
    s = lj_system
    _, _, f_ref, w_ref = numpy_nonbonded(s)
    s.integrator.run(0)
    np.testing.assert_allclose(s.part.all().f, f_ref, rtol=1e-9, atol=1e-9 * np.abs(f_ref).max())
    p = s.analysis.pressure_tensor()
    V = L ** 3
    np.testing.assert_allclose(p["non_bonded"], w_ref / V, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(p["total"], p["kinetic"] + w_ref / V, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(p["total"], p["total"].T, atol=1e-12)  # symmetric
    sc = s.analysis.pressure()
    assert sc["non_bonded"] == pytest.approx(np.trace(w_ref) / (3 * V), rel=1e-9)
    assert sc["total"] == pytest.approx(sc["kinetic"] + sc["non_bonded"], rel=1e-12)


@skipIfMissingFeatures("LENNARD_JONES")
def test_energy_after_moves_without_rebuild(lj_system):
    # Analysis between Verlet rebuilds (positions unfolded, ghosts refreshed).
    s = lj_system
    s.thermostat.turn_off()
    s.galilei.kill_particle_motion()
    parts = s.part.all()
    parts.v = np.random.default_rng(5).normal(0, 0.5, (len(parts), 3))
    s.integrator.run(20)
    e_ref, _, f_ref, _ = numpy_nonbonded(s)
    assert s.analysis.energy()["non_bonded"] == pytest.approx(e_ref, rel=1e-10)
    np.testing.assert_allclose(s.part.all().f, f_ref, rtol=1e-8, atol=1e-8 * np.abs(f_ref).max())


def test_min_dist_vs_numpy():
    rng = np.random.default_rng(7)
    s = marble.System(box_l=[5.0, 6.0, 7.0])
    pos = rng.uniform(-10, 10, size=(60, 3))
    types = rng.integers(0, 3, size=60)
    s.part.add(pos=pos, type=types)
    box = np.array([5.0, 6.0, 7.0])
    i, j = np.triu_indices(60, k=1)
    d = pos[i] - pos[j]
    r = np.linalg.norm(d - box * np.round(d / box), axis=1)
    assert s.analysis.min_dist() == pytest.approx(r.min(), rel=1e-12)
    for t1, t2 in (([0], [1]), ([2], [2]), ([0, 2], [1]), ([1], [0, 1, 2])):
        sel = (np.isin(types[i], t1) & np.isin(types[j], t2)) | \
              (np.isin(types[j], t1) & np.isin(types[i], t2))
        assert s.analysis.min_dist(t1, t2) == pytest.approx(r[sel].min(), rel=1e-12)


def test_galilei_transform_and_kill_motion():
    rng = np.random.default_rng(9)
    s = marble.System(box_l=[5.0] * 3, time_step=0.01)
    props = dict(pos=rng.uniform(0, 5, (30, 3)), v=rng.normal(1.0, 1.0, (30, 3)))
    if marble.has_features("MASS"):
        props["mass"] = rng.uniform(0.5, 3.0, 30)
    if marble.has_features("ROTATION"):
        props["rotation"] = [[True] * 3] * 30
        props["omega_lab"] = rng.normal(size=(30, 3))
    s.part.add(**props)
    v0 = s.part.all().v
    m = masses(s)
    vcm = np.sum(m[:, None] * v0, axis=0) / m.sum()
    assert np.linalg.norm(vcm) > 0.5
    s.galilei.galilei_transform()
    np.testing.assert_allclose(s.part.all().v, v0 - vcm, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(s.galilei.system_CMS_velocity(), 0.0, atol=1e-12)
    np.testing.assert_allclose(s.analysis.linear_momentum(), 0.0, atol=1e-11)
    if marble.has_features("ROTATION"):
        omega = s.part.all().omega_lab
        s.galilei.kill_particle_motion()  # rotation=False keeps omega
        np.testing.assert_array_equal(s.part.all().omega_lab, omega)
        np.testing.assert_array_equal(s.part.all().v, 0.0)
        s.galilei.kill_particle_motion(rotation=True)
        np.testing.assert_array_equal(s.part.all().omega_lab, 0.0)
    else:
        s.galilei.kill_particle_motion(rotation=True)
    np.testing.assert_array_equal(s.part.all().v, 0.0)
    assert s.analysis.energy()["kinetic"] == 0.0
    # empty system: no error
    s.part.clear()
    s.galilei.kill_particle_motion(rotation=True)
    s.galilei.galilei_transform()
    np.testing.assert_array_equal(s.galilei.system_CMS_velocity(), 0.0)
