# labels: python mpi
"""SRD on more than one MPI rank is not supported yet: setting system.srd on
2 ranks raises RuntimeError("... not supported on more than one MPI rank
yet ...") on every rank and leaves the system without a fluid."""
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
    pytest.mark.skipif(not marble.has_features("SRD"), reason="missing feature SRD"),
]

SCRIPT = """
import marble, marble.srd as srd
s = marble.System(box_l=[4.0] * 3, time_step=0.1)
try:
    s.srd = srd.SRDFluid(types=[0], tau=0.1, seed=1)
    print("NOT REFUSED", flush=True)
except RuntimeError as e:
    assert "more than one MPI rank" in str(e), str(e)
    assert s.srd is None and not s._core.srd_active()
    print("REFUSED", marble.mpi_rank(), flush=True)
"""


def test_two_ranks_refused():
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "scene.py")
        with open(path, "w") as f:
            f.write(SCRIPT)
        p = subprocess.run([MPIEXEC, "-n", "2", sys.executable, path], env=env,
                           capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    assert p.stdout.count("REFUSED") == 2 and "NOT REFUSED" not in p.stdout, p.stdout + p.stderr
