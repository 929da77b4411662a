# labels: python
"""marble.suspensions (doc/suspensions.md): the helper numbers of seed 004
(reference.md section 7), setup_suspension's placement (counts, no overlap,
no solvent in a core, masses, the interactions it sets), a short stable run,
and bad input (a clear ValueError, nothing changed)."""
import math
import unittest

import numpy as np

import marble
from unittest_decorators import skipIfMissingFeatures

sus = marble.suspensions


def min_image(d, L):
    return d - L * np.round(d / L)


class Helpers(unittest.TestCase):
    def test_equal_volume_cutoff(self):
        for R, want in ((1, 1.2599), (2, 2.0801), (3, 3.0366)):
            self.assertAlmostEqual(sus.equal_volume_cutoff(R), want, places=4)
            # the shell has the volume of the bead's sphere
            rc = sus.equal_volume_cutoff(R)
            self.assertAlmostEqual(rc ** 3 - R ** 3, 1.0, places=12)
        self.assertAlmostEqual(sus.surface_cutoff(3), 0.0366, places=4)

    def test_repulsion_rules(self):
        self.assertAlmostEqual(sus.colloid_solvent_repulsion(1, rule="seed"), 96.18, places=2)
        self.assertAlmostEqual(sus.colloid_solvent_repulsion(3, rule="seed"), 683.3, places=1)
        # mean field: int U dV over the shell = pi a r_c^4 / 15, checked by quadrature
        for R in (0.0, 1.0, 3.0):
            F = sus.colloid_solvent_repulsion(R)
            rp = sus.surface_cutoff(R)
            r = np.linspace(R, R + rp, 200001)
            f = F * (rp - (r - R)) ** 2 / (2 * rp) * 4 * np.pi * r ** 2
            integral = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r))
            self.assertAlmostEqual(integral, np.pi * 25 / 15, delta=1e-8)
        self.assertAlmostEqual(sus.colloid_solvent_repulsion(0.0), 25.0, places=12)

    def test_viscosity_targets(self):
        from marble import theory
        np.testing.assert_allclose(theory.batchelor_viscosity([0.05, 0.1, 0.2]),
                                   [1.141, 1.312, 1.748], atol=6e-4)
        np.testing.assert_allclose(theory.krieger_dougherty_viscosity([0.05, 0.1, 0.2, 0.3, 0.4]),
                                   [1.139, 1.313, 1.825, 2.77, 4.89], atol=6e-3)
        self.assertAlmostEqual(theory.carnahan_starling_contact(0.2), 1.758, places=3)
        with self.assertRaisesRegex(ValueError, "phi"):
            theory.krieger_dougherty_viscosity(0.7)

    def test_diffusion_time(self):
        # seed 004: R = 1, eta0 = 0.3, kT = 0.1 -> tau_D = R^2/D = 56.5
        self.assertAlmostEqual(sus.diffusion_time(1.0, 0.3, 0.1), 56.5487, places=3)
        self.assertAlmostEqual(sus.stokes_einstein_D(1.0, 0.3, 0.1), 0.1 / (6 * math.pi * 0.3))
        for bad in (dict(R=-1, eta=0.3, kT=0.1), dict(R=1, eta=0, kT=0.1)):
            with self.assertRaisesRegex(ValueError, list(k for k, v in bad.items() if v <= 0)[0]):
                sus.diffusion_time(**bad)


