# labels: python mpi
"""Domain decomposition (doc/parallel.md): the same scene on 1 and 2 (and 3)
MPI ranks. The DPD and marble noise is counter-based (keyed by step and
particle ids), so the trajectories agree to round-off: only the order of the
force sums differs between decompositions. Each scene runs in its own
`mpiexec` (testsuite/python/mpi_scenes.py)."""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import marble

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.join(HERE, "mpi_scenes.py")
MPIEXEC = shutil.which("mpiexec")

pytestmark = [
    pytest.mark.skipif(MPIEXEC is None, reason="no mpiexec"),
    pytest.mark.skipif("MPI" not in marble._marble.build_options(), reason="built without MPI"),
]


def needs(*features):
    return pytest.mark.skipif(not marble.has_features(*features),
                              reason=f"missing feature(s) {', '.join(features)}")


def mpi_env(**extra):
    """Environment for mpiexec: allowed as root (CI), more ranks than cores."""
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1", **extra)


def run(scene, ranks, **extra_env):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out.npz")
        env = mpi_env(**extra_env)
        cmd = [MPIEXEC, "-n", str(ranks), sys.executable, SCENES, scene, out]
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=1500)  # Open MPI polls: slow when the cores are shared (ctest allows 1800 s)
        assert p.returncode == 0, f"{' '.join(cmd)} failed:\n{p.stdout}\n{p.stderr}"
        with np.load(out) as f:
            return {k: f[k] for k in f.files}


def mean_and_block_error(x, blocks=10):
    """The mean of the series @p x and its error from @p blocks block means."""
    b = np.asarray(x).reshape(blocks, -1).mean(axis=1)
    return float(np.mean(x)), float(b.std(ddof=1) / np.sqrt(blocks))


def assert_same_trajectory(a, b, tol=1e-9):
    np.testing.assert_array_equal(a["ids"], b["ids"])
    for key in ("pos", "v", "f"):
        scale = max(1.0, np.abs(a[key]).max())
        err = np.abs(a[key] - b[key]).max() / scale
        assert err <= tol, f"{key}: max deviation {err:.3g} (relative to {scale:.3g})"


@pytest.fixture(scope="module")
def marble_runs():
    return {n: run("marble", n) for n in (1, 2)}


@needs("MARBLE", "DPD")
def test_marble_trajectory_1_vs_2_ranks(marble_runs):
    one, two = marble_runs[1], marble_runs[2]
    assert int(one["ranks"]) == 1 and int(two["ranks"]) == 2
    assert tuple(two["node_grid"]) == (2, 1, 1)
    assert_same_trajectory(one, two)
    for key in ("cpos", "cv", "comega", "ctorque"):
        np.testing.assert_allclose(two[key], one[key], rtol=0, atol=1e-9, err_msg=key)
    assert abs(two["energy"] - one["energy"]) <= 1e-9 * abs(one["energy"])


@needs("MARBLE", "DPD")
def test_marble_trajectory_4_and_8_ranks(marble_runs):
    """The half shell on a 2 x 2 x 1 and a 2 x 2 x 2 node grid: every pair across
    ranks (also across the periodic faces, all three axes split) computed once."""
    for n, grid in ((4, (2, 2, 1)), (8, (2, 2, 2))):
        res = run("marble", n)
        assert tuple(res["node_grid"]) == grid
        assert_same_trajectory(marble_runs[1], res)
        for key in ("cpos", "cv", "comega", "ctorque"):
            np.testing.assert_allclose(res[key], marble_runs[1][key], rtol=0, atol=1e-9, err_msg=key)


@needs("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS")
def test_large_range_types_on_1_4_8_ranks():
    """Colloids with their own large-range grid (full shell, pairs by id) in a
    half-shell solvent: 1 rank (one grid) vs 4 and 8 ranks (the split)."""
    one = run("suspension", 1)
    assert list(one["types"]) == []
    for n in (4, 8):
        res = run("suspension", n)
        assert list(res["types"]) == [1]
        assert_same_trajectory(one, res, tol=1e-8)


@needs("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS", "TRANS_DPD", "ROTATION")
@pytest.mark.parametrize("shared", ["full", "split"])
def test_stick_suspension_shared_shells_1_vs_2_and_4_ranks(shared):
    """Stick colloids whose friction shells overlap (phi = 0.25): the "split"
    treatment (and "off", setup_suspension's default, in
    test_lees_edwards_mpi.py) counts every colloid around a bead, also those on
    another rank (ghosts), so 2 and 4 ranks give the 1-rank trajectory; "full"
    (the default before session 36) needs no count."""
    one = run(f"suspension_stick_{shared}", 1)
    for n in (2, 4):
        res = run(f"suspension_stick_{shared}", n)
        assert res["node_grid"].prod() == n
        assert_same_trajectory(one, res, tol=1e-8)
        for key in ("comega", "ctorque"):
            scale = max(1.0, np.abs(one[key]).max())
            assert np.abs(res[key] - one[key]).max() / scale <= 1e-8, key


