# labels: python
"""marble.theory's radii of one sphere by mode (doc/suspensions.md section 7m): the
Navier-slip sphere's translational, rotational and stresslet radii (limits beta = 0
and inf, the first-order equality), the slip boundary condition of the flows behind
them checked numerically on the sphere, the inverse (a, beta) from (R_t, R_r), the
periodic box correction of the rotational friction, and bad input."""
import json
import math

import numpy as np
import pytest

from marble import theory

ETA = 0.329


def test_limits():
    assert theory.slip_sphere_intrinsic_viscosity(0.0) == pytest.approx(2.5, rel=1e-15)
    assert theory.slip_sphere_intrinsic_viscosity(np.inf) == pytest.approx(1.0, rel=1e-15)
    assert theory.slip_sphere_intrinsic_viscosity(1e9) == pytest.approx(1.0, rel=1e-8)
    a = 0.987
    Rt, Rr, Rs = theory.slip_sphere_radii(a, 0.0)
    assert (Rt, Rr, Rs) == pytest.approx((a, a, a), rel=1e-15)
    Rt, Rr, Rs = theory.slip_sphere_radii(a, np.inf)
    # perfect slip: zeta_t = 4 pi eta a, no rotational friction, [eta] = 1
    assert 6 * math.pi * ETA * Rt == pytest.approx(4 * math.pi * ETA * a, rel=1e-15)
    assert Rr == 0.0
    assert 2.5 * (Rs / a) ** 3 == pytest.approx(1.0, rel=1e-14)
    # the same as basset_friction at finite beta
    for beta in (0.05, 0.3, 2.0):
        Rt, Rr, _ = theory.slip_sphere_radii(a, beta)
        zt, zr = theory.basset_friction(ETA, a, beta * a)
        assert 6 * math.pi * ETA * Rt == pytest.approx(zt, rel=1e-14)
        assert 8 * math.pi * ETA * Rr ** 3 == pytest.approx(zr, rel=1e-14)


def test_first_order_equal():
    # a thin slip layer shifts every radius by -beta a to first order; R_r/R_t = 1 - beta^2 + ...
    for beta in (1e-3, -1e-3):
        Rt, Rr, Rs = theory.slip_sphere_radii(1.0, beta)
        for R in (Rt, Rr, Rs):
            assert R == pytest.approx(1 - beta, abs=5 * beta ** 2)
        assert Rr / Rt == pytest.approx(1 - beta ** 2, abs=5 * abs(beta) ** 3)


def _strain_flow(x, a, beta, E):
    A = -1.0 / (1 + 5 * beta)
    B = 1.5 * A - 1.0
    r = np.linalg.norm(x)
    Ex = E @ x
    xEx = x @ Ex
    return Ex + A * a ** 5 * (Ex / r ** 5 - 2.5 * xEx * x / r ** 7) + B * a ** 3 * xEx * x / r ** 5


def _rot_flow(x, a, beta, W):
    return a ** 3 / (1 + 3 * beta) * np.cross(W, x) / np.linalg.norm(x) ** 3


def _grad(u, x, h=1e-5):
    g = np.empty((3, 3))
    for j in range(3):
        dx = np.zeros(3)
        dx[j] = h
        g[:, j] = (u(x + dx) - u(x - dx)) / (2 * h)
    return g


