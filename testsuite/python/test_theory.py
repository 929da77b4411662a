# labels: python
"""marble.theory against the reference.md section 5 table (eta = 1.23, kT = 1,
R = 3) and its formulas, plus the inverse fits (slip length, hydrodynamic radius)."""
import unittest

import numpy as np

from marble import theory as th

ETA, R = 1.23, 3.0


class Theory(unittest.TestCase):

    def test_reference_table(self):
        # (computed, value as printed, half a unit of its last digit)
        table = [(th.hasimoto_D(ETA, R), 0.01438, 5e-6),
                 (th.hasimoto_D(ETA, R, 20.0), 0.00846, 5e-6),
                 (th.hasimoto_D(ETA, R, boundary="slip"), 0.02157, 5e-6),
                 (th.hasimoto_D(ETA, R, 20.0, boundary="slip"), 0.01545, 5e-6),
                 (th.rotational_diffusion_coefficient(ETA, R), 1.198e-3, 5e-7),
                 (th.rotational_diffusion_coefficient(ETA, R, 20.0), 1.181e-3, 5e-7)]
        for got, ref, delta in table:
            self.assertAlmostEqual(got, ref, delta=delta)

    def test_basset(self):
        zT, zR = th.basset_friction(ETA, R, 0.0)
        self.assertAlmostEqual(zT, 6 * np.pi * ETA * R, places=12)
        self.assertAlmostEqual(zR, 8 * np.pi * ETA * R ** 3, places=10)
        zT, zR = th.basset_friction(ETA, R, np.inf)
        self.assertAlmostEqual(zT, 4 * np.pi * ETA * R, places=12)
        self.assertEqual(zR, 0.0)
        b = 0.8
        zT, zR = th.basset_friction(ETA, R, b)
        self.assertAlmostEqual(zT, 6 * np.pi * ETA * R * (1 + 2 * b / R) / (1 + 3 * b / R),
                               places=12)
        self.assertAlmostEqual(zR, 8 * np.pi * ETA * R ** 3 / (1 + 3 * b / R), places=10)
        # partial slip interpolates between the two limits, monotonically
        Ds = [th.diffusion_coefficient(ETA, R, 20.0, b) for b in (0, 0.3, 1, 3, 30, np.inf)]
        self.assertTrue(np.all(np.diff(Ds) > 0))
        self.assertEqual(Ds[0], th.hasimoto_D(ETA, R, 20.0))
        self.assertEqual(Ds[-1], th.hasimoto_D(ETA, R, 20.0, boundary="slip"))
        self.assertAlmostEqual(th.diffusion_coefficient(ETA, R, 20.0, 1e9), Ds[-1], places=9)
        # D_r with slip and the surface-independent box correction kT/(6 eta L^3)
        self.assertAlmostEqual(th.rotational_diffusion_coefficient(ETA, R, 20.0, b),
                               1 / zR - 1 / (6 * ETA * 8000.0), places=14)
        self.assertEqual(th.rotational_diffusion_coefficient(ETA, R, b=np.inf), np.inf)

    def test_hasimoto_slope(self):
        """The 1/L coefficient is the same for every surface; kT and eta scale D."""
        for b in (0.0, 0.5, np.inf):
            L = np.array([4000.0, 8000.0])
            D = th.diffusion_coefficient(ETA, R, L, b)
            slope = (D[1] - D[0]) / (1 / L[1] - 1 / L[0])
            self.assertAlmostEqual(slope / (-th.HASIMOTO_XI / (6 * np.pi * ETA)), 1.0, places=4)
        self.assertAlmostEqual(th.hasimoto_D(2 * ETA, R, 20.0, kT=3.0),
                               1.5 * th.hasimoto_D(ETA, R, 20.0), places=14)

    def test_tails(self):
        nu, rho = ETA / 3.0, 3.0
        self.assertAlmostEqual(th.vacf_tail_amplitude(ETA, rho),
                               1 / (12 * rho * (np.pi * nu) ** 1.5), places=14)
        self.assertAlmostEqual(th.vacf_tail_amplitude(ETA, rho), 0.0190019, places=6)
        self.assertAlmostEqual(th.rotational_vacf_tail_amplitude(ETA, rho), 0.0173798, places=6)
        D = 0.01
        self.assertAlmostEqual(th.rotational_vacf_tail_amplitude(ETA, rho, 2.0, D),
                               2 * np.pi / (rho * (4 * np.pi * (nu + D)) ** 2.5), places=14)
        t = np.array([10.0, 40.0])
        np.testing.assert_allclose(th.vacf_tail(t, ETA, rho),
                                   th.vacf_tail_amplitude(ETA, rho) * t ** -1.5)
        np.testing.assert_allclose(th.rotational_vacf_tail(t, ETA, rho),
                                   th.rotational_vacf_tail_amplitude(ETA, rho) * t ** -2.5)

    def test_inverse_fits(self):
        for b in (-0.5, 0.0, 0.7, 5.0):
            D = th.diffusion_coefficient(ETA, R, 20.0, b)
            bf, err = th.slip_length_from_D(D, ETA, R, 20.0)
            self.assertAlmostEqual(bf, b, places=7)
            self.assertTrue(np.isnan(err))
        # several box sizes with errors: least squares, error from linearisation
        Ls = np.array([15.0, 20.0, 30.0])
        D = th.diffusion_coefficient(ETA, R, Ls, 0.7)
        bf, err = th.slip_length_from_D(D, ETA, R, Ls, D_err=1e-4)
        self.assertAlmostEqual(bf, 0.7, places=7)
        h = 1e-5
        dD = (th.diffusion_coefficient(ETA, R, Ls, 0.7 + h)
              - th.diffusion_coefficient(ETA, R, Ls, 0.7 - h)) / (2 * h)
        self.assertAlmostEqual(err, 1e-4 / np.sqrt(np.sum(dD ** 2)), places=6)
        Rh, err = th.hydrodynamic_radius_from_D(th.hasimoto_D(ETA, 3.3, 20.0), ETA, 20.0,
                                                D_err=1e-4)
        self.assertAlmostEqual(Rh, 3.3, places=7)
        self.assertGreater(err, 0)
        Rh, _ = th.hydrodynamic_radius_from_D(th.hasimoto_D(ETA, 2.5), ETA)
        self.assertAlmostEqual(Rh, 2.5, places=7)
        # faster than a perfectly slipping sphere: no slip length explains it
        with self.assertRaises(ValueError):
            th.slip_length_from_D(1.01 * th.hasimoto_D(ETA, R, 20.0, boundary="slip"),
                                  ETA, R, 20.0)

    def test_bad_parameters(self):
        for kw in (dict(eta=0.0), dict(eta=-1.0), dict(R=0.0), dict(L=-5.0), dict(b=-1.0),
                   dict(b=np.nan), dict(kT=0.0), dict(eta=np.inf)):
            p = dict(eta=ETA, R=R, L=20.0, b=0.0, kT=1.0)
            p.update(kw)
            with self.assertRaises(ValueError, msg=str(kw)):
                th.diffusion_coefficient(**p)
        with self.assertRaises(ValueError):
            th.hasimoto_D(ETA, R, boundary="partial")
        with self.assertRaises(ValueError):
            th.slip_length_from_D(-1.0, ETA, R)


if __name__ == "__main__":
    unittest.main()
