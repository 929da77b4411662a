"""DPD stress as an ESPResSo 4.2 script checks it: analysis.dpd_stress(),
observables.DPDStress, system.volume(), part.pairs()."""
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd
import espressomd.observables


def weight(r, r_cut):
    return 1.0 - r / r_cut


def friction(d, v, gamma, r_cut, trans_gamma, trans_r_cut):
    """DPD friction force on the particle at d (vector from its partner) with
    relative velocity v: radial gamma w^2 (v.d^)d^ plus transverse
    trans_gamma w_t^2 (v - (v.d^)d^), linear weights."""
    r = np.linalg.norm(d)
    u = d / r
    f = np.zeros(3)
    if r < r_cut:
        f -= gamma * weight(r, r_cut) ** 2 * np.dot(v, u) * u
    if r < trans_r_cut:
        f -= trans_gamma * weight(r, trans_r_cut) ** 2 * (v - np.dot(v, u) * u)
    return f


@utx.skipIfMissingFeatures("DPD")
class DPDStress(ut.TestCase):

    system = espressomd.System(box_l=3 * [4.0])
    system.time_step = 0.01
    system.cell_system.skin = 0.4

    def tearDown(self):
        self.system.part.clear()
        self.system.thermostat.turn_off()

    def test_volume(self):
        self.assertEqual(self.system.volume(), 64.0)
        other = espressomd.System(box_l=[2.0, 3.0, 4.5])
        self.assertEqual(other.volume(), 27.0)

    def test_dpd_stress(self):
        # DPDStress() reads the most recently created System (ESPResSo has only one)
        system = espressomd.System(box_l=3 * [4.0])
        system.time_step = 0.01
        system.cell_system.skin = 0.4
        gamma, r_cut = 5.0, 1.0
        trans = espressomd.has_features("TRANS_DPD")
        t_gamma, t_r_cut = (gamma / 2.0, r_cut) if trans else (0.0, 0.0)
        prm = dict(weight_function=1, gamma=gamma, r_cut=r_cut)
        if trans:
            prm.update(trans_weight_function=1, trans_gamma=t_gamma, trans_r_cut=t_r_cut)
        system.non_bonded_inter[0, 0].dpd.set_params(**prm)
        rng = np.random.default_rng(16)
        parts = system.part.add(pos=system.box_l * rng.random((60, 3)))
        dpd_obs = espressomd.observables.DPDStress()
        self.assertEqual(dpd_obs.shape(), (3, 3))
        for kT in (0.0, 2.0):
            system.thermostat.set_dpd(kT=kT, seed=3)
            parts.v = rng.normal(size=(60, 3))
            system.integrator.run(0, recalc_forces=True)
            stress = np.zeros((3, 3))
            n_pairs = 0
            for p_i, p_j in system.part.pairs():
                n_pairs += 1
                d = system.distance_vec(p_j, p_i)  # r_i - r_j
                if np.linalg.norm(d) < max(r_cut, t_r_cut):
                    stress += np.outer(d, friction(d, p_i.v - p_j.v, gamma, r_cut,
                                                   t_gamma, t_r_cut))
            self.assertEqual(n_pairs, 60 * 59 // 2)
            stress /= system.volume()
            self.assertGreater(np.abs(stress).max(), 1e-3)
            np.testing.assert_allclose(system.analysis.dpd_stress(), stress, rtol=0,
                                       atol=1e-12 * np.abs(stress).max())
            np.testing.assert_allclose(dpd_obs.calculate(), stress, rtol=0,
                                       atol=1e-12 * np.abs(stress).max())
            split = system.analysis.dpd_stress_split()
            np.testing.assert_array_equal(split["friction"], system.analysis.dpd_stress())
            if kT > 0.0:  # the noise is kept out of the viscous stress
                self.assertGreater(np.abs(split["noise"]).max(), 1e-3)
            else:
                np.testing.assert_array_equal(split["noise"], 0.0)

    def test_not_an_accumulator_observable(self):
        import espressomd.accumulators
        with self.assertRaisesRegex(ValueError, "DPDStress"):
            espressomd.accumulators.TimeSeries(obs=espressomd.observables.DPDStress())


if __name__ == "__main__":
    ut.main()
