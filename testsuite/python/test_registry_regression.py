# labels: python
"""Trajectories through the kernel registry are bit for bit those of the
engine before it (issue A): 500 steps of VV, Shardlow and DPD-VV of the scene
in registry_scene.py (DPD + hat + LJ solvent, a rotating marble colloid,
tunable-slip walls) against data/registry_reference.npz, written by the build
before the registry (commit 99f611b). A deliberate change of the force
arithmetic (e.g. a new noise generator) rewrites the reference with
`build/pymarble testsuite/python/registry_scene.py testsuite/python/data/registry_reference.npz`
and says so in its commit message."""
import os
import unittest

import numpy as np

from registry_scene import FEATURES, trajectory_end
from unittest_decorators import skipIfMissingFeatures

REF = os.path.join(os.path.dirname(__file__), "data", "registry_reference.npz")


@skipIfMissingFeatures(*FEATURES)
class RegistryRegression(unittest.TestCase):

    def check(self, integrator):
        ref = np.load(REF)
        got = trajectory_end(integrator)
        for key, value in got.items():
            want = ref[f"{integrator}_{key}"]
            diff = np.max(np.abs(value - want))
            self.assertTrue(np.array_equal(value, want),
                            f"{integrator}: '{key}' differs from the reference (max |diff| {diff:.3e})")

    def test_vv(self):
        self.check("vv")

    def test_shardlow(self):
        self.check("shardlow")

    def test_dpd_vv(self):
        self.check("dpd_vv")


if __name__ == "__main__":
    unittest.main()
