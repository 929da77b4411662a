# labels: python
"""marble.theory.stresslet_lattice_factor (doc/suspensions.md section 7p): the
stresslet of a sphere in a periodic cube under Lees-Edwards shear. Checks the
disturbance flow behind it (boundary condition, divergence), the lattice sums
(recomputed here), the conditionally convergent step (ball sum plus Eshelby's
inner strain) against an independent Fourier sum of the periodic field with the
mean strain fixed, the factor's small-R/L limit, and bad input."""
import math

import numpy as np
import pytest

from marble import theory

EXY = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])


def grad_A(x, E):
    """d u_i/d x_j of A = x (x.E.x)/r^5, shape (n, 3, 3)."""
    r = np.sqrt(np.sum(x * x, axis=1))[:, None, None]
    Ex = x @ E
    Q = np.sum(x * Ex, axis=1)[:, None, None]
    return (np.eye(3)[None] * Q / r ** 5 + 2 * x[:, :, None] * Ex[:, None, :] / r ** 5
            - 5 * x[:, :, None] * x[:, None, :] * Q / r ** 7)


def grad_B(x, E):
    """d u_i/d x_j of B = 2 E.x/r^5 - 5 x (x.E.x)/r^7."""
    r = np.sqrt(np.sum(x * x, axis=1))[:, None, None]
    Ex = x @ E
    Q = np.sum(x * Ex, axis=1)[:, None, None]
    return (2 * E[None] / r ** 5 - 10 * Ex[:, :, None] * x[:, None, :] / r ** 7 - 5 * np.eye(3)[None] * Q / r ** 7
            - 10 * x[:, :, None] * Ex[:, None, :] / r ** 7 + 35 * x[:, :, None] * x[:, None, :] * Q / r ** 9)


def sym(g):
    return 0.5 * (g + np.transpose(g, (0, 2, 1)))


def ball_sites(N):
    n = np.arange(-N, N + 1)
    X = np.stack(np.meshgrid(n, n, n, indexing="ij"), -1).reshape(-1, 3).astype(float)
    r = np.sqrt(np.sum(X * X, axis=1))
    return X[(r > 0) & (r <= N)]


def disturbance(x, E, R):
    """u' = -(5/2) R^3 A - (R^5/2) B of a no-slip sphere in the strain E."""
    r = np.sqrt(np.sum(x * x, axis=1))[:, None]
    Ex = x @ E
    Q = np.sum(x * Ex, axis=1)[:, None]
    return -2.5 * R ** 3 * x * Q / r ** 5 - 0.5 * R ** 5 * (2 * Ex / r ** 5 - 5 * x * Q / r ** 7)


def test_disturbance_flow():
    # no slip on the sphere (u' = -E.x at r = R), divergence-free, and the gradients above
    rng = np.random.default_rng(3)
    R = 0.8
    n = rng.normal(size=(50, 3))
    n /= np.linalg.norm(n, axis=1)[:, None]
    for E in (EXY, np.diag([1.0, -1.0, 0.0]), np.diag([1.0, 1.0, -2.0])):
        np.testing.assert_allclose(disturbance(R * n, E, R), -(R * n) @ E, atol=1e-14)
        x = rng.uniform(1.0, 3.0, size=(20, 3)) * rng.choice([-1, 1], size=(20, 3))
        h = 1e-5
        num = np.stack([(disturbance(x + h * d, E, R) - disturbance(x - h * d, E, R)) / (2 * h)
                        for d in np.eye(3)], axis=2)
        ana = -2.5 * R ** 3 * grad_A(x, E) - 0.5 * R ** 5 * grad_B(x, E)
        np.testing.assert_allclose(num, ana, rtol=1e-7, atol=1e-12)
        np.testing.assert_allclose(np.trace(ana, axis1=1, axis2=2), 0.0, atol=1e-13)


def test_lattice_sums():
    X = ball_sites(24)
    k3 = sym(grad_A(X, EXY))[:, 0, 1].sum()
    # the ball sum converges as ~N^-2: 0.1 % at N = 24
    assert k3 == pytest.approx(theory.STRESSLET_LATTICE_K3, rel=2e-3)
    assert k3 != pytest.approx(theory.STRESSLET_LATTICE_K3, rel=2e-5)  # (not the constant itself)
    X = ball_sites(14)
    k5 = sym(grad_B(X, EXY))[:, 0, 1].sum()
    assert k5 == pytest.approx(theory.STRESSLET_LATTICE_K5, rel=2e-5)
    # Faxen's Laplacian of A's strain sums to 2 K5 (used in the factor)
    h = 1e-3
    lap = sum((sym(grad_A(X + h * d, EXY))[:, 0, 1] + sym(grad_A(X - h * d, EXY))[:, 0, 1]
               - 2 * sym(grad_A(X, EXY))[:, 0, 1]).sum() / h ** 2 for d in np.eye(3))
    assert lap == pytest.approx(2 * theory.STRESSLET_LATTICE_K5, rel=1e-4)
    # only the cubic (l = 4) part survives the ball: the axial strain mode is -1.5 x the shear mode
    kd = sym(grad_A(ball_sites(24), np.diag([1.0, -1.0, 0.0])))[:, 0, 0].sum()
    assert kd / k3 == pytest.approx(-1.5, rel=1e-12)


