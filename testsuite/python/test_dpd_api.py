# labels: python
"""DPD thermostat API and semantics: seeding, the Philox counter, prefactors
recomputed whatever the order of the calls, run(0), turn_off(), validation,
FeaturesError without TRANS_DPD, and analysis.dpd_stress()."""
import unittest

import numpy as np

import marble

if not marble.has_features("DPD"):
    raise unittest.SkipTest("missing feature DPD")
from unittest_decorators import skipIfMissingFeatures
from test_dpd_forces import noise, ref_force

L = 4.0
PRM = dict(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)


def fluid(n=120, seed=1, dt=0.01, dpd=True, hat=False, thermo=True, kT=1.0):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = dt
    s.cell_system.skin = 0.3
    s.part.add(pos=rng.uniform(0, L, size=(n, 3)), v=rng.normal(size=(n, 3)))
    if dpd:
        s.non_bonded_inter[0, 0].dpd.set_params(**PRM)
    if hat:
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    if thermo:
        s.thermostat.set_dpd(kT=kT, seed=42)
    return s


class DPDApi(unittest.TestCase):

    def test_seed_required_first_time(self):
        s = fluid(thermo=False)
        with self.assertRaisesRegex(ValueError, "seed"):
            s.thermostat.set_dpd(kT=1.0)
        self.assertFalse(s.thermostat.dpd.active)
        s.thermostat.set_dpd(kT=1.0, seed=7)
        self.assertEqual(s.thermostat.dpd.seed, 7)
        s.thermostat.set_dpd(kT=2.0)  # later calls may omit it
        self.assertEqual(s.thermostat.dpd.seed, 7)
        self.assertEqual(s.thermostat.dpd.kT, 2.0)

    def test_validation(self):
        s = fluid(thermo=False)
        for kw in (dict(kT=-1.0, seed=1), dict(kT=1.0, seed=-3), dict(kT=np.nan, seed=1),
                   dict(kT=1.0, seed=1.5), dict(kT="1", seed=1)):
            with self.subTest(kw=kw), self.assertRaises(ValueError):
                s.thermostat.set_dpd(**kw)
        dpd = s.non_bonded_inter[0, 0].dpd
        for kw in (dict(gamma=-1.0, r_cut=1.0), dict(gamma=1.0, r_cut=-1.0),
                   dict(weight_function=2, gamma=1.0, r_cut=1.0),
                   dict(gamma=1.0, r_cut=1.0, k=0.0), dict(gamma=1.0, r_cut=1.0, foo=1)):
            with self.subTest(kw=kw), self.assertRaises(ValueError):
                dpd.set_params(**kw)
        self.assertEqual(dpd.get_params()["gamma"], PRM["gamma"])  # unchanged
        s.thermostat.set_dpd(kT=1.0, seed=1)
        with self.assertRaises(ValueError):
            s.thermostat.dpd.philox_counter = -1

    def test_philox_counter(self):
        s = fluid()
        self.assertEqual(s.thermostat.dpd.philox_counter, 0)
        s.integrator.run(10)
        self.assertEqual(s.thermostat.dpd.philox_counter, 10)
        self.assertEqual(s.step, 10)
        s.integrator.run(0)  # force recalculation only
        s.integrator.run(0, recalc_forces=True)
        self.assertEqual(s.thermostat.dpd.philox_counter, 10)
        self.assertEqual(s.step, 10)
        s.thermostat.dpd.philox_counter = 1000
        self.assertEqual(s.thermostat.dpd.philox_counter, 1000)
        s.thermostat.set_dpd(kT=1.0, seed=43)  # re-seeding keeps the counter
        self.assertEqual(s.thermostat.dpd.philox_counter, 1000)
        self.assertEqual(s.thermostat.dpd.seed, 43)
        s.integrator.run(3)
        self.assertEqual(s.thermostat.dpd.philox_counter, 1003)

    def test_counter_keys_the_noise(self):
        """Forces of run(0) use the current counter; setting it back reproduces them."""
        s = fluid(n=2, dt=0.01)
        p = s.part.all()
        p.pos = [[1.0, 1.0, 1.0], [1.5, 1.2, 1.1]]
        p.v = np.zeros((2, 3))
        s.thermostat.dpd.philox_counter = 17
        s.integrator.run(0)
        f17 = p.f.copy()
        d = np.array([-0.5, -0.2, -0.1])
        f_ref = ref_force(PRM, d, np.zeros(3), noise(42, 17, 0, 1), 1.0, 0.01)
        np.testing.assert_allclose(f17[0], f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
        s.thermostat.dpd.philox_counter = 18
        s.integrator.run(0)
        self.assertFalse(np.allclose(p.f, f17))
        s.thermostat.dpd.philox_counter = 17
        s.integrator.run(0)
        np.testing.assert_array_equal(p.f, f17)

    def test_prefactors_any_order(self):
        """The noise prefactor sqrt(24 kT gamma/dt) follows every change of kT,
        gamma and time_step, whatever the order: forces are bit-identical to a
        system set up directly with the final values."""
        ref = fluid(dt=0.02, kT=1.5)
        ref.integrator.run(0)
        f_ref = ref.part.all().f

        a = fluid(dt=0.005, dpd=False, thermo=False)  # dt first, changed last
        a.thermostat.set_dpd(kT=0.3, seed=42)
        a.non_bonded_inter[0, 0].dpd.set_params(**dict(PRM, gamma=1.0))
        a.non_bonded_inter[0, 0].dpd.set_params(**PRM)
        a.thermostat.set_dpd(kT=1.5)
        a.time_step = 0.02
        b = fluid(dt=0.02, dpd=False, thermo=False)  # thermostat before params
        b.thermostat.set_dpd(kT=1.5, seed=42)
        b.non_bonded_inter[0, 0].dpd.set_params(**PRM)
        c = fluid(dt=0.02, kT=0.0)  # kT changed after a run(0)
        c.integrator.run(0)
        c.thermostat.set_dpd(kT=1.5)
        for sys in (a, b, c):
            sys.integrator.run(0)
            np.testing.assert_array_equal(sys.part.all().f, f_ref)

        # noise only (v = 0): F scales exactly with sqrt(kT gamma / dt)
        ref.part.all().v = np.zeros((120, 3))
        ref.integrator.run(0)
        f0 = ref.part.all().f
        ref.time_step = 0.005
        ref.integrator.run(0)
        np.testing.assert_allclose(ref.part.all().f, 2.0 * f0, rtol=1e-13, atol=1e-13)
        ref.thermostat.set_dpd(kT=6.0)
        ref.integrator.run(0)
        np.testing.assert_allclose(ref.part.all().f, 4.0 * f0, rtol=1e-13, atol=1e-13)

    def test_turn_off(self):
        """turn_off() removes friction and noise exactly; set_dpd() restores them."""
        has_hat = marble.has_features("HAT")
        s = fluid(hat=has_hat)
        s.integrator.run(20)
        s.integrator.run(0)
        f_on = s.part.all().f
        c = fluid(dpd=False, hat=has_hat, thermo=False)  # same state, no DPD at all
        p = s.part.all()
        c.part.all().pos = p.pos
        c.part.all().v = p.v
        s.thermostat.turn_off()
        self.assertFalse(s.thermostat.dpd.active)
        s.integrator.run(0)
        c.integrator.run(0)
        f_c = c.part.all().f  # equal up to the order of the pair sums
        np.testing.assert_allclose(s.part.all().f, f_c, rtol=0, atol=1e-13 * np.abs(f_c).max())
        self.assertGreater(np.abs(f_on - f_c).max(), 1.0)
        np.testing.assert_array_equal(s.analysis.dpd_stress_split()["total"], np.zeros((3, 3)))
        if not has_hat:
            np.testing.assert_array_equal(s.part.all().f, 0.0)
        # the counter advances with every step, thermostat on or off
        s.integrator.run(5)
        self.assertEqual(s.thermostat.dpd.philox_counter, 25)
        s.integrator.run(0)
        s.thermostat.set_dpd(kT=1.0)
        self.assertEqual(s.thermostat.dpd.seed, 42)

    @unittest.skipIf(marble.has_features("TRANS_DPD"), "TRANS_DPD is compiled in")
    def test_trans_needs_feature(self):
        dpd = fluid(thermo=False).non_bonded_inter[0, 0].dpd
        for key in ("trans_gamma", "trans_r_cut", "trans_weight_function"):
            with self.subTest(key=key), self.assertRaisesRegex(marble.FeaturesError, "TRANS_DPD"):
                dpd.set_params(**dict(PRM, **{key: 1}))
        dpd.set_params(**dict(PRM, trans_gamma=0.0, trans_r_cut=0.0))  # zeros are allowed

    @skipIfMissingFeatures("TRANS_DPD")
    def test_trans_params_roundtrip(self):
        dpd = fluid(thermo=False).non_bonded_inter[0, 0].dpd
        prm = dict(PRM, trans_weight_function=0, trans_gamma=2.0, trans_r_cut=0.8)
        dpd.set_params(**prm)
        got = dpd.get_params()
        for k, v in prm.items():
            self.assertEqual(got[k], v)

    def test_dpd_stress(self):
        """dpd_stress = (1/V) sum_pairs d (x) F with d = r_i - r_j, F the DPD force
        on i: from the forces of a pair, and for a fluid against the reference."""
        s = fluid(n=2, kT=0.0)
        p = s.part.all()
        p.pos = [[1.0, 1.0, 1.0], [1.6, 1.3, 0.8]]
        p.v = [[0.5, 0.2, -0.1], [-0.3, 0.0, 0.4]]  # approaching: repulsive friction
        s.integrator.run(0)
        st = s.analysis.dpd_stress_split()
        np.testing.assert_array_equal(s.analysis.dpd_stress(), st["friction"])
        d = np.array([-0.6, -0.3, 0.2])
        np.testing.assert_allclose(st["total"], np.outer(d, p.f[0]) / L**3, rtol=1e-13,
                                   atol=0)
        np.testing.assert_array_equal(st["noise"], 0.0)
        self.assertGreater(np.trace(st["friction"]), 0.0)  # pressure sign
        np.testing.assert_allclose(st["total"], st["total"].T, rtol=1e-13, atol=0)

        prms = [PRM]
        if marble.has_features("TRANS_DPD"):  # transverse part: non-symmetric tensor
            prms.append(dict(PRM, trans_weight_function=0, trans_gamma=2.5, trans_r_cut=0.9))
        for prm in prms:
            s = fluid(n=100, kT=1.3)
            s.non_bonded_inter[0, 0].dpd.set_params(**prm)
            s.integrator.run(7)
            parts = s.part.all()
            pos, vel, ids = parts.pos, parts.v, parts.id
            counter = s.thermostat.dpd.philox_counter
            fric, rnd = np.zeros((3, 3)), np.zeros((3, 3))
            for i in range(len(ids)):
                for j in range(i + 1, len(ids)):
                    dd = pos[i] - pos[j]
                    dd -= L * np.round(dd / L)
                    if np.linalg.norm(dd) >= PRM["r_cut"]:
                        continue
                    xi = noise(42, counter, ids[i], ids[j])
                    fric += np.outer(dd, ref_force(prm, dd, vel[i] - vel[j], 0 * xi, 1.3, 0.01))
                    rnd += np.outer(dd, ref_force(prm, dd, 0 * xi, xi, 1.3, 0.01))
            st = s.analysis.dpd_stress_split()
            np.testing.assert_array_equal(s.analysis.dpd_stress(), st["friction"])
            for key, ref in (("friction", fric), ("noise", rnd), ("total", fric + rnd)):
                np.testing.assert_allclose(st[key], ref / L**3, rtol=0,
                                           atol=1e-12 * np.abs(ref).max() / L**3, err_msg=key)
            if len(prm) > len(PRM):
                self.assertGreater(np.abs(fric - fric.T).max(), 1e-3 * np.abs(fric).max())

if __name__ == "__main__":
    unittest.main()
