# labels: python
"""system.analysis.check_scene() (doc/stability.md): each rule fires on a scene
built to trigger it, quotes its measured number, and a good scene (the marble
paper's solvent at dt = 0.01, gamma = 5, R = 3 in a large box) gives no warning."""
import unittest

import numpy as np

import marble
from unittest_decorators import skipIfMissingFeatures


def solvent(L=8.0, rho=3.0, dt=0.01, gamma=5.0, a=0.0, skin=0.4, seed=1, kT=1.0):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L, L, L])
    s.time_step = dt
    s.cell_system.skin = skin
    n = int(rho * L**3)
    s.part.add(pos=rng.uniform(0, L, size=(n, 3)), v=rng.normal(size=(n, 3)))
    if a > 0:
        s.non_bonded_inter[0, 0].hat.set_params(F_max=a, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=kT, seed=seed)
    return s


def codes(s):
    return {w["code"]: w for w in s.analysis.check_scene()}


@skipIfMissingFeatures("DPD")
class SceneCheck(unittest.TestCase):

    def test_good_scene_is_quiet(self):
        self.assertEqual(solvent().analysis.check_scene(), [])

    def test_dt_above_1pc_limit(self):
        w = codes(solvent(dt=0.02))["dt_kT_error"]   # a = 0, gamma = 5: limit 0.014
        self.assertIn("1.014 at 0.02", w["message"])
        self.assertAlmostEqual(w["limit"], 0.014)
        self.assertIn("set_shardlow", w["message"])

    @skipIfMissingFeatures("HAT")
    def test_dt_rule_depends_on_scene_and_integrator(self):
        s = solvent(dt=0.02, a=25.0, gamma=4.5)
        self.assertNotIn("dt_kT_error", codes(s))    # a = 25: 1 % at 0.022
        s.time_step = 0.04
        w = codes(s)["dt_kT_error"]
        self.assertIn("1.0262 at 0.04", w["message"])
        s.integrator.set_shardlow()
        self.assertNotIn("dt_kT_error", codes(s))    # Shardlow: 1 % at 0.045
        s.time_step = 0.06
        self.assertIn("1.0141 at 0.05", codes(s)["dt_kT_error"]["message"])

    def test_low_density(self):
        w = codes(solvent(rho=2.0))["solvent_density"]
        self.assertAlmostEqual(w["value"], 2.0, places=2)
        self.assertIn("eta = 1.23", w["message"])

    def test_skin_small(self):
        w = codes(solvent(dt=0.01, skin=0.1))["skin_small"]
        self.assertAlmostEqual(w["value"], 0.06)

    def test_friction_near_limit(self):
        w = codes(solvent(gamma=80.0))["friction_near_limit"]   # 80 * 2.51 * 0.01 / 3 = 0.67
        self.assertAlmostEqual(w["value"], 80 * 0.01 * 2 * 3 * 4 * np.pi / 30 / 3.0, places=2)
        self.assertIn("3.3-3.5", w["message"])

    def test_langevin_friction(self):
        rng = np.random.default_rng(3)
        s = marble.System(box_l=[6.0] * 3)
        s.time_step = 0.01
        s.part.add(pos=rng.uniform(0, 6, size=(20, 3)))
        s.thermostat.set_langevin(kT=1.0, gamma=10.0, seed=1)  # a = 0.1: at the limit, quiet
        self.assertNotIn("langevin_friction", codes(s))
        s.part.by_id(7).gamma = 30.0                          # a = 0.3 on particle 7
        w = codes(s)["langevin_friction"]
        self.assertAlmostEqual(w["value"], 0.3)
        self.assertEqual(w["limit"], 0.1)
        self.assertIn("particle 7", w["message"])
        # -ln(0.7)/0.3 - 1 = 18.9 %
        self.assertIn(f"{100 * (-np.log(0.7) / 0.3 - 1):.3g} % too fast", w["message"])
        s.part.by_id(7).gamma = 150.0                         # a = 1.5: oscillating relaxation
        self.assertIn("alternating sign", codes(s)["langevin_friction"]["message"])

    @skipIfMissingFeatures("MARBLE")
    def test_colloid_rules(self):
        from marble.colloids import add_marble
        s = solvent(L=10.0)
        add_marble(s, pos=[5.0, 5.0, 5.0], radius=3.0, gamma=2.0)
        c = codes(s)
        # R/L = 0.3: 2.837 * 0.3 - (4 pi/3) 0.027 = 0.738
        self.assertAlmostEqual(c["box_too_small"]["value"], 2.837297 * 0.3 - 4 * np.pi / 3 * 0.027)
        self.assertIn("Hasimoto", c["box_too_small"]["message"])
        self.assertEqual(c["marble_slip"]["value"], 2.0)
        self.assertIn("Fig. 4", c["marble_slip"]["message"])
        self.assertNotIn("solvent_density", c)   # the colloid's volume is excluded
        # the marble paper's set-up: R = 3, gamma = 5 in a box with < 40 % correction
        s = solvent(L=24.0, seed=2)
        add_marble(s, pos=[12.0] * 3, radius=3.0, gamma=5.0)
        self.assertEqual(s.analysis.check_scene(), [])


if __name__ == "__main__":
    unittest.main()
