# labels: python
"""H5MD output (doc/io.md): a short DPD run written frame by frame and read
back with h5py and MDAnalysis equals the simulation's values exactly
(folded positions + images, velocities, forces, species, masses, ids, box,
step, time); the H5MD 1.1 layout; fields subsets; a change of the number of
particles and bad parameters raise clear errors."""
import os

import numpy as np
import pytest

import marble
import marble.io

try:
    import h5py
except ImportError:  # pragma: no cover
    h5py = None

needs_hdf5 = pytest.mark.skipif(not marble.io.have_hdf5() or h5py is None,
                                reason="built without HDF5, or h5py missing")

L = 5.0
N = 150
N_FRAMES = 4


def make_system():
    rng = np.random.default_rng(3)
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    mass = 1.0 + rng.integers(0, 2, N) if marble.has_features("MASS") else None
    kw = dict(pos=rng.uniform(0, L, (N, 3)), v=rng.normal(size=(N, 3)),
              type=rng.integers(0, 2, N))
    if mass is not None:
        kw["mass"] = mass
    s.part.add(**kw)
    s.part.all()[:N // 2].remove()  # ids with holes: rows are particles sorted by id
    if marble.has_features("DPD"):
        for a, b in ((0, 0), (0, 1), (1, 1)):
            s.non_bonded_inter[a, b].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=4)
    if marble.has_features("HAT"):
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    s.integrator.run(0)
    return s


def snapshot(s):
    p = s.part.all()
    return dict(position=p.pos_folded, image=p.image_box, velocity=p.v, force=p.f,
                species=p.type, mass=p.mass if marble.has_features("MASS") else np.ones(len(p)),
                id=p.id, step=s.step, time=s.time)


def write_run(path, fields="all"):
    s = make_system()
    frames = []
    with marble.io.H5md(file_path=str(path), system=s, fields=fields) as h5:
        for i in range(N_FRAMES):
            if i:
                s.integrator.run(7)
            h5.write()
            frames.append(snapshot(s))
        h5.flush()
        assert h5.n_frames == N_FRAMES
    assert not h5.is_open
    return s, frames


