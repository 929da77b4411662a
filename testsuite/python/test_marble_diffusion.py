# labels: python long
"""Diffusion of a marble colloid (Zhou & Schmid; reference.md sections 2, 3, 5)
at reduced size, by the three methods of the paper.

1. The solvent viscosity eta is measured here (reverse Poiseuille, a short run)
   and used for the theory; the drag-method D of a no-slip marble (gamma = 5,
   R = 2, L = 10) agrees with Hasimoto's D(L) within 3 sigma (errors of D and
   of eta combined), and within max(5 %, 3 sigma_D) of Hasimoto with the
   engine's reference eta = 1.24.
2. A slippery surface (gamma = 0.5) diffuses faster than the no-slip one by
   more than 4 combined sigma (drag method, same box).
3. In a small box (R = 1.5, L = 8) the Green-Kubo integral of the VACF and the
   MSD slope agree with the drag value of the same system within 3 combined
   sigma; errors from independent chunks of one equilibrium run. The errors
   must be below 15 % so that the comparison means something.

The equilibrium D's are those of the colloid-solvent relative coordinate (the
colloid's own divided by (Ms/(M+Ms))^2, see marble.colloid_runs), which is
what the drag method measures. The helpers live in marble.colloid_runs.

Measured: 225 s CPU (299 s wall on a shared, loaded 2-core machine)."""
import os
import time

import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(
    not marble.has_features("MARBLE", "EXTERNAL_FORCE"),
    reason="missing feature MARBLE or EXTERNAL_FORCE")

from marble.colloid_runs import (DT, analyse_equilibrium, drag_run, equilibrium_run,  # noqa: E402
                         make_system)
from marble import theory as th  # noqa: E402

ETA_REF = 1.24        # the engine's measured viscosity of this solvent
_cache = {}


def eta_measured():
    """Shear viscosity of the paper's solvent from a short reverse-Poiseuille run."""
    if "eta" not in _cache:
        from marble.viscosity import reverse_poiseuille
        t0 = time.time()
        rng = np.random.default_rng(11)
        box = np.array([8.0, 8.0, 10.0])
        n = int(round(3.0 * np.prod(box)))
        s = marble.System(box_l=box)
        s.time_step = DT
        s.cell_system.skin = 0.4
        v = rng.normal(size=(n, 3))
        s.part.add(pos=rng.random((n, 3)) * box, v=v - v.mean(axis=0))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=11)
        res = reverse_poiseuille(s, g=0.08, time=300.0, equilibration=20.0)
        print(f"\neta = {res.eta:.4f} +- {res.eta_err:.4f} (reverse Poiseuille, box {box}, "
              f"300 tau, {time.time() - t0:.0f} s)")
        _cache["eta"] = (res.eta, res.eta_err)
    return _cache["eta"]


def drag(R, L, gamma, speed, t_prod, seed):
    key = (R, L, gamma, speed, t_prod, seed)
    if key not in _cache:
        t0 = time.time()
        F = speed / th.hasimoto_D(ETA_REF, R, L)
        system, col, _ = make_system(L, R, gamma, seed)
        res = drag_run(system, col, F, t_prod)
        print(f"\ndrag R={R} L={L} gamma={gamma} F={F:.2f} {t_prod} tau: D = {res.D:.5f} +- "
              f"{res.D_err:.5f} (blocking alone {res.D_err_blocking:.5f}; v = {res.v:.4f}, "
              f"{time.time() - t0:.0f} s)")
        _cache[key] = (res.D, res.D_err)
    return _cache[key]


NO_SLIP = dict(R=2.0, L=10.0, gamma=5.0, speed=0.12, t_prod=1500.0, seed=5)


