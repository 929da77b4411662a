"""The DPD thermostat called as an ESPResSo 4.2 test script calls it: weight
functions, transverse part, ghosts across the periodic boundary, momentum
conservation, the counter-based noise, run(0) and turn_off()."""
import itertools
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd


@utx.skipIfMissingFeatures("DPD")
class DPDThermostat(ut.TestCase):

    system = espressomd.System(box_l=3 * [10.0])
    system.time_step = 0.01
    system.cell_system.skin = 0.4

    def tearDown(self):
        self.system.part.clear()
        self.system.constraints.clear()
        self.system.thermostat.turn_off()
        self.system.integrator.set_vv()

    def dpd(self, **params):
        if not espressomd.has_features("TRANS_DPD"):
            params = {k: v for k, v in params.items() if not k.startswith("trans_")}
        self.system.non_bonded_inter[0, 0].dpd.set_params(**params)

    def test_01_rng(self):
        system = self.system
        with self.assertRaises(ValueError):  # no seed the first time
            espressomd.System(box_l=3 * [5.0]).thermostat.set_dpd(kT=2.3)
        system.thermostat.set_dpd(kT=2.3, seed=41)
        self.dpd(weight_function=0, gamma=1.5, r_cut=1.5,
                 trans_weight_function=0, trans_gamma=1.5, trans_r_cut=1.5)
        # the radial noise acts along z only; the transverse one also along x, y
        comp = slice(None) if espressomd.has_features("TRANS_DPD") else slice(2, 3)

        def reset():
            system.part.clear()
            p = system.part.add(pos=[0, 0, 0])
            system.part.add(pos=[0, 0, 1])
            return p

        p = reset()
        system.integrator.run(0, recalc_forces=True)
        f0 = np.copy(p.f)
        system.integrator.run(0, recalc_forces=True)
        np.testing.assert_array_equal(np.copy(p.f), f0)  # run(0) keeps the counter
        self.assertGreater(np.linalg.norm(f0), 0.0)
        p = reset()
        system.integrator.run(1)
        self.assertTrue(np.all(np.not_equal(np.copy(p.f)[comp], f0[comp])))
        p = reset()
        system.integrator.run(0, recalc_forces=True)
        f2 = np.copy(p.f)
        system.thermostat.set_dpd(kT=2.3, seed=42)  # other seed, same counter
        system.integrator.run(0, recalc_forces=True)
        self.assertTrue(np.all(np.not_equal(np.copy(p.f)[comp], f2[comp])))

    def test_const_weight_function(self):
        system = self.system
        gamma = 1.42
        system.thermostat.set_dpd(kT=0.0, seed=42)
        self.dpd(weight_function=0, gamma=gamma, r_cut=1.2,
                 trans_weight_function=0, trans_gamma=gamma, trans_r_cut=1.4)
        p0 = system.part.add(pos=[5, 5, 5], type=0, v=[0, 0, 0])
        v = np.array([0.5, 0.8, 0.3])
        p1 = system.part.add(pos=[3, 5, 5], type=0, v=v)
        system.integrator.run(0)
        for f in system.part.all().f:
            np.testing.assert_array_equal(np.copy(f), [0.0, 0.0, 0.0])
        if espressomd.has_features("TRANS_DPD"):
            p1.pos = [5.0 - 1.3, 5, 5]  # only the transverse part reaches
            system.integrator.run(0)
            self.assertLess(abs(p0.f[0]), 1e-14)
            np.testing.assert_allclose(np.copy(p0.f[1:]), gamma * v[1:], rtol=0, atol=1e-11)
            np.testing.assert_array_equal(np.copy(p0.f), -np.copy(p1.f))
        p1.pos = [5.0 - 1.1, 5, 5]
        system.integrator.run(0)
        expected = gamma * v if espressomd.has_features("TRANS_DPD") else [gamma * v[0], 0, 0]
        np.testing.assert_allclose(np.copy(p0.f), expected, rtol=0, atol=1e-11)
        np.testing.assert_array_equal(np.copy(p0.f), -np.copy(p1.f))

    def test_linear_and_parabolic_weight_function(self):
        system = self.system
        gamma, r_cut = 1.42, 1.2
        system.thermostat.set_dpd(kT=0.0, seed=42)
        p0 = system.part.add(pos=[5, 5, 5], type=0, v=[0, 0, 0])
        v = np.array([0.5, 0.0, 0.0])
        p1 = system.part.add(pos=[3, 5, 5], type=0, v=v)
        for kappa in (1.0, 7.8):
            self.dpd(weight_function=1, gamma=gamma, k=kappa, r_cut=r_cut,
                     trans_weight_function=1, trans_gamma=0.0, trans_r_cut=0.0)
            for dist in (0.1, 0.5, 1.1):
                p1.pos = [5.0 + dist, 5.0, 5.0]
                system.integrator.run(0)
                omega = (1.0 - (dist / r_cut) ** kappa) ** 2
                np.testing.assert_allclose(np.copy(p0.f), omega * gamma * v, rtol=0,
                                           atol=1e-11)
                np.testing.assert_array_equal(np.copy(p0.f), -np.copy(p1.f))

    def test_ghosts_have_v(self):
        system = self.system
        r_cut = 1.5
        dx = 0.25 * r_cut
        corners = list(itertools.product([0, 1], [0, 1], [0, 1]))
        for ind in corners:
            system.part.add(pos=[dx if x == 0 else 10.0 - dx for x in ind], v=ind)
        system.thermostat.set_dpd(kT=0.0, seed=42)
        self.dpd(weight_function=0, gamma=1.0, r_cut=r_cut,
                 trans_weight_function=0, trans_gamma=1.0, trans_r_cut=r_cut)
        system.integrator.run(0)
        for p, ind in zip(system.part, corners):
            for i in ind:
                sgn = 1 if ind[i] == 0 else -1
                if espressomd.has_features("TRANS_DPD"):
                    self.assertAlmostEqual(sgn * 4.0, p.f[i])

    @utx.skipIfMissingFeatures("MASS")
    def test_momentum_conservation(self):
        system = self.system
        system.thermostat.set_dpd(kT=1.3, seed=42)
        parts = system.part.add(pos=((0, 0, 0), (0.1, 0.1, 0.1), (0.1, 0, 0)), mass=(1, 2, 3))
        self.dpd(weight_function=1, gamma=5.0, r_cut=2.9,
                 trans_weight_function=1, trans_gamma=2.5, trans_r_cut=2.9)
        momentum = np.matmul(parts.v.T, parts.mass)
        for _ in range(10):
            system.integrator.run(25)
            np.testing.assert_almost_equal(np.sum(parts.f), 3 * [0.0])
            np.testing.assert_allclose(np.matmul(parts.v.T, parts.mass), momentum, atol=1e-12)

    def test_turn_off(self):
        system = self.system
        system.thermostat.set_dpd(kT=1.0, seed=42)
        self.dpd(weight_function=0, gamma=1.0, r_cut=1.5)
        p = system.part.add(pos=[5, 5, 5], v=[1, 0, 0])
        system.part.add(pos=[5.5, 5, 5])
        system.integrator.run(0)
        self.assertGreater(np.linalg.norm(p.f), 0.0)
        system.thermostat.turn_off()
        system.integrator.run(0)
        np.testing.assert_array_equal(np.copy(p.f), 0.0)


if __name__ == "__main__":
    ut.main()