@pytest.mark.parametrize("beta", [0.0, 0.2, 1.5])
def test_slip_boundary_condition(beta):
    """The flows behind slip_sphere_intrinsic_viscosity and the rotational friction
    satisfy no penetration and Navier's u_t = (b/eta) (sigma n)_t on r = a (the
    pressure is normal and drops out of the tangential traction), are
    divergence-free, and their far fields give the stresslet and the torque."""
    rng = np.random.default_rng(3)
    a, eta = 1.3, 0.7
    b = beta * a
    E = rng.normal(size=(3, 3))
    E = 0.5 * (E + E.T)
    E -= np.trace(E) / 3 * np.eye(3)
    W = rng.normal(size=3)
    for flow, arg in ((_strain_flow, E), (_rot_flow, W)):
        def u(x):
            return flow(x, a, beta, arg)
        for _ in range(5):
            n = rng.normal(size=3)
            n /= np.linalg.norm(n)
            x = a * n
            P = np.eye(3) - np.outer(n, n)
            ub = u(x) if flow is _strain_flow else u(x) - np.cross(W, x)  # relative to the sphere
            assert abs(ub @ n) < 1e-12
            g = _grad(u, x)
            assert abs(np.trace(g)) < 1e-7
            traction_t = P @ (eta * (g + g.T) @ n)
            assert P @ ub == pytest.approx(b / eta * traction_t, abs=1e-7)
    # far field of the strain flow: -(3/(8 pi eta)) (x.S.x) x/r^5 with S = (20/3) pi eta a^3 E [eta]/2.5
    S = 20.0 / 3.0 * math.pi * eta * a ** 3 * E * theory.slip_sphere_intrinsic_viscosity(beta) / 2.5
    x = 1e3 * np.array([0.3, -0.5, 0.81])
    r = np.linalg.norm(x)
    far = -3.0 / (8 * math.pi * eta) * (x @ S @ x) * x / r ** 5
    assert _strain_flow(x, a, beta, E) - E @ x == pytest.approx(far, rel=1e-5)
    # the rotlet T x r/(8 pi eta r^3) of the torque 8 pi eta a^3 W/(1 + 3 beta)
    T = 8 * math.pi * eta * a ** 3 * W / (1 + 3 * beta)
    assert _rot_flow(x, a, beta, W) == pytest.approx(np.cross(T, x) / (8 * math.pi * eta * r ** 3), rel=1e-12)


@pytest.mark.parametrize("q", [0.999, 0.99, 0.95])
def test_inverse(q):
    for branch in ("positive", "negative"):
        if branch == "negative" and q < 0.905:
            continue
        a, beta = theory.slip_sphere_from_radii(1.2, 1.2 * q, branch=branch)
        assert (beta > 0) == (branch == "positive")
        Rt, Rr, _ = theory.slip_sphere_radii(a, beta)
        assert (Rt, Rr) == pytest.approx((1.2, 1.2 * q), rel=1e-10)
    assert theory.slip_sphere_from_radii(1.2, 1.2) == (1.2, 0.0)


def test_box_correction():
    R = 1.0
    z0 = 8 * math.pi * ETA * R ** 3
    assert theory.rotational_friction_unbounded(z0, ETA, np.inf) == pytest.approx(z0, rel=1e-15)
    for L in (4.3756, 6.0, 50.0):
        # the friction the box shows: kT/zeta_L = rotational_diffusion_coefficient(L)
        zL = 0.1 / theory.rotational_diffusion_coefficient(ETA, R, L, kT=0.1)
        assert theory.rotational_friction_unbounded(zL, ETA, L) == pytest.approx(z0, rel=1e-13)
        # the small-R limit: zeta_L = zeta_0 (1 + phi), phi = (4 pi/3) R^3/L^3
        phi = 4 * math.pi / 3 * R ** 3 / L ** 3
        assert zL / z0 - 1 == pytest.approx(phi, rel=2 * phi)
    z, ze = theory.rotational_friction_unbounded(9.0, ETA, 4.3756, zeta_err=0.09)
    assert ze / z == pytest.approx(0.01 * z / 9.0, rel=1e-12)
    Rr, err = theory.rotational_radius(z0, ETA, zeta_err=0.03 * z0, eta_err=0.0)
    assert Rr == pytest.approx(R, rel=1e-14)
    assert err == pytest.approx(0.01, rel=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="beta"):
        theory.slip_sphere_intrinsic_viscosity(-0.2)
    with pytest.raises(ValueError, match="beta"):
        theory.slip_sphere_intrinsic_viscosity(float("nan"))
    with pytest.raises(ValueError, match="'a'"):
        theory.slip_sphere_radii(0.0, 0.1)
    with pytest.raises(ValueError, match="R_r/R_t"):
        theory.slip_sphere_from_radii(1.0, 1.01)
    with pytest.raises(ValueError, match="negative branch"):
        theory.slip_sphere_from_radii(1.0, 0.9, branch="negative")
    with pytest.raises(ValueError, match="branch"):
        theory.slip_sphere_from_radii(1.0, 0.99, branch="both")
    with pytest.raises(ValueError, match="R_t"):
        theory.slip_sphere_from_radii(-1.0, 0.99)
    with pytest.raises(ValueError, match="zeta_L"):
        theory.rotational_friction_unbounded(0.0, ETA, 5.0)
    with pytest.raises(ValueError, match="'L'"):
        theory.rotational_friction_unbounded(8.0, ETA, -5.0)
    with pytest.raises(ValueError, match="zeta_err"):
        theory.rotational_friction_unbounded(8.0, ETA, 5.0, zeta_err=-1.0)
    with pytest.raises(ValueError, match="eta"):
        theory.rotational_radius(8.0, 0.0)
    with pytest.raises(ValueError, match="eta_err"):
        theory.rotational_radius(8.0, ETA, eta_err=float("inf"))


