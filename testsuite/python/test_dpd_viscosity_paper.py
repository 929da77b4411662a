# labels: paper
"""Full-size viscosity of the marble paper's solvent (label `paper`, run by hand;
~8 min on one core): reverse Poiseuille flow in a 12 x 12 x 16 box over 2000 time
units, eta to ~0.5 %. Must lie in [1.23, 1.26] within 2 error bars (measured:
1.2734 +/- 0.0067, at the edge; rerun 2026-12-04: 1.2776 +/- 0.0065, which fails by
0.005; Shardlow and dt = 0.005 give the same, doc/dpd.md discusses the ~2 % excess, an
open question, not fixed by loosening this bound)."""
import unittest

from test_dpd_viscosity import ETA_RANGE, measure_eta
from unittest_decorators import skipIfMissingFeatures


@skipIfMissingFeatures("EXTERNAL_FORCE")
class PaperSolventViscosity(unittest.TestCase):

    def test_paper_solvent_full(self):
        res = measure_eta([12, 12, 16], 2000.0, g=0.04, equilibration=50.0)
        self.assertLess(res.eta_err, 0.012)
        self.assertGreater(res.eta, ETA_RANGE[0] - 2 * res.eta_err)
        self.assertLess(res.eta, ETA_RANGE[1] + 2 * res.eta_err)


if __name__ == "__main__":
    unittest.main()
