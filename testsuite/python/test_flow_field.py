# labels: python
"""marble.flow: the binning of FlowField on hand-made configurations (known
averages, empty cells NaN, co-moving frame with minimum image, sub-boxes, type
selection, block errors), the VTK round trip (own reader and meshio), and the
Stokes solutions (boundary conditions; the periodic sum tends to the unbounded
solution plus Hasimoto's uniform shift as L grows). Needs no feature beyond
plain particles; the physics test is test_flow_field_stokes.py."""
import numpy as np
import pytest

import marble
from marble import flow, theory

L = 4.0


def make_system(pos, v, types=None):
    s = marble.System(box_l=[L, L, L], time_step=0.01)
    s.cell_system.skin = 0.4
    kw = {"pos": np.asarray(pos, float), "v": np.asarray(v, float)}
    if types is not None:
        kw["type"] = types
    s.part.add(**kw)
    return s


def test_lab_frame_average_and_empty_cells():
    pos = [[0.5, 0.5, 0.5], [1.5, 0.2, 1.9], [3.0, 3.0, 3.0], [2.5, 3.5, 3.9]]
    v = [[1, 0, 0], [3, 2, 0], [0, 0, -1], [0, 4, 0]]
    s = make_system(pos, v)
    ff = flow.FlowField(s, grid=(2, 2, 2))
    ff.sample()
    s.part.by_id(0).v = [-1.0, 2.0, 0.0]
    ff.sample()
    vel, cnt = ff.velocity, ff.counts
    assert vel.shape == (2, 2, 2, 3) and cnt.shape == (2, 2, 2)
    # cell (0, 0, 0): particle 0 (twice, v = (1,0,0) then (-1,2,0)) and 1 (twice)
    assert cnt[0, 0, 0] == 4
    np.testing.assert_allclose(vel[0, 0, 0], [(1 - 1 + 3 + 3) / 4, (0 + 2 + 2 + 2) / 4, 0])
    np.testing.assert_allclose(vel[1, 1, 1], [0, 2, -0.5])   # particles 2 and 3
    assert cnt[1, 1, 1] == 4
    empty = cnt == 0
    assert empty.sum() == 6
    assert np.all(np.isnan(vel[empty]))
    np.testing.assert_allclose(ff.density[0, 0, 0], 4 / (2 * 8.0))
    np.testing.assert_allclose(ff.density[empty], 0.0)
    np.testing.assert_allclose(ff.cell_centres[1, 0, 1], [3, 1, 3])
    np.testing.assert_allclose(ff.frame_velocity, 0.0)
    ff.reset()
    assert ff.n_samples == 0 and np.all(np.isnan(ff.velocity))


def test_co_moving_minimum_image_and_types():
    # colloid (type 1) near the corner; solvent beads on the other side of the box
    pos = [[0.2, 3.9, 2.0], [3.9, 0.1, 2.0], [0.6, 3.5, 2.1], [2.2, 2.0, 2.0], [0.3, 3.8, 2.0]]
    v = [[0.5, 0, 0], [1.5, 1, 0], [0.5, -2, 3], [9, 9, 9], [7, 7, 7]]
    s = make_system(pos, v, types=[1, 0, 0, 0, 2])
    ff = flow.FlowField(s, grid=(4, 4, 4), types=[0], co_moving=0)
    np.testing.assert_allclose(ff.lower, [-2, -2, -2])
    ff.sample()
    cnt, vel = ff.counts, ff.velocity
    # bead 1: relative (-0.3, 0.2, 0) -> cell (1, 2, 2); velocity (1, 1, 0)
    np.testing.assert_allclose(vel[1, 2, 2], [1.0, 1.0, 0.0])
    # bead 2: relative (0.4, -0.4, 0.1) -> cell (2, 1, 2); velocity (0, -2, 3)
    np.testing.assert_allclose(vel[2, 1, 2], [0.0, -2.0, 3.0])
    # bead 3: relative (2.0, -1.9, 0) -> x = 2.0 folds to -2.0 -> cell (0, 0, 2)
    np.testing.assert_allclose(vel[0, 0, 2], [8.5, 9.0, 9.0])
    assert cnt.sum() == 3      # the colloid itself and the type-2 particle are left out
    np.testing.assert_allclose(ff.frame_velocity, [0.5, 0, 0])
    # a sub-box around the colloid: only bead 1 and 2 (|rel| < 0.5)
    sub = flow.FlowField(s, grid=(1, 1, 1), types=0, co_moving=s.part.by_id(0),
                         lower=[-0.5] * 3, upper=[0.5] * 3)
    sub.sample()
    assert sub.counts[0, 0, 0] == 2
    np.testing.assert_allclose(sub.velocity[0, 0, 0], [0.5, -0.5, 1.5])


