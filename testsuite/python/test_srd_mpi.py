# labels: python mpi
"""SRD on several MPI ranks (doc/srd.md, "Parallel runs"): the same scene on
1, 2, 3 and 8 ranks gives the same trajectory bit for bit over 200 collisions
with a stochastic stick colloid that crosses the domain faces (the issue asked
for 1e-9). The noise is keyed by (seed, collision, global cell index) and by
particle ids, the collision cells straddling the domain faces have their
(exact, integer) sums exchanged with the ranks they overlap (a neighbour
exchange, 8 ranks at a 2x2x2 corner), every rank runs the same event-ordered
sequence of colloid bounces, and each rank sorts only its local cell grid.
Also: a pure fluid drifting across the domains (the particles leaving a
domain are listed by the streaming step and migrated at the collision), the
Andersen rule with angular-momentum conservation, the
cell thermostat, stochastic Couette walls split across ranks, a colloid next
to a wall (bounce events with wall bounces), checkpoints
restored on another rank count, and H5MD output written by 2 ranks. Each scene runs in its own `mpiexec`
(testsuite/python/mpi_scenes.py)."""
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import marble
import marble.io

try:
    import h5py
except ImportError:  # pragma: no cover
    h5py = None

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "mpi_scenes.py")
MPIEXEC = shutil.which("mpiexec")

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
    pytest.mark.skipif(not marble.has_features("SRD", "ROTATION", "MASS"),
                       reason="missing feature SRD, ROTATION or MASS"),
]


def run(scene, ranks, **extra_env):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1", **extra_env)
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.npz")
        cmd = [MPIEXEC, "-n", str(ranks), sys.executable, SCENES, scene, out]
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
        assert p.returncode == 0, f"{' '.join(cmd)} failed:\n{p.stdout}\n{p.stderr}"
        with np.load(out) as f:
            return {k: f[k] for k in f.files}


def assert_same(a, b, tol=0.0, keys=("pos", "v")):
    np.testing.assert_array_equal(a["ids"], b["ids"])
    assert int(a["n_collisions"]) == int(b["n_collisions"])
    for key in keys:
        scale = max(1.0, np.abs(a[key]).max())
        err = np.abs(a[key] - b[key]).max() / scale
        assert err <= tol, f"{key}: max deviation {err:.3g} (relative to {scale:.3g})"


@pytest.fixture(scope="module")
def colloid_runs():
    return {n: run("srd_colloid", n) for n in (1, 2, 3, 4, 8)}


# 8 ranks: a 2x2x2 grid, where a collision cell at a domain corner is shared by
# up to 8 ranks (the neighbour exchange adds their sums in rank order)
@pytest.mark.parametrize("ranks", [2, 3, 4, 8])
def test_stick_colloid_same_trajectory(colloid_runs, ranks):
    one, many = colloid_runs[1], colloid_runs[ranks]
    assert int(one["ranks"]) == 1 and int(many["ranks"]) == ranks
    assert int(one["n_collisions"]) == 200
    assert len(one["ids"]) == int(round(5 * 8.0 ** 3))
    assert_same(one, many)
    for key in ("cpos", "cv", "comega", "to_colloids"):
        np.testing.assert_array_equal(many[key], one[key], err_msg=key)
    # the colloid took momentum from the fluid and crossed a domain face (x = 4)
    assert np.abs(one["to_colloids"]).max() > 1.0
    assert one["cpos"][0] > 4.5


@pytest.fixture(scope="module")
def fluid_runs():
    return {n: run("srd_fluid", n) for n in (1, 2, 3, 4, 8)}


# the pure fluid: the particles leaving a domain are listed by the streaming
# step (no colloid), migrated at the collision; 8 ranks as 2 x 2 x 2
@pytest.mark.parametrize("ranks", [2, 3, 4, 8])
def test_pure_fluid_same_trajectory(fluid_runs, ranks):
    one, many = fluid_runs[1], fluid_runs[ranks]
    assert int(one["n_collisions"]) == 100 and int(many["ranks"]) == ranks
    assert int(np.prod(many["node_grid"])) == ranks
    assert_same(one, many)


def test_andersen_angular_same_trajectory():
    # 25 collisions (see scene_srd_at); with exact cell sums bit for bit
    one, two = run("srd_at", 1), run("srd_at", 2)
    assert int(one["n_collisions"]) == 25
    assert_same(one, two)


def test_thermostat_same_trajectory():
    assert_same(run("srd_thermo", 1), run("srd_thermo", 2))


def test_couette_walls_same_trajectory():
    one, two = run("srd_walls", 1), run("srd_walls", 2)
    assert tuple(two["node_grid"]) == (1, 1, 2)
    assert_same(one, two)
    np.testing.assert_array_equal(two["to_walls"], one["to_walls"])
    assert np.abs(one["to_walls"]).max() > 1.0


@pytest.mark.parametrize("ranks", [2, 3])
def test_walled_channel_colloid_same_trajectory(ranks):
    """Colloid next to a wall (bounce events with wall bounces, doc/srd.md
    "Channel walls"): the same bits on 1, 2 (split across the walls' axis)
    and 3 ranks (the momentum handed to the walls, summed in storage order on
    each rank, to round-off)."""
    one, many = run("srd_walls_colloid", 1), run("srd_walls_colloid", ranks)
    assert_same(one, many)
    for key in ("cpos", "cv", "comega", "to_colloids"):
        np.testing.assert_array_equal(many[key], one[key], err_msg=key)
    np.testing.assert_allclose(many["to_walls"], one["to_walls"], rtol=1e-13, atol=0)
    assert np.abs(one["to_colloids"]).max() > 1.0


@pytest.mark.parametrize("n1,n2", [(1, 2), (2, 1), (2, 2)])
def test_checkpoint_other_rank_count(n1, n2):
    with tempfile.TemporaryDirectory() as d:
        ref = run("srd_ckpt_reference", n1, MARBLE_CKPT_DIR=d)
        got = run("srd_ckpt_restart", n2, MARBLE_CKPT_DIR=d)
    assert int(ref["n_collisions"]) == int(got["n_collisions"]) == 120
    if n1 == n2:  # the same ranks hold the same particles in the same order
        np.testing.assert_array_equal(ref["pos"], got["pos"])
        np.testing.assert_array_equal(ref["v"], got["v"])
    assert_same(ref, got)


@pytest.mark.skipif(not marble.io.have_hdf5() or h5py is None, reason="built without HDF5, or h5py missing")
def test_h5md_on_two_ranks():
    with tempfile.TemporaryDirectory() as d:
        out = run("srd_h5md", 2, MARBLE_CKPT_DIR=d)
        with h5py.File(os.path.join(d, "srd.h5"), "r") as f:
            g = f["particles/srd"]
            assert g["position/value"].shape == (2,) + out["pos"].shape
            np.testing.assert_array_equal(g["id/value"][1], out["ids"])
            np.testing.assert_array_equal(g["position/value"][1], out["pos"])
            np.testing.assert_array_equal(g["velocity/value"][1], out["v"])
            np.testing.assert_array_equal(g["position/step"][:], [20, 24])
