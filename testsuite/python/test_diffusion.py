# labels: python
"""marble.diffusion: blocking on AR(1) series with a known error of the mean,
Green-Kubo and MSD fits on an Ornstein-Uhlenbeck process with a known D, and
the constant-force drag helper on a small DPD system."""
import unittest

import numpy as np

import marble
from marble import accumulators as acc
from marble import diffusion as dif
from unittest_decorators import skipIfMissingFeatures


def ar1(rng, n, a, shape=()):
    """x_{k+1} = a x_k + sqrt(1 - a^2) xi: stationary, unit variance,
    correlation a^k."""
    x = np.empty((n,) + shape)
    x[0] = rng.normal(size=shape)
    xi = rng.normal(size=(n,) + shape) * np.sqrt(1 - a * a)
    for k in range(1, n):
        x[k] = a * x[k - 1] + xi[k]
    return x


class Blocking(unittest.TestCase):

    def test_correlated_series(self):
        rng = np.random.default_rng(21)
        n, a = 2 ** 16, 0.9
        x = ar1(rng, n, a) + 3.0
        exact = np.sqrt((1 + a) / (1 - a) / n)  # standard error of the mean of AR(1)
        mean, err, plateau = dif.blocking(x)
        self.assertAlmostEqual(err / exact, 1.0, delta=0.2)
        self.assertLess(abs(mean - 3.0), 4 * exact)
        self.assertGreaterEqual(plateau, 8)  # correlation time ~ (1+a)/(1-a) = 19 samples
        naive = np.std(x) / np.sqrt(n)
        self.assertGreater(err, 3 * naive)

    def test_uncorrelated_series(self):
        rng = np.random.default_rng(22)
        x = rng.normal(size=4096)
        res = dif.blocking(x)
        self.assertTrue(res.converged)
        self.assertLessEqual(res.plateau, 4)
        self.assertAlmostEqual(res.error * np.sqrt(4096), 1.0, delta=0.1)
        self.assertEqual(len(res.errors), len(res.block_sizes))

    def test_too_short(self):
        rng = np.random.default_rng(23)
        walk = np.cumsum(rng.normal(size=512))
        with self.assertWarns(RuntimeWarning):
            res = dif.blocking(walk)
        self.assertFalse(res.converged)
        self.assertIsNone(res.plateau)
        with self.assertRaises(ValueError):
            dif.blocking(np.ones(10))
        with self.assertRaises(ValueError):
            dif.blocking([np.nan] * 64)


