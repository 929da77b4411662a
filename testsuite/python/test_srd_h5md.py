# labels: python
"""H5MD output of an SRD solvent (doc/io.md, doc/srd.md): the SRD particles
in their own group /particles/srd (position, velocity, species, id; rows by
increasing SRD id; box, step and time shared with /particles/atoms), written
next to an SRD colloid in /particles/atoms, read back with h5py equal the
simulation's values exactly; the `srd` field can be left out; appending
continues the SRD series; a change of the SRD particle number is refused."""
import os

import numpy as np
import pytest

import marble
import marble.io

try:
    import h5py
except ImportError:  # pragma: no cover
    h5py = None

pytestmark = [
    pytest.mark.skipif(not marble.has_features("SRD", "ROTATION", "MASS"),
                       reason="missing feature SRD, ROTATION or MASS"),
    pytest.mark.skipif(not marble.io.have_hdf5() or h5py is None,
                       reason="built without HDF5, or h5py missing"),
]

if marble.has_features("SRD"):
    import marble.srd as srd

L = 6.0


def make():
    s = marble.System(box_l=[L] * 3, time_step=0.05)
    s.cell_system.skin = 0.4
    s.srd = srd.SRDFluid(types=[0, 2], tau=0.1, angle=130, kT=1.0, seed=3)
    srd.add_fluid(s, density=3, type=0, kT=1.0, seed=4)
    srd.add_fluid(s, density=1, type=2, kT=1.0, seed=5)
    col = srd.add_colloid(s, pos=[L / 2] * 3, radius=1.2, mass=30.0, type=1, srd_types=(0, 2),
                          v=(0.2, 0.0, 0.0))
    return s, col


def by_id(s):
    ids = np.asarray(s.srd.ids)
    o = np.argsort(ids)
    return ids[o], s.srd.pos[o], s.srd.v[o], np.asarray(s.srd.type)[o]


def test_srd_group_reads_back(tmp_path):
    s, col = make()
    path = os.fspath(tmp_path / "srd.h5")
    h5 = marble.io.H5md(file_path=path, system=s)
    frames = []
    for _ in range(3):
        s.integrator.run(4)
        h5.write()
        frames.append((by_id(s), np.asarray(col.pos), s.step))
    h5.close()
    with h5py.File(path, "r") as f:
        g = f["particles/srd"]
        assert set(g) >= {"box", "position", "velocity", "species", "id"}
        assert "image" not in g and "force" not in g
        n = int(round(4 * L ** 3))
        assert g["position/value"].shape == (3, n, 3)
        assert list(g["box"].attrs["dimension"].flat) == [3]
        np.testing.assert_array_equal(g["box/edges/value"][:], f["particles/atoms/box/edges/value"][:])
        for k, ((ids, pos, v, typ), cpos, step) in enumerate(frames):
            np.testing.assert_array_equal(g["id/value"][k], ids)
            np.testing.assert_array_equal(g["position/value"][k], pos)
            np.testing.assert_array_equal(g["velocity/value"][k], v)
            np.testing.assert_array_equal(g["species/value"][k], typ)
            assert g["position/step"][k] == step == f["particles/atoms/position/step"][k]
            np.testing.assert_allclose(g["velocity/time"][k], 0.05 * step)
            # the colloid is an MD particle: /particles/atoms
            np.testing.assert_array_equal(f["particles/atoms/position/value"][k][0]
                                          + f["particles/atoms/image/value"][k][0] * L, cpos)
        assert set(np.unique(g["species/value"][0])) == {0, 2}


def test_srd_field_off_and_append(tmp_path):
    s, _ = make()
    path = os.fspath(tmp_path / "a.h5")
    h5 = marble.io.H5md(file_path=path, system=s, fields=["position", "velocity", "id"])
    h5.write()
    h5.close()
    with h5py.File(path, "r") as f:
        assert "srd" not in f["particles"]
    h5 = marble.io.H5md(file_path=path, system=s, fields=["position", "srd"])
    h5.write()
    h5.close()
    h5 = marble.io.H5md(file_path=path, system=s, fields=["position", "srd"], mode="append")
    s.integrator.run(2)
    h5.write()
    h5.close()
    with h5py.File(path, "r") as f:
        g = f["particles/srd"]
        assert set(g) == {"box", "position"}
        assert g["position/value"].shape[0] == 2
        ids, pos, _, _ = by_id(s)
        np.testing.assert_array_equal(g["position/value"][1], pos)


def test_srd_number_change_refused(tmp_path):
    s, _ = make()
    h5 = marble.io.H5md(file_path=os.fspath(tmp_path / "c.h5"), system=s)
    h5.write()
    srd.add_fluid(s, density=0, n=10, type=0, seed=9)
    with pytest.raises(RuntimeError, match="number of SRD particles changed"):
        h5.write()
    h5.close()