@needs("MARBLE", "DPD")
def test_particles_cross_domain_boundaries(marble_runs):
    # in 100 steps of a DPD fluid (thermal speed ~ 1) many beads change rank
    assert int(marble_runs[2]["migrated"]) > 50
    np.testing.assert_allclose(marble_runs[2]["momentum"], marble_runs[1]["momentum"], atol=1e-9)


@needs("MARBLE", "DPD")
def test_marble_wider_than_a_domain():
    one, two, three = (run("marble_big", n) for n in (1, 2, 3))
    assert tuple(three["node_grid"]) == (3, 1, 1)
    for other in (two, three):
        assert_same_trajectory(one, other)
        for key in ("cpos", "cv", "comega"):
            np.testing.assert_allclose(other[key], one[key], rtol=0, atol=1e-9, err_msg=key)


@needs("LENNARD_JONES")
def test_lj_energy_conserved_and_equal():
    one, two = run("lj", 1), run("lj", 2)
    assert_same_trajectory(one, two)
    assert abs(two["energy"] - two["e0"]) < 1e-3 * abs(two["e0"])
    assert abs(two["pressure"] - one["pressure"]) < 1e-9 * abs(one["pressure"])


@needs("TUNABLE_SLIP", "LENNARD_JONES", "EXTERNAL_FORCE", "DPD")
def test_walls_channel():
    """Tunable-slip walls and a body force; the box is 4 x 4 x 8, so 2 ranks split z
    (the non-periodic axis): beads near a wall interact with it on their own rank."""
    one, two = run("channel", 1), run("channel", 2)
    assert tuple(two["node_grid"]) == (1, 1, 2)
    assert_same_trajectory(one, two)


@needs("DPD")
def test_checkpoint_restart_on_two_ranks_bit_exact(tmp_path):
    """n steps + checkpoint + n steps == restart in a new 2-rank process + n steps,
    bit for bit (particles, forces, torques, correlator, mean/variance)."""
    ref = run("ckpt_reference", 2, MARBLE_CKPT_DIR=str(tmp_path))
    got = run("ckpt_restart", 2, MARBLE_CKPT_DIR=str(tmp_path))
    for key in ref:
        np.testing.assert_array_equal(got[key], ref[key], err_msg=key)


def test_io_on_two_ranks():
    """test_io_mpi.py (H5MD rows gathered from both ranks' locals, in-process
    checkpoint continuation) under mpiexec -n 2."""
    env = mpi_env()
    with tempfile.TemporaryDirectory() as d:
        cmd = [MPIEXEC, "-n", "2", sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
               os.path.join(HERE, "test_io_mpi.py")]
        p = subprocess.run(cmd, env=env, cwd=d, capture_output=True, text=True, timeout=1500)  # Open MPI polls: slow when the cores are shared (ctest allows 1800 s)
    assert p.returncode == 0, f"{p.stdout}\n{p.stderr}"
    assert p.stdout.count("passed") == 2, p.stdout


@needs("DPD")
def test_uncaught_exception_on_one_rank_aborts_all():
    env = mpi_env()
    with tempfile.TemporaryDirectory() as d:
        cmd = [MPIEXEC, "-n", "2", sys.executable, SCENES, "uncaught", os.path.join(d, "o.npz")]
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    assert p.returncode != 0
    assert "raised on rank 1 only" in p.stderr


@needs("MARBLE", "DPD")
def test_sample_on_two_ranks():
    """A paper sample (colloid set-up, drag and equilibrium runs, correlators,
    JSON + PNG written by rank 0) runs under mpiexec -n 2 in its short test mode."""
    env = mpi_env(MARBLE_SAMPLE_TEST="1", MPLBACKEND="Agg")
    sample = os.path.join(HERE, "..", "..", "samples", "marble_diffusion_vs_gamma.py")
    with tempfile.TemporaryDirectory() as d:
        cmd = [MPIEXEC, "-n", "2", sys.executable, sample, "--out", d]
        p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=1500)  # Open MPI polls: slow when the cores are shared (ctest allows 1800 s)
        assert p.returncode == 0, p.stdout + p.stderr
        assert sorted(os.listdir(d)) == ["marble_diffusion_vs_gamma.json",
                                         "marble_diffusion_vs_gamma.png"]


@needs("DPD")
def test_blowup_stops_every_rank_cleanly():
    res = run("blowup", 2)
    msg = str(res["msg"])
    # particle 7 or a neighbour hit by its friction: the first offender on the lowest rank
    assert re.search(r"integration stopped at step 1: particle \d+ moved", msg), msg
    assert "reduce time_step" in msg
    assert int(res["step"]) == 10  # the refused step changed nothing; 10 more steps ran


