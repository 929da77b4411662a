# labels: python long
"""One stick colloid at volume fraction 0.05 (setup_suspension(boundary="stick"),
doc/suspensions.md sections 7c and 7d), built with setup_suspension's default radius
calibration: R = 1 is the HYDRODYNAMIC radius, the core 1/STICK_RADIUS_RATIO (the
geometry of the calibration is unit-tested in test_suspension.py). Seed 004's solvent and colloid (rho = 3,
kT = 0.1, gamma = 4.5, mean-field colloid-solvent hat and DPD on the gap,
colloid mass 3 (4/3) pi a^3) plus the tangential surface_friction (gamma 45) on the
colloid-solvent shell and a rotating colloid (I = 2/5 M a^2), one colloid in a
periodic cube of edge L = 4.376 with exactly round(3 x free volume) = 239 beads
(solvent_count="exact": a Poisson count scatters D by ~7 % between seeds), Shardlow dt = 0.01.

- D by drag (marble.diffusion.measure_drag, F = 0.5, 3000 time units; error the
  larger of blocking and sqrt(2 D/T)) within 10 % + 3 sigma of Hasimoto's STICK
  D(L) at R_h = R (the calibrated radius) with the solvent's measured
  eta_0 = 0.3106 +/- 0.0049 (the calibration's), and below
  0.6 x the slip formula (seed 004's slip colloid gives 1.11 x slip, test_suspension_hasimoto.py);
- rotational equipartition <I w^2>/3 = kT within 3 % + 3 sigma (blocking), 1000
  time units after the drag (the spins see the Shardlow pair update's torques only).
"""
import math

import numpy as np
import pytest

import marble
from marble import theory

if not marble.has_features("DPD", "TRANS_DPD", "ROTATION", "HAT", "CONTACT", "LUBRICATION", "MASS",
                           "EXTERNAL_FORCE"):
    pytest.skip("needs DPD, TRANS_DPD, ROTATION, HAT, CONTACT, LUBRICATION, MASS, EXTERNAL_FORCE",
                allow_module_level=True)

import marble.suspensions as sus
from suspension_common import ETA0 as ETA, ETA0_ERR as ETA_ERR, KT, L, R, drag_D, single_colloid

T = 3000.0


def test_stick_colloid_diffuses_as_hasimoto_stick_and_rotates_at_kT():
    s, info = single_colloid(7, boundary="stick", solvent_count="exact")
    a = R / sus.STICK_RADIUS_RATIO
    assert info["radius_calibration"] == "stick"
    assert info["core_radius"] == pytest.approx(a, rel=1e-14)
    assert info["hydrodynamic_radius"] == pytest.approx(R, rel=1e-14)
    assert info["rinertia"] == pytest.approx(0.4 * info["colloid_mass"] * a * a)
    D, D_err = drag_D(s, info, T)
    rel = math.hypot(D_err / D, ETA_ERR / ETA)
    stick = D / theory.hasimoto_D(ETA, R, L, kT=KT, boundary="stick")
    slip = D / theory.hasimoto_D(ETA, R, L, kT=KT, boundary="slip")
    # spins, force off
    c = s.part.by_ids(info["colloid_ids"])
    w = []
    for _ in range(20000):
        s.integrator.run(5)
        w.append(c.omega_lab[0])
    ke = info["rinertia"] * np.array([np.mean(b ** 2) for b in np.array_split(np.array(w), 10)]) / KT
    ke_m, ke_e = ke.mean(), ke.std(ddof=1) / math.sqrt(len(ke))
    print(f"D = {D:.5f} +- {D_err:.5f}; D / stick Hasimoto = {stick:.3f} +- {stick * rel:.3f}, "
          f"D / slip Hasimoto = {slip:.3f}; <I w^2>/(3 kT) = {ke_m:.4f} +- {ke_e:.4f}")
    assert D_err / D < 0.08, f"statistics too poor: D = {D} +- {D_err}"
    assert abs(stick - 1) < 0.10 + 3 * stick * rel, f"D / Hasimoto(stick, R) = {stick} +- {stick * rel}"
    assert slip < 0.6, f"D / Hasimoto(slip, R) = {slip}: expected a stick sphere"
    assert ke_e < 0.02, f"statistics too poor: {ke_m} +- {ke_e}"
    assert abs(ke_m - 1) < 0.03 + 3 * ke_e, f"<I w^2>/(3 kT) = {ke_m} +- {ke_e}"
