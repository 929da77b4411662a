# labels: python
"""marble.viscosity: the blocking analysis on series with known errors, the
joint parabola fit on exact profiles, input validation, a short reverse
Poiseuille run (zero net force, ext_force restored, profile of the right sign),
and lees_edwards_viscosity: bad input (ValueError naming the parameter, nothing
changed), a short run against an independent sampling loop on the same
trajectory with the shear along z across x (eta, kT, profile, the weighted
line fit and its chi^2), the mass-weighted momentum removal (P along the
normal, conserved under Lees-Edwards, is zero afterwards, and kept without it)."""
import unittest

import numpy as np

import marble
import marble.lees_edwards
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


class LeesEdwardsViscosityRun(unittest.TestCase):

    def fluid(self, heavy=False):
        s = marble.System(box_l=[5.0, 4.0, 4.0])
        s.time_step = 0.01
        rng = np.random.default_rng(3)
        n = 240
        v = rng.normal(size=(n, 3))
        s.part.add(pos=rng.uniform(0, 1, size=(n, 3)) * s.box_l, v=v - v.mean(axis=0))
        if heavy:  # unequal masses: the unweighted zero mean leaves a momentum
            p = s.part.all()
            m = np.where(np.arange(n) % 4 == 0, 5.0, 1.0)
            p.mass = m
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=1)
        return s

    def test_validation(self):
        s = self.fluid()
        v0 = np.asarray(s.part.all().v).copy()
        bad = [("rate", dict(rate=0.0)), ("rate", dict(rate=float("nan"))), ("rate", dict(rate="0.1")),
               ("time", dict(time=0.0)), ("time", dict(time=-1.0)), ("equilibration", dict(equilibration=-1.0)),
               ("sample_every", dict(sample_every=0)), ("sample_every", dict(sample_every=2.5)),
               ("n_bins", dict(n_bins=2)), ("min_blocks", dict(min_blocks=1)),
               ("shear_direction", dict(shear_direction="w")),
               ("shear_direction", dict(shear_direction="y", shear_plane_normal="y"))]
        for name, kw in bad:
            args = dict(rate=0.1, time=1.0)
            args.update(kw)
            with self.subTest(kw=kw), self.assertRaisesRegex(ValueError, name):
                viscosity.lees_edwards_viscosity(s, **args)
        self.assertIsNone(s.lees_edwards.protocol)
        self.assertEqual(s.time, 0.0)
        np.testing.assert_array_equal(s.part.all().v, v0)

    def reference(self, s, rate, time, equil, every, n_bins, sa, na, min_blocks):
        """The measurement written out independently (shear along sa, normal na)."""
        L = np.asarray(s.box_l, dtype=float)
        s.lees_edwards.set_boundary_conditions(shear_direction="xyz"[sa], shear_plane_normal="xyz"[na],
                                               protocol=marble.lees_edwards.LinearShear(
                                                   shear_velocity=rate * L[na], time_0=s.time))
        s.galilei.galilei_transform()
        p = s.part.all()
        v = np.asarray(p.v)
        v[:, sa] += rate * (np.asarray(p.pos_folded)[:, na] - L[na] / 2)
        p.v = v
        s.integrator.run(int(round(equil / s.time_step)))
        stress, kts, prof = [], [], []
        width = L[na] / n_bins
        for _ in range(int(round(time / (every * s.time_step)))):
            s.integrator.run(every)
            t = s.analysis.pressure_tensor()
            stress.append(0.5 * (t["total"][sa, na] + t["dpd"][sa, na] + t["total"][na, sa] + t["dpd"][na, sa]))
            y = np.asarray(p.pos_folded)[:, na]
            u = np.asarray(p.v)
            b = np.minimum((y / width).astype(int), n_bins - 1)
            prof.append([u[b == k, sa].mean() for k in range(n_bins)])
            c = u.copy()
            c[:, sa] -= rate * y
            c -= c.mean(axis=0)
            kts.append((c ** 2).sum() / (3 * (len(u) - 1)))
        prof = np.array(prof)
        stats = [viscosity.block_average(prof[:, k], min_blocks=min_blocks) for k in range(n_bins)]
        means = np.array([m for m, _ in stats])
        errs = np.array([e for _, e in stats])
        yc = (np.arange(n_bins) + 0.5) * width
        slope, icpt = np.polyfit(yc, means, 1, w=1 / errs)
        chi2 = (((means - slope * yc - icpt) / errs) ** 2).sum()
        return -viscosity.block_average(stress, min_blocks)[0] / rate, \
            viscosity.block_average(kts, min_blocks)[0], means, slope, chi2

    def test_against_independent_loop(self):
        kw = dict(rate=0.4, time=1.5, equilibration=0.5, sample_every=5, n_bins=5,
                  shear_direction="z", shear_plane_normal="x", min_blocks=4)
        res = viscosity.lees_edwards_viscosity(self.fluid(), **kw)
        eta, kt, means, slope, chi2 = self.reference(self.fluid(), 0.4, 1.5, 0.5, 5, 5, 2, 0, 4)
        self.assertEqual(res.n_samples, 30)
        self.assertEqual(res.dof, 3)
        self.assertAlmostEqual(res.eta / eta, 1.0, delta=1e-12)
        self.assertAlmostEqual(res.kT / kt, 1.0, delta=1e-12)
        np.testing.assert_allclose(res.v, means, rtol=1e-12, atol=1e-14)
        self.assertAlmostEqual(res.slope / slope, 1.0, delta=1e-9)
        self.assertAlmostEqual(res.chi2 / chi2, 1.0, delta=1e-9)
        self.assertEqual(len(res.p_sn), 30)
        self.assertGreater(res.eta_err, 0.0)

    @skipIfMissingFeatures("MASS")
    def test_momentum_removal(self):
        for remove in (True, False):
            s = self.fluid(heavy=True)
            p = s.part.all()
            m = np.asarray(p.mass, dtype=float)
            P0 = (m[:, None] * np.asarray(p.v)).sum(axis=0)
            self.assertGreater(abs(P0[1]), 1.0)  # the unweighted zero mean left a momentum along y
            with self.subTest(zero_momentum=remove):
                viscosity.lees_edwards_viscosity(s, rate=0.2, time=0.2, equilibration=0.0, linear_start=False,
                                                 sample_every=2, zero_momentum=remove, min_blocks=2)
                P = (m[:, None] * np.asarray(p.v)).sum(axis=0)
                # P along the normal (y) is conserved under Lees-Edwards with DPD
                self.assertAlmostEqual(P[1], 0.0 if remove else P0[1], delta=1e-9 * np.abs(m[:, None] * np.asarray(p.v)).sum())
                self.assertEqual(s.lees_edwards.shear_direction, "x")


if __name__ == "__main__":
    unittest.main()