class GreenKuboAndMSD(unittest.TestCase):
    """OU velocities with C(t) = exp(-t/tau) per component: D = tau (kT/m = 1)."""
    dt, tau, T, runs = 0.01, 0.5, 20000, 8

    @classmethod
    def setUpClass(cls):
        rng = np.random.default_rng(24)
        a = np.exp(-cls.dt / cls.tau)
        cls.v = [ar1(rng, cls.T, a, (3,)) for _ in range(cls.runs)]
        # exact D of the discrete process with trapezoidal integration
        cls.D = cls.dt * (0.5 + a / (1 - a))

    def test_green_kubo(self):
        lags = np.arange(401)
        vacf = np.array([acc.fft_correlate(v, max_lag=400)[:, 0] for v in self.v])
        res = dif.green_kubo(lags * self.dt, vacf, window=(2.5, 4.0))
        D, err = res
        self.assertEqual(res.method, "independent runs")
        self.assertLess(err, 0.15 * self.D)
        self.assertLess(abs(D - self.D), 4 * err)
        # one run: plateau spread, finite
        D1, err1 = dif.green_kubo(lags * self.dt, vacf[0], window=(2.5, 4.0))
        self.assertTrue(np.isfinite(err1) and err1 > 0)
        self.assertLess(abs(D1 - self.D), 0.2 * self.D)
        # the (n_lags, 1) shape of scalar_product results is accepted
        D2, _ = dif.green_kubo(lags * self.dt, vacf[0][:, None], window=(2.5, 4.0))
        self.assertEqual(D1, D2)
        # n_particles divides; a tail adds 2 A / sqrt(t)
        D3, _ = dif.green_kubo(lags * self.dt, 2 * vacf[0], window=(2.5, 4.0), n_particles=2)
        self.assertAlmostEqual(D3, D1, places=14)
        w = (3.9999, 4.0001)  # only t = 4
        D4 = dif.green_kubo(lags * self.dt, vacf[0], window=w, tail_amplitude=0.1).value
        D5 = dif.green_kubo(lags * self.dt, vacf[0], window=w).value
        self.assertAlmostEqual(D4 - D5, 2 * 0.1 / np.sqrt(4.0), places=12)
        for w in (None, (3.0, 2.0), (10.0, 20.0)):
            with self.assertRaises(ValueError):
                dif.green_kubo(lags * self.dt, vacf, window=w)
        bad = vacf[0].copy()
        bad[100] = np.nan
        with self.assertRaises(ValueError):
            dif.green_kubo(lags * self.dt, bad, window=(2.5, 4.0))

    def test_msd(self):
        lags = np.arange(601)
        msd = []
        for v in self.v:
            x = np.cumsum(v, axis=0) * self.dt
            msd.append(acc.fft_correlate(x, operation="square_distance_componentwise",
                                         max_lag=600).sum(axis=1))
        msd = np.array(msd)
        D, err = dif.msd_fit(lags * self.dt, msd, window=(3.0, 6.0))
        self.assertLess(err, 0.1 * self.D)
        self.assertLess(abs(D - self.D), 4 * err + 0.01 * self.D)
        res = dif.msd_fit(lags * self.dt, msd[0], window=(3.0, 6.0))
        self.assertEqual(res.method, "fit residuals")
        self.assertTrue(res.error > 0)
        res = dif.msd_fit(lags * self.dt, msd[0], window=(3.0, 6.0), msd_err=np.full(601, 0.01))
        self.assertEqual(res.method, "weighted fit")
        self.assertAlmostEqual(res.value, dif.msd_fit(lags * self.dt, msd[0], (3.0, 6.0)).value,
                               places=10)


@skipIfMissingFeatures("DPD", "EXTERNAL_FORCE", "MASS")
class Drag(unittest.TestCase):

    def test_drag_small_system(self):
        """A heavy DPD bead pulled through a DPD solvent (zero net force): finite
        friction with a blocked error; momentum conserved; ext_force restored."""
        rng = np.random.default_rng(25)
        L = 5.0
        s = marble.System(box_l=[L, L, L], time_step=0.02)
        s.cell_system.skin = 0.3
        n = int(3 * L ** 3)
        s.part.add(pos=rng.uniform(0, L, size=(n, 3)), v=rng.normal(size=(n, 3)))
        tracer = s.part.add(pos=[2.5, 2.5, 2.5], type=1, mass=2.0)
        for t in ((0, 0), (0, 1)):
            s.non_bonded_inter[t].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=5)
        s.integrator.run(200)
        p0 = s.analysis.linear_momentum()
        # samples ~ one velocity correlation time apart; 1000 of them
        res = dif.measure_drag(s, [tracer], force=[0.0, 0.0, 2.0], steps=16000,
                               equilibration_steps=300, delta_N=16)
        zeta, zeta_err = res
        self.assertTrue(np.isfinite(zeta) and zeta > 0)
        self.assertTrue(np.isfinite(zeta_err) and 0 < zeta_err < 0.2 * zeta)
        self.assertTrue(res.blocking.converged)
        self.assertAlmostEqual(res.D * zeta, 1.0, places=12)
        self.assertEqual(res.v_parallel.shape, (1000,))
        # a bead with the solvent's own DPD coupling: D ~ the solvent's D ~ 0.67
        # (reference.md section 2), zeta ~ 1.5
        self.assertGreater(zeta, 0.3)
        self.assertLess(zeta, 10.0)
        np.testing.assert_allclose(s.analysis.linear_momentum(), p0, atol=1e-8 * n)
        np.testing.assert_array_equal(s.part.all().ext_force, 0.0)
        with self.assertRaises(ValueError):
            dif.measure_drag(s, [tracer], force=[0, 0, 0], steps=1000)
        with self.assertRaises(ValueError):
            dif.measure_drag(s, [tracer], force=[0, 0, 1], steps=10)
        with self.assertRaises(IndexError):
            dif.measure_drag(s, [10 ** 6], force=[0, 0, 1], steps=1000)


if __name__ == "__main__":
    unittest.main()