@skipIfMissingFeatures("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS")
class Setup(unittest.TestCase):
    L = 9.0

    def system(self):
        s = marble.System(box_l=[self.L] * 3)
        s.time_step = 0.001
        return s

    def test_placement(self):
        s = self.system()
        info = sus.setup_suspension(s, phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=3,
                                    h_cut=0.4)
        V = self.L ** 3
        n_c = round(0.1 * V / (4 / 3 * math.pi))
        self.assertEqual(info["n_colloids"], n_c)
        col = s.part.by_ids(info["colloid_ids"])
        sol = s.part.by_ids(info["solvent_ids"])
        np.testing.assert_allclose(col.mass, 3 * 4 / 3 * math.pi)
        cp = np.asarray(col.pos)
        for i in range(n_c):
            d = np.linalg.norm(min_image(cp[i + 1:] - cp[i], self.L), axis=1)
            self.assertTrue(np.all(d >= 2.0), "colloids overlap")
        sp = np.asarray(sol.pos)
        for c in cp:
            self.assertTrue(np.all(np.linalg.norm(min_image(sp - c, self.L), axis=1) >= 1.0))
        # solvent count: Poisson(3 V) thinned to the free volume, 5 sigma
        free = V - n_c * 4 / 3 * math.pi
        self.assertLess(abs(info["n_solvent"] - 3 * free), 5 * math.sqrt(3 * free))
        ia = s.non_bonded_inter
        self.assertAlmostEqual(ia[1, 0].hat.get_params()["cutoff"], 2 ** (1 / 3) - 1, places=12)
        self.assertEqual(ia[1, 0].hat.get_params()["offset"], 1.0)
        self.assertAlmostEqual(ia[1, 0].hat.get_params()["F_max"],
                               sus.colloid_solvent_repulsion(1.0, a_ss=2.5), places=10)
        self.assertEqual(ia[1, 1].lubrication.get_params()["eta"], 0.3)
        self.assertEqual(ia[1, 1].contact.get_params()["offset"], 2.0)
        self.assertEqual(ia[1, 1].dpd.get_params()["offset"], 2.0)
        self.assertEqual(s.thermostat.dpd.kT, 0.1)
        # a short run: no blow-up, temperature near kT
        s.integrator.set_shardlow()
        s.integrator.run(200)
        self.assertTrue(np.all(np.isfinite(s.part.all().pos)))

    def test_bad_input_changes_nothing(self):
        base = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1)
        cases = [(dict(phi=0.7), "phi"), (dict(phi=-0.1), "phi"), (dict(radius=0.0), "radius"),
                 (dict(h_min=-0.001), "h_min"), (dict(delta=-1e-3), "delta"),
                 (dict(h_cut=-0.5), "h_cut"), (dict(h_min=0.5, h_cut=0.4), "h_min"),
                 (dict(eta=None), "eta"), (dict(eta=-1.0), "eta"),
                 (dict(positions=[[1, 1, 1], [2.5, 1, 1]]), "positions"),
                 (dict(seed=None), "seed"), (dict(boundary="rough"), "boundary"),
                 (dict(trans_gamma=45.0), "trans_gamma")]
        if marble.has_features("TRANS_DPD", "ROTATION"):
            cases += [(dict(boundary="stick", trans_gamma=-1.0), "trans_gamma"),
                      (dict(boundary="stick", rinertia=0.0), "rinertia")]
        for extra, key in cases:
            with self.subTest(key=key, extra=extra):
                s = self.system()
                with self.assertRaisesRegex(ValueError, key):
                    sus.setup_suspension(s, **dict(base, **extra))
                self.assertEqual(len(s.part.all()), 0)
                self.assertEqual(s.non_bonded_inter[1, 1].contact.get_params(), {})
                self.assertFalse(s.thermostat.dpd.active)

    def test_stick(self):
        """boundary="slip" is seed 004 (no spins, no surface friction); "stick" keeps
        the positions and velocities and adds rotating colloids and the surface friction."""
        kw = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=3, h_cut=0.4)
        s1, s2 = self.system(), self.system()
        i1 = sus.setup_suspension(s1, **kw)
        if not marble.has_features("TRANS_DPD", "ROTATION"):
            with self.assertRaises(marble.FeaturesError):
                sus.setup_suspension(s2, boundary="stick", **kw)
            return
        i2 = sus.setup_suspension(s2, boundary="stick", **kw)
        for prop in ("pos", "v", "type", "mass"):
            np.testing.assert_array_equal(getattr(s1.part.all(), prop), getattr(s2.part.all(), prop))
        c1, c2 = s1.part.by_ids(i1["colloid_ids"]), s2.part.by_ids(i2["colloid_ids"])
        self.assertFalse(np.any(c1.rotation))
        self.assertEqual(s1.non_bonded_inter[1, 0].surface_friction.get_params(), {})
        self.assertTrue(np.all(c2.rotation))
        np.testing.assert_allclose(c2.rinertia, 0.4 * i2["colloid_mass"])
        self.assertGreater(np.std(c2.omega_lab), 0.0)
        sf = s2.non_bonded_inter[1, 0].surface_friction.get_params()
        self.assertEqual((sf["gamma"], sf["a1"], sf["a2"]), (45.0, 1.0, 0.0))
        self.assertAlmostEqual(sf["r_cut"], i2["cutoff_surface"], places=12)
        self.assertEqual(i2["trans_gamma"], 45.0)
        s2.integrator.set_shardlow()
        s2.integrator.run(200)
        self.assertTrue(np.all(np.isfinite(s2.part.all().pos)))

    def test_positions(self):
        s = self.system()
        info = sus.setup_suspension(s, phi=0.01, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1,
                                    positions=[[1, 1, 1], [4, 4, 4]], h_cut=0.4)
        self.assertEqual(info["n_colloids"], 2)
        np.testing.assert_allclose(s.part.by_ids(info["colloid_ids"]).pos, [[1, 1, 1], [4, 4, 4]])


if __name__ == "__main__":
    unittest.main()
