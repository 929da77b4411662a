# labels: python long
"""Shear viscosity of the marble paper's DPD solvent (reference.md section 2:
rho = 3, gamma = 5, no conservative force, w_D = (1 - r)^2, r_cut = 1, kT = 1)
by reverse Poiseuille flow (marble.viscosity). The paper measured
eta = 1.23 +/- 0.01 and an independent check 1.25 +/- 0.01; the measured value
must lie in [1.23, 1.26] within 3 error bars of this (CI-sized, ~2 % precise)
run, and far from the mean-field value 0.896 that a convention bug would give.
The full-size version is test_dpd_viscosity_paper.py (label `paper`)."""
import os
import unittest

import numpy as np

import marble
from marble.viscosity import reverse_poiseuille
from unittest_decorators import skipIfMissingFeatures

ETA_RANGE = (1.23, 1.26)
ETA_MEAN_FIELD = 45 / (4 * np.pi * 5) + 2 * np.pi * 5 * 9 / 1575  # 0.896


def measure_eta(box, time, g, a=0.0, gamma=5.0, dt=0.01, seed=3, equilibration=20.0):
    rng = np.random.default_rng(seed)
    box = np.asarray(box, dtype=float)
    n = int(round(3.0 * np.prod(box)))
    s = marble.System(box_l=box)
    s.time_step = dt
    s.cell_system.skin = 0.4
    v = rng.normal(size=(n, 3))
    s.part.add(pos=rng.uniform(0, 1, size=(n, 3)) * box, v=v - v.mean(axis=0))
    if a > 0:
        s.non_bonded_inter[0, 0].hat.set_params(F_max=a, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    s.integrator.run(200)
    res = reverse_poiseuille(s, g=g, time=time, equilibration=equilibration)
    print(f"\n{res}: box {box}, a = {a}, gamma = {gamma}, g = {g}, time {res.time}, "
          f"kT = {res.kT:.4f}, v_max = {res.v_max:.3f}")
    return res


@skipIfMissingFeatures("EXTERNAL_FORCE")
class DPDSolventViscosity(unittest.TestCase):

    def test_paper_solvent(self):
        time = float(os.environ.get("MARBLE_DPD_ETA_TIME", 400.0))
        res = measure_eta([10, 10, 12], time, g=0.06)
        self.assertLess(res.eta_err, 0.05, "run too short for a meaningful check")
        self.assertGreater(res.eta, ETA_RANGE[0] - 3 * res.eta_err)
        self.assertLess(res.eta, ETA_RANGE[1] + 3 * res.eta_err)
        self.assertGreater(res.eta - ETA_MEAN_FIELD, 6 * res.eta_err)


if __name__ == "__main__":
    unittest.main()
