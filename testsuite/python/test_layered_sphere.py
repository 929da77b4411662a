# labels: python
"""marble.layered_sphere (doc/suspensions.md section 7o): the radial ODEs of a
sphere with a graded, anisotropic Brinkman layer against independent results:
the Stokes solutions, the free-slip and no-slip spheres, Brinkman's porous sphere
(translation: Neale, Epstein & Nader 1973; rotation), and a Navier-slip sphere
built from a thin layer of low viscosity (marble.theory.slip_sphere_radii, which
is Basset's friction and the slip sphere's stresslet); bad input."""
import math

import numpy as np
import pytest

from marble import layered_sphere as ls
from marble import theory


def const(x):
    return lambda r: x + 0.0 * r


ZERO, ONE = const(0.0), const(1.0)


@pytest.mark.parametrize("l,k", [(1, -1), (1, -3), (1, 0), (1, 2), (2, -2), (2, -4), (2, 1), (2, 3)])
def test_stokes_solutions_solve_the_odes(l, k):
    # the four power-law Stokes solutions of each harmonic satisfy the first-order system
    rhs = ls._poloidal_rhs(l, ZERO, ZERO, const(0.7))
    for r in (0.8, 1.7, 3.1):
        eps = 1e-6 * r
        y = ls.free_solution(l, k, r, eta=0.7)
        dy = (ls.free_solution(l, k, r + eps, eta=0.7) - ls.free_solution(l, k, r - eps, eta=0.7)) / (2 * eps)
        assert np.allclose(rhs(r, y), dy, rtol=1e-6, atol=1e-8 * np.max(np.abs(dy)))
    # and a power that is not a Stokes solution does not
    y = ls.free_solution(l, k + 0.5, 1.3)
    dy = (ls.free_solution(l, k + 0.5, 1.3 + 1e-6) - ls.free_solution(l, k + 0.5, 1.3 - 1e-6)) / 2e-6
    assert not np.allclose(rhs(1.3, y), dy, rtol=1e-4)


def test_free_slip_core():
    # no friction: the free-slip sphere r0 (zeta_t = 4 pi eta r0, no torque, [eta] = 1)
    eta, r0 = 0.329, 0.9
    zt, Rt = ls.translation(r0, 1.3, ZERO, ZERO, const(eta), eta)
    assert zt == pytest.approx(4 * math.pi * eta * r0, rel=1e-8)
    assert Rt == pytest.approx(2 * r0 / 3, rel=1e-8)
    zr, Rr = ls.rotation(r0, 1.3, ZERO, const(eta), eta)
    assert abs(zr) < 1e-10
    iv, Rs = ls.stresslet(r0, 1.3, ZERO, ZERO, const(eta), eta)
    assert iv * (1 / r0) ** 3 == pytest.approx(1.0, rel=1e-8)


def test_impermeable_layer_is_a_no_slip_sphere():
    # K -> inf: the fluid in the layer moves with the sphere; radii -> r1 - O(sqrt(eta/K))
    K, r1 = 1e5, 1.4
    ell = math.sqrt(1.0 / K)
    for R in (ls.translation(1.0, r1, const(K), const(K), ONE, 1.0, max_step=1e-3)[1],
              ls.rotation(1.0, r1, const(K), ONE, 1.0, max_step=1e-3)[1],
              ls.stresslet(1.0, r1, const(K), const(K), ONE, 1.0, max_step=1e-3)[1]):
        assert r1 - 3 * ell < R < r1 + 1e-9


@pytest.mark.parametrize("beta", [5.0, 10.0])
def test_brinkman_porous_sphere(beta):
    # a uniform K = eta beta^2/b^2 on a sphere of radius b = 1 around a vanishing core
    eta, b = 0.5, 1.0
    Kf = const(eta * beta ** 2 / b ** 2)
    zt, _ = ls.translation(1e-3, b, Kf, Kf, const(eta), eta, max_step=1e-3)
    zr, _ = ls.rotation(1e-3, b, Kf, const(eta), eta, max_step=1e-3)
    g = 1 - math.tanh(beta) / beta
    zt_th = 6 * math.pi * eta * b * 2 * beta ** 2 * g / (2 * beta ** 2 + 3 * g)
    zr_th = 8 * math.pi * eta * b ** 3 * (1 + 3 / beta ** 2 - 3 / (beta * math.tanh(beta)))
    assert zt == pytest.approx(zt_th, rel=2e-5)
    assert zr == pytest.approx(zr_th, rel=1e-9)


