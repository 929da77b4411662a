# labels: python mpi
"""H5MD output and checkpoints on several MPI ranks (doc/io.md). Written for
`mpiexec -n 2 build/pymarble -m pytest test_io_mpi.py` (every rank runs the
same test; files go to a fixed directory all ranks see); it passes on one
rank too. Checks that the rows gathered from every rank's locals equal the
particles' values (read back on rank 0) and that a checkpoint reloaded with
the same number of ranks continues bit for bit."""
import os
import shutil

import numpy as np
import pytest

import marble
import marble.checkpointing
import marble.io
from marble import _marble

DIR = os.path.abspath("io_mpi_files")
RANK = marble.mpi_rank()


def setup_module():
    if RANK == 0:
        shutil.rmtree(DIR, ignore_errors=True)
        os.makedirs(DIR)
    _marble.comm_barrier()


def make():
    rng = np.random.default_rng(7)
    s = marble.System(box_l=[6.0, 6.0, 6.0])
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    s.part.add(pos=rng.uniform(0, 6, (400, 3)), v=rng.normal(size=(400, 3)))
    if marble.has_features("DPD"):
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=9)
    if marble.has_features("HAT"):
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    s.integrator.run(0)
    return s


@pytest.mark.skipif(not marble.has_features("DPD"), reason="missing feature DPD")
def test_checkpoint_same_rank_count_bitwise():
    s = make()
    s.integrator.run(20)
    cp = marble.checkpointing.Checkpoint(checkpoint_id="mpi", checkpoint_path=DIR,
                                         namespace={"system": s})
    cp.register("system")
    cp.save(0)
    s.integrator.run(20)
    ns = {}
    marble.checkpointing.Checkpoint(checkpoint_id="mpi", checkpoint_path=DIR, namespace=ns).load(0)
    s2 = ns["system"]
    s2.integrator.run(20)
    for name in ("id", "pos", "v", "f"):
        assert getattr(s2.part.all(), name).tobytes() == getattr(s.part.all(), name).tobytes(), name


@pytest.mark.skipif(not marble.io.have_hdf5(), reason="built without HDF5")
def test_h5md_rows_from_every_rank():
    s = make()
    path = os.path.join(DIR, "traj.h5")
    frames = []
    with marble.io.H5md(file_path=path, system=s) as h5:
        for _ in range(2):
            s.integrator.run(5)
            h5.write()
            p = s.part.all()
            frames.append((p.id, p.pos_folded, p.image_box, p.v, p.f))
    _marble.comm_barrier()
    if RANK == 0:
        h5py = pytest.importorskip("h5py")
        with h5py.File(path, "r") as f:
            g = f["particles/atoms"]
            for k, (ids, pos, img, v, force) in enumerate(frames):
                np.testing.assert_array_equal(g["id/value"][k], ids)
                np.testing.assert_array_equal(g["position/value"][k], pos)
                np.testing.assert_array_equal(g["image/value"][k], img)
                np.testing.assert_array_equal(g["velocity/value"][k], v)
                np.testing.assert_array_equal(g["force/value"][k], force)
    _marble.comm_barrier()
