# labels: python
"""Multiple-tau correlator, time series, mean/variance and the offline FFT
correlator against independent numpy computations (doc/analysis.md):
- linear part (lags <= tau_lin): the exact all-origins average,
- compressed levels: the same block compression followed by a direct average,
- FFT (FFTW / numpy.fft) vs the direct O(T^2) sum,
- live: a ballistic particle gives MSD = v^2 t^2 exactly; a DPD fluid sampled
  during integrator.run matches the FFT of the stored series."""
import unittest

import numpy as np

import marble
from marble import accumulators as acc
from marble import observables as obs

OPS = ("scalar_product", "componentwise_product", "square_distance_componentwise")


def op_numpy(op, a, b):
    """op(a[t], b[t]) for rows (T, n) -> (T, dim_corr)."""
    if op == "scalar_product":
        return np.sum(a * b, axis=1, keepdims=True)
    if op == "componentwise_product":
        return a * b
    return (b - a) ** 2


def direct_numpy(op, x, y, max_lag):
    """C[k] = mean_t op(x[t], y[t+k]) by explicit loops over lags."""
    T = len(x)
    return np.array([op_numpy(op, x[:T - k], y[k:]).mean(axis=0) for k in range(max_lag + 1)])


def compress_numpy(y, how):
    m = len(y) // 2
    older, newer = y[0:2 * m:2], y[1:2 * m:2]
    return {"discard1": newer, "discard2": older, "linear": 0.5 * (older + newer)}[how]


