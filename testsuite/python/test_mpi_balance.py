# labels: python mpi
"""Domain cuts and load balance (doc/parallel.md "Load balance"): uneven
domains set by hand or by `cell_system.balance()` / `set_load_balance()` give
the trajectory of one rank to round-off (the physics does not depend on the
decomposition), every rank owns exactly the particles inside its domain, a
balance by particles equalises the counts, and bad cuts are refused. Each
scene runs in its own `mpiexec` (testsuite/python/mpi_scenes.py)."""
import glob
import os
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import marble
from test_mpi import MPIEXEC, SCENES, assert_same_trajectory, mpi_env, needs

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
]


def run(scene, ranks, **extra_env):
    """The scene's output (rank 0) and every rank's own state (if it wrote one)."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.npz")
        cmd = [MPIEXEC, "-n", str(ranks), sys.executable, SCENES, scene, out]
        p = subprocess.run(cmd, env=mpi_env(**extra_env), capture_output=True, text=True, timeout=1500)
        assert p.returncode == 0, f"{' '.join(cmd)} failed:\n{p.stdout}\n{p.stderr}"
        with np.load(out) as f:
            data = {k: f[k] for k in f.files}
        ranks_state = []
        for path in sorted(glob.glob(out + ".rank*.npz"), key=lambda q: int(q.split("rank")[-1][:-4])):
            with np.load(path) as f:
                ranks_state.append({k: f[k] for k in f.files})
        return data, ranks_state


def check_ownership(states, n_total, box_l):
    """Every particle on exactly one rank, inside that rank's domain, which
    is the box between its cuts."""
    ids = np.concatenate([s["local_ids"] for s in states])
    assert len(ids) == n_total and len(np.unique(ids)) == n_total
    for r, s in enumerate(states):
        grid = tuple(int(g) for g in s["grid"])
        coords = (r // (grid[1] * grid[2]), (r // grid[2]) % grid[1], r % grid[2])
        pos = dict(zip(s["all_ids"].tolist(), s["all_pos"]))
        x_local = np.array([pos[i] for i in s["local_ids"].tolist()]).reshape(-1, 3)
        for d, cuts in enumerate((s["cuts_x"], s["cuts_y"], s["cuts_z"])):
            assert len(cuts) == grid[d] + 1 and cuts[0] == 0.0 and cuts[-1] == box_l[d]
            lo, hi = cuts[coords[d]], cuts[coords[d] + 1]
            assert s["dom_lo"][d] == lo and abs(s["dom_lo"][d] + s["dom_size"][d] - hi) <= 1e-12 * box_l[d]
            x = np.mod(x_local[:, d], box_l[d])
            assert np.all(x >= lo - 1e-9) and np.all(x < hi + 1e-9), (r, d, x.min(), x.max(), lo, hi)


@needs("MARBLE", "DPD")
def test_uneven_cuts_by_hand_give_the_one_rank_trajectory():
    one, _ = run("cuts_marble", 1)
    for ranks in (2, 3):
        many, states = run("cuts_marble", ranks)
        assert len(states) == ranks
        cuts = states[0]["cuts_x"]
        expect = 8.0 * (np.arange(ranks + 1) / ranks) ** 1.4
        np.testing.assert_allclose(cuts, expect, rtol=0, atol=1e-12)
        check_ownership(states, len(one["ids"]) - 0, [8.0] * 3)  # (the marble's beads are particles too)
        # the domains differ in size, so the counts do (the narrowest the fewest)
        counts = [len(s["local_ids"]) for s in states]
        assert counts[0] < counts[-1]
        assert_same_trajectory(one, many)
        np.testing.assert_allclose(many["cpos"], one["cpos"], rtol=0, atol=1e-9)
        np.testing.assert_allclose(many["comega"], one["comega"], rtol=0, atol=1e-9)
        assert abs(many["energy"] - one["energy"]) <= 1e-9 * abs(one["energy"])


@needs("DPD")
def test_balance_by_particles_equalises_the_counts():
    one, _ = run("balance_particles", 1)
    assert not bool(one["moved"])  # one rank: nothing to balance
    two, states = run("balance_particles", 2)
    n = len(one["ids"])
    # before: the crowded lower half holds ~(2/3 + 1/3 * 1/2 ... ) of the particles
    before = int(states[0]["n_before"])
    assert before > 0.7 * n
    assert float(two["imbalance"]) == pytest.approx(2 * before / n, rel=1e-12)
    assert bool(two["moved"])
    check_ownership(states, n, [8.0] * 3)
    counts = np.array([len(s["local_ids"]) for s in states])
    # equal up to the histogram's resolution: one bin (L / 128) of the crowded
    # region holds ~ n * (2/3) / (128 / 3) particles
    assert abs(counts[0] - counts[1]) <= 2 * n * (2 / 3) * 3 / 128, counts
    assert 1.0 < states[0]["cuts_x"][1] < 8.0 / 3
    assert_same_trajectory(one, two)


@needs("DPD")
def test_balance_by_pairs_gives_the_denser_side_fewer_particles():
    """by="pairs" weights a particle by 1 + its listed pairs: the crowded
    third (three times the density, about three times the pairs per
    particle) gets fewer particles than by="particles" gives it."""
    one, _ = run("balance_pairs", 1)
    two, states = run("balance_pairs", 2)
    _, by_count = run("balance_particles", 2)
    assert bool(two["moved"])
    check_ownership(states, len(one["ids"]), [8.0] * 3)
    counts = [len(s["local_ids"]) for s in states]
    assert counts[0] < 0.45 * sum(counts), counts
    assert states[0]["cuts_x"][1] < by_count[0]["cuts_x"][1] - 0.1
    assert_same_trajectory(one, two)


@needs("DPD")
def test_automatic_balance_by_time():
    one, _ = run("balance_auto", 1)
    assert int(one["n_balances"]) == 0
    two, states = run("balance_auto", 2)
    assert int(two["n_balances"]) >= 1
    check_ownership(states, len(one["ids"]), [8.0] * 3)
    cut = states[0]["cuts_x"][1]
    assert cut != 4.0 and 1.4 <= cut <= 8.0 - 1.4  # moved, each domain >= the pair range
    assert_same_trajectory(one, two)


@needs("DPD")
def test_automatic_balance_by_time_under_shardlow():
    one, _ = run("balance_auto_shardlow", 1)
    two, states = run("balance_auto_shardlow", 2)
    assert int(two["n_balances"]) >= 1
    check_ownership(states, len(one["ids"]), [8.0] * 3)
    cut = states[0]["cuts_x"][1]
    assert cut != 4.0 and 2 * 1.4 <= cut <= 8.0 - 2 * 1.4  # moved, each domain >= twice the pair range
    # Shardlow's pair order follows the decomposition (test_mpi.py): the
    # trajectories differ, the pair updates still conserve momentum exactly
    for data in (one, two):
        assert np.abs(data["dp"]).max() <= 1e-9 * len(data["ids"])


@needs("DPD")
def test_bad_cuts_are_refused():
    data, _ = run("cuts_bad", 2)
    msgs = [str(m) for m in data["msgs"]]
    for m, what in zip(msgs[:6], ("must have node_grid[0] + 1 = 3 positions", "strictly increasing",
                                  "must run from 0 to box_l[0]", "must run from 0 to box_l[0]",
                                  "three entries", "three entries")):
        assert what in m, (what, m)
    np.testing.assert_array_equal(data["unchanged"], [0.0, 4.0, 8.0])
    assert "cannot integrate with the Shardlow integrator" in msgs[6] and "2 wide along axis 0" in msgs[6]


def _close(one, many, tol, keys=("pos", "v", "f")):
    np.testing.assert_array_equal(one["ids"], many["ids"])
    for key in keys:
        scale = max(1.0, np.abs(one[key]).max())
        err = np.abs(many[key] - one[key]).max() / scale
        assert err <= tol, f"{key}: max deviation {err:.3g} (relative to {scale:.3g})"


@pytest.mark.parametrize("scene, features, tol, keys", [
    ("dpd_vv", ("MARBLE", "DPD"), 1e-9, ("pos", "v", "f")),
    ("suspension", ("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS"), 1e-8, ("pos", "v", "f")),
    ("lees_edwards", ("DPD",), 1e-9, ("pos", "v", "f")),
    ("respa", ("MARBLE", "DPD"), 1e-9, ("pos", "v", "f")),
    # SRD: the same bits on any decomposition (test_srd_mpi.py)
    ("srd_colloid", ("SRD",), 0.0, ("pos", "v")),
    ("srd_walls_colloid", ("SRD",), 0.0, ("pos", "v")),
])
def test_other_scenes_on_uneven_domains(scene, features, tol, keys):
    """test_mpi.py's scenes on uneven domains (mpi_scenes.py cuts_of_SCENE,
    planes at (j / p)^1.4 of the box) against one rank."""
    if not marble.has_features(*features):
        pytest.skip(f"missing feature(s) {features}")
    one, _ = run(scene, 1)
    for ranks in (2, 3):
        many, _ = run("cuts_of_" + scene, ranks)
        split = [many["domain_cuts_" + a] for a in "xyz" if len(many["domain_cuts_" + a]) > 2]
        assert len(split) == 1 and len(split[0]) == ranks + 1  # one axis split into `ranks` domains
        widths = np.diff(split[0])
        assert widths.max() - widths.min() > 0.3 * widths.max(), split  # uneven
        _close(one, many, tol, keys)


@needs("SRD")
def test_balance_counts_srd_particles():
    """An SRD fluid with 2/3 of its particles in the lowest third of a 12 x 8 x
    8 box: balance(by="particles") puts the planes at the count quantiles
    (x (7/36) = j/p below x = 4) and the SRD trajectory stays that of one rank,
    to the bit."""
    one, _ = run("srd_balance", 1)
    assert not bool(one["moved"])
    for ranks in (2, 3):
        many, _ = run("srd_balance", ranks)
        assert bool(many["moved"])
        expect = [36 / 7 * j / ranks for j in range(1, ranks)]
        np.testing.assert_allclose(many["domain_cuts_x"][1:-1], expect, rtol=0, atol=2 * 12 / (64 * ranks))
        for key in ("ids", "pos", "v"):
            np.testing.assert_array_equal(many[key], one[key], err_msg=key)


@needs("MARBLE", "DPD", "HAT")
def test_checkpoint_keeps_the_planes(tmp_path):
    """test_mpi.py's 2-rank checkpoint scene on uneven domains: the restart
    (a new mpiexec that does not set the planes) continues bit for bit, so
    the planes came back from the checkpoint (format 6)."""
    ref, _ = run("cuts_of_ckpt_reference", 2, MARBLE_CKPT_DIR=str(tmp_path))
    got, _ = run("ckpt_restart", 2, MARBLE_CKPT_DIR=str(tmp_path))
    assert len(ref["domain_cuts_x"]) == 3 and ref["domain_cuts_x"][1] != 0.5 * ref["domain_cuts_x"][2]
    for key in ref:
        np.testing.assert_array_equal(got[key], ref[key], err_msg=key)


@needs("DPD")
def test_checkpoint_keeps_the_automatic_balance(tmp_path):
    """The automatic balance (by pairs, every 10 steps) is part of the
    checkpoint (format 7): a new mpiexec that loads it and sets nothing
    balances at the same steps, so it ends on the same planes, with the same
    count of balances, and bit for bit on the same trajectory as the
    uninterrupted run."""
    ref, _ = run("balance_ckpt_reference", 2, MARBLE_CKPT_DIR=str(tmp_path))
    got, _ = run("balance_ckpt_restart", 2, MARBLE_CKPT_DIR=str(tmp_path))
    assert int(ref["every"]) == 10 and str(ref["by"]) == "pairs" and int(ref["n_balances"]) >= 4
    for key in ref:
        np.testing.assert_array_equal(got[key], ref[key], err_msg=key)


def test_balance_arguments_checked_on_one_rank():
    s = marble.System(box_l=[6.0] * 3)
    cs = s.cell_system
    for kwargs, what in ((dict(by="work"), "'by'"), (dict(by=None), "'by'"), (dict(damping=0.0), "'damping'"),
                         (dict(damping=1.5), "'damping'"), (dict(threshold=-0.1), "'threshold'")):
        with pytest.raises(ValueError, match=what):
            cs.balance(**kwargs)
    with pytest.raises(ValueError, match="'every'"):
        cs.set_load_balance(-1)
    with pytest.raises(ValueError, match="'every'"):
        cs.set_load_balance(2.5)
    assert cs.get_load_balance()["every"] == 0
    cs.set_load_balance(50, by="particles", damping=0.25, threshold=0.1)
    assert cs.get_load_balance() == {"every": 50, "by": "particles", "damping": 0.25, "threshold": 0.1,
                                     "n_balances": 0}
    # one rank: the domain is the box, whatever the cuts
    cs.domain_cuts = [None, [0.0, 6.0], None]
    assert [c.tolist() for c in cs.domain_cuts] == [[0.0, 6.0]] * 3
    assert cs.balance()["moved"] is False
