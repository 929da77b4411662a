# labels: python
"""DPD integrators that remove most of the kT(dt) drift of plain velocity
Verlet (doc/stability.md): Shardlow S1 splitting (set_shardlow) and DPD-VV
(set_dpd_vv). Groot-Warren water (a = 25, gamma = 4.5, rho = 3, w = 1 - r,
kT = 1) at dt = 0.04, where plain VV runs ~2.6 % hot (reference.md section 2).
Measured (doc/stability.md, L = 6, 1000 time units): Shardlow +0.85 %, DPD-VV
+0.57 %, VV +2.63 %; the < 0.5 % goal of the issue is reached at dt <= 0.03
(Shardlow) / 0.04 within error (DPD-VV) only. Asserted here: the drift is cut
by at least half (|kT - 1| < 1.3 % against VV's 2.6 %), at > 3 error bars from
VV's value. The marble paper's solvent (a = 0, gamma = 5, rho = 3) at
dt = 0.04: Shardlow within 0.5 % of kT (error bar < 0.15 %), where plain VV
is ~3.5 % hot (issue 6, item 2; bench/speed_accuracy.py sweeps dt). Plus:
momentum conservation to 1e-12, fixed-seed reproducibility, colloid and wall
scenes, the API and FeaturesError."""
import time
import unittest

import numpy as np

import marble
from marble.viscosity import block_average
from unittest_decorators import skipIfMissingFeatures

L = 6.0
RHO = 3.0
DT = 0.04


