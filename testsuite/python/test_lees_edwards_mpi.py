# labels: python mpi
"""Lees-Edwards boundary conditions on several MPI ranks (doc/lees-edwards.md,
doc/parallel.md). The node grid then splits only the vorticity axis (neither
the shear direction nor the shear-plane normal), so every image across the
shear plane is made by the rank that owns the particle and reaches the other
ranks as an ordinary ghost, with its shift along the normal (its velocity
jump) attached. Each scene runs in its own `mpiexec`
(testsuite/python/mpi_scenes.py):

(1) velocity Verlet (DPD fluid with noise, offset drifting by 3 over the run;
    stick colloids with their own large-range grid; Lees-Edwards switched on and
    off mid-run, which changes the node grid): 2 and 3 (4) ranks give the
    1-rank trajectory, pressure tensor and energy to round-off;
(2) Shardlow: four isolated pairs across the shear plane (partners as own
    images or other ranks' particles) get the exact update on any rank count;
    a sheared fluid has the same temperature and shear stress on 1, 2 and 3
    ranks within the runs' errors.
"""
import numpy as np
import pytest

import marble
from test_mpi import assert_same_trajectory, mean_and_block_error, needs, run

pytestmark = pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI")


def _same_observables(one, res, tol):
    for key in ("pressure", "energy"):
        scale = max(1.0, np.abs(one[key]).max())
        assert np.abs(res[key] - one[key]).max() / scale <= tol, key
    assert float(res["offset"]) == float(one["offset"])


@needs("DPD")
@pytest.mark.parametrize("scene, axis", [("lees_edwards", 2), ("lees_edwards_zx", 1)])
def test_sheared_fluid_1_2_3_ranks(scene, axis):
    """Shear along x (normal y) and along z (normal x): the grid splits the
    third axis only, and the trajectories agree with one rank."""
    one = run(scene, 1)
    for n in (2, 3):
        res = run(scene, n)
        grid = [1, 1, 1]
        grid[axis] = n
        assert tuple(res["node_grid"]) == tuple(grid), res["node_grid"]
        assert_same_trajectory(one, res)
        _same_observables(one, res, 1e-9)


@needs("DPD")
def test_switching_on_and_off_1_2_4_ranks():
    """Switching Lees-Edwards on and off mid-run changes the node grid (the
    particles move to their new ranks at the next list build, through the
    all-rank exchange): 2 and 4 ranks follow one rank's trajectory."""
    one = run("lees_edwards_switch", 1)
    for n, first in ((2, (2, 1, 1)), (4, (2, 2, 1))):
        res = run("lees_edwards_switch", n)
        assert [tuple(g) for g in res["grids"]] == [first, (1, 1, n), first], res["grids"]
        assert_same_trajectory(one, res)


@needs("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS", "TRANS_DPD", "ROTATION")
def test_sheared_stick_suspension_1_2_3_ranks():
    """Stick colloids (a full shell of colloid ghosts from every side, pairs by
    id) in a half-shell solvent under shear: 2 and 3 ranks (domains 4.5 and 3
    wide, narrower than the colloid pair range 3.4 on 3) give the 1-rank
    trajectory, spins and torques included."""
    one = run("lees_edwards_stick", 1)
    for n in (2, 3):
        res = run("lees_edwards_stick", n)
        assert tuple(res["node_grid"]) == (1, 1, n)
        assert_same_trajectory(one, res, tol=1e-8)
        _same_observables(one, res, 1e-8)
        for key in ("comega", "ctorque"):
            scale = max(1.0, np.abs(one[key]).max())
            assert np.abs(res[key] - one[key]).max() / scale <= 1e-8, key


@needs("DPD")
def test_shardlow_pairs_across_the_plane_1_2_3_ranks():
    """Isolated pairs across the shear plane under Shardlow (kT = 0): their
    partners are own images on one rank and other ranks' particles on 2 and 3
    (across the domain faces z = 4.5; 3 and 6; and the periodic face z = 0).
    The sweep reads another rank's particle from one slot filled with its
    owner's velocity and adds the jump of the image's shift, so the exact pair
    update, hence every velocity, is the 1-rank one."""
    one = run("lees_edwards_shardlow_pairs", 1)
    assert np.abs(one["v"]).max() > 1e-2  # the pairs did feel the jump
    for n in (2, 3):
        res = run("lees_edwards_shardlow_pairs", n)
        assert tuple(res["node_grid"]) == (1, 1, n)
        np.testing.assert_array_equal(res["ids"], one["ids"])
        np.testing.assert_allclose(res["v"], one["v"], rtol=0, atol=1e-12)
        np.testing.assert_allclose(res["pos"], one["pos"], rtol=0, atol=1e-12)


@needs("DPD")
def test_sheared_fluid_under_shardlow_1_2_3_ranks():
    """The ideal DPD fluid sheared under Shardlow (dt = 0.04, shear rate 1/9):
    the temperature of the velocities relative to their slab's mean flow is
    kT (1 - 9/N) plus the profile's spread within a slab (gamma_dot^2 h^2 / 36),
    the shear stress is negative and well resolved, and both agree across rank
    counts within the runs' errors (the trajectories differ: the sweep's order
    follows the decomposition)."""
    N, rate = int(3 * 9.0**3), 1.0 / 9.0
    expected = 1.0 - 9.0 / N + rate**2 / 36.0
    kT, sxy = [], []
    for n in (1, 2, 3):
        r = run("lees_edwards_shardlow", n)
        assert tuple(r["node_grid"]) == (1, 1, n), r["node_grid"]
        m, e = mean_and_block_error(r["kT"])
        assert e < 0.006, (n, e)  # so the test can fail
        assert abs(m - expected) < 4 * e + 0.003, (n, m, e, expected)
        s, es = mean_and_block_error(r["sxy"])
        assert s < -5 * es, (n, s, es)
        kT.append((m, e)), sxy.append((s, es))
    for k in (1, 2):
        for name, x in (("kT", kT), ("stress", sxy)):
            assert abs(x[k][0] - x[0][0]) < 4 * np.hypot(x[k][1], x[0][1]), (name, x)
