# labels: python
"""cell_system.list_check (doc/benchmarks.md, "The Verlet list's life"): with
"pairs" a Verlet list outlives the half-skin mark until a pair may be missing
from it. The forces it gives are those of a list built afresh at the current
positions, at every step of a run in which it was kept longer than the
half-skin rule would keep it; where the test does not apply it falls back to
the half-skin rule; bad values are refused."""
import pickle

import numpy as np
import pytest

import marble

needs_hat = pytest.mark.skipif(not marble.has_features("HAT"), reason="needs HAT")
needs_hat_dpd = pytest.mark.skipif(not marble.has_features("HAT", "DPD"), reason="needs HAT, DPD")


def fluid(check, L=7.0, seed=3):
    """A soft-sphere (hat, a = 25) fluid at rho = 3, NVE, kT about 1; the box
    is more than 3 pair ranges wide (the pair test applies)."""
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    s.cell_system.list_check = check
    n = int(round(3 * L**3))
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    s.integrator.run(30)
    return s


@needs_hat
def test_kept_lists_give_the_forces_of_fresh_lists():
    s = fluid("pairs")
    assert s.cell_system.get_state()["pair_test_applies"]
    r0 = s.cell_system.get_state()["verlet_rebuilds"]
    fmax = 0.0
    for _ in range(40):
        s.integrator.run(1)
        f = np.array(s.part.all().f)
        fresh = pickle.loads(pickle.dumps(s))  # the same list (rebuilt at the build's positions)
        fresh.cell_system.skin = 0.4  # a new list at the current positions
        fresh.integrator.run(0)
        np.testing.assert_allclose(np.array(fresh.part.all().f), f, rtol=0, atol=1e-11)
        fmax = max(fmax, float(np.abs(f).max()))
    assert fmax > 1.0  # (the forces are not trivially zero)
    kept = s.cell_system.get_state()["verlet_rebuilds"] - r0
    # the same 40 steps under the half-skin rule rebuild more often: the
    # lists above were kept past half the skin
    h = fluid("half_skin")
    r0 = h.cell_system.get_state()["verlet_rebuilds"]
    h.integrator.run(40)
    half = h.cell_system.get_state()["verlet_rebuilds"] - r0
    assert kept < 0.85 * half, (kept, half)
    # NVE from the same start: both runs keep its total energy
    e_pairs, e_half = s.analysis.energy()["total"], h.analysis.energy()["total"]
    assert abs(e_pairs - e_half) < 1e-6 * abs(e_half), (e_pairs, e_half)


@needs_hat_dpd
def test_where_the_pair_test_does_not_apply():
    # a box under 3 pair ranges: the half-skin rule
    s = fluid("pairs", L=4.0)
    assert not s.cell_system.get_state()["pair_test_applies"]
    # Shardlow and Brownian dynamics keep the half-skin rule too
    s = fluid("pairs")
    s.thermostat.set_dpd(kT=1.0, seed=1)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.integrator.set_shardlow()
    assert not s.cell_system.get_state()["pair_test_applies"]
    s.integrator.set_vv()
    assert s.cell_system.get_state()["pair_test_applies"]
    s.cell_system.list_check = "half_skin"
    assert not s.cell_system.get_state()["pair_test_applies"]


def test_bad_values_are_refused():
    s = marble.System(box_l=[8.0] * 3)
    assert s.cell_system.list_check == "pairs"
    for bad in ("exact", "", None, 0, True):
        with pytest.raises(ValueError, match="list_check"):
            s.cell_system.list_check = bad
        assert s.cell_system.list_check == "pairs"
    s.cell_system.list_check = "half_skin"
    assert s.cell_system.get_state()["list_check"] == "half_skin"


@needs_hat
def test_restart_continues_bit_for_bit():
    """A checkpoint (pickle) taken at any step of a list's life, past the
    half-skin mark included, continues bit for bit: the test's decisions
    depend only on the saved positions and those at the list's build."""
    s = fluid("pairs")
    copies = []
    for _ in range(8):  # more than one list's life
        copies.append(pickle.dumps(s))
        s.integrator.run(1)
    s.integrator.run(30)
    want = {k: np.array(getattr(s.part.all(), k)) for k in ("id", "pos", "v", "f")}
    for k, blob in enumerate(copies):
        c = pickle.loads(blob)
        for _ in range(8 - k):
            c.integrator.run(1)
        c.integrator.run(30)
        for key, ref in want.items():
            assert np.array(getattr(c.part.all(), key)).tobytes() == ref.tobytes(), (k, key)