@needs("DPD")
def test_list_check_pairs_1_vs_2_vs_3_ranks():
    """cell_system.list_check = "pairs" on several ranks: the same trajectory
    as on one rank (1e-9) and the same rebuild steps, fewer than under the
    half-skin rule (so the lists were kept past it, across the domain faces)."""
    runs = {n: run("fluid_pairs", n) for n in (1, 2, 3)}
    for n in (2, 3):
        assert bool(runs[n]["pair_test"])
        assert_same_trajectory(runs[1], runs[n])
        assert int(runs[n]["rebuilds"]) == int(runs[1]["rebuilds"])
    half = run("fluid_half_skin", 2)
    assert int(runs[2]["rebuilds"]) < int(half["rebuilds"]), (runs[2]["rebuilds"], half["rebuilds"])
    assert_same_trajectory(runs[2], half, tol=1e-6)  # (another list order: round-off, grown over 150 steps)


def _hat_forces(pos, L, f_max=25.0, cut=1.0):
    """The hat forces of all particles by brute force (minimum images)."""
    f = np.zeros_like(pos)
    for i in range(len(pos)):
        d = pos[i] - pos
        d -= L * np.round(d / L)
        r = np.linalg.norm(d, axis=1)
        m = (r < cut) & (r > 0)
        f[i] = (f_max * (1.0 - r[m] / cut) / r[m])[:, None].T @ d[m]
    return f


@needs("DPD", "HAT")
def test_list_check_pairs_under_shardlow_2_and_3_ranks():
    """cell_system.list_check = "pairs" under Shardlow on several ranks (the
    sweep's order, and so the trajectory, follows the decomposition): at every
    step the forces are those of every pair in range (brute force over the
    minimum images: no pair is missing from a kept list, across the domain
    faces included), the momentum is conserved, and the lists are rebuilt
    less often than under the half-skin rule."""
    for n in (2, 3):
        r = run("shardlow_pairs", n)
        assert bool(r["pair_test"])
        L = float(r["L"])
        for k in range(0, len(r["pos"]), 3):
            np.testing.assert_allclose(r["f"][k], _hat_forces(r["pos"][k], L), rtol=0, atol=1e-9,
                                       err_msg=f"{n} ranks, step {k + 1}")
        assert np.abs(r["f"]).max() > 1.0
        np.testing.assert_allclose(r["p1"], r["p0"], rtol=0, atol=1e-9, err_msg=f"{n} ranks: momentum")
        half = run("shardlow_half_skin", n)
        assert int(r["rebuilds"]) < 0.9 * int(half["rebuilds"]), (n, r["rebuilds"], half["rebuilds"])


@needs("DPD", "HAT")
@pytest.mark.parametrize("integrator", ["vv", "shardlow"])
def test_list_check_finds_pairs_closing_across_the_faces(integrator):
    """Three pairs that come into range in one step without having been in
    the list, across the domain faces of 2 and 3 ranks and the periodic face,
    in a fluid at rest: only the pair test's search of the hot particles of
    every rank against the warm ones can find them. One rebuild, and the
    forces of every pair in range (brute force)."""
    for n in (1, 2, 3):
        r = run("pairs_closing_" + integrator, n)
        L, pos = float(r["L"]), r["pos"]
        for k in range(3):
            d = pos[2 * k] - pos[2 * k + 1]
            d -= L * np.round(d / L)
            assert np.linalg.norm(d) < 1.0, (n, k, d)  # (in range after the step)
        assert int(r["rebuilds"]) == 1, (n, r["rebuilds"])
        np.testing.assert_allclose(r["f"], _hat_forces(pos, L), rtol=0, atol=1e-9, err_msg=f"{n} ranks")


@needs("MARBLE", "DPD")
def test_dpd_vv_1_vs_2_ranks():
    one, two = run("dpd_vv", 1), run("dpd_vv", 2)
    assert_same_trajectory(one, two)
    for key in ("cpos", "comega"):
        np.testing.assert_allclose(two[key], one[key], rtol=0, atol=1e-9, err_msg=key)


@needs("DPD")
def test_shardlow_dimers_1_vs_2_vs_3_ranks():
    """Shardlow on several ranks (integrators/shardlow.cpp): isolated pairs,
    so the sweep's order does not matter and 1, 2 and 3 ranks must give the
    same trajectory; the pairs straddling the domain faces go through the
    boundary rounds (the ghost's velocity change sent to its owner)."""
    runs = {n: run("shardlow_dimers", n) for n in (1, 2, 3)}
    pos0 = runs[1]["pos0"]
    half = len(pos0) // 2
    a, b = pos0[:half, 0], pos0[half:, 0]  # the two particles of each dimer
    for faces in ([0.0, 6.0], [0.0, 4.0, 8.0]):  # the node grids 2 x 1 x 1 and 3 x 1 x 1 of the 12^3 box
        dom = lambda x: np.searchsorted(faces, x, side="right")
        assert np.sum(dom(a) != dom(b)) >= 5, faces  # pairs across a face (periodic x = 0 included)
    for n in (2, 3):
        assert_same_trajectory(runs[1], runs[n], tol=1e-12)


