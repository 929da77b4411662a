"""Particle and Galilei calls of ESPResSo scripts: part.pairs(), p.virtual,
GalileiTransform() without arguments."""
import unittest as ut

import numpy as np
import unittest_decorators as utx

import espressomd
import espressomd.galilei


class Particles(ut.TestCase):

    system = espressomd.System(box_l=3 * [5.0])

    def tearDown(self):
        self.system.part.clear()

    def test_pairs(self):
        self.assertEqual(list(self.system.part.pairs()), [])
        self.system.part.add(pos=np.zeros((4, 3)), id=[7, 2, 5, 9])
        pairs = [(a.id, b.id) for a, b in self.system.part.pairs()]
        self.assertEqual(pairs, [(2, 5), (2, 7), (2, 9), (5, 7), (5, 9), (7, 9)])

    def test_virtual(self):
        p = self.system.part.add(pos=[1.0, 1.0, 1.0])
        self.assertIs(p.virtual, False)
        p.virtual = False
        with self.assertRaisesRegex(espressomd.FeaturesError, "VIRTUAL_SITES"):
            p.virtual = True
        with self.assertRaisesRegex(espressomd.FeaturesError, "VIRTUAL_SITES"):
            self.system.part.add(pos=[2.0, 1.0, 1.0], virtual=True)
        self.assertEqual(len(self.system.part), 1)
        q = self.system.part.add(pos=[2.0, 1.0, 1.0], virtual=False)
        self.assertEqual(q.virtual, False)
        np.testing.assert_array_equal(self.system.part.all().virtual, [False, False])
        self.assertFalse(espressomd.has_features("VIRTUAL_SITES"))

    def test_galilei_without_arguments(self):
        # acts on the most recently created System (ESPResSo has only one)
        system = espressomd.System(box_l=3 * [5.0])
        kw = dict(mass=[1.0, 3.0]) if espressomd.has_features("MASS") else {}
        parts = system.part.add(pos=[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]],
                                v=[[1.0, 0.0, 0.0], [0.0, 2.0, 0.0]], **kw)
        gt = espressomd.galilei.GalileiTransform()
        m = np.array(kw.get("mass", [1.0, 1.0]))
        v_cms = (m[:, None] * parts.v).sum(0) / m.sum()
        np.testing.assert_allclose(gt.system_CMS_velocity(), v_cms, rtol=1e-14)
        gt.galilei_transform()
        np.testing.assert_allclose(system.analysis.linear_momentum(), 0.0, atol=1e-14)
        gt.kill_particle_motion()
        np.testing.assert_array_equal(parts.v, 0.0)

    def test_rotate_system(self):
        system = self.system
        kw = dict(mass=[1.0, 3.0]) if espressomd.has_features("MASS") else {}
        parts = system.part.add(pos=[[1.0, 2.0, 2.0], [2.0, 2.0, 2.0]],
                                v=[[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]], **kw)
        m = np.array(kw.get("mass", [1.0, 1.0]))
        com = (m[:, None] * parts.pos).sum(0) / m.sum()
        # axis z (theta = 0), a quarter turn: x -> y
        system.rotate_system(phi=0.0, theta=0.0, alpha=np.pi / 2.0)
        rel = np.array([[1.0, 2.0, 2.0], [2.0, 2.0, 2.0]]) - com
        expected = com + np.stack([-rel[:, 1], rel[:, 0], rel[:, 2]], axis=1)
        np.testing.assert_allclose(parts.pos, expected, atol=1e-14)
        np.testing.assert_array_equal(parts.v, [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        # axis x (phi = 0, theta = pi/2), half a turn: y, z -> -y, -z about the com
        before = np.copy(parts.pos)
        system.rotate_system(phi=0.0, theta=np.pi / 2.0, alpha=np.pi)
        rel = before - com
        np.testing.assert_allclose(parts.pos, com + rel * [1.0, -1.0, -1.0], atol=1e-14)
        with self.assertRaisesRegex(ValueError, "alpha"):
            system.rotate_system(phi=0.0, theta=0.0)
        with self.assertRaisesRegex(ValueError, "theta"):
            system.rotate_system(phi=0.0, theta=float("nan"), alpha=1.0)

    @utx.skipIfMissingFeatures("EXTERNAL_FORCES")
    def test_kill_forces(self):
        p = self.system.part.add(pos=[1.0, 1.0, 1.0], ext_force=[1.0, 2.0, 3.0])
        self.system.galilei.kill_particle_forces()
        np.testing.assert_array_equal(p.ext_force, 0.0)


if __name__ == "__main__":
    ut.main()
