# labels: python long
"""Shear viscosity of Groot-Warren DPD water (a = 25, gamma = 4.5, rho = 3,
w_D = (1 - r)^2, kT = 1; reference.md section 2: eta ~ 0.85) by reverse
Poiseuille flow, CI-sized (~2 % precise). Accepted: within 0.02 (the "~" of
the reference) plus 3 error bars of 0.85."""
import os
import unittest

from test_dpd_viscosity import measure_eta
from unittest_decorators import skipIfMissingFeatures

ETA_GW = 0.85


@skipIfMissingFeatures("EXTERNAL_FORCE", "HAT")
class GrootWarrenViscosity(unittest.TestCase):

    def test_groot_warren_water(self):
        time = float(os.environ.get("MARBLE_DPD_ETA_TIME", 300.0))
        res = measure_eta([10, 10, 12], time, g=0.045, a=25.0, gamma=4.5)
        self.assertLess(res.eta_err, 0.03, "run too short for a meaningful check")
        self.assertLess(abs(res.eta - ETA_GW), 0.02 + 3 * res.eta_err)


if __name__ == "__main__":
    unittest.main()