def test_shell_average_and_eshelby():
    # a point stresslet's strain averaged over a sphere around it vanishes, and its
    # integral over the ball is -S/(5 eta) (the surface integral of u n)
    th = np.linspace(0, math.pi, 401)
    ph = np.linspace(0, 2 * math.pi, 801)
    T, P = np.meshgrid(th, ph, indexing="ij")
    n = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1).reshape(-1, 3)
    w = (np.sin(T)[:, :, None, None] * np.ones((1, 1, 3, 3)))

    def quad(f):  # integral over the unit sphere's solid angle of f (n, 3, 3)
        f = f.reshape(len(th), len(ph), 3, 3) * w
        return np.trapz(np.trapz(f, ph, axis=1), th, axis=0)

    for rad in (0.5, 2.0):
        g = sym(grad_A(rad * n, EXY)) * (-3.0 / (8 * math.pi))  # eta = 1, S = EXY
        np.testing.assert_allclose(quad(g), 0.0, atol=1e-9)
        u = -3.0 / (8 * math.pi) * (rad * n) * np.sum((rad * n) * ((rad * n) @ EXY), axis=1)[:, None] / rad ** 5
        ball = quad(u[:, :, None] * n[:, None, :]) * rad ** 2
        np.testing.assert_allclose(0.5 * (ball + ball.T), -EXY / 5.0, atol=1e-9)


def periodic_strain_fourier(sigma, M):
    """xy strain at the origin of the periodic field of unit point stresslets (S = EXY,
    eta = 1, L = 1) with zero mean strain, the self field removed: the sum over k != 0
    of the Gaussian-smoothed field minus its free-space self part (angular average
    1/5 times the radial integral); the smoothing shifts the images' fields by O(sigma^2)."""
    m = np.arange(-M, M + 1)
    K = 2 * math.pi * np.stack(np.meshgrid(m, m, m, indexing="ij"), -1).reshape(-1, 3)
    k2 = np.sum(K * K, axis=1)
    K, k2 = K[k2 > 0], k2[k2 > 0]
    kh = K / np.sqrt(k2)[:, None]
    SK = kh @ EXY
    Pi = SK - kh * np.sum(SK * kh, axis=1)[:, None]
    g = np.exp(-0.5 * k2 * sigma ** 2)
    per = -0.5 * np.sum(g * (Pi[:, 0] * kh[:, 1] + Pi[:, 1] * kh[:, 0]))  # f = div(S delta)
    self_part = -0.2 * 4 * math.pi * math.sqrt(math.pi / 2) / sigma ** 3 / (2 * math.pi) ** 3
    return per - self_part


def test_periodic_convention_fourier():
    # the conditionally convergent image sum with the box's mean strain fixed, summed
    # independently in Fourier space (Richardson in sigma^2), against the ball sum
    # plus Eshelby's inner strain: -(3/(8 pi)) K3 + 1/5
    s1, s2 = 0.06, 0.045
    v1, v2 = periodic_strain_fourier(s1, 32), periodic_strain_fourier(s2, 42)
    v0 = (v2 * s1 ** 2 - v1 * s2 ** 2) / (s1 ** 2 - s2 ** 2)
    expect = -3.0 / (8 * math.pi) * theory.STRESSLET_LATTICE_K3 + 0.2
    assert v0 == pytest.approx(expect, abs=3e-4)
    # without Eshelby's term (the ball sum alone) it would fail
    assert abs(v0 - (expect - 0.2)) > 0.1


def test_factor():
    assert theory.stresslet_lattice_factor(1.0, 1e6) == pytest.approx(1.0, abs=1e-12)
    # small R/L: 1/s - 1 -> (-1 + (15/(8 pi)) K3) phi (the R^5 terms are 1e-5 of it here)
    R, L = 0.01, 10.0
    phi = 4 * math.pi * R ** 3 / (3 * L ** 3)
    s = theory.stresslet_lattice_factor(R, L)
    assert (1 / s - 1) / phi == pytest.approx(-1 + 15 / (8 * math.pi) * theory.STRESSLET_LATTICE_K3, rel=1e-4)
    # the scene of doc/suspensions.md 7p
    assert theory.stresslet_lattice_factor(1.0, 4.3756) == pytest.approx(0.9733, abs=1e-4)
    for bad in ((-1.0, 4.0), (0.0, 4.0), (2.0, 4.0), (1.0, float("nan")), (1.0, -4.0)):
        with pytest.raises(ValueError):
            theory.stresslet_lattice_factor(*bad)