# --- bench/stick_colloid_radii.py's bookkeeping of the stick settings (section 7n) ---

def _bench():
    from bench_module import load_bench
    return load_bench("stick_colloid_radii")


def _drive(b, Rr, a, seed, L=None, torque=0.85, Dt=None, **setting):
    """A synthetic drive run of a sphere with rotational radius Rr (and, if given, the
    equilibrium MSD D of a stick sphere of radius Dt, in the lab frame) in the box L."""
    L = b.L_PHI05 if L is None else L
    z0 = 8 * math.pi * ETA * Rr ** 3
    zL = 1.0 / (1.0 / z0 - 1.0 / (6 * ETA * L ** 3))  # inverse of the box correction
    r = dict(part="drive", L=L, torque=torque, seed=seed, time=10000.0, core_radius=a, n_solvent=239,
             zeta_L=zL, zeta_L_err=0.01 * zL, omega_z=torque / zL, D_r_gk=0.1 / zL, D_r_gk_err=0.01 / zL,
             kT_rot=1.0, kT_rot_err=0.002, cpu_s=90.0)
    if Dt is not None:
        fac = (1.0 + 4.0 * math.pi * a ** 3 / 239) ** 2
        r.update(D_msd=theory.hasimoto_D(ETA, Dt, L, kT=0.1) / fac, D_msd_err=1e-4)
    r.update(setting)
    return r


