"""Cell-system calls of ESPResSo scripts: skin = 0, set_regular_decomposition
without Verlet lists, set_n_square."""
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd


def lj_gas(skin):
    system = espressomd.System(box_l=[6.0, 6.0, 6.0])
    system.time_step = 0.005
    system.cell_system.skin = skin
    rng = np.random.default_rng(5)
    grid = np.stack(np.meshgrid(*3 * [np.arange(4)], indexing="ij"), -1).reshape(-1, 3)
    system.part.add(pos=1.5 * grid + 0.1 * rng.random((64, 3)), v=rng.normal(size=(64, 3)))
    system.non_bonded_inter[0, 0].lennard_jones.set_params(
        epsilon=1.0, sigma=1.0, cutoff=2.5, shift="auto")
    return system


@utx.skipIfMissingFeatures("LENNARD_JONES")
class CellSystem(ut.TestCase):

    def test_skin_zero_runs_like_any_skin(self):
        system = lj_gas(0.0)
        self.assertEqual(system.cell_system.skin, 0.0)
        self.assertGreater(system.cell_system.get_state()["effective_skin"], 0.0)
        ref = lj_gas(0.25)
        system.integrator.run(200)
        ref.integrator.run(200)
        # same physics; only the order of the pair sums may differ
        np.testing.assert_allclose(system.part.all().pos, ref.part.all().pos, rtol=0, atol=1e-8)
        self.assertEqual(system.cell_system.skin, 0.0)
        system.cell_system.skin = 0.3  # back to a real skin
        self.assertAlmostEqual(system.cell_system.skin, 0.3)
        self.assertEqual(system.cell_system.get_state()["effective_skin"], 0.3)

    def test_skin_zero_survives_pickling(self):
        import pickle
        system = lj_gas(0.0)
        system.integrator.run(10)
        restored = pickle.loads(pickle.dumps(system))
        self.assertEqual(restored.cell_system.skin, 0.0)
        restored.integrator.run(10)
        system.integrator.run(10)
        np.testing.assert_array_equal(restored.part.all().pos, system.part.all().pos)

    def test_skin_validation_kept(self):
        system = espressomd.System(box_l=[6.0, 6.0, 6.0])
        for bad in (-0.1, float("nan"), 3.5, "0"):
            with self.assertRaisesRegex(ValueError, "skin"):
                system.cell_system.skin = bad

    def test_decompositions(self):
        system = lj_gas(0.4)
        system.integrator.run(0)
        f_ref = system.part.all().f
        self.assertGreater(np.abs(f_ref).max(), 0.1)
        for use_verlet_lists in (False, True):
            system.cell_system.set_regular_decomposition(use_verlet_lists=use_verlet_lists)
            system.integrator.run(0, recalc_forces=True)
            np.testing.assert_allclose(system.part.all().f, f_ref, rtol=1e-12, atol=1e-12)
        system.cell_system.set_n_square(use_verlet_lists=False)
        system.integrator.run(0, recalc_forces=True)
        np.testing.assert_allclose(system.part.all().f, f_ref, rtol=1e-12, atol=1e-12)
        with self.assertRaisesRegex(ValueError, "use_verlet_lists"):
            system.cell_system.set_regular_decomposition(use_verlet_lists="no")


if __name__ == "__main__":
    ut.main()
