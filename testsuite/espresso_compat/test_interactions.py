"""Non-bonded interactions the way ESPResSo scripts set them: through the
type-pair handle (4.2) and as objects constructed on their own, then
assigned (4.3)."""
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd
import espressomd.interactions


@utx.skipIfMissingFeatures("LENNARD_JONES")
class NonBonded(ut.TestCase):

    system = espressomd.System(box_l=3 * [10.0])
    system.time_step = 0.01
    system.cell_system.skin = 0.4

    def tearDown(self):
        self.system.part.clear()
        self.system.non_bonded_inter.reset()

    def test_handle_and_object_agree(self):
        params = dict(epsilon=1.0, sigma=1.0, cutoff=2**(1. / 6.), shift="auto")
        self.system.non_bonded_inter[0, 0].lennard_jones.set_params(**params)
        self.system.part.add(pos=[[1., 1., 1.], [2.05, 1., 1.]])
        self.system.integrator.run(0)
        f_handle = np.copy(self.system.part.all().f)
        self.system.non_bonded_inter[0, 0].lennard_jones.deactivate()
        self.system.integrator.run(0, recalc_forces=True)
        np.testing.assert_array_equal(self.system.part.all().f, 0.)
        lj = espressomd.interactions.LennardJonesInteraction(**params)
        self.system.non_bonded_inter[0, 0].lennard_jones = lj
        self.system.integrator.run(0, recalc_forces=True)
        np.testing.assert_array_equal(self.system.part.all().f, f_handle)
        self.assertGreater(np.abs(f_handle).max(), 0.)
        self.assertAlmostEqual(self.system.non_bonded_inter[0, 0].lennard_jones.get_params()["epsilon"], 1.0)

    def test_invalid_object(self):
        with self.assertRaises(ValueError):
            espressomd.interactions.LennardJonesInteraction(epsilon=-1., sigma=1., cutoff=2.)


if __name__ == "__main__":
    ut.main()