def test_table_groups_by_setting(tmp_path):
    """--part table groups the drive runs by (L, T, core, trans_gamma, stick_shell): runs without
    the keys are setup_suspension's defaults (45, the shell r'_c) and group with runs that carry
    them; another time step is its own group, left out of the combined blocks, and the scan
    uses T <= 0.85 only; the 7m blocks (all calibrated groups) use the default setting only; the settings scan
    gives each setting's R_r/a, R_t/a (drag and MSD) and R_r/R_t."""
    b = _bench()
    a_cal = 1.0 / b.C_T
    L = b.L_PHI05
    runs = [_drive(b, 1.05 * a_cal, a_cal, 1),                                    # 7m's lines: no keys
            _drive(b, 1.05 * a_cal, a_cal, 2, trans_gamma=45.0, stick_shell=None),  # the defaults, spelt out
            _drive(b, 1.10, 1.0, 1, Dt=1.02, trans_gamma=15.0, stick_shell=None),
            _drive(b, 1.10, 1.0, 2, Dt=1.02, trans_gamma=15.0),
            _drive(b, 1.20, 1.0, 1, Dt=1.10, trans_gamma=45.0, stick_shell=0.5),
            _drive(b, 1.50, 1.0, 3, Dt=1.50, stick_shell=0.5, dt=0.005),  # another time step: its own row only
            _drive(b, 1.40, 1.0, 4, Dt=1.40, stick_shell=0.5, torque=1.7)]  # T > 0.85: its own row only
    drags = [dict(part="drag", boundary="stick", solvent_count="exact", trans_gamma=0.0, stick_gamma=15.0,
                  stick_shell=None, core_radius=1.0, L=L, force=1.0, time=10000.0, seed=s, cpu_s=90.0,
                  D=theory.hasimoto_D(ETA, 1.04, L, kT=0.1), D_err=1e-4) for s in (1, 2)]
    drags.append(dict(part="drag", boundary="slip", solvent_count="exact", core_radius=1.0, L=L, force=1.0,
                      time=1.0, D=1.0, D_err=0.1))  # not a stick run: ignored
    fn = tmp_path / "runs.jsonl"
    fn.write_text("".join(json.dumps(r) + "\n" for r in runs + drags))
    out = b.table(b.parse(["--part", "table", "--results", str(fn), "--eta0", str(ETA), "0.003"]))
    groups = {(g["core_radius"], g["trans_gamma"], g["stick_shell"], g["dt"], g["torque"]): g for g in out["groups"]}
    assert {k: g["n"] for k, g in groups.items()} == {
        (1.0, 15.0, None, 0.01, 0.85): 2, (1.0, 45.0, 0.5, 0.01, 0.85): 1, (1.0, 45.0, 0.5, 0.005, 0.85): 1,
        (1.0, 45.0, 0.5, 0.01, 1.7): 1, (round(a_cal, 6), 45.0, None, 0.01, 0.85): 2}
    # the calibrated (default) block sees only its own two runs
    assert out["R_r_over_a"] == pytest.approx(1.05, rel=1e-5)  # the group keys round a to 1e-6 and L to 1e-4
    for g in out["groups"]:
        assert g["zeta_0"] == pytest.approx(8 * math.pi * ETA * (g["R_r"]) ** 3, rel=1e-12)
    scan = {(x["core_radius"], x["trans_gamma"], x["stick_shell"]): x for x in out["settings"]}
    s15 = scan[(1.0, 15.0, None)]
    assert (s15["n_drive"], s15["n_drag"]) == (2, 2)
    assert s15["R_r_over_a"] == pytest.approx(1.10, rel=1e-5)
    assert s15["R_t_drag_over_a"] == pytest.approx(1.04, rel=1e-6)
    assert s15["R_t_msd_over_a"] == pytest.approx(1.02, rel=1e-6)
    assert s15["R_t_over_a"] == s15["R_t_drag_over_a"]  # the drag's R_t where there is one
    assert s15["ratio_r_t"] == pytest.approx(s15["R_r_over_a"] / s15["R_t_over_a"], rel=1e-12)
    assert s15["ratio_r_t_err"] > 0
    s5 = scan[(1.0, 45.0, 0.5)]
    assert (s5["n_drive"], s5["n_drag"], s5["stick_shell_used"]) == (1, 0, 0.5)
    assert s5["R_t_drag_over_a"] is None
    assert s5["ratio_r_t"] == pytest.approx(1.20 / 1.10, rel=1e-5)
    # without drag runs and with the defaults only, no settings block (7m's output unchanged)
    fn2 = tmp_path / "defaults.jsonl"
    fn2.write_text("".join(json.dumps(r) + "\n" for r in runs[:2]))
    assert "settings" not in b.table(b.parse(["--part", "table", "--results", str(fn2)]))


@pytest.mark.parametrize("opt", ["--trans-gamma", "--stick-shell"])
@pytest.mark.parametrize("val", ["0", "-0.1", "nan", "inf"])
def test_drive_options_bad_input(opt, val, capsys):
    b = _bench()
    with pytest.raises(SystemExit):
        b.parse(["--part", "drive", opt, val])
    assert f"{opt} must be > 0" in capsys.readouterr().err
    args = b.parse(["--part", "drive", opt, "0.3"])
    assert getattr(args, opt[2:].replace("-", "_")) == 0.3