def multiple_tau_numpy(op, a, b, tau_lin, depth, ca, cb):
    """Lags (in samples), means and counts of the multiple-tau scheme done the
    slow way: compress the whole series level by level, correlate directly."""
    lags, res, counts = [], [], []
    for level in range(depth):
        ks = range(tau_lin + 1) if level == 0 else range(tau_lin // 2 + 1, tau_lin + 1)
        N = len(a)
        for k in ks:
            lags.append(k * 2 ** level)
            counts.append(max(N - k, 0))
            res.append(op_numpy(op, a[:N - k], b[k:]).mean(axis=0) if N > k
                       else np.full(op_numpy(op, a[:1], b[:1]).shape[1], np.nan))
        a, b = compress_numpy(a, ca), compress_numpy(b, cb)
    return np.array(lags), np.array(res), np.array(counts)


def make_system(n=2, dt=0.01, L=5.0):
    s = marble.System(box_l=[L, L, L], time_step=dt)
    s.part.add(pos=np.arange(3 * n, dtype=float).reshape(n, 3) % L)
    return s


def feed(system, corr_list, samples_a, samples_b=None):
    """Set the velocities of particle 0..n-1 to each sample and update."""
    for t in range(len(samples_a)):
        v = samples_a[t].reshape(-1, 3)
        if samples_b is not None:
            v = np.concatenate([v, samples_b[t].reshape(-1, 3)])
        system.part.all().v = v
        for c in corr_list:
            c.update()


class CorrelatorSynthetic(unittest.TestCase):

    def test_linear_part_is_exact(self):
        rng = np.random.default_rng(1)
        s = make_system(n=2)
        x = rng.normal(size=(300, 6)) + 0.3
        o = obs.ParticleVelocities(ids=[0, 1], system=s)
        tau_lin = 16
        corrs = {op: acc.Correlator(obs1=o, tau_lin=tau_lin, tau_max=tau_lin * s.time_step,
                                    corr_operation=op) for op in OPS}
        feed(s, corrs.values(), x)
        for op, c in corrs.items():
            self.assertEqual(c.hierarchy_depth, 1)
            ref = direct_numpy(op, x, x, tau_lin)
            res = c.result().reshape(tau_lin + 1, -1)
            np.testing.assert_allclose(res, ref, rtol=1e-12, atol=1e-12, err_msg=op)
            np.testing.assert_allclose(c.lag_times(), s.time_step * np.arange(tau_lin + 1))
            np.testing.assert_array_equal(c.sample_sizes(), 300 - np.arange(tau_lin + 1))
            self.assertEqual(c.n_samples, 300)
        self.assertEqual(corrs["scalar_product"].result().shape, (tau_lin + 1, 1))
        self.assertEqual(corrs["componentwise_product"].result().shape, (tau_lin + 1, 2, 3))

    def test_compressed_levels_match_numpy(self):
        rng = np.random.default_rng(2)
        s = make_system(n=2)
        T, tau_lin = 1000, 8  # T not a power of 2: incomplete blocks are dropped
        # a slowly varying signal, so that compression matters
        x = np.cumsum(rng.normal(size=(T, 6)), axis=0) * 0.1 + rng.normal(size=(T, 6))
        o = obs.ParticleVelocities(ids=[0, 1], system=s)
        cases = [(op, c) for op in OPS for c in ("discard1", "discard2", "linear")]
        corrs = [acc.Correlator(obs1=o, tau_lin=tau_lin, tau_max=600 * s.time_step,
                                corr_operation=op, compress1=c) for op, c in cases]
        feed(s, corrs, x)
        for (op, c), corr in zip(cases, corrs):
            depth = corr.hierarchy_depth
            self.assertEqual(tau_lin * 2 ** (depth - 1), 1024)  # smallest cover of 600
            lags, ref, counts = multiple_tau_numpy(op, x, x, tau_lin, depth, c, c)
            np.testing.assert_array_equal(np.round(corr.lag_times() / s.time_step).astype(int),
                                          lags)
            np.testing.assert_array_equal(corr.sample_sizes(), counts)
            res = corr.result().reshape(len(lags), -1)
            ok = counts > 0
            np.testing.assert_allclose(res[ok], ref[ok], rtol=1e-11, atol=1e-12,
                                       err_msg=f"{op} {c}")
            self.assertTrue(np.all(np.isnan(res[~ok])))
        # lags beyond the run (1024 > 1000 samples) have no pairs
        self.assertEqual(corrs[0].sample_sizes()[-1], 0)

    def test_two_observables(self):
        """obs2 != obs1 with different compressions: C(k) = <A(t) op B(t+k)>."""
        rng = np.random.default_rng(3)
        s = make_system(n=2)
        T, tau_lin = 257, 4
        a = np.cumsum(rng.normal(size=(T, 3)), axis=0) * 0.2
        b = rng.normal(size=(T, 3)) + 0.5 * a
        oa = obs.ParticleVelocities(ids=[0], system=s)
        ob = obs.ParticleVelocities(ids=[1], system=s)
        for op in OPS:
            c = acc.Correlator(obs1=oa, obs2=ob, tau_lin=tau_lin, tau_max=100 * s.time_step,
                               corr_operation=op, compress1="linear", compress2="discard2")
            feed(s, [c], a, b)
            lags, ref, counts = multiple_tau_numpy(op, a, b, tau_lin, c.hierarchy_depth,
                                                   "linear", "discard2")
            ok = counts > 0
            np.testing.assert_allclose(c.result().reshape(len(lags), -1)[ok], ref[ok],
                                       rtol=1e-11, atol=1e-12, err_msg=op)

    def test_finalize(self):
        s = make_system(n=1)
        c = acc.Correlator(obs1=obs.ParticlePositions(ids=[0], system=s), tau_lin=4,
                           tau_max=1.0, corr_operation="scalar_product")
        c.update()
        before = c.result().copy()
        c.finalize()
        np.testing.assert_array_equal(c.result(), before)
        with self.assertRaisesRegex(RuntimeError, "finalize"):
            c.update()


class CorrelatorValidation(unittest.TestCase):

    def setUp(self):
        self.s = make_system(n=2)
        self.o = obs.ParticlePositions(ids=[0, 1], system=self.s)

    def corr(self, **kw):
        p = dict(obs1=self.o, tau_lin=16, tau_max=1.0, corr_operation="scalar_product")
        p.update(kw)
        return acc.Correlator(**p)

    def test_bad_parameters(self):
        for kw in (dict(tau_lin=3), dict(tau_lin=0), dict(tau_lin=1), dict(tau_lin=-2),
                   dict(tau_lin=2.5), dict(tau_lin="16"), dict(tau_max=0.0),
                   dict(tau_max=-1.0), dict(tau_max=np.inf), dict(tau_max=np.nan),
                   dict(delta_N=0), dict(delta_N=-1), dict(delta_N=1.5),
                   dict(corr_operation="tensor"), dict(compress1="average"),
                   dict(compress2="discard3"), dict(obs1=[0, 1]), dict(obs1=None),
                   dict(obs2=obs.ParticlePositions(ids=[0], system=self.s)),
                   dict(foo=1), dict(tau_max=None)):
            with self.assertRaises(ValueError, msg=str(kw)):
                self.corr(**kw)

    def test_needs_time_step(self):
        s = marble.System(box_l=[5, 5, 5])
        s.part.add(pos=[1, 1, 1])
        with self.assertRaisesRegex(ValueError, "time_step"):
            acc.Correlator(obs1=obs.ParticlePositions(ids=[0], system=s), tau_max=1.0,
                           corr_operation="scalar_product")

    def test_depth_and_lags(self):
        c = self.corr(tau_lin=16, tau_max=1.0, delta_N=2)  # dt = 0.02: 50 samples
        self.assertEqual(c.hierarchy_depth, 3)  # 16, 32, 64 >= 50
        lags = np.round(c.lag_times() / 0.02).astype(int)
        np.testing.assert_array_equal(lags, list(range(17)) + list(range(18, 33, 2))
                                      + list(range(36, 65, 4)))
        self.assertEqual(c.delta_N, 2)
        self.assertGreaterEqual(c.lag_times()[-1], 1.0)
        self.assertEqual(self.corr(tau_max=1e-6).hierarchy_depth, 1)

    def test_auto_update_list(self):
        s = self.s
        c = self.corr(delta_N=5)
        aul = s.auto_update_accumulators
        aul.add(c)
        self.assertEqual(len(aul), 1)
        self.assertIn(c, aul)
        with self.assertRaises(ValueError):
            aul.add(c)
        with self.assertRaises(ValueError):
            aul.add(self.o)
        s.integrator.run(50)
        self.assertEqual(c.n_samples, 10)
        aul.remove(c)
        s.integrator.run(50)
        self.assertEqual(c.n_samples, 10)
        with self.assertRaises(ValueError):
            aul.remove(c)
        ts = acc.TimeSeries(obs=self.o)
        aul.add(c)
        aul.add(ts)
        self.assertEqual(len(aul), 2)
        aul.clear()
        self.assertEqual(len(aul), 0)
        s.integrator.run(10)
        self.assertEqual(ts.n_samples, 0)
        # an accumulator of another system
        s2 = make_system(n=1)
        with self.assertRaises(ValueError):
            s2.auto_update_accumulators.add(self.corr())

    def test_time_step_change_and_removed_particle(self):
        s = self.s
        c = self.corr()
        s.auto_update_accumulators.add(c)
        s.integrator.run(3)
        s.time_step = 0.02
        with self.assertRaisesRegex(RuntimeError, "time step changed"):
            s.integrator.run(1)
        s.auto_update_accumulators.clear()
        s.time_step = 0.01
        ts = acc.TimeSeries(obs=self.o)
        s.auto_update_accumulators.add(ts)
        s.part.by_id(1).remove()
        with self.assertRaisesRegex(IndexError, "particle 1"):
            s.integrator.run(1)


class LiveCorrelator(unittest.TestCase):

    def test_ballistic_msd_and_vacf(self):
        """Free particles (no forces): MSD_d(t) = v_d^2 t^2 and <v(0).v(t)> = |v|^2,
        with unfolded positions across many box crossings; exact for every
        compression (block averages of a linear motion move linearly)."""
        L, dt = 4.0, 0.01
        s = marble.System(box_l=[L, L, L], time_step=dt)
        s.cell_system.skin = 0.4
        v = np.array([[3.0, -1.5, 0.25], [-2.0, 0.5, 1.0]])
        s.part.add(pos=[[0.5, 0.5, 0.5], [2.0, 3.0, 1.0]], v=v)
        pos = obs.ParticlePositions(ids=[0, 1])
        vel = obs.ParticleVelocities(ids=[0, 1])
        msd = {c: acc.Correlator(obs1=pos, tau_lin=8, tau_max=3.0, delta_N=2,
                                 corr_operation="square_distance_componentwise", compress1=c)
               for c in ("discard1", "discard2", "linear")}
        vacf = acc.Correlator(obs1=vel, tau_lin=8, tau_max=3.0, delta_N=2,
                              corr_operation="scalar_product", compress1="linear")
        for c in list(msd.values()) + [vacf]:
            s.auto_update_accumulators.add(c)
        s.integrator.run(1000)
        self.assertGreater(np.max(np.abs(s.part.all().image_box)), 3)  # crossed the box
        for name, c in msd.items():
            t = c.lag_times()
            ok = c.sample_sizes() > 0
            expected = v[None, :, :] ** 2 * t[:, None, None] ** 2
            np.testing.assert_allclose(c.result()[ok], expected[ok], rtol=1e-9, atol=1e-9,
                                       err_msg=name)
        np.testing.assert_allclose(vacf.result()[:, 0], np.sum(v * v), rtol=1e-12)
        self.assertEqual(vacf.n_samples, 500)

    def test_dpd_fluid_fft_vs_multiple_tau(self):
        """Velocities of a DPD fluid sampled during the run: the correlator's
        level 0 equals the all-origins FFT correlation of the stored series, and
        every level equals the numpy multiple-tau of the same series."""
        if not marble.has_features("DPD"):
            self.skipTest("needs DPD")
        rng = np.random.default_rng(4)
        L, n = 4.0, 192
        s = marble.System(box_l=[L, L, L], time_step=0.02)
        s.cell_system.skin = 0.3
        s.part.add(pos=rng.uniform(0, L, size=(n, 3)), v=rng.normal(size=(n, 3)))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=7)
        ids = [0, 5, 17]
        vel = obs.ParticleVelocities(ids=ids)
        pos = obs.ParticlePositions(ids=ids)
        tau_lin = 8
        cv = acc.Correlator(obs1=vel, tau_lin=tau_lin, tau_max=5.0, corr_operation="scalar_product",
                            compress1="linear")
        cm = acc.Correlator(obs1=pos, tau_lin=tau_lin, tau_max=5.0,
                            corr_operation="square_distance_componentwise")
        tv, tp = acc.TimeSeries(obs=vel), acc.TimeSeries(obs=pos)
        for a in (cv, cm, tv, tp):
            s.auto_update_accumulators.add(a)
        s.integrator.run(600)
        xv, xp = tv.time_series(), tp.time_series()
        self.assertEqual(xv.shape, (600, 3, 3))
        fv = acc.fft_correlate(xv, operation="scalar_product", max_lag=tau_lin)
        fm = acc.fft_correlate(xp, operation="square_distance_componentwise", max_lag=tau_lin)
        np.testing.assert_allclose(cv.result()[:tau_lin + 1], fv, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(cm.result()[:tau_lin + 1], fm, rtol=1e-9, atol=1e-12)
        for c, x, op, comp in ((cv, xv, "scalar_product", "linear"),
                               (cm, xp, "square_distance_componentwise", "discard1")):
            lags, ref, counts = multiple_tau_numpy(op, x.reshape(600, -1), x.reshape(600, -1),
                                                   tau_lin, c.hierarchy_depth, comp, comp)
            ok = counts > 0
            np.testing.assert_allclose(c.result().reshape(len(lags), -1)[ok], ref[ok],
                                       rtol=1e-9, atol=1e-12)
        # equipartition: C(0) = sum over 3 particles of <|v|^2> = 9 kT (+- ~8 %)
        self.assertAlmostEqual(cv.result()[0, 0] / 9.0, 1.0, delta=0.25)


class FFTCorrelator(unittest.TestCase):

    def test_fft_vs_direct(self):
        rng = np.random.default_rng(5)
        T = 500
        x = rng.normal(size=(T, 2, 3)) + 2.0
        y = rng.normal(size=(T, 2, 3)) + 0.5 * x
        methods = ["numpy", "direct"] + (["fftw"] if acc.have_fftw() else [])
        for op in OPS:
            for yy in (None, y):
                ref = direct_numpy(op, x.reshape(T, -1), (x if yy is None else yy).reshape(T, -1),
                                   T - 1)
                for m in methods:
                    res = acc.fft_correlate(x, yy, operation=op, method=m)
                    self.assertEqual(res.shape, (T, 1) if op == "scalar_product" else (T, 2, 3))
                    np.testing.assert_allclose(res.reshape(T, -1), ref, rtol=1e-9, atol=1e-9,
                                               err_msg=f"{op} {m} y={yy is not None}")
                res = acc.fft_correlate(x, yy, operation=op, max_lag=10)
                np.testing.assert_allclose(res.reshape(11, -1), ref[:11], rtol=1e-9, atol=1e-9)

    def test_msd_of_offset_positions(self):
        """Centring keeps the FFT MSD accurate for positions far from the origin."""
        rng = np.random.default_rng(6)
        x = 1e4 + np.cumsum(rng.normal(size=(2000, 3)) * 0.01, axis=0)
        ref = direct_numpy("square_distance_componentwise", x, x, 50)
        for m in ("auto", "numpy"):
            res = acc.fft_correlate(x, operation="square_distance_componentwise", max_lag=50,
                                    method=m)
            np.testing.assert_allclose(res, ref, rtol=1e-6, atol=1e-10)
            self.assertEqual(res[0].tolist(), [0.0, 0.0, 0.0])

    def test_one_dimensional_series(self):
        x = np.sin(np.arange(64) * 0.3)
        res = acc.fft_correlate(x, operation="componentwise_product", max_lag=5)
        self.assertEqual(res.shape, (6,))
        np.testing.assert_allclose(res, direct_numpy("componentwise_product", x[:, None],
                                                     x[:, None], 5)[:, 0], atol=1e-12)

    def test_bad_input(self):
        x = np.ones((10, 3))
        for kw in (dict(operation="foo"), dict(max_lag=10), dict(max_lag=-1), dict(method="x"),
                   dict(y=np.ones((9, 3))), dict(max_lag=2.5)):
            with self.assertRaises(ValueError, msg=str(kw)):
                acc.fft_correlate(x, **kw)
        for bad in ([], np.array(1.0), [[np.nan, 1, 2]]):
            with self.assertRaises(ValueError):
                acc.fft_correlate(bad)


class TimeSeriesAndMeanVariance(unittest.TestCase):

    def test_samples_and_statistics(self):
        if not marble.has_features("DPD"):
            self.skipTest("needs DPD")
        rng = np.random.default_rng(8)
        L = 4.0
        s = marble.System(box_l=[L, L, L], time_step=0.02)
        s.cell_system.skin = 0.3
        s.part.add(pos=rng.uniform(0, L, size=(100, 3)))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=3)
        o = obs.ParticleVelocities(ids=[3, 4])
        ts = acc.TimeSeries(obs=o, delta_N=3)
        mv = acc.MeanVarianceCalculator(obs=o, delta_N=3)
        self.assertTrue(np.all(np.isnan(mv.mean())))
        s.auto_update_accumulators.add(ts)
        s.auto_update_accumulators.add(mv)
        manual = []
        for _ in range(20):
            s.integrator.run(3)
            manual.append(s.part.by_ids([3, 4]).v)
        x = ts.time_series()
        np.testing.assert_array_equal(x, np.array(manual))
        self.assertEqual(mv.n_samples, 20)
        np.testing.assert_allclose(mv.mean(), x.mean(axis=0), rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(mv.variance(), x.var(axis=0, ddof=1), rtol=1e-10)
        np.testing.assert_allclose(mv.std_error(), np.sqrt(x.var(axis=0, ddof=1) / 20),
                                   rtol=1e-10)
        ts.clear()
        self.assertEqual(ts.time_series().shape, (0, 2, 3))
        for kw in (dict(delta_N=0), dict(obs=None), dict(obs=o, foo=1)):
            kw.setdefault("obs", o)
            with self.assertRaises(ValueError):
                acc.TimeSeries(**kw)
            with self.assertRaises(ValueError):
                acc.MeanVarianceCalculator(**kw)


if __name__ == "__main__":
    unittest.main()
