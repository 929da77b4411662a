# labels: python mpi
"""Checkpoint restart on another number of MPI ranks (doc/io.md): a DPD fluid
with a hat potential (and, with MARBLE, a marble colloid) run for N steps on
n1 ranks, checkpointed, reloaded on n2 ranks (1 -> 2, 2 -> 1, 1 -> 3) and run
for N more steps equals the uninterrupted 2N-step run on n1 ranks to 1e-9
(relative), like the 1-vs-2-rank trajectories of test_mpi.py. It is not bit
for bit: the particles are redistributed to the new domains and the pair lists
rebuilt at the current positions, so force sums are added in another order.
The noise is counter-based (keyed by step and ids), so it is the same."""
import os
import shutil
import subprocess
import sys
import tempfile
import textwrap

import numpy as np
import pytest

import marble

MPIEXEC = shutil.which("mpiexec")

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
    pytest.mark.skipif(not marble.has_features("DPD", "HAT"), reason="needs DPD and HAT"),
]

N = 40

SCRIPT = textwrap.dedent("""
    import sys
    import numpy as np
    import marble, marble.checkpointing
    mode, d, out = sys.argv[1], sys.argv[2], sys.argv[3]
    N = int(sys.argv[4])

    def dump(system, path):
        p = system.part.all()
        data = dict(ids=p.id, pos=p.pos, v=p.v, f=p.f, step=system.step,
                    ranks=marble._marble.mpi_size())
        if marble._marble.mpi_rank() == 0:
            np.savez(path, **data)

    if mode == "load":
        cp = marble.checkpointing.Checkpoint(checkpoint_id="r", checkpoint_path=d)
        cp.load()
        system.integrator.run(N)
        dump(system, out)
        sys.exit(0)
    L = 8.0
    system = marble.System(box_l=[L] * 3)
    system.time_step = 0.01
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(42)
    n = int(3 * L ** 3)
    system.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
    system.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    system.thermostat.set_dpd(kT=1.0, seed=7)
    if marble.has_features("MARBLE"):
        from marble.colloids import add_marble
        add_marble(system, pos=[L / 2] * 3, radius=1.5, gamma=5.0)
    system.integrator.run(N)
    cp = marble.checkpointing.Checkpoint(checkpoint_id="r", checkpoint_path=d)
    cp.register("system")
    cp.save()
    system.integrator.run(N)
    dump(system, out)
""")


def mpirun(n, *args):
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    cmd = [MPIEXEC, "-n", str(n), sys.executable, *map(str, args)]
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, f"{' '.join(cmd)} failed:\n{p.stdout}\n{p.stderr}"


def load(path):
    with np.load(path) as f:
        return {k: f[k] for k in f.files}


@pytest.mark.parametrize("n1,n2", [(1, 2), (2, 1), (1, 3)])
def test_restart_on_other_rank_count(n1, n2):
    with tempfile.TemporaryDirectory() as d:
        script = os.path.join(d, "scene.py")
        with open(script, "w") as f:
            f.write(SCRIPT)
        ref, got = os.path.join(d, "ref.npz"), os.path.join(d, "got.npz")
        mpirun(n1, script, "save", d, ref, N)
        mpirun(n2, script, "load", d, got, N)
        a, b = load(ref), load(got)
    assert int(a["ranks"]) == n1 and int(b["ranks"]) == n2
    assert int(a["step"]) == int(b["step"]) == 2 * N
    np.testing.assert_array_equal(a["ids"], b["ids"])
    for key in ("pos", "v", "f"):
        scale = max(1.0, np.abs(a[key]).max())
        err = np.abs(a[key] - b[key]).max() / scale
        print(f"{n1} -> {n2} ranks, {key}: max relative deviation {err:.3g}, "
              f"bitwise equal: {a[key].tobytes() == b[key].tobytes()}")
        assert err <= 1e-9, f"{key}: {n1} -> {n2} ranks deviates by {err:.3g} (relative)"