def test_drag_no_slip_hasimoto():
    """Drag D of a no-slip marble against Hasimoto with the measured eta.

    Compared at L -> infinity: Hasimoto's finite-size terms are the same for any
    surface (reference.md section 5), so D_inf = D(L) + kT/(6 pi eta) (2.837297/L
    - (4 pi/3) R^2/L^3), and D_inf / D_stokes = R (6 pi eta D(L) + 2.837297/L -
    (4 pi/3) R^2/L^3). reference.md expects agreement "within ~3-5 %" (the
    marble's hydrodynamic radius need not be exactly R); the tolerance is that
    5 % plus 3 standard errors (from D and eta). Comparing D(L) itself would
    amplify the same few-% radius offset ~2x at L = 5R (bench/speed_accuracy:
    R_h = 1.900 +- 0.010 for R = 2). A perfectly slipping sphere gives ~1.5."""
    eta, eta_err = eta_measured()
    assert eta_err < 0.05, "viscosity run too short for a meaningful check"
    D, D_err = drag(**NO_SLIP)
    R, L = NO_SLIP["R"], NO_SLIP["L"]
    D_h = th.hasimoto_D(eta, R, L)
    fs = 2.837297 / L - 4.0 * np.pi / 3.0 * R**2 / L**3
    ratio = R * (6.0 * np.pi * eta * D + fs)
    ratio_err = 6.0 * np.pi * R * np.hypot(eta * D_err, D * eta_err)
    print(f"\nno slip: D(L) = {D:.5f} +- {D_err:.5f}; Hasimoto stick (eta = {eta:.3f} +- "
          f"{eta_err:.3f} measured) {D_h:.5f}; D_inf / D_stokes = {ratio:.3f} +- {ratio_err:.3f}")
    assert D_err < 0.035 * D, "drag run too short for a meaningful check"
    assert abs(ratio - 1.0) < 0.05 + 3.0 * ratio_err
    # clearly not the perfect-slip value
    assert th.hasimoto_D(eta, R, L, boundary="slip") - D > 5 * D_err


def test_slippery_surface_diffuses_faster():
    D_ns, e_ns = drag(**NO_SLIP)
    D_sl, e_sl = drag(R=2.0, L=10.0, gamma=0.5, speed=0.12, t_prod=400.0, seed=6)
    R, L = NO_SLIP["R"], NO_SLIP["L"]
    D_slip = th.hasimoto_D(ETA_REF, R, L, boundary="slip")
    print(f"\ngamma=0.5: D = {D_sl:.5f} +- {e_sl:.5f}; gamma=5: {D_ns:.5f} +- {e_ns:.5f}; "
          f"perfect slip {D_slip:.5f}")
    assert D_sl - D_ns > 4 * np.hypot(e_sl, e_ns)
    # a partially slipping sphere stays below the perfect-slip limit
    assert D_sl < D_slip + 3 * e_sl


def test_equilibrium_methods_agree_with_drag():
    R, L, gamma = 1.5, 8.0, 5.0
    D_d, e_d = drag(R, L, gamma, speed=0.15, t_prod=600.0, seed=21)
    t0 = time.time()
    system, col, _ = make_system(L, R, gamma, seed=22)
    eq = equilibrium_run(system, col, t_chunk=200.0, n_chunks=12, vacf_tau_max=40.0,
                         msd_tau_max=50.0)
    gk, win_gk, msd, win_msd = analyse_equilibrium(eq, L, ETA_REF)
    print(f"\nR={R} L={L}, 12 x 200 tau ({time.time() - t0:.0f} s): "
          f"Green-Kubo D = {gk.value:.5f} +- {gk.error:.5f} (window {win_gk[0]:.1f}-"
          f"{win_gk[1]:.1f}); MSD D = {msd.value:.5f} +- {msd.error:.5f} (window "
          f"{win_msd[0]:.1f}-{win_msd[1]:.1f}); drag D = {D_d:.5f} +- {e_d:.5f}; "
          f"Hasimoto {th.hasimoto_D(ETA_REF, R, L):.5f}")
    assert e_d < 0.06 * D_d
    for name, (D, e) in (("Green-Kubo", (gk.value, gk.error)), ("MSD", (msd.value, msd.error))):
        assert e < 0.15 * D, f"{name}: error too large for a meaningful check"
        assert abs(D - D_d) < 3 * np.hypot(e, e_d), f"{name} disagrees with drag"
