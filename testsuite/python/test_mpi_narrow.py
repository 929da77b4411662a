# labels: python mpi
"""Domains thinner than the interaction range (doc/parallel.md, "Limits"):
a DPD fluid whose cutoff + skin exceeds a rank's domain (and, in one scene,
the box itself) gets its ghosts from several domains and periodic images;
the trajectory on 2, 3, 4 and 8 ranks must agree with one rank to 1e-9
over 30 steps, as for the other scenes of test_mpi.py. And the SPMD mistake
that looked like a hang in this geometry (a particle read on rank 0 only)
now stops every rank with a message instead."""
import os
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import marble
from test_mpi import MPIEXEC, SCENES, assert_same_trajectory, mpi_env, run

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
    pytest.mark.skipif(not marble.has_features("DPD"), reason="missing feature DPD"),
]


@pytest.mark.parametrize("scene, ranks, grid", [
    ("narrow", 2, (2, 1, 1)),  # domains 3 x 6 x 4, range 2.7
    ("narrow", 3, (3, 1, 1)),  # domains 2 wide: thinner than the cutoff 2.3
    ("narrow", 4, (2, 2, 1)),
    ("narrow", 8, (2, 2, 2)),  # 3 x 3 x 2: thin along z
    ("thin", 3, (3, 1, 1)),    # cutoff 1.8 < domain 2 < cutoff + skin 2.2
    ("images", 3, (3, 1, 1)),  # box 2 < range 2.7 along y and z
])
def test_thin_domains_agree_with_one_rank(scene, ranks, grid):
    one, many = run(scene, 1), run(scene, ranks)
    assert int(many["ranks"]) == ranks
    assert tuple(many["node_grid"]) == grid
    assert_same_trajectory(one, many)


def test_particles_moved_to_a_far_rank():
    """Migration talks to the neighbour ranks only during a run (no all-rank
    alltoallv), but particles moved by the script to a rank that is not a
    neighbour of their owner arrive through the all-rank fallback."""
    one, six = run("teleport", 1), run("teleport", 6)
    assert tuple(six["node_grid"]) == (6, 1, 1)
    assert_same_trajectory(one, six)
    assert int(six["a2a_run"]) == 0
    assert int(six["a2a_teleport"]) >= 1


def test_read_on_rank0_only_stops_all_ranks():
    env = mpi_env(MARBLE_MPI_EXIT_TIMEOUT="4")
    with tempfile.TemporaryDirectory() as d:
        cmd = [MPIEXEC, "-n", "2", sys.executable, SCENES, "rank0_read", os.path.join(d, "o.npz")]
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode != 0
    assert "reached the end of the script" in p.stderr, p.stderr
    assert "mpi_rank() == 0" in p.stderr and "MARBLE_MPI_EXIT_TIMEOUT" in p.stderr, p.stderr