def test_radial_friction_does_not_rotate_and_tangential_layer_is_anisotropic():
    # the radial friction K_n does not enter rotation; in translation, a tangential-only layer
    # gives less drag than the same friction on both components
    K = const(200.0)
    zr1 = ls.rotation(1.0, 1.3, K, ONE, 1.0)[0]
    assert ls.translation(1.0, 1.3, ZERO, K, ONE, 1.0)[0] < ls.translation(1.0, 1.3, K, K, ONE, 1.0)[0]
    assert ls.rotation(1.0, 1.3, K, ONE, 1.0)[0] == pytest.approx(zr1, rel=1e-12)


def test_thin_low_viscosity_layer_is_a_navier_slip_sphere():
    # a rigid shell (large K) on [1, a], then a gap of width d and viscosity eta d/b: slip length b at a
    eta, a, d, b = 1.0, 1.2, 2e-3, 0.6
    Kbig = 4e5

    def K(r):
        return np.where(r < a, Kbig, 0.0)

    def et(r):
        return np.where(r < a, eta, eta * d / b)
    kw = dict(max_step=2e-4)
    Rt = ls.translation(1.0, a + d, K, K, et, eta, **kw)[1]
    Rr = ls.rotation(1.0, a + d, K, et, eta, **kw)[1]
    Rs = ls.stresslet(1.0, a + d, K, K, et, eta, **kw)[1]
    Rt_th, Rr_th, Rs_th = theory.slip_sphere_radii(a, b / a)
    for got, want in ((Rt, Rt_th), (Rr, Rr_th), (Rs, Rs_th)):
        assert got == pytest.approx(want, rel=6e-3)
    # and the three differ: the check resolves the slip
    assert Rt_th - Rr_th > 0.05 and Rs_th - Rr_th > 0.05


def test_dpd_pair_viscosity_fraction_against_monte_carlo():
    # an independent Monte-Carlo count of the DPD pairs that straddle a plane at height z (weight
    # w^2 r_x^2 r_z^2/r^2 n(z1) n(z2)), relative to the same count in the bulk
    rng = np.random.default_rng(7)
    m = 400000
    d = rng.normal(size=(m, 3))
    d *= (rng.random(m) ** (1 / 3) / np.linalg.norm(d, axis=1))[:, None]  # uniform in the unit ball
    d[:, 2] = np.abs(d[:, 2])
    r = np.linalg.norm(d, axis=1)
    wgt = (1 - r) ** 2 * d[:, 0] ** 2 * d[:, 2] ** 2 / r ** 2
    h = np.linspace(-0.5, 3.0, 351)
    for n in (np.where(h > 0, 3.0, 0.0), 3.0 * np.clip(h / 0.3, 0, 1) * (1 + 0.8 * np.exp(-((h - 0.35) / 0.1) ** 2))):
        for z in (0.0, 0.1, 0.3, 0.6, 1.2):
            z1 = z - rng.random(m) * d[:, 2]  # the lower end, uniform within r_z below the plane
            dens = np.interp(z1, h, n, left=0) * np.interp(z1 + d[:, 2], h, n, left=0) / 9.0
            mc = np.sum(wgt * d[:, 2] * dens) / np.sum(wgt * d[:, 2])
            f = ls.dpd_pair_viscosity_fraction(z, h, n, 3.0)
            assert f == pytest.approx(mc, abs=0.01)
    uni = np.where(h > 0, 3.0, 0.0)
    assert ls.dpd_pair_viscosity_fraction(0.0, h, uni, 3.0) == pytest.approx(0.0, abs=1e-12)
    assert ls.dpd_pair_viscosity_fraction(1.0, h, uni, 3.0) == pytest.approx(1.0, rel=1e-3)
    f = ls.dpd_pair_viscosity_fraction(np.linspace(0, 1, 11), h, uni, 3.0)
    assert np.all(np.diff(f) > 0)


