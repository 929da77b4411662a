# labels: python
"""Particles: add (single / many), properties, lookup, removal, folding."""
import numpy as np
import pytest

import marble
from marble.particle_data import ParticleHandle, ParticleSlice
from unittest_decorators import skipIfMissingFeatures


@pytest.fixture
def system():
    return marble.System(box_l=[10.0, 10.0, 10.0])


def test_add_single_returns_handle(system):
    p = system.part.add(pos=[1.0, 2.0, 3.0], v=[0.5, -0.5, 0.25], type=2)
    assert isinstance(p, ParticleHandle)
    assert p.id == 0
    np.testing.assert_array_equal(p.pos, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(p.v, [0.5, -0.5, 0.25])
    assert p.type == 2 and isinstance(p.type, int)
    np.testing.assert_array_equal(p.f, [0.0, 0.0, 0.0])
    q = system.part.add(pos=[4.0, 4.0, 4.0], id=17)
    assert q.id == 17
    r = system.part.add(pos=[5.0, 5.0, 5.0])
    assert r.id == 18  # next id after the highest
    assert system.part.highest_particle_id == 18
    assert len(system.part) == 3


def test_add_many_returns_slice(system):
    rng = np.random.default_rng(3)
    pos = rng.uniform(0, 10, size=(50, 3))
    v = rng.normal(size=(50, 3))
    types = rng.integers(0, 4, size=50)
    sl = system.part.add(pos=pos, v=v, type=types)
    assert isinstance(sl, ParticleSlice) and len(sl) == 50
    np.testing.assert_array_equal(sl.id, np.arange(50))
    allp = system.part.all()
    assert isinstance(allp.pos, np.ndarray) and allp.pos.shape == (50, 3)
    np.testing.assert_array_equal(allp.pos, pos)
    np.testing.assert_array_equal(allp.v, v)
    np.testing.assert_array_equal(allp.type, types)
    # one value for all particles is broadcast
    sl2 = system.part.add(pos=pos[:5], v=[1.0, 2.0, 3.0], type=3)
    np.testing.assert_array_equal(sl2.v, np.tile([1.0, 2.0, 3.0], (5, 1)))
    np.testing.assert_array_equal(sl2.type, [3] * 5)
    # explicit ids in any order; all() is in ascending id order
    sl3 = system.part.add(pos=pos[:3], id=[1000, 200, 300])
    np.testing.assert_array_equal(sl3.id, [1000, 200, 300])
    ids = system.part.all().id
    np.testing.assert_array_equal(ids, np.sort(ids))
    assert len(system.part) == 58
    # a slice indexes and iterates as handles
    assert sl[3].id == 3 and isinstance(sl[3], ParticleHandle)
    assert [p.id for p in sl[2:5]] == [2, 3, 4]
    assert sum(1 for _ in system.part) == 58


def test_non_contiguous_input_arrays(system):
    # Regression: rows of a transposed / strided array were read as if C-ordered.
    g = np.arange(3) * 2.0 + 0.5
    pos = np.array(np.meshgrid(g, g, g)).reshape(3, -1).T  # Fortran-ordered view
    assert not pos.flags["C_CONTIGUOUS"]
    sl = system.part.add(pos=pos)
    np.testing.assert_array_equal(sl.pos, pos)
    big = np.arange(27 * 6, dtype=float).reshape(27, 6) / 100.0
    sl.v = big[:, ::2]  # strided columns
    np.testing.assert_array_equal(sl.v, big[:, ::2])
    sl.type = np.arange(54)[::2] % 3
    np.testing.assert_array_equal(sl.type, np.arange(54)[::2] % 3)
    assert system.analysis.min_dist() == pytest.approx(2.0)


def test_set_properties_on_slice_and_handle(system):
    sl = system.part.add(pos=np.zeros((4, 3)) + 1.0)
    sl.v = np.arange(12.0).reshape(4, 3)
    np.testing.assert_array_equal(system.part.by_id(2).v, [6.0, 7.0, 8.0])
    system.part.by_id(2).v = [0.0, 0.0, 1.0]
    np.testing.assert_array_equal(sl.v[2], [0.0, 0.0, 1.0])
    sl.type = [0, 1, 0, 1]
    np.testing.assert_array_equal(system.part.select(type=1).id, [1, 3])
    sl.pos = [[1, 1, 1], [2, 2, 2], [3, 3, 3], [4, 4, 4]]
    np.testing.assert_array_equal(system.part.by_id(3).pos, [4.0, 4.0, 4.0])


def test_by_id_and_exists(system):
    system.part.add(pos=np.ones((3, 3)), id=[5, 7, 9])
    assert system.part.by_id(7).id == 7
    assert system.part.exists(9) and not system.part.exists(6)
    with pytest.raises(IndexError):
        system.part.by_id(6)
    assert [p.id for p in system.part.by_ids([9, 5])] == [9, 5]
    with pytest.raises(IndexError):
        system.part.by_ids([5, 6])
    assert system.part.by_id(5) == system.part.by_id(5)


def test_remove_and_clear(system):
    system.part.add(pos=np.random.default_rng(0).uniform(0, 10, (10, 3)))
    pos_before = system.part.all().pos
    system.part.by_id(3).remove()
    system.part.by_ids([0, 9]).remove()
    np.testing.assert_array_equal(system.part.all().id, [1, 2, 4, 5, 6, 7, 8])
    # the others keep their data
    np.testing.assert_array_equal(system.part.all().pos, pos_before[[1, 2, 4, 5, 6, 7, 8]])
    with pytest.raises(IndexError):
        system.part.by_id(3).pos
    # a new particle gets the next free id above the highest
    assert system.part.add(pos=[1, 1, 1]).id == 9
    system.part.clear()
    assert len(system.part) == 0 and system.part.highest_particle_id == -1
    assert system.part.add(pos=[1, 1, 1]).id == 0


def test_folding_outside_box(system):
    L = 10.0
    raw = np.array([[25.0, -3.0, 9.99], [-0.5, 10.0, -20.0], [1e4 + 0.5, -1e4 + 2.0, 5.0]])
    sl = system.part.add(pos=raw)
    np.testing.assert_allclose(sl.pos, raw, rtol=0, atol=1e-9)  # unfolded is kept
    folded = sl.pos_folded
    assert np.all(folded >= 0.0) and np.all(folded < L)
    np.testing.assert_allclose(folded, raw - L * np.floor(raw / L), atol=1e-9)
    np.testing.assert_array_equal(sl.image_box, np.floor(raw / L).astype(int))
    np.testing.assert_allclose(folded + L * sl.image_box, raw, atol=1e-9)
    # moving across the boundary during a run keeps pos continuous
    system.time_step = 0.1
    p = system.part.add(pos=[9.9, 0.05, 5.0], v=[1.0, -1.0, 0.0])
    system.integrator.run(10)
    np.testing.assert_allclose(p.pos, [10.9, -0.95, 5.0], atol=1e-12)
    np.testing.assert_allclose(p.pos_folded, [0.9, 9.05, 5.0], atol=1e-12)
    np.testing.assert_array_equal(p.image_box, [1, -1, 0])


@skipIfMissingFeatures("MASS")
def test_mass(system):
    p = system.part.add(pos=[1, 1, 1], mass=2.5)
    assert p.mass == 2.5
    sl = system.part.add(pos=np.ones((3, 3)), mass=[1.0, 2.0, 3.0])
    np.testing.assert_array_equal(sl.mass, [1.0, 2.0, 3.0])
    assert system.part.add(pos=[2, 2, 2]).mass == 1.0  # default
    p.mass = 4.0
    assert p.mass == 4.0


@skipIfMissingFeatures("ROTATION")
def test_rotation_properties(system):
    p = system.part.add(pos=[1, 1, 1], rotation=[True, True, True], rinertia=[2.0, 2.0, 2.0],
                        omega_lab=[0.1, 0.2, 0.3])
    np.testing.assert_array_equal(p.rotation, [True, True, True])
    np.testing.assert_array_equal(p.rinertia, [2.0, 2.0, 2.0])
    np.testing.assert_array_equal(p.omega_lab, [0.1, 0.2, 0.3])
    q = system.part.add(pos=[1, 1, 1])
    np.testing.assert_array_equal(q.rotation, [False] * 3)
    np.testing.assert_array_equal(q.omega_lab, [0.0] * 3)
    sl = system.part.add(pos=np.ones((2, 3)), rotation=[[True] * 3, [False] * 3],
                         rinertia=[[1.0] * 3, [3.0] * 3])
    np.testing.assert_array_equal(sl.rotation, [[True] * 3, [False] * 3])
    np.testing.assert_array_equal(sl.rinertia, [[1.0] * 3, [3.0] * 3])


@skipIfMissingFeatures("EXTERNAL_FORCE")
def test_ext_force_and_fix_properties(system):
    p = system.part.add(pos=[1, 1, 1], ext_force=[1.0, 0.0, -2.0], fix=[True, False, True])
    np.testing.assert_array_equal(p.ext_force, [1.0, 0.0, -2.0])
    np.testing.assert_array_equal(p.fix, [True, False, True])
    p.fix = [False, False, False]
    np.testing.assert_array_equal(p.fix, [False] * 3)


@skipIfMissingFeatures("EXTERNAL_FORCE", "ROTATION")
def test_ext_torque_property(system):
    p = system.part.add(pos=[1, 1, 1], ext_torque=[0.0, 1.5, 0.0])
    np.testing.assert_array_equal(p.ext_torque, [0.0, 1.5, 0.0])


def test_to_dict_has_compiled_properties(system):
    p = system.part.add(pos=[1, 2, 3])
    d = p.to_dict()
    for k in ("id", "type", "pos", "v", "f", "pos_folded", "image_box"):
        assert k in d
    assert ("mass" in d) == marble.has_features("MASS")
    assert ("omega_lab" in d) == marble.has_features("ROTATION")
