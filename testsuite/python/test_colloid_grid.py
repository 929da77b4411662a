# labels: python
"""Two cell grids (doc/architecture.md, "Two cell grids"): the colloids of a
suspension (types whose pairs reach much farther than the solvent's) get a
coarse grid and a wide ghost layer of their own, so the solvent's cells keep
the solvent's range. The one pair list is the union of the solvent-grid pairs,
the colloid-colloid pairs and the colloid-solvent pairs; every consumer
(forces, energy, pressure, DPD stress, Shardlow, DPD-VV) reads it unchanged.

Checked here: the automatic choice of the large-range types; the pairs within
their cutoff are the same set with and without the split, each listed once
(also when the colloid range exceeds half the box, i.e. several periodic
images interact); forces with the DPD noise, energy, pressure tensor and DPD
stress agree with the one-grid list to round-off, and so do short VV
trajectories; 1 and 2 MPI ranks agree (the split on 2 ranks against one grid on
1 rank); bad input.

Run as a script (``python test_colloid_grid.py OUT.npz``) it is the MPI scene.
"""
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import marble

if not marble.has_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS"):
    pytest.skip("needs DPD, HAT, CONTACT, LUBRICATION, MASS", allow_module_level=True)

sus = marble.suspensions


def suspension(mode, L=9.0, phi=0.2, h_cut=1.0, seed=4):
    s = marble.System(box_l=[L] * 3)
    s.time_step = 1e-3
    s.cell_system.skin = 0.4
    s.cell_system.large_range_types = mode
    info = sus.setup_suspension(s, phi=phi, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=seed,
                                h_cut=h_cut)
    s.integrator.set_vv()
    return s, info


def small_box(mode, L=5.0):
    """Colloid pair range 3 + skin > L/2: several images of a colloid interact."""
    rng = np.random.default_rng(2)
    s = marble.System(box_l=[L] * 3)
    s.time_step = 1e-3
    s.cell_system.skin = 0.3
    s.cell_system.large_range_types = mode
    s.part.add(pos=[[1.0, 1.0, 1.0], [3.3, 2.9, 1.4]], type=[1, 1], mass=[5.0, 5.0])
    n = 150
    s.part.add(pos=rng.uniform(0, L, (n, 3)), type=[0] * n, v=rng.normal(size=(n, 3)) * 0.3)
    ia = s.non_bonded_inter
    ia[0, 0].hat.set_params(F_max=2.0, cutoff=1.0)
    ia[0, 0].dpd.set_params(weight_function=1, gamma=2.0, r_cut=1.0)
    ia[1, 0].hat.set_params(F_max=1.0, cutoff=0.6, offset=0.8)
    ia[1, 0].dpd.set_params(weight_function=1, gamma=2.0, r_cut=0.6, offset=0.8)
    ia[1, 1].hat.set_params(F_max=1.0, cutoff=1.3, offset=1.7)
    ia[1, 1].dpd.set_params(weight_function=1, gamma=2.0, r_cut=1.3, offset=1.7)
    s.thermostat.set_dpd(kT=0.5, seed=7)
    s.integrator.set_vv()
    return s


def by_id(s, key):
    p = s.part.all()
    order = np.argsort(p.id)
    return np.asarray(getattr(p, key))[order]


def interacting_pairs(s, cut):
    """The listed pairs within their cutoff (minimum image) as a sorted array, and
    the number of times each unordered pair is listed."""
    pairs = np.array(s._core.verlet_pairs(), int).reshape(-1, 2)
    pos = by_id(s, "pos")
    typ = by_id(s, "type")
    L = np.asarray(s.box_l)
    d = pos[pairs[:, 0]] - pos[pairs[:, 1]]
    d -= L * np.round(d / L)
    r = np.linalg.norm(d, axis=1)
    keep = r < cut[typ[pairs[:, 0]], typ[pairs[:, 1]]]
    inside = np.sort(pairs[keep], axis=1)
    uniq, counts = np.unique(inside, axis=0, return_counts=True)
    return uniq, counts


def suspension_cutoff_matrix(info):
    R = info["radius"]
    cut = np.zeros((2, 2))
    cut[0, 0] = 1.0
    cut[0, 1] = cut[1, 0] = info["cutoff_centre"]
    cut[1, 1] = 2 * R + max(info["h_cut"], 1.0, info["delta"])
    return cut


def test_auto_choice():
    s, info = suspension("auto")
    s.integrator.run(0)
    st = s.cell_system.get_state()
    assert st["large_range_types"] == [1]
    # the solvent grid keeps the solvent's range; the colloids' ranges are their own
    assert st["pair_range_small"] == pytest.approx(1.0 + 0.4)
    assert st["pair_range_large"] == pytest.approx(2.0 + 1.0 + 0.4)
    assert st["pair_range_large_small"] == pytest.approx(info["cutoff_centre"] + 0.4)
    s2, _ = suspension(None)
    s2.integrator.run(0)
    st2 = s2.cell_system.get_state()
    assert st2["large_range_types"] == [] and st2["pair_range_small"] == pytest.approx(3.4)
    assert s2.cell_system.large_range_types is None


def test_no_split_for_one_range_scale():
    # a binary WCA/LJ-like mixture of one range scale: no split, the old list
    if not marble.has_features("LENNARD_JONES"):
        pytest.skip("needs LENNARD_JONES")
    rng = np.random.default_rng(1)
    s = marble.System(box_l=[8.0] * 3)
    s.time_step = 1e-3
    s.part.add(pos=rng.uniform(0, 8, (200, 3)), type=rng.integers(0, 2, 200))
    ia = s.non_bonded_inter
    ia[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5, shift="auto")
    ia[1, 1].lennard_jones.set_params(epsilon=1.0, sigma=1.5, cutoff=3.75, shift="auto")
    ia[0, 1].lennard_jones.set_params(epsilon=1.0, sigma=1.25, cutoff=3.1, shift="auto")
    s.integrator.run(0)
    assert s.cell_system.get_state()["large_range_types"] == []


