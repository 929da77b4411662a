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
        # de Kruif et al. (1985)'s hard-sphere fits (1 - phi/phi_m)^-2: 0.3/0.63 = 10/21,
        # (11/21)^-2 = 441/121; 0.3/0.71 = 30/71, (41/71)^-2 = 5041/1681
        self.assertAlmostEqual(theory.quemada_viscosity(0.3), 441 / 121, places=12)
        self.assertAlmostEqual(theory.quemada_viscosity(0.3, phi_m=0.71), 5041 / 1681, places=12)
        phi = np.array([0.05, 0.2, 0.4])
        np.testing.assert_allclose(theory.quemada_viscosity(phi, 0.63, exponent=1.575),
                                   theory.krieger_dougherty_viscosity(phi), rtol=1e-14)
        for bad, name in ((dict(phi=0.63), "phi"), (dict(phi=-0.1), "phi"),
                          (dict(phi=0.1, phi_m=0), "phi_m"), (dict(phi=0.1, exponent=-2), "exponent")):
            with self.assertRaisesRegex(ValueError, name):
                theory.quemada_viscosity(**bad)

    def test_place_colloids(self):
        L = np.array([8.0, 8.0, 8.0])

        def rsa(n, d, seed):  # the addition of every earlier version, written out
            rng, pos = np.random.default_rng(seed), np.empty((0, 3))
            while len(pos) < n:
                x = rng.uniform(0, 1, size=3) * L
                if len(pos) and np.min(np.linalg.norm(min_image(pos - x, L), axis=1)) < d:
                    continue
                pos = np.vstack([pos, x])
            return pos

        def distances(p, box):  # every centre distance, inf on the diagonal
            r = np.linalg.norm(min_image(p[:, None, :] - p[None, :, :], box), axis=2)
            r[np.diag_indices(len(p))] = np.inf
            return r

        # up to PHI_RSA: random sequential addition, bit for bit
        n = 37  # phi 0.303 of R = 1 in 8^3 (0.312 with the gap 0.02)
        p = sus.place_colloids(L, n, 1.0, np.random.default_rng(11), min_gap=0.02)
        np.testing.assert_array_equal(p, rsa(n, 2.02, 11))
        # above: compressed to a random packing of the target spheres
        n = 59  # phi 0.48 (0.50 with the gap)
        p = sus.place_colloids(L, n, 1.0, np.random.default_rng(5), min_gap=0.01)
        self.assertEqual(p.shape, (n, 3))
        self.assertTrue(np.all((p >= 0) & (p < L)))
        r = distances(p, L)
        self.assertGreaterEqual(r.min(), 2.01)
        np.testing.assert_array_equal(p, sus.place_colloids(L, n, 1.0, np.random.default_rng(5),
                                                            min_gap=0.01))
        # amorphous, not a lattice: the number of neighbours closer than 2.3 spreads
        # (measured 2-10, std 1.1-1.4 over seeds 0-4; every sphere of an fcc packing at
        # this density has its 12 neighbours at 2.61, i.e. none closer than 2.3)
        self.assertGreater(np.std(np.sum(r < 2.3, axis=1)), 0.8)
        with self.assertRaisesRegex(ValueError, "phi"):
            sus.place_colloids(L, 70, 1.0, np.random.default_rng(5))  # 0.573 > PHI_PLACE_MAX
        # more than PLACE_MC_MAX_N colloids: overlap removal, the same checks
        n = 200
        L2 = np.full(3, (n * 4 / 3 * math.pi / 0.45) ** (1 / 3))  # phi 0.45 (0.457 with the gap)
        p = sus.place_colloids(L2, n, 1.0, np.random.default_rng(0), min_gap=0.01)
        self.assertEqual(p.shape, (n, 3))
        self.assertTrue(np.all((p >= 0) & (p < L2)))
        r = distances(p, L2)
        self.assertGreaterEqual(r.min(), 2.01)
        self.assertGreater(np.std(np.sum(r < 2.3, axis=1)), 0.8)  # measured 1.3-1.4, seeds 0-2
        np.testing.assert_array_equal(p, sus.place_colloids(L2, n, 1.0, np.random.default_rng(0),
                                                            min_gap=0.01))

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
        the positions and velocities and adds rotating colloids and the surface friction
        (with the same solvent count: the stick default "bulk" adds beads)."""
        kw = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=3, h_cut=0.4, solvent_count="poisson")
        s1, s2 = self.system(), self.system()
        i1 = sus.setup_suspension(s1, **kw)
        if not marble.has_features("TRANS_DPD", "ROTATION"):
            with self.assertRaises(marble.FeaturesError):
                sus.setup_suspension(s2, boundary="stick", **kw)
            return
        i2 = sus.setup_suspension(s2, boundary="stick", radius_calibration="none", **kw)
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

    def test_stick_radius_calibration(self):
        """boundary="stick" takes ``radius`` as the hydrodynamic radius by default: the whole
        colloid is built on the core a = radius / STICK_RADIUS_RATIO (offsets, equal-volume
        shell, solvent removal, mass, inertia, colloid-colloid kernels), phi counts spheres
        of the given radius; "none" is the uncalibrated colloid bit for bit; a number is
        taken as the ratio. (Slip's solvent count and colloid DPD for both, so that the
        solvent and the colloid-colloid DPD offset compare.)"""
        if not marble.has_features("TRANS_DPD", "ROTATION"):
            self.skipTest("needs TRANS_DPD and ROTATION")
        c = sus.STICK_RADIUS_RATIO
        self.assertGreater(c, 1.0)
        self.assertLess(c, 1.2)
        R = 1.2
        kw = dict(phi=0.1, radius=R, kT=0.1, gamma=4.5, eta=0.3, seed=5, h_cut=0.4, solvent_count="poisson",
                  colloid_dpd=True)
        s0, s1, s2 = self.system(), self.system(), self.system()
        i0 = sus.setup_suspension(s0, **kw)  # slip: no calibration
        i1 = sus.setup_suspension(s1, boundary="stick", **kw)
        i2 = sus.setup_suspension(s2, boundary="stick", radius_calibration=1.1, **kw)
        V = self.L ** 3
        n_c = round(0.1 * V / (4 / 3 * math.pi * R ** 3))
        self.assertEqual((i0["radius_calibration"], i0["radius_ratio"], i0["core_radius"]), ("none", 1.0, R))
        self.assertIsNone(i0["hydrodynamic_radius"])
        for s, info, ratio in ((s1, i1, c), (s2, i2, 1.1)):
            a = R / ratio
            with self.subTest(ratio=ratio):
                self.assertEqual(info["n_colloids"], n_c)
                self.assertAlmostEqual(info["core_radius"], a, places=14)
                self.assertEqual((info["radius"], info["radius_ratio"]), (R, ratio))
                self.assertAlmostEqual(info["phi"], n_c * 4 / 3 * math.pi * R ** 3 / V, places=14)
                self.assertAlmostEqual(info["phi_core"], info["phi"] / ratio ** 3, places=14)
                self.assertAlmostEqual(info["hydrodynamic_radius"], R, places=14)
                self.assertAlmostEqual(info["phi_hydrodynamic"], info["phi"], places=14)
                self.assertAlmostEqual(info["diffusion_time"], sus.diffusion_time(R, 0.3, 0.1), places=12)
                col = s.part.by_ids(info["colloid_ids"])
                m = 3 * 4 / 3 * math.pi * a ** 3
                np.testing.assert_allclose(col.mass, m, rtol=1e-14)
                np.testing.assert_allclose(col.rinertia, 0.4 * m * a * a, rtol=1e-14)
                # the same placement as slip (hydrodynamic spheres kept apart), cores emptied
                np.testing.assert_array_equal(col.pos, s0.part.by_ids(i0["colloid_ids"]).pos)
                cp = np.asarray(col.pos)
                for i in range(n_c):
                    d = np.linalg.norm(min_image(cp[i + 1:] - cp[i], self.L), axis=1)
                    self.assertTrue(np.all(d >= 2 * R), "hydrodynamic spheres overlap at placement")
                sp = np.asarray(s.part.by_ids(info["solvent_ids"]).pos)
                dmin = np.min([np.linalg.norm(min_image(sp - x, self.L), axis=1) for x in cp], axis=0)
                self.assertGreaterEqual(dmin.min(), a)
                self.assertGreater(np.count_nonzero(dmin < R), 0, "no solvent between core and R")
                self.assertEqual(info["n_solvent"], i0["n_solvent"] + np.count_nonzero(dmin < R))
                rp = sus.surface_cutoff(a)
                self.assertAlmostEqual(info["cutoff_surface"], rp, places=14)
                ia = s.non_bonded_inter
                hat = ia[1, 0].hat.get_params()
                self.assertAlmostEqual(hat["offset"], a, places=14)
                self.assertAlmostEqual(hat["cutoff"], rp, places=12)
                self.assertAlmostEqual(hat["F_max"], sus.colloid_solvent_repulsion(a, a_ss=2.5), places=10)
                dpd = ia[1, 0].dpd.get_params()
                self.assertAlmostEqual(dpd["offset"], a, places=14)
                self.assertAlmostEqual(dpd["r_cut"], rp, places=12)
                sf = ia[1, 0].surface_friction.get_params()
                self.assertAlmostEqual(sf["a1"], a, places=14)
                self.assertAlmostEqual(sf["r_cut"], rp, places=12)
                self.assertAlmostEqual(info["stick_shell"], rp, places=12)
                self.assertAlmostEqual(ia[1, 1].contact.get_params()["offset"], 2 * a, places=14)
                self.assertAlmostEqual(ia[1, 1].dpd.get_params()["offset"], 2 * a, places=14)
                lub = ia[1, 1].lubrication.get_params()
                self.assertAlmostEqual(lub["a1"], a, places=14)
                self.assertAlmostEqual(lub["a2"], a, places=14)
        # "none": the core is the given radius, as before the calibration
        s3 = self.system()
        i3 = sus.setup_suspension(s3, boundary="stick", radius_calibration="none", **kw)
        self.assertEqual((i3["core_radius"], i3["phi_core"], i3["radius_ratio"]), (R, i3["phi"], 1.0))
        self.assertAlmostEqual(i3["hydrodynamic_radius"], c * R, places=14)
        for prop in ("pos", "v", "type", "mass"):
            np.testing.assert_array_equal(getattr(s0.part.all(), prop), getattr(s3.part.all(), prop))
        self.assertEqual(s3.non_bonded_inter[1, 0].surface_friction.get_params()["a1"], R)
        # positions may come as close as the cores
        s4 = self.system()
        d = 2 * R / c + 0.01
        i4 = sus.setup_suspension(s4, boundary="stick", positions=[[2, 2, 2], [2 + d, 2, 2]], **kw)
        self.assertEqual(i4["n_colloids"], 2)
        # bad input: a clear ValueError, nothing changed
        for extra, key in ((dict(radius_calibration="stick"), "radius_calibration"),
                           (dict(radius_calibration="rotation"), "radius_calibration"),
                           (dict(radius_calibration="stresslet"), "radius_calibration"),
                           (dict(boundary="stick", radius_calibration="hydro"), "radius_calibration"),
                           (dict(boundary="stick", radius_calibration=-1.0), "radius_calibration"),
                           (dict(boundary="stick", radius_calibration=0.0), "radius_calibration"),
                           (dict(boundary="stick", radius_calibration="none",
                                 positions=[[2, 2, 2], [2 + 2 * R - 0.01, 2, 2]]), "positions")):
            with self.subTest(extra=extra):
                s = self.system()
                with self.assertRaisesRegex(ValueError, key):
                    sus.setup_suspension(s, **dict(kw, **extra))
                self.assertEqual(len(s.part.all()), 0)
                self.assertFalse(s.thermostat.dpd.active)

    def test_stick_named_calibrations(self):
        """radius_calibration="rotation" or "stresslet" builds the stick colloid on the
        core a = radius / STICK_ROTATIONAL_RADIUS_RATIO (section 7m) or radius /
        STICK_STRESSLET_RADIUS_RATIO (section 7p), so that its rotational or strain radius
        is ``radius``. The constants carry the measured order drag < strain < rotation
        (7m: rotation above drag by 7 sigma). Every stick calibration, the default
        "stick" included, reports the three radii and their volume fractions; "slip"
        reports none."""
        if not marble.has_features("TRANS_DPD", "ROTATION"):
            self.skipTest("needs TRANS_DPD and ROTATION")
        ct, cs, cr = sus.STICK_RADIUS_RATIO, sus.STICK_STRESSLET_RADIUS_RATIO, sus.STICK_ROTATIONAL_RADIUS_RATIO
        self.assertGreater(cr - ct, 3 * math.hypot(sus.STICK_ROTATIONAL_RADIUS_RATIO_ERR,
                                                   sus.STICK_RADIUS_RATIO_ERR))
        self.assertLess(ct, cs)
        self.assertLess(cs, cr)
        R = 1.2
        kw = dict(phi=0.1, radius=R, kT=0.1, gamma=4.5, eta=0.3, seed=5, h_cut=0.4, solvent_count="poisson",
                  boundary="stick")
        infos = [(sus.setup_suspension(self.system(), **kw), ct)]  # "stick"
        for name, c in (("rotation", cr), ("stresslet", cs)):
            with self.subTest(radius_calibration=name):
                s = self.system()
                info = sus.setup_suspension(s, radius_calibration=name, **kw)
                a = R / c
                self.assertEqual((info["radius_calibration"], info["radius_ratio"]), (name, c))
                self.assertAlmostEqual(info["core_radius"], a, places=14)
                self.assertAlmostEqual(info["phi_core"], info["phi"] / c ** 3, places=14)
                col = s.part.by_ids(info["colloid_ids"])
                np.testing.assert_allclose(col.mass, 3 * 4 / 3 * math.pi * a ** 3, rtol=1e-14)
                self.assertAlmostEqual(s.non_bonded_inter[1, 0].surface_friction.get_params()["a1"], a, places=14)
                self.assertEqual(info["n_colloids"], infos[0][0]["n_colloids"])
                infos.append((info, c))
        for info, ratio in infos:  # the given radius is the calibration's (ratio x core)
            for key, c in (("hydrodynamic", ct), ("rotational", cr), ("stresslet", cs)):
                self.assertAlmostEqual(info[key + "_radius"], R * c / ratio, places=14)
                self.assertAlmostEqual(info["phi_" + key], info["phi"] * (c / ratio) ** 3, places=14)
        slip = sus.setup_suspension(self.system(), **dict(kw, boundary="slip"))
        for key in ("rotational_radius", "phi_rotational", "stresslet_radius", "phi_stresslet"):
            self.assertIsNone(slip[key])

    def test_radius_calibration_arg(self):
        """The command-line form of radius_calibration (samples, benches): the names
        as they are, numbers as numbers, anything else a ValueError naming it."""
        for name in ("none", "stick", "rotation", "stresslet"):
            self.assertEqual(sus.radius_calibration_arg(name), name)
        self.assertEqual(sus.radius_calibration_arg("1.02"), 1.02)
        for bad in ("hydro", "", None):
            with self.assertRaisesRegex(ValueError, "radius_calibration"):
                sus.radius_calibration_arg(bad)

    def test_boundary_defaults(self):
        """The defaults that depend on ``boundary`` (doc/suspensions.md 7i): slip is seed
        004's (plain lubrication to h_cut = r_c, colloid-colloid DPD, Poisson count);
        stick gets the shifted kernel to STICK_LUBRICATION_H_CUT, no colloid-colloid
        DPD and the "bulk" count; explicit arguments win; the old stick settings given
        explicitly build the same scene as slip's placement and kernels."""
        kw = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=3)
        s0 = self.system()
        i0 = sus.setup_suspension(s0, **kw)
        lub = s0.non_bonded_inter[1, 1].lubrication.get_params()
        self.assertEqual((lub["form"], lub["h_cut"]), ("plain", 1.0))
        self.assertEqual(s0.non_bonded_inter[1, 1].dpd.get_params()["offset"], 2.0)
        self.assertEqual((i0["solvent_count"], i0["lubrication_form"], i0["colloid_dpd"], i0["h_cut"]),
                         ("poisson", "plain", True, 1.0))
        if not marble.has_features("TRANS_DPD", "ROTATION"):
            return
        s1 = self.system()
        i1 = sus.setup_suspension(s1, boundary="stick", **kw)
        lub = s1.non_bonded_inter[1, 1].lubrication.get_params()
        self.assertEqual((lub["form"], lub["h_cut"]), ("shifted", sus.STICK_LUBRICATION_H_CUT))
        self.assertEqual(sus.STICK_LUBRICATION_H_CUT, 0.15)
        self.assertEqual(s1.non_bonded_inter[1, 1].dpd.get_params(), {})
        self.assertEqual((i1["solvent_count"], i1["lubrication_form"], i1["colloid_dpd"], i1["h_cut"]),
                         ("bulk", "shifted", False, 0.15))
        # a bead in several colloids' friction shells gets no friction by default
        # (doc/suspensions.md 7t, 7u; "full" before session 36)
        self.assertEqual(i1["shared"], "off")
        self.assertEqual(s1.non_bonded_inter[1, 0].surface_friction.get_params()["shared"], "off")
        free = self.L ** 3 - i1["n_colloids"] * 4 / 3 * math.pi * i1["core_radius"] ** 3
        self.assertEqual(i1["n_solvent"], round(3 * free) + round(i1["adsorbed"] * i1["n_colloids"]))
        # explicit arguments win; the plain form's h_cut default is r_c for stick too
        s2 = self.system()
        i2 = sus.setup_suspension(s2, boundary="stick", radius_calibration="none", lubrication_form="plain",
                                  colloid_dpd=True, solvent_count="poisson", **kw)
        lub = s2.non_bonded_inter[1, 1].lubrication.get_params()
        self.assertEqual(lub, s0.non_bonded_inter[1, 1].lubrication.get_params())
        self.assertEqual(s2.non_bonded_inter[1, 1].dpd.get_params(), s0.non_bonded_inter[1, 1].dpd.get_params())
        self.assertEqual(i2["solvent_count"], "poisson")
        for prop in ("pos", "v"):
            np.testing.assert_array_equal(getattr(s0.part.all(), prop), getattr(s2.part.all(), prop))
        s3 = self.system()
        sus.setup_suspension(s3, boundary="stick", h_cut=0.3, **kw)
        lub = s3.non_bonded_inter[1, 1].lubrication.get_params()
        self.assertEqual((lub["form"], lub["h_cut"]), ("shifted", 0.3))
        s4 = self.system()
        sus.setup_suspension(s4, lubrication_form="shifted", **kw)  # slip with the shifted form: h_cut = r_c
        lub = s4.non_bonded_inter[1, 1].lubrication.get_params()
        self.assertEqual((lub["form"], lub["h_cut"]), ("shifted", 1.0))
        s5 = self.system()
        i5 = sus.setup_suspension(s5, boundary="stick", lubrication=False, **kw)
        self.assertEqual(s5.non_bonded_inter[1, 1].lubrication.get_params(), {})
        self.assertIsNone(i5["lubrication_form"])
        for extra in (dict(lubrication_form="log"), dict(boundary="stick", lubrication_form=None, h_cut=0.0)):
            s = self.system()
            with self.assertRaisesRegex(ValueError, "lubrication_form" if "log" in str(extra) else "h_cut"):
                sus.setup_suspension(s, **dict(kw, **extra))
            self.assertEqual(len(s.part.all()), 0)
        # the stick default "bulk" needs seed 004's solvent (or adsorbed=, or another count)
        s = self.system()
        with self.assertRaisesRegex(ValueError, "solvent_count='exact'"):
            sus.setup_suspension(s, boundary="stick", **dict(kw, density=4.0))
        self.assertEqual(len(s.part.all()), 0)

    def test_stick_friction_in_stability_check(self):
        """The explicit stability check (integrators/stability.cpp) counts the stick
        surface_friction with velocity Verlet: a bead's gamma/m (45 at dt = 0.05: nu = 2.25)
        and the colloid's rotational friction from its shell (tiny inertia); the
        same scenes pass as slip (no surface friction) and under Shardlow (exact pair update)."""
        if not marble.has_features("TRANS_DPD", "ROTATION"):
            self.skipTest("needs TRANS_DPD and ROTATION")
        kw = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=3, h_cut=0.4,
                  lubrication=False, f_contact=0.5, delta=0.1)
        for dt, extra, where in ((0.05, dict(boundary="stick"), "surface_friction of types 1-0"),
                                 (0.005, dict(boundary="stick", trans_gamma=10.0, rinertia=0.01),
                                  "rotational stick friction")):
            for integ, fails in (("set_vv", True), ("set_shardlow", False)):
                with self.subTest(dt=dt, integrator=integ):
                    s = self.system()
                    s.time_step = dt
                    sus.setup_suspension(s, **kw, **extra)
                    getattr(s.integrator, integ)()
                    if fails:
                        with self.assertRaisesRegex(RuntimeError, where):
                            s.integrator.run(1)
                    else:
                        s.integrator.run(1)
            s = self.system()  # the same scene with slip colloids: no surface friction, runs
            s.time_step = dt
            sus.setup_suspension(s, **kw)
            s.integrator.set_vv()
            s.integrator.run(1)

    def test_solvent_count(self):
        """solvent_count="exact": round(density x free volume) beads outside the cores;
        "poisson" (the default) is the seed-004 scene bit for bit; bad input."""
        kw = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=4, h_cut=0.4)
        s0, s1, s2 = self.system(), self.system(), self.system()
        i0 = sus.setup_suspension(s0, **kw)
        i1 = sus.setup_suspension(s1, solvent_count="poisson", **kw)
        np.testing.assert_array_equal(s0.part.all().pos, s1.part.all().pos)
        np.testing.assert_array_equal(s0.part.all().v, s1.part.all().v)
        i2 = sus.setup_suspension(s2, solvent_count="exact", **kw)
        self.assertEqual((i0["solvent_count"], i2["solvent_count"]), ("poisson", "exact"))
        free = self.L ** 3 - i2["n_colloids"] * 4 / 3 * math.pi
        self.assertEqual(i2["n_solvent"], round(3 * free))
        np.testing.assert_array_equal(s2.part.by_ids(i2["colloid_ids"]).pos, s0.part.by_ids(i0["colloid_ids"]).pos)
        sp = np.asarray(s2.part.by_ids(i2["solvent_ids"]).pos)
        for c in np.asarray(s2.part.by_ids(i2["colloid_ids"]).pos):
            self.assertTrue(np.all(np.linalg.norm(min_image(sp - c, self.L), axis=1) >= 1.0))
        self.assertTrue(np.all((sp >= 0) & (sp < self.L)))
        s = self.system()
        with self.assertRaisesRegex(ValueError, "solvent_count"):
            sus.setup_suspension(s, solvent_count="fixed", **kw)
        self.assertEqual(len(s.part.all()), 0)
        self.assertFalse(s.thermostat.dpd.active)

    @skipIfMissingFeatures("TRANS_DPD", "ROTATION")
    def test_cs_shell(self):
        """cs_shell: the colloid-solvent hat, DPD and stick friction on a given shell;
        the shell of the default (equal-volume) rule given explicitly is the default
        scene bit for bit; the rule's F_max uses the given shell; a larger colloid with
        the R = 1 colloid's shell and F_max (doc/suspensions.md 7q); bad input."""
        kw = dict(phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=5, boundary="stick")
        s0, s1 = self.system(), self.system()
        i0 = sus.setup_suspension(s0, **kw)
        a = i0["core_radius"]
        i1 = sus.setup_suspension(s1, cs_shell=sus.surface_cutoff(a), solvent_count="bulk",
                                  adsorbed=sus.ADSORBED_PER_AREA * 4 * math.pi * a * a, **kw)
        for prop in ("pos", "v", "type", "mass", "omega_lab"):
            np.testing.assert_array_equal(getattr(s0.part.all(), prop), getattr(s1.part.all(), prop))
        for kind in ("hat", "dpd", "surface_friction"):
            self.assertEqual(getattr(s0.non_bonded_inter[1, 0], kind).get_params(),
                             getattr(s1.non_bonded_inter[1, 0], kind).get_params())
        self.assertEqual((i0["cutoff_surface"], i0["a_cs"]), (i1["cutoff_surface"], i1["a_cs"]))
        self.assertAlmostEqual(i1["cutoff_centre"], i0["cutoff_centre"], places=14)
        # the rules on a given shell: "seed" a_ss/shell, "mean_field" by quadrature
        for R, rp in ((1.0, 0.4), (2.0, 0.265)):
            self.assertAlmostEqual(sus.colloid_solvent_repulsion(R, rule="seed", shell=rp), 25.0 / rp, places=12)
            F = sus.colloid_solvent_repulsion(R, shell=rp)
            r = np.linspace(R, R + rp, 200001)
            f = F * (rp - (r - R)) ** 2 / (2 * rp) * 4 * np.pi * r ** 2
            self.assertAlmostEqual(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(r)), np.pi * 25 / 15, delta=1e-8)
        # R = 2 with the R = 1 colloid's shell and F_max: every colloid-solvent kernel on that shell
        s2 = marble.System(box_l=[12.0] * 3)
        s2.time_step = 0.001
        rp1, F1 = sus.surface_cutoff(a), sus.colloid_solvent_repulsion(a, a_ss=2.5)
        i2 = sus.setup_suspension(s2, **dict(kw, radius=2.0, radius_calibration="none", phi=0.15),
                                  cs_shell=rp1, a_cs=F1, solvent_count="exact")
        ia = s2.non_bonded_inter
        hat, dpd, sf = ia[1, 0].hat.get_params(), ia[1, 0].dpd.get_params(), ia[1, 0].surface_friction.get_params()
        self.assertEqual((hat["offset"], hat["cutoff"], hat["F_max"]), (2.0, rp1, F1))
        self.assertEqual((dpd["offset"], dpd["r_cut"]), (2.0, rp1))
        self.assertEqual((sf["a1"], sf["r_cut"], i2["stick_shell"]), (2.0, rp1, rp1))
        self.assertEqual((i2["cutoff_surface"], i2["cutoff_centre"]), (rp1, 2.0 + rp1))
        # without a_cs the rule takes the given shell
        s3 = marble.System(box_l=[12.0] * 3)
        i3 = sus.setup_suspension(s3, **dict(kw, radius=2.0, radius_calibration="none", phi=0.15),
                                  cs_shell=rp1, solvent_count="exact")
        self.assertAlmostEqual(i3["a_cs"], sus.colloid_solvent_repulsion(2.0, a_ss=2.5, shell=rp1), places=12)
        # a stick_shell still wins for the friction
        s4 = marble.System(box_l=[12.0] * 3)
        sus.setup_suspension(s4, **dict(kw, radius=2.0, radius_calibration="none", phi=0.15),
                             cs_shell=rp1, stick_shell=0.4, solvent_count="exact")
        self.assertEqual(s4.non_bonded_inter[1, 0].surface_friction.get_params()["r_cut"], 0.4)
        # bad input: a clear ValueError, nothing changed
        for bad, msg in ((dict(cs_shell=0.0), "cs_shell"), (dict(cs_shell=-0.2), "cs_shell"),
                         (dict(cs_shell="thin"), "cs_shell"), (dict(cs_shell=0.3), "adsorbed")):
            s = self.system()
            with self.assertRaisesRegex(ValueError, msg):
                sus.setup_suspension(s, **kw, **bad)
            self.assertEqual(len(s.part.all()), 0)
            self.assertFalse(s.thermostat.dpd.active)
        with self.assertRaisesRegex(ValueError, "shell"):
            sus.colloid_solvent_repulsion(1.0, shell=0.0)

    def test_positions(self):
        s = self.system()
        info = sus.setup_suspension(s, phi=0.01, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1,
                                    positions=[[1, 1, 1], [4, 4, 4]], h_cut=0.4)
        self.assertEqual(info["n_colloids"], 2)
        np.testing.assert_allclose(s.part.by_ids(info["colloid_ids"]).pos, [[1, 1, 1], [4, 4, 4]])


if __name__ == "__main__":
    unittest.main()