# --- bench/stick_colloid_stresslet.py's table (section 7p) ---

def _bench():
    from bench_module import load_bench
    return load_bench("stick_colloid_stresslet")


def test_bench_table_recovers_radius(tmp_path, capsys):
    """Synthetic runs: the reference's box stress -eta_0 rate, the colloid's more by the
    stresslet of a no-slip sphere of radius R_s in the lattice; the table gives R_s back,
    the excess S_xy and the weighted means of the seeds."""
    import json
    b = _bench()
    eta0, L, Rs = 0.33, 4.3756, 1.03
    lines = []
    for rate in (0.05, 0.1):
        S = (10.0 / 3.0) * math.pi * eta0 * Rs ** 3 * rate * theory.stresslet_lattice_factor(Rs, L)
        for seed, d in ((1, 1e-5), (2, -1e-5)):
            common = dict(part="run", rate=rate, L=L, seed=seed, time=1000.0, cpu_s=10.0, kT=0.1, n_solvent=251)
            lines.append(dict(common, reference=True, pxy=-eta0 * rate + d, pxy_err=1e-4, pxy_err_blocks=1e-4))
            lines.append(dict(common, reference=False, pxy=-eta0 * rate - S / L ** 3 - d, pxy_err=2e-4,
                              pxy_err_blocks=1e-4, far_density=3.0, far_density_err=0.01, omega_z=-rate / 2))
    fn = tmp_path / "runs.jsonl"
    fn.write_text("".join(json.dumps(x) + "\n" for x in lines))
    rows = b.table(b.parse(["--part", "table", "--results", str(fn)]))
    assert len(rows) == 2
    for row in rows:
        assert row["R_s"] == pytest.approx(Rs, rel=1e-9)
        assert row["eta_ref"] == pytest.approx(eta0, rel=1e-12)
        S = (10.0 / 3.0) * math.pi * eta0 * Rs ** 3 * row["rate"] * theory.stresslet_lattice_factor(Rs, L)
        assert row["S"] == pytest.approx(S, rel=1e-9)
        assert row["S_err"] == pytest.approx(L ** 3 * math.hypot(2e-4, 1e-4) / math.sqrt(2), rel=1e-9)
        assert row["R_s_range"][0] < Rs < row["R_s_range"][1]
    # the extrapolation to rate 0: the same radius at both rates has slope 0 and gives R_s back;
    # a law S0 + b rate^2 is recovered exactly by the p = 2 fit
    fits = b.extrapolate(rows, L_of=lambda r: r["L"], R_t=1.0, R_r=1.05)
    assert [f["p"] for f in fits] == [2.0, 1.5]
    for f in fits:
        assert f["R_s"] == pytest.approx(Rs, rel=1e-9)
        assert f["slope"] == pytest.approx(0.0, abs=1e-6)
    fake = [dict(L=L, rate=x, S_over=21.0 + 300.0 * x * x, S_over_err=0.5 + x) for x in (0.05, 0.1, 0.2)]
    f2 = b.extrapolate(fake, L_of=lambda r: r["L"], R_t=1.0, R_r=1.05)[0]
    assert (f2["S0"], f2["slope"], f2["chi2"]) == pytest.approx((21.0, 300.0, 0.0), abs=1e-9)
    # a reference at another bead count gives the viscosity's density slope; a colloid run at
    # the exact count is reported beside the bulk count, neither enters S
    extra = [dict(lines[0], n_solvent=259, pxy=-eta0 * 0.05 * (259 / 251) ** 1.5, seed=3),
             dict(lines[1], solvent_count="exact", n_solvent=239, pxy=lines[1]["pxy"] + 1e-3, seed=3)]
    fn.write_text("".join(json.dumps(x) + "\n" for x in lines + extra))
    capsys.readouterr()
    rows = b.table(b.parse(["--part", "table", "--results", str(fn)]))
    out = capsys.readouterr().out
    assert rows[0]["R_s"] == pytest.approx(Rs, rel=1e-9)
    assert "d ln eta / d ln rho = 1.50" in out
    assert rows[0]["S_exact"] == pytest.approx(rows[0]["S"] - (1e-3 - 1e-5) * L ** 3, rel=1e-9)  # seed 1: -1e-5
    # a group without its reference is reported, not used
    fn.write_text("".join(json.dumps(x) + "\n" for x in lines if not (x["reference"] and x["rate"] == 0.1)))
    rows = b.table(b.parse(["--part", "table", "--results", str(fn)]))
    assert [r["rate"] for r in rows] == [0.05]
    assert "needs both colloid and reference runs" in capsys.readouterr().out
