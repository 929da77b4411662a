"""Integrator calls of ESPResSo scripts: steepest descent run(0) computes
forces, bad parameters raise RuntimeError, gamma = 0, run keywords, progress."""
import contextlib
import io
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd


@utx.skipIfMissingFeatures("LENNARD_JONES")
class SteepestDescent(ut.TestCase):

    system = espressomd.System(box_l=[10.0, 10.0, 10.0])
    system.time_step = 0.01
    system.cell_system.skin = 0.4

    def setUp(self):
        self.system.non_bonded_inter[0, 0].lennard_jones.set_params(
            epsilon=1.0, sigma=1.0, cutoff=2.5, shift=0.0)
        self.p0 = self.system.part.add(pos=[5.0, 5.0, 5.0])
        self.p1 = self.system.part.add(pos=[6.0, 5.0, 5.0])

    def tearDown(self):
        self.system.part.clear()
        self.system.integrator.set_vv()

    def test_run0_computes_forces(self):
        self.system.integrator.set_steepest_descent(f_max=0.0, gamma=0.1, max_displacement=0.01)
        np.testing.assert_array_equal(self.p0.f, 0.0)
        self.assertEqual(self.system.integrator.run(0), 0)
        # LJ at r = sigma: F = 24 epsilon / sigma, repulsive
        np.testing.assert_allclose(self.p0.f, [-24.0, 0.0, 0.0], rtol=1e-12)
        np.testing.assert_allclose(self.p1.f, [24.0, 0.0, 0.0], rtol=1e-12)
        np.testing.assert_array_equal(self.p1.pos, [6.0, 5.0, 5.0])  # nothing moved
        self.p1.pos = [6.2, 5.0, 5.0]
        self.system.integrator.run(0)
        r = 1.2
        f = 24.0 * (2.0 * r**-13 - r**-7)
        np.testing.assert_allclose(self.p1.f, [f, 0.0, 0.0], rtol=1e-12)

    def test_missing_and_bad_parameters(self):
        params = {"f_max": 0.0, "gamma": 0.1, "max_displacement": 0.1}
        for key in params:
            invalid = dict(params)
            del invalid[key]
            with self.assertRaisesRegex(RuntimeError, f"Parameter '{key}' is missing"):
                self.system.integrator.set_steepest_descent(**invalid)
        for key in params:
            with self.assertRaisesRegex(RuntimeError, f"parameter '{key}'"):
                self.system.integrator.set_steepest_descent(**dict(params, **{key: -1.0}))
        # the same errors are ValueErrors for Marble scripts
        with self.assertRaises(ValueError):
            self.system.integrator.set_steepest_descent(f_max=-1.0, gamma=0.1,
                                                        max_displacement=0.1)
        self.assertEqual(self.system.integrator.get_state()["name"], "VelocityVerlet")

    def test_gamma_zero(self):
        self.system.integrator.set_steepest_descent(f_max=0.0, gamma=0.0, max_displacement=0.1)
        self.assertEqual(self.system.integrator.get_state()["gamma"], 0.0)
        self.assertEqual(self.system.integrator.run(5), 5)
        np.testing.assert_array_equal(self.p1.pos, [6.0, 5.0, 5.0])
        self.system.integrator.set_steepest_descent(f_max=0.0, gamma=0.01, max_displacement=0.1)
        self.system.integrator.run(5)
        self.assertGreater(self.p1.pos[0], 6.0)


class RunKeywords(ut.TestCase):

    def test_keywords_and_progress(self):
        system = espressomd.System(box_l=[5.0, 5.0, 5.0])
        system.time_step = 0.01
        system.cell_system.skin = 0.4
        p = system.part.add(pos=[1.0, 1.0, 1.0], v=[1.0, 0.0, 0.0])
        system.integrator.run(steps=10, reuse_forces=True)
        with self.assertRaisesRegex(ValueError, "cannot reuse old forces and recalculate"):
            system.integrator.run(1, recalc_forces=True, reuse_forces=True)
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            self.assertEqual(system.integrator.run(250, progress=True), 250)
        self.assertIn("step 250/250", err.getvalue())
        self.assertIn("steps/s", err.getvalue())
        self.assertIn("ETA", err.getvalue())
        self.assertEqual(system.step, 260)
        np.testing.assert_allclose(p.pos, [1.0 + 2.6, 1.0, 1.0], rtol=1e-12)


if __name__ == "__main__":
    ut.main()
