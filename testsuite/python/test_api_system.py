# labels: python
"""System-level API: box, time step, skin, cell system, distances."""
import numpy as np
import pytest

import marble


def test_box_and_defaults():
    s = marble.System(box_l=[4.0, 5.0, 6.5])
    np.testing.assert_array_equal(s.box_l, [4.0, 5.0, 6.5])
    assert s.time_step == -1.0  # unset
    assert s.cell_system.skin == pytest.approx(0.4)
    assert s.time == 0.0 and s.step == 0
    np.testing.assert_array_equal(s.periodicity, [True, True, True])
    assert len(s.part) == 0
    # box_l may change while the box is empty
    s.box_l = [3.0, 3.0, 3.0]
    np.testing.assert_array_equal(s.box_l, [3.0] * 3)
    # integer and numpy inputs are accepted
    s2 = marble.System(box_l=np.array([2, 3, 4]), time_step=0.01)
    np.testing.assert_array_equal(s2.box_l, [2.0, 3.0, 4.0])
    assert s2.time_step == 0.01


def test_time_step_and_skin_roundtrip():
    s = marble.System(box_l=[10.0] * 3)
    for dt in (0.001, 0.05, 1):
        s.time_step = dt
        assert s.time_step == dt
    for skin in (0.01, 0.1, 2.5, 5.0):
        s.cell_system.skin = skin
        assert s.cell_system.skin == skin
    s.time = 12.5
    assert s.time == 12.5


def test_cell_system_state():
    s = marble.System(box_l=[10.0] * 3)
    s.cell_system.skin = 0.5
    s.cell_system.set_regular_decomposition(use_verlet_lists=True)
    st = s.cell_system.get_state()
    assert st["skin"] == 0.5
    assert st["max_cut"] == 0.0
    if marble.has_features("LENNARD_JONES"):
        s.non_bonded_inter[0, 1].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=2.0, offset=0.5)
        s.analysis.energy()  # builds the cell grid
        st = s.cell_system.get_state()
        assert st["max_cut"] == pytest.approx(2.5)
        # cells are at least max_cut + skin wide: 10 / 3 = 3.33 >= 3.0
        assert st["n_cells"] == [3, 3, 3]


def _mi_numpy(a, b, L):
    d = np.asarray(b, float) - np.asarray(a, float)
    return d - L * np.round(d / L)


def test_distance_vec_minimum_image():
    L = np.array([4.0, 6.0, 9.0])
    s = marble.System(box_l=L)
    rng = np.random.default_rng(1)
    pos = rng.uniform(-20, 20, size=(40, 3))
    parts = s.part.add(pos=pos)
    for k in range(len(parts) - 1):
        p, q = parts[k], parts[k + 1]
        ref = _mi_numpy(pos[k], pos[k + 1], L)
        np.testing.assert_allclose(s.distance_vec(p, q), ref, atol=1e-10)
        assert np.all(np.abs(ref) <= L / 2 + 1e-12)
        assert s.distance(p, q) == pytest.approx(np.linalg.norm(ref), abs=1e-10)
        # positions and particles may be mixed
        np.testing.assert_allclose(s.distance_vec(pos[k], q), ref, atol=1e-10)
        np.testing.assert_allclose(s.distance_vec(q, p), -ref, atol=1e-10)
        # the core's own minimum image agrees
        np.testing.assert_allclose(s._core.distance_vec(int(p.id), int(q.id)), ref, atol=1e-10)
    # a known value across the boundary
    np.testing.assert_allclose(s.distance_vec([0.5, 0.5, 0.5], [3.5, 5.5, 8.5]), [-1, -1, -1])
    assert s.distance([0.5, 0.5, 0.5], [3.5, 5.5, 8.5]) == pytest.approx(np.sqrt(3))


def test_steps_and_time_advance():
    s = marble.System(box_l=[5.0] * 3, time_step=0.02)
    s.part.add(pos=[1.0, 1.0, 1.0], v=[0.1, 0.0, 0.0])
    s.integrator.run(25)
    assert s.step == 25
    assert s.time == pytest.approx(0.5)
    s.integrator.run(0)  # forces only
    assert s.step == 25
