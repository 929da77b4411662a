# labels: python
"""marble.viscosity: the blocking analysis on series with known errors, the
joint parabola fit on exact profiles, input validation, and a short reverse
Poiseuille run (zero net force, ext_force restored, profile of the right sign)."""
import unittest

import numpy as np

import marble
from marble import viscosity
from unittest_decorators import skipIfMissingFeatures


class BlockAverage(unittest.TestCase):

    def test_white_and_correlated_noise(self):
        rng = np.random.default_rng(1)
        n = 2**16
        x = rng.normal(3.0, 2.0, size=n)
        m, err = viscosity.block_average(x)
        self.assertAlmostEqual(err / (2.0 / np.sqrt(n)), 1.0, delta=0.25)
        self.assertLess(abs(m - 3.0), 5 * err)
        # AR(1), phi = 0.9: error of the mean = sigma_eps / (1 - phi) / sqrt(n)
        phi, eps = 0.9, rng.normal(size=n)
        y = np.empty(n)
        y[0] = 0.0
        for i in range(1, n):
            y[i] = phi * y[i - 1] + eps[i]
        m, err = viscosity.block_average(y)
        self.assertAlmostEqual(err / (1.0 / (1.0 - phi) / np.sqrt(n)), 1.0, delta=0.25)
        with self.assertRaises(ValueError):
            viscosity.block_average([1.0])


class ParabolaFit(unittest.TestCase):

    def test_exact_profile(self):
        L, nb, c = 12.0, 24, -0.037
        z = (np.arange(nb) + 0.5) * L / nb
        v = np.where(z < L / 2, 0.3 + 0.01 * z + c * (z - L / 4) ** 2,
                     -0.2 - 0.02 * z - c * (z - 3 * L / 4) ** 2)
        v_bad = v.copy()
        v_bad[[0, 11, 12, 23]] = 99.0  # bins within the margin are not used
        for prof in (v, v_bad):
            used, A, pinv = viscosity._fit_matrix(z, L, margin=1.0)
            self.assertAlmostEqual(prof[used] @ pinv[4], c, places=12)
        self.assertEqual(len(used), nb - 8)


class ReversePoiseuilleRun(unittest.TestCase):

    def fluid(self):
        s = marble.System(box_l=[4.0, 4.0, 8.0])
        s.time_step = 0.01
        rng = np.random.default_rng(2)
        v = rng.normal(size=(384, 3))
        s.part.add(pos=rng.uniform(0, 1, size=(384, 3)) * s.box_l, v=v - v.mean(axis=0))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=1)
        return s

    @skipIfMissingFeatures("EXTERNAL_FORCE")
    def test_validation(self):
        s = self.fluid()
        for kw in (dict(g=0.0, time=10), dict(g=-1, time=10), dict(g=0.1, time=10, flow_dir=2),
                   dict(g=0.1, time=10, n_bins=7), dict(g=0.1, time=10, n_blocks=1),
                   dict(g=0.1, time=0.01), dict(g=0.1, time=10, margin=3.0)):
            with self.subTest(kw=kw), self.assertRaises(ValueError):
                viscosity.reverse_poiseuille(s, **kw)

    @skipIfMissingFeatures("EXTERNAL_FORCE")
    def test_short_run(self):
        s = self.fluid()
        p = s.part.all()
        own = np.zeros((len(p), 3))
        own[:, 1] = 1e-3  # a user's own external force is kept and restored
        p.ext_force = own
        mom0 = s.analysis.linear_momentum()
        res = viscosity.reverse_poiseuille(s, g=0.2, time=4.0, equilibration=2.0, margin=0.5,
                                           n_blocks=4)
        np.testing.assert_array_equal(p.ext_force, own)
        # zero net x force during the run: x momentum conserved to round-off
        dp = s.analysis.linear_momentum() - mom0
        self.assertLess(abs(dp[0]), 1e-9)
        self.assertGreater(res.v[4], 0.0)   # lower half flows along +x
        self.assertLess(res.v[12], 0.0)     # upper half along -x
        self.assertTrue(np.isfinite(res.eta) and np.isfinite(res.eta_err))
        self.assertEqual(len(res.eta_blocks), 4)


if __name__ == "__main__":
    unittest.main()