def test_same_interacting_pairs():
    for h_cut in (0.3, 1.0):
        s1, info = suspension("auto", h_cut=h_cut)
        s0, _ = suspension(None, h_cut=h_cut)
        cut = suspension_cutoff_matrix(info)
        p1, c1 = interacting_pairs(s1, cut)
        p0, c0 = interacting_pairs(s0, cut)
        assert np.all(c1 == 1) and np.all(c0 == 1), "a pair listed twice"
        np.testing.assert_array_equal(p1, p0)
        assert len(p1) > 1000
        # the split list is shorter (the solvent's candidates are not within 2R + h_cut)
        n1 = len(s1._core.verlet_pairs())
        n0 = len(s0._core.verlet_pairs())
        assert n1 < 0.5 * n0, (n1, n0)


def assert_close(a, b, rtol=1e-10):
    a, b = np.asarray(a, float), np.asarray(b, float)
    scale = max(1.0, np.abs(b).max())
    assert np.abs(a - b).max() <= rtol * scale, np.abs(a - b).max() / scale


@pytest.mark.parametrize("scene", ["suspension", "small_box"])
def test_forces_and_observables_agree(scene):
    make = (lambda m: suspension(m)[0]) if scene == "suspension" else small_box
    s1, s0 = make("auto"), make(None)
    for s in (s1, s0):
        s.integrator.run(0)
    if scene == "small_box":
        assert s1.cell_system.get_state()["large_range_types"] == [1]
    assert_close(by_id(s1, "f"), by_id(s0, "f"))
    e1, e0 = s1.analysis.energy(), s0.analysis.energy()
    assert e1["total"] == pytest.approx(e0["total"], rel=1e-12)
    assert_close(s1.analysis.pressure_tensor()["total"], s0.analysis.pressure_tensor()["total"])
    assert_close(s1.analysis.dpd_stress(), s0.analysis.dpd_stress())
    # short VV trajectories with the DPD noise: round-off apart
    for s in (s1, s0):
        s.integrator.run(30)
    assert_close(by_id(s1, "pos"), by_id(s0, "pos"), 1e-9)
    assert_close(by_id(s1, "v"), by_id(s0, "v"), 1e-8)


def test_shardlow_runs_and_conserves_momentum():
    s, _ = suspension("auto")
    s.integrator.set_shardlow()
    p0 = np.asarray(s.analysis.linear_momentum())
    s.integrator.run(50)
    p1 = np.asarray(s.analysis.linear_momentum())
    # the conservative kernels and the pair updates conserve momentum pair by pair
    assert np.abs(p1 - p0).max() < 1e-9


def test_explicit_types_and_bad_input():
    s, _ = suspension([1])
    s.integrator.run(0)
    assert s.cell_system.get_state()["large_range_types"] == [1]
    assert s.cell_system.large_range_types == [1]
    for bad in ("yes", [0.5], ["a"], [-1], 3.0):
        with pytest.raises(ValueError, match="large_range_types"):
            s.cell_system.large_range_types = bad
    # every type large-range: nothing left for the solvent grid, so no split
    s.cell_system.large_range_types = [0, 1]
    s.integrator.run(0)
    assert s.cell_system.get_state()["large_range_types"] == []


def test_pickle_keeps_the_choice():
    import pickle
    s, _ = suspension(None)
    s.integrator.run(0)
    s2 = pickle.loads(pickle.dumps(s))
    assert s2.cell_system.large_range_types is None
    s2.integrator.run(1)
    assert s2.cell_system.get_state()["large_range_types"] == []


MPIEXEC = shutil.which("mpiexec")


def mpi_scene(out):
    """Every rank runs this: the split suspension, 20 VV steps with DPD noise."""
    s, _ = suspension(None if os.environ.get("MARBLE_GRID_MODE") == "none" else "auto")
    s.integrator.run(20)
    p = s.part.all()
    order = np.argsort(p.id)
    data = dict(pos=np.asarray(p.pos)[order], v=np.asarray(p.v)[order], f=np.asarray(p.f)[order],
                types=np.array(s.cell_system.get_state()["large_range_types"]))
    if marble.mpi_rank() == 0:
        np.savez(out, **data)


@pytest.mark.skipif(MPIEXEC is None or "MPI" not in marble._marble.build_options(),
                    reason="no mpiexec or built without MPI")
def test_one_vs_two_ranks():
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    res = {}
    with tempfile.TemporaryDirectory() as d:
        for ranks, mode in ((1, "none"), (2, "auto")):
            out = os.path.join(d, f"{ranks}.npz")
            cmd = [MPIEXEC, "-n", str(ranks), sys.executable, os.path.abspath(__file__), out]
            p = subprocess.run(cmd, env=dict(env, MARBLE_GRID_MODE=mode), capture_output=True,
                               text=True, timeout=600)
            assert p.returncode == 0, f"{' '.join(cmd)} failed:\n{p.stdout}\n{p.stderr}"
            with np.load(out) as f:
                res[ranks] = {k: f[k] for k in f.files}
    assert list(res[2]["types"]) == [1] and list(res[1]["types"]) == []
    for key, tol in (("pos", 1e-9), ("v", 1e-8), ("f", 1e-7)):
        assert_close(res[2][key], res[1][key], tol)


if __name__ == "__main__":
    mpi_scene(sys.argv[1])
