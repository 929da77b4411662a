# labels: python
"""H5MD append (doc/io.md): ``marble.io.H5md(..., mode="append")`` continues the
time series of an existing file, so that a run written as 3 frames + close +
(new process state: a checkpoint) + reopen with mode="append" + 3 frames gives
the same file contents as 6 frames written in one go; a file with other fields,
another number of particles, a non-H5MD file and a bad mode are refused with
clear errors; append to a missing file creates it."""
import numpy as np
import pytest

import marble
import marble.io

try:
    import h5py
except ImportError:  # pragma: no cover
    h5py = None

pytestmark = pytest.mark.skipif(not marble.io.have_hdf5() or h5py is None,
                                reason="built without HDF5, or h5py missing")

L = 5.0
N = 60
GROUPS = ("position", "image", "velocity", "force", "species", "mass", "id")


def make_system():
    rng = np.random.default_rng(9)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    s.part.add(pos=rng.uniform(0, L, (N, 3)), v=rng.normal(size=(N, 3)))
    if marble.has_features("DPD"):
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=4)
    s.integrator.run(0)
    return s


def read_all(path):
    out = {}
    with h5py.File(path, "r") as f:
        atoms = f["particles/atoms"]
        for g in GROUPS + ("box/edges",):
            if g in atoms:
                for k in ("value", "step", "time"):
                    if k in atoms[g]:
                        out[f"{g}/{k}"] = atoms[g][k][:]
        out["version"] = f["h5md"].attrs["version"][:]
    return out


def write_frames(h5, s, n, steps=5):
    for _ in range(n):
        s.integrator.run(steps)
        h5.write()


@pytest.mark.parametrize("fields", ["all", ["position", "velocity"], ["box"]])
def test_append_equals_one_go(tmp_path, fields):
    one, two = tmp_path / "one.h5", tmp_path / "two.h5"
    s = make_system()
    with marble.io.H5md(file_path=str(one), system=s, fields=fields) as h5:
        write_frames(h5, s, 6)
    s = make_system()
    with marble.io.H5md(file_path=str(two), system=s, fields=fields) as h5:
        write_frames(h5, s, 3)
    with marble.io.H5md(file_path=str(two), system=s, fields=fields, mode="append") as h5:
        assert h5.n_frames == 3 and h5.mode == "append"
        write_frames(h5, s, 3)
        assert h5.n_frames == 6
    a, b = read_all(one), read_all(two)
    assert a.keys() == b.keys() and len(a) > 1
    for k in a:
        assert a[k].shape == b[k].shape, k
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    steps = b["position/step" if fields != ["box"] else "box/edges/step"]
    assert list(steps) == [5 * (k + 1) for k in range(6)]


def test_append_after_checkpoint_restart(tmp_path):
    """The use case: continue a trajectory after loading a checkpoint."""
    import pickle
    path = tmp_path / "traj.h5"
    s = make_system()
    with marble.io.H5md(file_path=str(path), system=s) as h5:
        write_frames(h5, s, 2)
    blob = pickle.dumps(s)
    with marble.io.H5md(file_path=str(tmp_path / "ref.h5"), system=s) as h5:
        write_frames(h5, s, 2)      # the uninterrupted continuation
    s2 = pickle.loads(blob)         # the restart
    with marble.io.H5md(file_path=str(path), system=s2, mode="append") as h5:
        write_frames(h5, s2, 2)
    got, ref = read_all(path), read_all(tmp_path / "ref.h5")
    assert got["position/value"].shape == (4, N, 3)
    np.testing.assert_array_equal(got["position/step"], [5, 10, 15, 20])
    for g in ("position", "velocity", "force"):
        np.testing.assert_array_equal(got[f"{g}/value"][2:], ref[f"{g}/value"], err_msg=g)


def test_append_to_missing_file_creates_it(tmp_path):
    s = make_system()
    path = tmp_path / "new.h5"
    with marble.io.H5md(file_path=str(path), system=s, mode="append") as h5:
        assert h5.n_frames == 0
        write_frames(h5, s, 2)
    assert read_all(path)["position/value"].shape == (2, N, 3)


def test_append_to_file_without_frames(tmp_path):
    s = make_system()
    path = tmp_path / "empty.h5"
    marble.io.H5md(file_path=str(path), system=s).close()
    with marble.io.H5md(file_path=str(path), system=s, mode="append") as h5:
        assert h5.n_frames == 0
        write_frames(h5, s, 1)
    assert read_all(path)["velocity/value"].shape == (1, N, 3)


def test_append_refusals(tmp_path):
    s = make_system()
    path = tmp_path / "t.h5"
    with marble.io.H5md(file_path=str(path), system=s, fields=["position", "time"]) as h5:
        write_frames(h5, s, 2)
    before = read_all(path)
    with pytest.raises(RuntimeError, match="cannot append .*holds the fields \\[position\\]"):
        marble.io.H5md(file_path=str(path), system=s, fields="all", mode="append")
    with pytest.raises(RuntimeError, match="time: yes.*time: no"):
        marble.io.H5md(file_path=str(path), system=s, fields=["position"], mode="append")
    # another number of particles: refused at write(), the file keeps its frames
    s.part.add(pos=[1.0, 1.0, 1.0])
    with marble.io.H5md(file_path=str(path), system=s, fields=["position", "time"],
                        mode="append") as h5:
        with pytest.raises(RuntimeError, match="number of particles changed from 60 to 61"):
            h5.write()
    after = read_all(path)
    for k in before:
        np.testing.assert_array_equal(before[k], after[k], err_msg=k)
    # not an HDF5 file / not an H5MD file
    bad = tmp_path / "bad.h5"
    bad.write_text("not hdf5")
    with pytest.raises(RuntimeError, match="cannot open .*bad.h5.* to append"):
        marble.io.H5md(file_path=str(bad), system=s, mode="append")
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f.create_group("foo")
    with pytest.raises(RuntimeError, match="not an H5MD file"):
        marble.io.H5md(file_path=str(other), system=s, mode="append")
    with pytest.raises(ValueError, match="parameter 'mode'"):
        marble.io.H5md(file_path=str(path), system=s, mode="a+")