@needs_hdf5
def test_h5py_values_and_layout(tmp_path):
    path = tmp_path / "traj.h5"
    s, frames = write_run(path)
    # the positions are unwrapped across the box by then
    assert np.any(frames[-1]["image"] != 0)
    with h5py.File(path, "r") as f:
        assert list(f["h5md"].attrs["version"]) == [1, 1]
        assert "name" in f["h5md/author"].attrs and "name" in f["h5md/creator"].attrs
        box = f["particles/atoms/box"]
        assert box.attrs["dimension"] == 3
        assert [b.decode() for b in box.attrs["boundary"]] == ["periodic"] * 3
        edges = box["edges/value"][:]
        assert edges.shape == (N_FRAMES, 3, 3)
        np.testing.assert_array_equal(edges[-1], np.diag(s.box_l))
        g = f["particles/atoms"]
        for name in ("position", "image", "velocity", "force", "species", "mass", "id"):
            ds = g[name]["value"]
            assert ds.maxshape[0] is None and ds.chunks is not None, name
            assert ds.shape[:2] == (N_FRAMES, N - N // 2), name
            np.testing.assert_array_equal(g[name]["step"][:], [fr["step"] for fr in frames])
            np.testing.assert_array_equal(g[name]["time"][:], [fr["time"] for fr in frames])
            for k, fr in enumerate(frames):
                np.testing.assert_array_equal(ds[k], fr[name], err_msg=f"{name} frame {k}")
        assert g["position"]["value"].dtype == np.float64
        assert g["image"]["value"].dtype == np.int32
        # position + image * box_l is the unfolded position
        np.testing.assert_allclose(g["position/value"][-1] + g["image/value"][-1] * L,
                                   s.part.all().pos, rtol=0, atol=1e-12)


@needs_hdf5
def test_mdanalysis(tmp_path):
    mda = pytest.importorskip("MDAnalysis")
    path = tmp_path / "traj.h5md"
    s, frames = write_run(path)
    n = len(frames[0]["id"])
    u = mda.Universe.empty(n, trajectory=True)
    u.load_new(str(path), format="H5MD", convert_units=False)
    assert len(u.trajectory) == N_FRAMES
    for ts, fr in zip(u.trajectory, frames):
        # MDAnalysis keeps float32 coordinates
        np.testing.assert_array_equal(ts.positions, fr["position"].astype(np.float32))
        np.testing.assert_array_equal(ts.velocities, fr["velocity"].astype(np.float32))
        np.testing.assert_array_equal(ts.forces, fr["force"].astype(np.float32))
        np.testing.assert_allclose(ts.dimensions, [L, L, L, 90, 90, 90])
        assert ts.data["step"] == fr["step"]
        assert ts.time == pytest.approx(fr["time"], rel=1e-6)


@needs_hdf5
def test_fields_subset(tmp_path):
    path = tmp_path / "sub.h5"
    _, frames = write_run(path, fields=["position", "velocity", "time"])
    with h5py.File(path, "r") as f:
        assert sorted(f["particles/atoms"].keys()) == ["box", "position", "velocity"]
        assert "edges" not in f["particles/atoms/box"]
        np.testing.assert_array_equal(f["particles/atoms/velocity/value"][2], frames[2]["velocity"])
        assert "time" in f["particles/atoms/position"]
    write_run(tmp_path / "nt.h5", fields="position")
    with h5py.File(tmp_path / "nt.h5", "r") as f:
        assert "time" not in f["particles/atoms/position"]
        assert "step" in f["particles/atoms/position"]


@needs_hdf5
def test_particle_number_change(tmp_path):
    s = make_system()
    h5 = marble.io.H5md(file_path=str(tmp_path / "t.h5"), system=s)
    h5.write()
    s.part.add(pos=[1.0, 1.0, 1.0])
    with pytest.raises(RuntimeError, match="number of particles changed"):
        h5.write()
    s.part.by_ids([max(s.part.all().id)]).remove()
    h5.write()
    h5.close()
    with pytest.raises(RuntimeError, match="closed"):
        h5.write()
    with h5py.File(tmp_path / "t.h5", "r") as f:
        assert f["particles/atoms/position/value"].shape[0] == 2


@needs_hdf5
def test_bad_parameters(tmp_path):
    s = make_system()
    with pytest.raises(ValueError, match="fields"):
        marble.io.H5md(file_path=str(tmp_path / "a.h5"), system=s, fields=["position", "charge"])
    with pytest.raises(ValueError, match="fields"):
        marble.io.H5md(file_path=str(tmp_path / "a.h5"), system=s, fields=[])
    with pytest.raises(ValueError, match="file_path"):
        marble.io.H5md(system=s)
    with pytest.raises(ValueError, match="file_path"):
        marble.io.H5md(file_path=3, system=s)
    with pytest.raises(ValueError, match="unknown parameter"):
        marble.io.H5md(file_path=str(tmp_path / "a.h5"), system=s, unit_system=None)
    with pytest.raises(ValueError, match="system"):
        marble.io.H5md(file_path=str(tmp_path / "a.h5"), system="not a system")
    with pytest.raises(RuntimeError, match="cannot create"):
        marble.io.H5md(file_path=str(tmp_path / "no" / "such" / "dir.h5"), system=s)
    empty = marble.System(box_l=[3, 3, 3])
    h5 = marble.io.H5md(file_path=str(tmp_path / "e.h5"), system=empty)
    with pytest.raises(RuntimeError, match="no particles"):
        h5.write()
    h5.close()
    assert os.path.exists(tmp_path / "e.h5")


@pytest.mark.skipif(marble.io.have_hdf5(), reason="built with HDF5")
def test_features_error_without_hdf5(tmp_path):
    s = make_system()
    with pytest.raises(marble.FeaturesError, match="H5MD"):
        marble.io.H5md(file_path=str(tmp_path / "t.h5"), system=s)
