# labels: python mpi
"""RESPA substeps (integrator.set_vv(substeps=n), doc/speed-accuracy.md) on several MPI
ranks: between substeps the other ranks' colloid copies get the new positions and the
fast (colloid pair) forces on them go back to their owners (every other ghost waits for
the step's end); the colloid list's staleness test and the
step's refusal are voted on over the ranks.

The scene (testsuite/python/mpi_scenes.py `respa`): a DPD fluid (L = 8) with a rotating
marble (R = 2) started at 6.3 tau^-1 across the domain faces, 60 steps of 3 substeps. It
rebuilds the lists 17 times, twice inside a step (the colloid list gone stale after the
second substep, steps 3 and 7, on 1 and 2 ranks alike: checked with a print when the
test was written), and ~145 particles change rank. Under Shardlow the scene runs on 2
ranks too (momentum conserved; its sweep's order, so the trajectory, follows the ranks)."""
import re

import numpy as np
import pytest

import marble
from test_mpi import MPIEXEC, assert_same_trajectory, run

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
    pytest.mark.skipif(not marble.has_features("DPD", "MARBLE"), reason="missing feature DPD or MARBLE"),
]


@pytest.fixture(scope="module")
def respa_runs():
    return {n: run("respa", n) for n in (1, 2, 3)}


@pytest.mark.parametrize("ranks", [2, 3])
def test_respa_trajectory_1_vs_n_ranks(respa_runs, ranks):
    one, other = respa_runs[1], respa_runs[ranks]
    assert int(other["ranks"]) == ranks
    assert_same_trajectory(one, other)
    for key in ("cpos", "cv", "comega"):
        np.testing.assert_allclose(other[key], one[key], rtol=0, atol=1e-9, err_msg=key)
    # the same list rebuilds (mid-step ones included), and particles did cross
    assert int(other["rebuilds"]) == int(one["rebuilds"])
    assert int(other["migrated"]) > 50


@pytest.fixture(scope="module")
def respa_plain_one():
    return run("respa_plain", 1)


@pytest.mark.parametrize("ranks", [2, 3])
def test_respa_without_colloids_or_ghosts(respa_plain_one, ranks):
    """No colloid and no pair range (no ghosts at all): the substeps' exchange of
    colloid copies must have its (empty) lists all the same (this scene crashed on
    2 ranks before they were reset with every ghost set-up)."""
    one, other = respa_plain_one, run("respa_plain", ranks)
    assert int(other["ranks"]) == ranks
    assert_same_trajectory(one, other)
    assert int(other["migrated"]) > 50


def test_respa_moved_the_colloid(respa_runs):
    """The scene is not trivial: the marble crossed a domain face (x = 4 on 2 ranks)."""
    assert respa_runs[1]["cpos"][0] > 4.5


def test_respa_blowup_stops_every_rank_cleanly():
    res = run("respa_blowup", 2)
    msg = str(res["msg"])
    assert re.search(r"integration stopped at step 3: particle \d+ moved .* in one of the 3 substeps", msg), msg
    assert "raise the integrator's substeps" in msg
    assert int(res["step"]) == 12  # the refused step did not count; 10 more steps ran


def test_shardlow_substeps_on_two_ranks():
    """RESPA under Shardlow on 2 ranks (since session 22; the marble coupling's
    sweep goes rank by rank): the marble crosses the domain face, the lists
    are rebuilt (17 times when written), particles change rank, and the
    total momentum is conserved to round-off. (Its exactness on several ranks: test_mpi.py,
    test_shardlow_marble_clusters_follow_a_sequential_order with RESPA.)"""
    r = run("respa_shardlow", 2)
    assert int(r["node_grid"][0]) == 2
    np.testing.assert_allclose(r["p1"], r["p0"], rtol=0, atol=1e-9)
    assert r["cpos"][0] > 4.5 and int(r["rebuilds"]) > 5 and int(r["migrated"]) > 50, r


def test_respa_runs_on_one_rank_under_mpiexec(respa_runs):
    assert int(respa_runs[1]["ranks"]) == 1 and int(respa_runs[1]["rebuilds"]) > 0
