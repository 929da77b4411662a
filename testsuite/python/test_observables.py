# labels: python
"""Observables against the particle properties they read, and their errors."""
import unittest

import numpy as np

import marble
from marble import observables as obs
from unittest_decorators import skipIfMissingFeatures

L = 5.0


class Observables(unittest.TestCase):

    def setUp(self):
        rng = np.random.default_rng(11)
        self.s = marble.System(box_l=[L, L, L], time_step=0.01)
        self.s.cell_system.skin = 0.4
        # unfolded start positions (several images away) and fast particles
        pos = rng.uniform(0, L, size=(6, 3)) + L * rng.integers(-3, 4, size=(6, 3))
        self.s.part.add(pos=pos, v=rng.normal(scale=5.0, size=(6, 3)))

    def test_positions_velocities(self):
        s = self.s
        ids = [4, 0, 2]  # order is kept
        p = obs.ParticlePositions(ids=ids)
        v = obs.ParticleVelocities(ids=ids, system=s)
        self.assertIs(p.system, s)
        self.assertEqual(p.shape(), (3, 3))
        self.assertEqual(p.ids, ids)
        for _ in range(3):
            s.integrator.run(40)  # crosses the boundaries
            np.testing.assert_array_equal(p.calculate(), s.part.by_ids(ids).pos)
            np.testing.assert_array_equal(v.calculate(), s.part.by_ids(ids).v)
        self.assertFalse(np.allclose(p.calculate(), s.part.by_ids(ids).pos_folded))

    @skipIfMissingFeatures("MASS")
    def test_com_velocity(self):
        s = self.s
        s.part.all().mass = np.arange(1.0, 7.0)
        ids = [1, 3, 5]
        c = obs.ComVelocity(ids=ids)
        self.assertEqual(c.shape(), (3,))
        parts = s.part.by_ids(ids)
        expected = (parts.mass[:, None] * parts.v).sum(axis=0) / parts.mass.sum()
        np.testing.assert_allclose(c.calculate(), expected, rtol=1e-14)

    def test_angular_velocities(self):
        s = self.s
        if not marble.has_features("ROTATION"):
            with self.assertRaises(marble.FeaturesError):
                obs.ParticleAngularVelocities(ids=[0])
            return
        s.part.all().rotation = True
        s.part.all().omega_lab = np.arange(18.0).reshape(6, 3)
        o = obs.ParticleAngularVelocities(ids=[5, 1])
        np.testing.assert_array_equal(o.calculate(), s.part.by_ids([5, 1]).omega_lab)

    def test_bad_ids(self):
        s = self.s
        cls_list = [obs.ParticlePositions, obs.ParticleVelocities, obs.ComVelocity]
        if marble.has_features("ROTATION"):
            cls_list.append(obs.ParticleAngularVelocities)
        for cls in cls_list:
            with self.assertRaises(IndexError):
                cls(ids=[0, 17])
            for bad in ([], [-1], [0.5], ["a"], [[0, 1]], 3, None, "0"):
                with self.assertRaises(ValueError, msg=f"{cls.__name__} {bad!r}"):
                    cls(ids=bad)
            with self.assertRaises(ValueError):
                cls(ids=[0], foo=1)
            with self.assertRaises(ValueError):
                cls(ids=[0], system="not a system")
        o = obs.ParticlePositions(ids=[0, 3])
        s.part.by_id(3).remove()
        with self.assertRaisesRegex(IndexError, "particle 3"):
            o.calculate()

    def test_system_binding(self):
        s2 = marble.System(box_l=[3, 3, 3])
        s2.part.add(pos=[1, 1, 1], v=[1, 2, 3])
        # without system=, the most recent System
        o = obs.ParticleVelocities(ids=[0])
        self.assertIs(o.system, s2)
        np.testing.assert_array_equal(o.calculate(), [[1, 2, 3]])
        o1 = obs.ParticleVelocities(ids=[0], system=self.s)
        np.testing.assert_array_equal(o1.calculate(), self.s.part.by_ids([0]).v)


if __name__ == "__main__":
    unittest.main()