def test_lab_sub_box_wraps():
    s = make_system([[3.9, 1.0, 1.0], [0.1, 1.0, 1.0], [2.0, 1.0, 1.0]],
                    [[1, 0, 0], [3, 0, 0], [5, 0, 0]])
    ff = flow.FlowField(s, grid=(2, 1, 1), lower=[3.5, 0, 0], upper=[4.5, 4, 4])
    ff.sample()
    np.testing.assert_allclose(ff.counts[:, 0, 0], [1, 1])
    np.testing.assert_allclose(ff.velocity[:, 0, 0, 0], [1, 3])
    np.testing.assert_allclose(ff.axes[0], [3.75, 4.25])


def test_blocks_and_axis_profile():
    s = make_system([[0.5, 0.1, 3.9], [3.4, 0.2, 0.0]], [[1, 0, 0], [3, 0, 0]])
    ff = flow.FlowField(s, grid=(4, 5, 5), lower=[-2, -2, -2], upper=[2, 2, 2],
                        block_size=2)
    with pytest.raises(ValueError, match="blocks"):
        ff.velocity_error
    p = s.part.all()
    for k, vx in enumerate([1, 1, 3, 3, 5, 5]):
        p.v = [[vx, 0, 0], [vx + 1, 0, 0]]
        ff.sample()
    assert ff.n_blocks == 3
    # particle 0 is in cell x-index (0.5 + 2) -> 2, particle 1 at 3.4 - 4 = -0.6 -> 1
    err = ff.velocity_error
    np.testing.assert_allclose(err[2, 2, 2, 0], np.std([1, 3, 5], ddof=1) / np.sqrt(3))
    assert np.isnan(err[0, 0, 0, 0])
    prof = flow.axis_profile(ff, [0.0, 2.0], theory=np.ones(ff.grid + (3,)))
    # both cells on the axis (|y|, |z| <= half a cell), |x| < 2
    np.testing.assert_allclose(prof["u"], [(3 + 4) / 2])
    np.testing.assert_allclose(prof["counts"], [12])
    np.testing.assert_allclose(prof["r"], [0.5])
    np.testing.assert_allclose(prof["theory"], [1.0])
    assert prof["err"][0] > 0


def test_bad_input():
    s = make_system([[1, 1, 1]], [[0, 0, 0]])
    for kw in ({"grid": (0, 2, 2)}, {"grid": (2, 2)}, {"grid": (2.5, 2, 2)},
               {"grid": (2, 2, 2), "co_moving": 7},
               {"grid": (2, 2, 2), "lower": [0, 0, 0], "upper": [5, 1, 1]},
               {"grid": (2, 2, 2), "lower": [1, 0, 0], "upper": [1, 1, 1]},
               {"grid": (2, 2, 2), "block_size": 0}):
        with pytest.raises(ValueError):
            flow.FlowField(s, **kw)
    ff = flow.FlowField(s, grid=(2, 2, 2))
    with pytest.raises(ValueError, match="every"):
        ff.sample_run(1, 0)
    assert np.all(np.isnan(ff.density))


