# labels: python mpi
"""The halo that bench/mpi_weak_model.py extrapolates from: on 1, 2 and 4 ranks
every rank's ghost count (`_core.n_ghosts()`) equals an independent count
from the particle positions of the half-shell rule in doc/parallel.md (an
image, shifted by sh box lengths, of a particle of the rank at node
coordinates a lies within r = max cutoff + skin of the domain of the rank at
b and outside it, and a + sh * grid - b is lexicographically positive: the
rank's own images with a positive shift, other ranks' particles from half of
the sides), and the traffic counters (`_core.comm_stats()`) count two
point-to-point ghost exchanges per step on several ranks, no all-rank alltoallv (migration and ghost set-up at a rebuild go to the
neighbour ranks only), and nothing on one. Trajectories on
1-4 ranks agreeing (every pair computed once) is test_mpi's part."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import pytest

import marble

MPIEXEC = shutil.which("mpiexec")
pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
    pytest.mark.skipif(not marble.has_features("DPD"), reason="missing feature DPD"),
]

SCRIPT = r"""
import itertools, json, sys
import numpy as np
import marble
L, r_cut, skin = 9.0, 1.0, 0.4
rng = np.random.default_rng(3)
s = marble.System(box_l=[L] * 3)
s.time_step = 0.01
s.cell_system.skin = skin
s.part.add(pos=rng.random((int(3 * L**3), 3)) * L, v=rng.normal(size=(int(3 * L**3), 3)))
s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=r_cut)
s.thermostat.set_dpd(kT=1.0, seed=3)
s.integrator.run(0)                       # lists built at these positions
core = s._core
ghosts = core.n_ghosts()
pos = np.mod(np.asarray(s.part.all().pos), L)   # collective read
grid = np.asarray(s.cell_system.node_grid)
dl = L / grid
lo = np.asarray(s.cell_system.local_domain()[0])
r = r_cut + skin
owner = np.floor(pos / dl).astype(int)     # node coordinates of each particle's rank
me = np.floor((lo + 0.5 * dl) / dl).astype(int)
count = 0
for sh in itertools.product((-1, 0, 1), repeat=3):
    # half shell: the image pos + L sh of a particle of the rank at node coordinates
    # `owner` is a ghost here if owner + sh * grid - me is lexicographically positive
    # (own particles: a positive shift; other ranks' particles: half of the sides)
    off = owner + np.asarray(sh) * grid - me
    first = np.where(off[:, 0] != 0, off[:, 0], np.where(off[:, 1] != 0, off[:, 1], off[:, 2]))
    q = pos + L * np.asarray(sh)
    inside = np.all((q >= lo - r) & (q < lo + dl + r), axis=1)
    in_domain = np.all((q >= lo) & (q < lo + dl), axis=1)
    count += int(np.count_nonzero((first > 0) & inside & ~in_domain))
core.reset_comm_stats()
rebuilds = core.n_rebuilds()
s.integrator.run(10)
out = dict(rank=marble.mpi_rank(), ghosts=ghosts, expected=count, stats=dict(core.comm_stats()),
           rebuilds=core.n_rebuilds() - rebuilds)
with open(sys.argv[1] + f".{marble.mpi_rank()}", "w") as f:
    json.dump(out, f)
"""


def run(ranks):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "scene.py")
        with open(path, "w") as f:
            f.write(SCRIPT)
        p = subprocess.run([MPIEXEC, "-n", str(ranks), sys.executable, path, os.path.join(d, "o")],
                           env=env, capture_output=True, text=True, timeout=300)
        assert p.returncode == 0, p.stdout + p.stderr
        res = []
        for k in range(ranks):
            with open(os.path.join(d, f"o.{k}")) as f:
                res.append(json.load(f))
        return res


@pytest.mark.parametrize("ranks", [1, 2, 4])
def test_ghosts_and_traffic(ranks):
    for rec in run(ranks):
        assert rec["ghosts"] == rec["expected"], rec
        st = rec["stats"]
        if ranks == 1:
            assert st == dict(allreduce=0, alltoallv=0, neighbor=0, other=0, messages=0, bytes=0,
                              cpu_seconds=0.0, wall_seconds=0.0, wall_allreduce=0.0, wall_alltoallv=0.0,
                              wall_neighbor=0.0, wall_other=0.0), st
        else:
            # ghost positions/velocities out (but at a Verlet-list rebuild, which sends
            # whole ghost records) and ghost forces back: neighbour exchanges (point to
            # point, no count exchange); at a rebuild the migration and the ghost set-up
            # are neighbour exchanges too (sizes probed): no all-rank alltoallv at all
            assert st["neighbor"] == 2 * 10 + rec["rebuilds"], st
            assert st["alltoallv"] == 0, st
            assert st["messages"] >= 2 * 10 * (ranks - 1), st
            assert st["bytes"] > 0 and st["allreduce"] >= 10, st
            assert 0.0 < st["wall_seconds"] and 0.0 <= st["cpu_seconds"], st
            # the wall time by kind: every call in one kind, none in the alltoallv
            kinds = [st["wall_" + k] for k in ("allreduce", "alltoallv", "neighbor", "other")]
            assert min(kinds) >= 0.0 and st["wall_alltoallv"] == 0.0, st
            assert st["wall_neighbor"] > 0.0 and st["wall_allreduce"] > 0.0, st
            assert sum(kinds) == pytest.approx(st["wall_seconds"], rel=1e-9, abs=1e-12), st