def test_layer_from_profile_and_bad_input():
    h = np.linspace(-0.3, 2.0, 231)
    n = 3.0 * np.clip((h + 0.1) / 0.2, 0.0, 1.0)
    lay = ls.layer_from_profile(h, n, a=1.0, trans_gamma=45.0, shell=0.26, gamma=4.5, dpd_shell=0.26, eta=0.329)
    assert lay["r0"] == pytest.approx(1.0 + h[np.nonzero(n > 0.03)[0][0]])
    res = ls.radii(lay)
    # a partly permeable, friction-coated sphere: between the free-slip core and the outer edge
    assert 2.0 / 3.0 * lay["r0"] < res["R_t"] < lay["r1"]
    assert 0.0 < res["R_r"] < lay["r1"]
    # a stiffer layer is larger in every mode
    stiff = ls.radii(ls.layer_from_profile(h, n, a=1.0, trans_gamma=135.0, shell=0.26, gamma=4.5,
                                           dpd_shell=0.26, eta=0.329))
    assert all(stiff[k] > res[k] for k in ("R_t", "R_r", "R_s"))
    # the near-wall loss of DPD partners lowers the viscosity there: smaller radii
    pairs = ls.radii(ls.layer_from_profile(h, n, a=1.0, trans_gamma=45.0, shell=0.26, gamma=4.5, dpd_shell=0.26,
                                           eta=0.329, eta_model="pairs"))
    assert all(pairs[k] < res[k] for k in ("R_t", "R_r", "R_s"))
    # mass continuity div(n v) = 0: the same as div v = 0 for a uniform fluid, rotation unchanged
    # for any profile, and a different translation for this one
    flat = np.where(h > -0.1, 3.0, 0.0)
    kw = dict(a=1.0, trans_gamma=45.0, shell=0.26, gamma=4.5, dpd_shell=0.26, eta=0.329, n_bulk=3.0)
    flat_v = ls.radii(ls.layer_from_profile(h, flat, continuity="volume", **kw))
    flat_m = ls.layer_from_profile(h, flat, continuity="mass", smooth=0.0, **kw)
    assert flat_m["dlnn"](np.linspace(1.0, 2.4, 50)) == pytest.approx(0.0, abs=1e-12)
    flat_m = ls.radii(flat_m)
    for k in ("R_t", "R_r", "R_s"):
        assert flat_m[k] == pytest.approx(flat_v[k], rel=1e-6)
    mass = ls.radii(ls.layer_from_profile(h, n, continuity="mass", **kw))
    vol = ls.radii(ls.layer_from_profile(h, n, **kw))
    assert mass["R_r"] == pytest.approx(vol["R_r"], rel=1e-6)
    assert abs(mass["R_t"] / vol["R_t"] - 1) > 1e-4
    for bad in (dict(a=0.0), dict(shell=-1.0), dict(trans_gamma=float("nan")), dict(eta=0.0),
                dict(eta_model="viscous"), dict(eta_kinetic=1.0), dict(continuity="incompressible"),
                dict(continuity="mass", h_bulk=0.1), dict(continuity="mass", smooth=-1.0)):
        kw = dict(a=1.0, trans_gamma=45.0, shell=0.26, gamma=4.5, dpd_shell=0.26, eta=0.329)
        kw.update(bad)
        with pytest.raises(ValueError, match=list(bad)[-1]):
            ls.layer_from_profile(h, n, **kw)
    with pytest.raises(ValueError, match="'h', 'n'"):
        ls.layer_from_profile(h[::-1], n, a=1.0, trans_gamma=45.0, shell=0.26, gamma=4.5, dpd_shell=0.26, eta=0.3)
    with pytest.raises(ValueError, match="r1"):
        ls.rotation(1.0, 0.9, ZERO, ONE, 1.0)
    with pytest.raises(ValueError, match="eta_out"):
        ls.translation(1.0, 1.2, ZERO, ZERO, ONE, -1.0)


# --- bench/stick_colloid_layer.py (section 7o) ---

def _bench():
    import os
    from bench_module import BENCH_DIR, load_bench
    return load_bench("stick_colloid_layer"), os.path.join(BENCH_DIR, "results", "stick_colloid_layer.jsonl")


def test_bench_density_and_model(tmp_path, capsys):
    import json
    import marble
    mod, committed = _bench()
    if not marble.has_features("ROTATION", "TRANS_DPD", "DPD"):
        pytest.skip("needs ROTATION, TRANS_DPD, DPD")
    out = tmp_path / "d.jsonl"
    mod.main(["--part", "density", "--time", "10", "--every", "50", "--json", str(out)])
    r = json.loads(out.read_text().splitlines()[0])
    h, n = np.array(r["h"]), np.array(r["n"])
    # the bulk is seed 004's density; the hat keeps beads out of the core and adsorbs them in the shell
    assert r["n_bulk"] == pytest.approx(3.0, rel=0.05)
    assert np.all(n[h < -0.3] == 0)
    shell = (h > 0.1) & (h < 0.26)
    assert np.mean(n[shell]) > 1.5 * r["n_bulk"]
    # the model on the committed profile: one row per setting of section 7n, the default as by hand
    rows = mod.model(mod.parse(["--part", "model", "--results", committed]))
    assert len(rows) == len(mod.MEASURED)
    prof = mod.load_profiles([committed])
    hh, nn, nb, a = mod.combined_profile(prof)
    import marble.suspensions as sus
    rc = sus.surface_cutoff(a)
    ref = ls.radii(ls.layer_from_profile(hh, nn, a=a, trans_gamma=45.0, shell=rc, gamma=4.5, dpd_shell=rc,
                                         eta=mod.ETA0, n_bulk=nb))
    assert rows[1]["R_t"] == pytest.approx(ref["R_t"], rel=1e-12)
    assert rows[1]["R_r"] > rows[1]["R_t"]