def test_vtk_round_trip(tmp_path):
    rng = np.random.default_rng(3)
    pos = rng.random((200, 3)) * L
    s = make_system(pos, rng.normal(size=(200, 3)))
    ff = flow.FlowField(s, grid=(3, 4, 5), lower=[0.5, 0, 0], upper=[3.5, 4, 4])
    ff.sample()
    path = tmp_path / "f.vtk"
    ff.write_vtk(path)
    origin, spacing, fields = flow.read_vtk(path)
    np.testing.assert_allclose(origin, ff.cell_centres[0, 0, 0])
    np.testing.assert_allclose(spacing, ff.cell_size)
    np.testing.assert_array_equal(fields["velocity"], ff.velocity)
    np.testing.assert_array_equal(fields["density"], ff.density)
    meshio = pytest.importorskip("meshio")
    m = meshio.read(str(path))
    # meshio: points in VTK order (x fastest)
    np.testing.assert_allclose(m.points, ff.cell_centres.transpose(2, 1, 0, 3).reshape(-1, 3))
    np.testing.assert_array_equal(m.point_data["velocity"],
                                  ff.velocity.transpose(2, 1, 0, 3).reshape(-1, 3))
    np.testing.assert_array_equal(np.ravel(m.point_data["density"]),
                                  ff.density.transpose(2, 1, 0).reshape(-1))


def test_stokes_boundary_conditions():
    U = np.array([0.3, 0.0, 0.0])
    R = 2.0
    rng = np.random.default_rng(5)
    n = rng.normal(size=(50, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    # stick: u = U on the surface
    np.testing.assert_allclose(flow.stokes_velocity(R * n * (1 + 1e-12), U, R), U[None] + 0 * n,
                               atol=1e-9)
    for b in (0.7, np.inf):
        u = flow.stokes_velocity(R * n * (1 + 1e-12), U, R, b=b)
        # impermeable: normal velocity = sphere's
        np.testing.assert_allclose(np.sum(u * n, 1), n @ U, atol=1e-9)
    # far field: Stokeslet of force zeta U, zeta = Basset's
    far = flow.stokes_velocity([[1e4, 0, 0]], U, R, b=0.7)[0, 0]
    lam = 0.7 / R
    np.testing.assert_allclose(far * 1e4, 0.3 * 1.5 * R * (1 + 2 * lam) / (1 + 3 * lam),
                               rtol=1e-6)


@pytest.mark.parametrize("b", [0.0, 1.0])
def test_periodic_stokes_tends_to_unbounded(b):
    eta, R, F = 1.3, 2.0, np.array([1.0, 0.0, 0.0])
    pts = np.array([[3.5, 0, 0], [0, 3.5, 0], [3, 3, 1], [5, 0, 0]], float)
    zeta = theory.basset_friction(eta, R, b)[0]
    unb = flow.stokes_velocity(pts, F / zeta, R, b)
    dev = []
    for Lb in (16.0, 32.0):
        per = flow.periodic_stokes_velocity(pts, F, eta, R, Lb, b=b, sigma=0.4,
                                            fluid_counter_force=False)
        # Hasimoto: the images' uniform part is -xi F/(6 pi eta L) (plus O(1/L^3))
        per[:, 0] += theory.HASIMOTO_XI / (6 * np.pi * eta * Lb)
        dev.append(np.max(np.abs(per - unb)) * zeta)
    assert dev[1] < 0.01 and dev[1] < dev[0] / 3
    # the mean velocity of the box is zero; the sphere moves at Hasimoto's D F
    Lb = 12.0
    D = theory.diffusion_coefficient(eta, R, Lb, b)
    xs = (np.arange(12) + 0.5) * Lb / 12 - Lb / 2
    grid = np.stack(np.meshgrid(xs, xs, xs, indexing="ij"), -1)
    u = flow.periodic_stokes_velocity(grid, F, eta, R, Lb, b=b, sigma=0.4)
    assert abs(np.mean(u[..., 0])) < 0.02 * D
    # Stokes: on the axis at 1.5 R the lab-frame flow is far below the sphere's speed
    assert u[9, 6, 6, 0] < D