def make(integrator, a=25.0, gamma=4.5, seed=1, L=L, dt=DT):
    rng = np.random.default_rng(seed)
    n = int(RHO * L**3)
    s = marble.System(box_l=[L, L, L])
    s.time_step = dt
    s.cell_system.skin = 0.4
    v = rng.normal(size=(n, 3))
    v -= v.mean(axis=0)
    s.part.add(pos=rng.uniform(0, L, size=(n, 3)), v=v)
    if a > 0 and marble.has_features("HAT"):  # the API tests do not need the conservative force
        s.non_bonded_inter[0, 0].hat.set_params(F_max=a, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    getattr(s.integrator, "set_" + integrator)()
    return s


def measure_kT(integrator, prod_time, a=25.0, gamma=4.5, seed=1, L=L):
    s = make(integrator, a=a, gamma=gamma, seed=seed, L=L)
    n = len(s.part.all())
    s.integrator.run(int(round(5.0 / DT)))
    series = []
    every = int(round(0.1 / DT))
    for _ in range(int(round(prod_time / DT)) // every):
        s.integrator.run(every)
        series.append(2.0 * s.analysis.energy()["kinetic"] / (3.0 * n - 3.0))
    p = s.analysis.linear_momentum()
    assert np.max(np.abs(p)) < 1e-12 * n, p
    return block_average(series)


@skipIfMissingFeatures("DPD")
class DPDIntegratorAPI(unittest.TestCase):

    def test_select_and_state(self):
        s = make("shardlow", a=0.0, L=4.0)
        self.assertEqual(s.integrator.get_state()["name"], "Shardlow")
        s.integrator.set_dpd_vv()
        self.assertEqual(s.integrator.get_state()["name"], "DPDVV")
        s.integrator.set_vv()
        self.assertEqual(s.integrator.get_state()["name"], "VelocityVerlet")

    def test_reproducible_and_momentum(self):
        for integ in ("shardlow", "dpd_vv"):
            runs = []
            for _ in range(2):
                s = make(integ, L=5.0, seed=7)
                s.integrator.run(50)
                runs.append((s.part.all().pos.copy(), s.part.all().v.copy()))
                p = s.analysis.linear_momentum()
                self.assertLess(np.max(np.abs(p)), 1e-12 * len(s.part.all()), integ)
            np.testing.assert_array_equal(runs[0][0], runs[1][0])
            np.testing.assert_array_equal(runs[0][1], runs[1][1])

    def test_differs_from_vv_and_switch_back(self):
        """Switching back to VV gives VV's forces (DPD in the pair loop) again."""
        s = make("vv", L=4.0, seed=3)
        s.integrator.run(0)
        f_vv = s.part.all().f.copy()
        s.integrator.set_shardlow()
        s.integrator.run(0)
        f_sh = s.part.all().f.copy()
        self.assertGreater(np.abs(f_vv - f_sh).max(), 1e-3)  # no DPD pair force with Shardlow
        s.integrator.set_vv()
        s.integrator.run(0)
        np.testing.assert_array_equal(s.part.all().f, f_vv)

    def test_kT0_relaxes_relative_velocity_exactly(self):
        """kT = 0, one pair: Shardlow damps the relative velocity along e by
        exp(-gamma w^2 dt / mu) per step (mu = 1/2), the centre of mass is kept."""
        s = marble.System(box_l=[5.0] * 3)
        s.time_step = 0.1
        s.part.add(pos=[[1.0, 1.0, 1.0], [1.5, 1.0, 1.0]], v=[[0.3, 0.2, 0.0], [-0.1, 0.0, 0.1]])
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=50.0, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=0.0, seed=1)
        s.integrator.set_shardlow()
        s.integrator.run(1)   # gamma dt / mu = 10: explicit friction would explode
        p0, p1 = s.part.by_id(0), s.part.by_id(1)
        v = s.part.all().v
        d = np.asarray(p0.pos) - np.asarray(p1.pos)  # the sweep acts at the drifted positions
        r = np.linalg.norm(d)
        e = d / r
        v_rel0 = np.array([0.4, 0.2, -0.1])  # no force before the sweep: drift only
        u0 = np.dot(v_rel0, e)
        w = 1.0 - r
        expect = v_rel0 + (np.exp(-50.0 * w * w * 0.1 / 0.5) - 1.0) * u0 * e
        np.testing.assert_allclose(v[0] - v[1], expect, atol=1e-12)
        np.testing.assert_allclose(v.sum(axis=0), [0.2, 0.2, 0.1], atol=1e-14)

    @skipIfMissingFeatures("MARBLE")
    def test_with_colloid(self):
        """Colloid pairs and walls keep their explicit friction inside the VV
        part: the run works and conserves momentum."""
        from marble.colloids import add_marble
        s = make("shardlow", a=0.0, gamma=5.0, L=8.0, dt=0.01)
        add_marble(s, pos=[4.0, 4.0, 4.0], radius=2.0, gamma=5.0)
        p0 = s.analysis.linear_momentum()
        s.integrator.run(200)
        p = s.analysis.linear_momentum()
        np.testing.assert_allclose(p, p0, atol=1e-10, rtol=0)
        self.assertTrue(np.all(np.isfinite(s.part.all().v)))

    @skipIfMissingFeatures("TUNABLE_SLIP")
    def test_with_walls(self):
        from marble.shapes import Wall
        rng = np.random.default_rng(2)
        s = marble.System(box_l=[5.0, 5.0, 6.0])
        s.time_step = 0.01
        s.part.add(pos=rng.uniform([0, 0, 1.2], [5, 5, 4.8], (200, 3)), v=rng.normal(size=(200, 3)))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
        for wt, nrm, dist in ((1, [0, 0, 1], 0.0), (2, [0, 0, -1], -6.0)):
            s.constraints.add(shape=Wall(normal=nrm, dist=dist), particle_type=wt)
            s.non_bonded_inter[wt, 0].lennard_jones.set_params(epsilon=1.0, sigma=1.0,
                                                               cutoff=2 ** (1 / 6), shift="auto")
            s.non_bonded_inter[wt, 0].tunable_slip.set_params(gamma=2.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=3)
        s.integrator.set_shardlow()
        s.integrator.run(300)
        self.assertTrue(np.all(np.isfinite(s.part.all().v)))
        self.assertLess(abs(s.analysis.kinetic_temperature() - 1.0), 0.3)


@unittest.skipIf(marble.has_features("DPD"), "DPD is compiled in")
class NoDPD(unittest.TestCase):

    def test_features_error(self):
        s = marble.System(box_l=[4.0] * 3)
        for name in ("set_shardlow", "set_dpd_vv"):
            with self.assertRaises(marble.FeaturesError):
                getattr(s.integrator, name)()


@skipIfMissingFeatures("DPD", "HAT")
class DPDIntegratorTemperature(unittest.TestCase):

    def test_kT_drift_removed(self):
        t0 = time.time()
        res = {integ: measure_kT(integ, 600.0) for integ in ("vv", "shardlow", "dpd_vv")}
        for k, (kT, err) in res.items():
            print(f"dt = {DT}: {k:9s} kT = {kT:.4f} +/- {err:.4f}")
        print(f"{time.time() - t0:.1f} s")
        vv, vv_err = res["vv"]
        self.assertGreater(vv - 1.0, 0.018)  # plain VV: the reference drift (~2.6 %)
        for k in ("shardlow", "dpd_vv"):
            kT, err = res[k]
            self.assertLess(err, 0.002, k)
            self.assertLess(abs(kT - 1.0), 0.013, f"{k}: kT = {kT:.4f} +/- {err:.4f}")
            self.assertGreater(vv - kT, 3 * np.hypot(err, vv_err), k)

    def test_shardlow_exact_without_conservative_force(self):
        """The marble paper's solvent (a = 0, gamma = 5, rho = 3, w = 1 - r) at
        dt = 0.04, L = 8 (1536 beads): Shardlow's pair updates keep kT = 1
        (|kT - 1| < 0.5 % with an error bar < 0.15 %), while plain VV in the
        same box runs > 2.5 % hot (reference.md: 1.035). ~15 s."""
        t0 = time.time()
        kT, err = measure_kT("shardlow", 400.0, a=0.0, gamma=5.0, L=8.0)
        vv, vv_err = measure_kT("vv", 150.0, a=0.0, gamma=5.0, L=8.0)
        print(f"a = 0, gamma = 5, dt = {DT}, L = 8: shardlow kT = {kT:.4f} +/- {err:.4f}, "
              f"vv kT = {vv:.4f} +/- {vv_err:.4f} ({time.time() - t0:.1f} s)")
        self.assertLess(err, 0.0015)
        self.assertLess(abs(kT - 1.0), 0.005)
        self.assertLess(abs(kT - 1.0), 3 * err + 0.002)
        self.assertLess(vv_err, 0.003)
        self.assertGreater(vv - 1.0, 0.025)


@skipIfMissingFeatures("DPD", "TRANS_DPD", "MASS")
class ShardlowTransverse(unittest.TestCase):

    def test_trans_dpd_mass_mixture(self):
        """Transverse DPD (gamma_perp = 3) on a mixture of masses 1 and 3 (with
        DPD_MASS_* if compiled in), a = 0: Shardlow's pair updates stay exact
        (measured 0.9987 +/- 0.0015; DPD-VV gives 0.958 here, doc/stability.md)."""
        rng = np.random.default_rng(1)
        n = int(RHO * L**3)
        s = marble.System(box_l=[L] * 3)
        s.time_step = DT
        s.cell_system.skin = 0.4
        v = rng.normal(size=(n, 3))
        v -= v.mean(axis=0)
        s.part.add(pos=rng.uniform(0, L, (n, 3)), v=v, mass=rng.choice([1.0, 3.0], size=n))
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0,
                                                trans_weight_function=1, trans_gamma=3.0,
                                                trans_r_cut=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=2)
        s.integrator.set_shardlow()
        p0 = s.analysis.linear_momentum()
        s.integrator.run(100)
        series = []
        for _ in range(1000):
            s.integrator.run(5)
            series.append(2.0 * s.analysis.energy()["kinetic"] / (3.0 * n - 3.0))
        kT, err = block_average(series)
        print(f"TRANS_DPD + masses, shardlow: kT = {kT:.4f} +/- {err:.4f}")
        self.assertLess(abs(kT - 1.0), 3 * err + 0.002)
        np.testing.assert_allclose(s.analysis.linear_momentum(), p0, atol=1e-12 * n, rtol=0)


if __name__ == "__main__":
    unittest.main()
