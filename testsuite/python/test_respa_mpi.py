# labels: python mpi
"""RESPA substeps (integrator.set_vv/set_shardlow(substeps=n), doc/speed-accuracy.md) run on
one MPI rank only: on two ranks the run is refused on every rank with a message naming
the option; on one rank under mpiexec it runs."""
import pytest

import marble
from test_mpi import MPIEXEC, run

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
    pytest.mark.skipif(not marble.has_features("DPD"), reason="missing feature DPD"),
]


def test_substeps_refused_on_two_ranks():
    msg = str(run("respa", 2)["msg"])
    assert "substeps = 2" in msg and "one MPI rank" in msg, msg


def test_substeps_run_on_one_rank():
    assert str(run("respa", 1)["msg"]) == "no error"