def _dpd_pair_update(L, dt, gamma):
    """delta(xi, xj, vi, vj): the exact kT = 0 Shardlow update of a DPD pair
    of unit masses (weight 1 - r, r_cut 1): u' = a u along e, a =
    exp(-gamma w^2 dt / mu), mu = 1/2, in a periodic box @p L (integrators/
    shardlow.cpp); returns the change of v_i (v_j changes by its negative)."""
    def delta(xi, xj, vi, vj):
        d = xi - xj
        d -= L * np.round(d / L)
        rr = np.linalg.norm(d)
        assert rr < 1.0
        e = d / rr
        mu = 0.5
        a = np.exp(-gamma * (1.0 - rr) ** 2 * dt / mu)
        return mu * (a - 1.0) * np.dot(e, vi - vj) * e
    return delta


def _shardlow_cluster_orders(r):
    """The velocities of each cluster a1 - p - a2 after one step, for the two
    sequential orders of its pairs (a1, p) and (p, a2), and for both at once
    (the simultaneous update a schedule without rounds would give): unit masses,
    kT = 0, the external force's two half kicks, then the exact pair updates
    u' = a u along e at the drifted positions (integrators/shardlow.cpp)."""
    L, dt, gamma = float(r["L"]), float(r["dt"]), float(r["gamma"])
    x0, v0, F = r["pos0"], r["v0"], r["force"]
    v = v0 + dt * F  # (the two half kicks of a constant force)
    x = x0 + dt * (v0 + 0.5 * dt * F)
    delta = _dpd_pair_update(L, dt, gamma)

    out = []
    for c in range(len(x) // 3):
        k1, kp, k2 = 3 * c, 3 * c + 1, 3 * c + 2
        orders = {}
        for name, seq in (("a1 first", ((k1, kp), (kp, k2))), ("a2 first", ((kp, k2), (k1, kp)))):
            w = v.copy()
            for i, j in seq:
                dp = delta(x[i], x[j], w[i], w[j])
                w[i] += dp
                w[j] -= dp
            orders[name] = w[[k1, kp, k2]]
        w = v.copy()
        d1, d2 = delta(x[k1], x[kp], v[k1], v[kp]), delta(x[kp], x[k2], v[kp], v[k2])
        w[k1] += d1
        w[kp] += -d1 + d2
        w[k2] -= d2
        orders["simultaneous"] = w[[k1, kp, k2]]
        out.append(orders)
    return out


@needs("DPD", "EXTERNAL_FORCE")
@pytest.mark.parametrize("ranks", [1, 2, 3, 4])
def test_shardlow_clusters_follow_a_sequential_order(ranks):
    """Clusters of two pairs sharing a particle across the domain faces (and
    one whose pairs see the shared particle through two periodic images):
    each cluster's velocities after a step must be those of one of the two
    sequential orders of its pairs, to round-off. The orders differ from each
    other and from the simultaneous update by far more than the tolerance, so
    a schedule that let two ranks (or two ghost copies) update the shared
    particle at once, or swept with stale ghost velocities, fails."""
    r = run("shardlow_clusters", ranks)
    assert int(np.prod(r["node_grid"])) == ranks
    order = np.argsort(r["ids"])
    v = r["v"][order]
    for c, orders in enumerate(_shardlow_cluster_orders(r)):
        got = v[3 * c:3 * c + 3]
        names = list(orders)
        for a in range(3):
            for b in range(a + 1, 3):
                assert np.abs(orders[names[a]] - orders[names[b]]).max() > 1e-3, (c, names[a], names[b])
        err = {k: np.abs(got - w).max() for k, w in orders.items()}
        assert min(err["a1 first"], err["a2 first"]) < 1e-12, (ranks, c, err)


@needs("DPD", "EXTERNAL_FORCE")
@pytest.mark.parametrize("wide", [False, True])
@pytest.mark.parametrize("ranks", [2, 3])
def test_shardlow_chains_across_a_narrow_domain_follow_a_sequential_order(ranks, wide):
    """Domains narrower than three pair ranges (mpi_scenes.CHAIN): a chain
    k - i - j - m whose middle pair (i, j) touches both faces of one domain,
    each of i and j in another rank's pair across a face. After one step each
    chain's velocities must be those of one of the six sequential orders of
    its three pairs, to round-off; the orders differ from each other by far
    more. With the grid split along x the middle pair touches both faces only
    with large-range types (wide: their full shell sends a domain's locals to
    both sides); sweeping it in the lower or in the upper face round, while a neighbour rank sweeps
    its pair with j or i, gives none of the orders (checked: 0.005 and 0.02)."""
    import itertools
    from mpi_scenes import CHAIN
    r = run("shardlow_chains_wide" if wide else "shardlow_chains", ranks)
    assert list(r["node_grid"]) == [ranks, 1, 1]
    assert list(r["types"]) == ([0] if wide else [])
    L, dt, gamma = r["L"], CHAIN["dt"], CHAIN["gamma"]
    x0, v0, F = r["pos0"], r["v0"], r["force"]
    v = v0 + dt * F  # (unit masses: the two half kicks of a constant force)
    x = x0 + dt * (v0 + 0.5 * dt * F)
    delta = _dpd_pair_update(L, dt, gamma)

    got = r["v"][np.argsort(r["ids"])]
    for c in range(len(x) // 4):
        k = [4 * c + m for m in range(4)]
        pairs = [(k[0], k[1]), (k[1], k[2]), (k[2], k[3])]
        orders = []
        for seq in itertools.permutations(pairs):
            w = v.copy()
            for i, j in seq:
                dp = delta(x[i], x[j], w[i], w[j])
                w[i] += dp
                w[j] -= dp
            orders.append(w[k])
        # (orders with (k, i) and (j, m) swapped are the same: they share no particle)
        distinct = [w for n, w in enumerate(orders) if all(np.abs(w - u).max() > 1e-12 for u in orders[:n])]
        assert len(distinct) == 4
        assert min(np.abs(a - b).max() for a, b in itertools.combinations(distinct, 2)) > 1e-3
        err = min(np.abs(got[k] - w).max() for w in orders)
        assert err < 1e-12, (ranks, c, err)


def _after_kicks_and_drift(r, is_colloid):
    """Velocities, positions and spins at the sweep of the one-step colloid
    scenes (mpi_scenes.STICK_CLUSTER's masses, time step; kT = 0): the two
    half kicks of the constant external forces and torques, and the drift."""
    from mpi_scenes import STICK_CLUSTER as p
    dt = p["dt"]
    x0, v0, F = r["pos0"], r["v0"], r["force"]
    m = np.where(is_colloid, p["mass"], 1.0)[:, None]
    return v0 + dt * F / m, x0 + dt * (v0 + 0.5 * dt * F / m), r["omega0"] + dt * r["torque"] / p["rinertia"]


def _shell_pair(xc, xb):
    """d = x_C - x_b (minimum image in STICK_CLUSTER's box), |d| and the shell
    weight w = 1 - (|d| - R)/r_cut of the colloid C and the bead b (asserted
    in (0, 1]: the bead inside the shell)."""
    from mpi_scenes import STICK_CLUSTER as p
    d = xc - xb
    d -= p["L"] * np.round(d / p["L"])
    rr = np.linalg.norm(d)
    w = 1.0 - (rr - p["radius"]) / p["r_cut"]
    assert 0.0 < w <= 1.0
    return d, rr, w


def _stick_impulse(xc, xb, vc, vb, wc, scale=1.0):
    """The stick friction's exact kT = 0 pair update (nonbonded/
    surface_friction_apply.hpp) of colloid C (STICK_CLUSTER's radius, mass M,
    inertia I) and point bead b: u_t' = a u_t for u = v_C - v_b - omega_C x d
    (lever 1), a = exp(-gamma scale w^2 dt / mu_t), 1/mu_t = 1/M + 1 + r^2/I.
    Returns the impulse J on C (-J on b) and C's spin change -(d x J)/I."""
    from mpi_scenes import STICK_CLUSTER as p
    dt, gamma, M, I = p["dt"], p["gamma"], p["mass"], p["rinertia"]
    d, rr, w = _shell_pair(xc, xb)
    e = d / rr
    u = vc - vb - np.cross(wc, d)
    ut = u - np.dot(e, u) * e
    inv_mu = 1.0 / M + 1.0 + rr * rr / I
    J = (np.exp(-gamma * scale * w * w * dt * inv_mu) - 1.0) * ut / inv_mu
    return J, -np.cross(d, J) / I


def _marble_impulse(xc, xb, vc, vb, wc):
    """The marble coupling's (tunable_slip) exact kT = 0 pair update
    (marble/Colloids.cpp) with STICK_CLUSTER's parameters: the impulse J on
    the bead, -J on C at its surface point R n; the normal and tangential
    parts of u = v_b - (v_C + omega x R n), each its own exact step. Returns
    the impulse on C and C's spin change, as _stick_impulse."""
    from mpi_scenes import STICK_CLUSTER as p
    dt, gamma, R, M, I = p["dt"], p["gamma"], p["radius"], p["mass"], p["rinertia"]
    d, rr, w = _shell_pair(xc, xb)
    n = -d / rr  # (from C to b)
    rA = R * n
    u = vb - (vc + np.cross(wc, rA))
    g = gamma * w * w * dt
    inv_n, inv_t = 1.0 + 1.0 / M, 1.0 + 1.0 / M + R * R / I
    un = np.dot(n, u)
    J = (np.exp(-g * inv_n) - 1.0) * un * n / inv_n
    J = J + (np.exp(-g * inv_t) - 1.0) * (u - un * n) / inv_t
    return -J, np.cross(rA, -J) / I


def _shardlow_stick_cluster_orders(r, kind="stick"):
    """As _shardlow_cluster_orders for the stick clusters b1 - C - b2
    (mpi_scenes.shardlow_stick_clusters): each pair's exact update
    (_stick_impulse). Returns per cluster the velocities (3 x 3) and C's spin
    for the two orders and for both pairs at once. @p kind "marble": the
    marble coupling (_marble_impulse) of
    mpi_scenes.scene_shardlow_marble_clusters instead."""
    from mpi_scenes import STICK_CLUSTER as p
    M = p["mass"]
    v, x, om = _after_kicks_and_drift(r, np.tile([False, True, False], len(r["pos0"]) // 3))
    impulse = _marble_impulse if kind == "marble" else _stick_impulse

    out = []
    for c in range(len(x) // 3):
        kb1, kc, kb2 = 3 * c, 3 * c + 1, 3 * c + 2
        orders = {}
        for name, seq in (("b1 first", (kb1, kb2)), ("b2 first", (kb2, kb1))):
            w, wc = v.copy(), om[c].copy()
            for kb in seq:
                J, dw = impulse(x[kc], x[kb], w[kc], w[kb], wc)
                w[kc] += J / M
                w[kb] -= J
                wc += dw
            orders[name] = np.concatenate([w[[kb1, kc, kb2]], wc[None]])
        w, wc = v.copy(), om[c].copy()
        for kb in (kb1, kb2):
            J, dw = impulse(x[kc], x[kb], v[kc], v[kb], om[c])
            w[kc] += J / M
            w[kb] -= J
            wc += dw
        orders["simultaneous"] = np.concatenate([w[[kb1, kc, kb2]], wc[None]])
        out.append(orders)
    return out


_STICK = needs("TRANS_DPD", "ROTATION", "MASS", "EXTERNAL_FORCE")
_MARBLE = needs("MARBLE", "EXTERNAL_FORCE")


@pytest.mark.parametrize("kind, ranks, respa", [
    *(pytest.param("stick", n, False, marks=_STICK) for n in (1, 2, 3, 4)),
    *(pytest.param("marble", n, False, marks=_MARBLE) for n in (1, 2, 3, 4)),
    *(pytest.param("marble", n, True, marks=_MARBLE) for n in (2, 4))])
def test_shardlow_colloid_clusters_follow_a_sequential_order(kind, ranks, respa):
    """The stick friction (surface_friction, kind "stick": its spins go
    through the colour rounds) and the marble coupling ("marble": its pairs
    rank by rank) in the Shardlow sweep on several ranks: clusters of two
    bead - colloid pairs across the domain faces, one through two periodic
    images of the colloid, one whose beads lie on two ranks neither of which
    owns the colloid (4 ranks). Each cluster's velocities and the colloid's
    spin after one step must be those of one of the two sequential orders of
    its pair updates, to round-off; the orders differ from each other and
    from the simultaneous update by > 1e-3. Marble also through RESPA's step
    (set_shardlow(substeps=3)). Checked to fail: stick without the spins in
    the rounds (0.25-1.1) or without refreshing the ghosts' spins before the
    sweep (0.011); marble without the copies' changes sent to the owners
    (0.3-0.9) or without refreshing the copies between the ranks' turns (the
    corner cluster on 4 ranks then gives the simultaneous update)."""
    r = run(f"shardlow_{kind}_clusters" + ("_respa" if respa else ""), ranks)
    assert int(np.prod(r["node_grid"])) == ranks
    order = np.argsort(r["ids"])
    v, om = r["v"][order], r["omega"][order]
    for c, orders in enumerate(_shardlow_stick_cluster_orders(r, kind)):
        got = np.concatenate([v[3 * c:3 * c + 3], om[3 * c + 1][None]])
        names = list(orders)
        for a in range(3):
            for b in range(a + 1, 3):
                assert np.abs(orders[names[a]] - orders[names[b]]).max() > 1e-3, (c, names[a], names[b])
        err = {k: np.abs(got - w).max() for k, w in orders.items()}
        assert min(err["b1 first"], err["b2 first"]) < 1e-12, (kind, ranks, respa, c, err)


@needs("MARBLE", "EXTERNAL_FORCE")
def test_shardlow_fixed_marbles_equal_one_rank():
    """The marble clusters with every colloid fixed (infinitely heavy): the
    pair updates no longer depend on their order, so 2, 3 and 4 ranks must
    give one rank's velocities and spins to round-off, and the colloids stay
    at rest. The copies on other ranks learn that their colloid is fixed
    (the fixed flags are the locals' only); without that the copy moves and
    its change reaches the fixed owner."""
    runs = {n: run("shardlow_marble_clusters_fixed", n) for n in (1, 2, 3, 4)}
    order = {n: np.argsort(r["ids"]) for n, r in runs.items()}
    v1, w1 = runs[1]["v"][order[1]], runs[1]["omega"][order[1]]
    assert np.abs(v1[1::3]).max() == 0.0  # the colloids (every second of three) at rest
    assert np.abs(v1[0::3] - runs[1]["v0"][0::3]).max() > 0.1  # the beads did change
    for n in (2, 3, 4):
        np.testing.assert_allclose(runs[n]["v"][order[n]], v1, rtol=0, atol=1e-12, err_msg=f"{n} ranks: v")
        np.testing.assert_allclose(runs[n]["omega"][order[n]], w1, rtol=0, atol=1e-12, err_msg=f"{n} ranks: omega")


def _shardlow_stick_shared_orders(r, scale):
    """The groups A - b - B of mpi_scenes.scene_shardlow_stick_shared after one
    step: the stick friction's exact kT = 0 updates of (A, b) and (B, b) in
    the two orders, with gamma scaled by @p scale (shared="split": 1/2, b lying
    in two shells). Returns per group the velocities of A, b, B and the spins
    of A, B for each order."""
    from mpi_scenes import STICK_CLUSTER as p
    M = p["mass"]
    v, x, om = _after_kicks_and_drift(r, r["types"] == 1)

    def stick(xc, xb, vc, vb, wc):
        return _stick_impulse(xc, xb, vc, vb, wc, scale)

    out = []
    for g in range(len(x) // 3):
        kA, kb, kB = 3 * g, 3 * g + 1, 3 * g + 2
        res = {}
        for name, seq in (("A first", (kA, kB)), ("B first", (kB, kA))):
            w, ww = v.copy(), om.copy()
            for kc in seq:
                J, dw = stick(x[kc], x[kb], w[kc], w[kb], ww[kc])
                w[kc] += J / M
                w[kb] -= J
                ww[kc] += dw
            res[name] = np.concatenate([w[[kA, kb, kB]], ww[[kA, kB]]])
        out.append(res)
    return out


@needs("TRANS_DPD", "ROTATION", "MASS", "EXTERNAL_FORCE")
@pytest.mark.parametrize("ranks", [1, 2, 3, 4])
def test_shardlow_stick_shared_shells_across_ranks(ranks):
    """shared="split" in the Shardlow sweep on several ranks: a bead in the
    shells of two colloids that live on two ranks has n = 2 (counted over the
    ranks), so each of its pairs acts with gamma/2. Each group must equal one
    of the two sequential orders at gamma/2 to round-off; gamma (n = 1, the
    count of one rank's pairs) differs by > 1e-2."""
    r = run("shardlow_stick_shared", ranks)
    assert int(np.prod(r["node_grid"])) == ranks
    order = np.argsort(r["ids"])
    v, om = r["v"][order], r["omega"][order]
    half, full = _shardlow_stick_shared_orders(r, 0.5), _shardlow_stick_shared_orders(r, 1.0)
    for g in range(len(half)):
        got = np.concatenate([v[3 * g:3 * g + 3], om[[3 * g, 3 * g + 2]]])
        assert np.abs(half[g]["A first"] - half[g]["B first"]).max() > 1e-3, g
        assert min(np.abs(got - w).max() for w in full[g].values()) > 1e-2, g  # so the test can fail
        err = {k: np.abs(got - w).max() for k, w in half[g].items()}
        assert min(err.values()) < 1e-12, (ranks, g, err)


@pytest.mark.parametrize("kind", [
    pytest.param("stick", marks=needs("TRANS_DPD", "ROTATION", "MASS")),
    pytest.param("marble", marks=needs("MARBLE"))])
def test_shardlow_colloid_temperature_and_momentum_1_2_ranks(kind):
    """Rotating colloids coupled to the ideal DPD fluid only by the stick
    friction (40 colloids) or the marble coupling (12 marbles), under Shardlow
    at dt = 0.02 on 1 and 2 ranks (600 samples 10 steps apart): the total
    momentum is conserved to round-off; the beads' kT and the colloids'
    translational and rotational kT are 1 within 4 sigma + 0.003 of the run's
    error (20 blocks; every update is exact or free flight). A check of the
    fluctuation-dissipation balance on several ranks, not of the order (the
    cluster tests do that).
    (Longer marble runs, 2000 samples: colloid kT 1.005(5) and 1.002(5) on
    one rank, 1.000(6) and 0.995(5) on two.)"""
    for n in (1, 2):
        r = run(f"shardlow_{kind}_temperature", n)
        assert int(r["node_grid"][0]) == n
        np.testing.assert_allclose(r["p1"], r["p0"], rtol=0, atol=1e-9, err_msg=f"{n} ranks: momentum")
        for key, bound in (("kT_beads", 0.004), ("kT_trans", 0.015), ("kT_rot", 0.015)):
            m, e = mean_and_block_error(r[key], blocks=20)
            assert e < bound, (n, key, e)  # so the test can fail
            assert abs(m - 1.0) < 4 * e + 0.003, (n, key, m, e)


@needs("DPD")
def test_shardlow_temperature_and_momentum_1_2_3_ranks():
    """The ideal DPD fluid under Shardlow at dt = 0.04 (kT exact for any dt) on
    1, 2 and 3 ranks: the total momentum is conserved to round-off, the
    kinetic temperature is kT within the run's error, and the rank counts
    agree statistically (their trajectories differ: the sweep's order follows
    the decomposition)."""
    means, errs = [], []
    for n in (1, 2, 3):
        r = run("shardlow_temperature", n)
        np.testing.assert_allclose(r["p1"], r["p0"], rtol=0, atol=1e-9, err_msg=f"{n} ranks: momentum")
        m, e = mean_and_block_error(r["kT"])
        assert e < 0.006, (n, e)  # so the test can fail
        # (N - 1 degrees of freedom of the relative motion: <2/3 KE / N> = kT (1 - 1/N) + |P|^2 / (3 N M))
        assert abs(m - 1.0) < 4 * e + 0.002, (n, m, e)
        means.append(m), errs.append(e)
    for k in (1, 2):
        assert abs(means[k] - means[0]) < 4 * np.hypot(errs[k], errs[0]), (means, errs)


@needs("DPD", "LUBRICATION")
def test_shardlow_suspension_momentum_2_ranks():
    """Colloids on their own large-range grid (full-shell ghosts from every
    side) with lubrication in the sweep: the total momentum m v of colloids
    and beads is conserved on 2 ranks as on one."""
    for n in (1, 2):
        r = run("shardlow_suspension", n)
        assert list(r["types"]) == [1] and int(r["node_grid"][0]) == n, (r["types"], r["node_grid"])
        np.testing.assert_allclose(r["p1"], r["p0"], rtol=0, atol=1e-9, err_msg=f"{n} ranks")


@needs("DPD")
@pytest.mark.parametrize("scene", ["shardlow_narrow",
                                   pytest.param("shardlow_narrow_respa", marks=needs("MARBLE"))])
def test_shardlow_refused_where_its_rounds_cannot_run(scene):
    """Domains narrower than twice the pair range: refused before any step,
    also through RESPA's run (set_shardlow(substeps=2) with a marble)."""
    one, two = run(scene, 1), run(scene, 2)
    assert str(one["msg"]) == "no error"
    msg = str(two["msg"])
    assert "Shardlow" in msg and "twice the pair range" in msg and "node grid 2 x 1 x 1" in msg, msg
    assert int(two["step"]) == 0  # refused before the first step


@needs("DPD")
def test_temperature_statistically_equal():
    """Trajectories diverge over 1400 steps (chaos amplifies the round-off),
    but the mean kinetic temperature agrees within the statistical error."""
    one, two = run("temperature", 1), run("temperature", 2)
    means, errs = zip(*(mean_and_block_error(r["kT"]) for r in (one, two)))
    assert abs(means[0] - means[1]) < 4 * np.hypot(*errs) + 1e-4
    for m, e in zip(means, errs):
        assert abs(m - 1.0) < 4 * e + 0.02  # VV at dt = 0.01: kT ~ 1.007


@needs("LENNARD_JONES")
@pytest.mark.parametrize("scene", ["langevin", "brownian"])
def test_langevin_and_brownian_1_vs_2_ranks(scene):
    """The Langevin / Brownian noise is keyed by (seed, step, particle id): the
    same trajectory on 1 and 2 ranks (to round-off of the force sums)."""
    one, two = run(scene, 1), run(scene, 2)
    assert int(two["ranks"]) == 2
    assert_same_trajectory(one, two)
    if "omega" in one:
        np.testing.assert_allclose(two["omega"], one["omega"], rtol=0, atol=1e-9)