@pytest.mark.parametrize("opt,val", [("--time", "0"), ("--L", "3"), ("--bin", "nan"), ("--every", "0")])
def test_bench_bad_input(opt, val, capsys):
    mod, _ = _bench()
    with pytest.raises(SystemExit):
        mod.parse(["--part", "density", opt, val])
    assert opt in capsys.readouterr().err


@pytest.mark.parametrize("l", [1, 2])
def test_first_order_system_is_the_stress_divergence(l):
    # independent of the hand derivation: sympy writes the r and theta components of
    # div(sigma) + f in spherical coordinates for v_r = A P_l, v_theta = B (-2/(l(l+1))) sin P_l',
    # p = P P_l, with a radially varying eta and arbitrary (non-solution) A, P, eta, K; the code's
    # S' and T' must differ from the true derivatives of S and T by exactly those residuals
    sp = pytest.importorskip("sympy")
    r, th = sp.symbols("r theta", positive=True)
    X = sp.Symbol("X")
    A = 0.3 + sp.sin(r) / r ** 2
    P = sp.exp(-r) * (1 + r)
    eta = 0.4 + 0.1 * sp.cos(2 * r)
    Kn, Kt = 2 + r ** 2, 5 * sp.exp(-r / 3)
    B = A + r * sp.diff(A, r) / 2  # div v = 0
    x = sp.cos(th)
    Pl = sp.legendre(l, x)
    ang = -sp.Rational(2, l * (l + 1)) * sp.sin(th) * sp.diff(sp.legendre(l, X), X).subs(X, x)
    vr, vt, p = A * Pl, B * ang, P * Pl
    err = sp.diff(vr, r)
    ett = sp.diff(vt, th) / r + vr / r
    epp = vr / r + vt * sp.cot(th) / r
    ert = (r * sp.diff(vt / r, r) + sp.diff(vr, th) / r) / 2
    srr, stt, spp, srt = -p + 2 * eta * err, -p + 2 * eta * ett, -p + 2 * eta * epp, 2 * eta * ert
    res_r = (sp.diff(srr, r) + sp.diff(srt, th) / r + (2 * srr - stt - spp + srt * sp.cot(th)) / r
             - Kn * vr) / Pl
    res_t = (sp.diff(srt, r) + sp.diff(stt, th) / r + ((stt - spp) * sp.cot(th) + 3 * srt) / r - Kt * vt) / ang
    S, T = sp.simplify(srr / Pl), sp.simplify(srt / ang)
    f = {k: sp.lambdify(r, e, "numpy") for k, e in dict(A=A, B=B, S=S, T=T, dS=sp.diff(S, r), dT=sp.diff(T, r),
                                                         eta=eta, Kn=Kn, Kt=Kt).items()}
    th0 = 0.7
    rr = sp.lambdify(r, res_r.subs(th, th0), "numpy")
    rt = sp.lambdify(r, res_t.subs(th, th0), "numpy")
    rhs = ls._poloidal_rhs(l, f["Kn"], f["Kt"], f["eta"])
    for rv in (0.9, 1.3, 2.2):
        y = np.array([f["A"](rv), f["B"](rv), f["S"](rv), f["T"](rv)], dtype=float)
        dA, dB, dS, dT = rhs(rv, y)
        assert dS == pytest.approx(f["dS"](rv) - rr(rv), rel=1e-10, abs=1e-12)
        assert dT == pytest.approx(f["dT"](rv) - rt(rv), rel=1e-10, abs=1e-12)
        # and the kinematics: A' from continuity, B' from the definition of T
        assert dA == pytest.approx(float(sp.diff(A, r).subs(r, rv)), rel=1e-12)
        assert dB == pytest.approx(float(sp.diff(B, r).subs(r, rv)), rel=1e-12)
