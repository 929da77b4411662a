# labels: python
"""Planar walls (constraints) and tunable-slip wall friction (reference.md
section 4, doc/walls.md): analytic forces against an independent Python
implementation (WCA at r = z, friction -gamma w(z) (v - v_wall) with and
without layer offset, Philox noise keyed by particle id, wall id and the DPD
counter), the force on the wall, penetration errors, non-periodic boxes and
bad input."""
import unittest

import numpy as np

import marble
from marble.shapes import Wall
from unittest_decorators import skipIfMissingFeatures

from reference_noise import SALT_WALL, uniform3


def wall_noise(seed, counter, pid, wid):
    return uniform3(seed, SALT_WALL, counter, pid, wid)


RC_WCA = 2.0 ** (1.0 / 6.0)


def wca_force(z, eps=1.0, sig=1.0):
    """Magnitude of the WCA force at distance z (along the wall normal)."""
    if z >= RC_WCA * sig:
        return 0.0
    return 24.0 * eps * (2.0 * (sig / z) ** 12 - (sig / z) ** 6) / z


def wca_energy(z, eps=1.0, sig=1.0):
    if z >= RC_WCA * sig:
        return 0.0
    return 4.0 * eps * ((sig / z) ** 12 - (sig / z) ** 6) + eps


def slip_weight(z, r_cut, offset):
    zl = z - offset
    if zl >= r_cut:
        return 0.0
    return 1.0 if zl <= 0.0 else 1.0 - zl / r_cut


def make_system(L=(6.0, 6.0, 8.0), periodic_z=False, dt=0.01):
    s = marble.System(box_l=list(L))
    s.periodicity = [True, True, periodic_z]
    s.time_step = dt
    s.cell_system.skin = 0.3
    return s


class WallForces(unittest.TestCase):

    @skipIfMissingFeatures("LENNARD_JONES")
    def test_wca_at_distance(self):
        s = make_system()
        L = s.box_l[2]
        lo = s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0), particle_type=1)
        hi = s.constraints.add(shape=Wall(normal=[0, 0, -2.0], dist=-L), particle_type=2)
        for wt in (1, 2):
            s.non_bonded_inter[wt, 0].lennard_jones.set_params(
                epsilon=1.0, sigma=1.0, cutoff=RC_WCA, shift="auto")
        z = np.array([0.9, 1.0, 1.05, 1.2, 3.0, L - 0.95, L - 1.1, L - 1.5])
        n = len(z)
        pos = np.column_stack([np.linspace(0.5, 5.5, n), np.linspace(5.0, 1.0, n), z])
        p = s.part.add(pos=pos, type=[0] * n)
        s.integrator.run(0)
        f = p.f
        for k in range(n):
            expect = np.array([0.0, 0.0, wca_force(z[k]) - wca_force(L - z[k])])
            np.testing.assert_allclose(f[k], expect, rtol=1e-12, atol=1e-12)
        # momentum to the walls: each wall's total force is minus the sum of its forces
        np.testing.assert_allclose(lo.total_force(), [0, 0, -sum(wca_force(x) for x in z)],
                                   rtol=1e-12)
        np.testing.assert_allclose(hi.total_force(), [0, 0, sum(wca_force(L - x) for x in z)],
                                   rtol=1e-12)
        np.testing.assert_allclose(lo.total_force() + hi.total_force() + f.sum(0), 0.0,
                                   atol=1e-9)
        e = sum(wca_energy(x) + wca_energy(L - x) for x in z)
        self.assertAlmostEqual(s.analysis.energy()["non_bonded"], e, delta=1e-10 * e)
        # type 3 has no wall interaction: no force
        p[0].type = 3
        s.integrator.run(0)
        np.testing.assert_array_equal(p[0].f, [0.0, 0.0, 0.0])

    @skipIfMissingFeatures("LENNARD_JONES")
    def test_tilted_wall(self):
        s = make_system(L=(10.0, 10.0, 10.0), periodic_z=True)
        n = np.array([1.0, 2.0, 2.0]) / 3.0
        w = s.constraints.add(shape=Wall(normal=[1, 2, 2], dist=2.0), particle_type=1)
        s.non_bonded_inter[1, 0].lennard_jones.set_params(
            epsilon=1.5, sigma=0.8, cutoff=RC_WCA * 0.8, shift="auto")
        pos = np.array([[3.0, 2.0, 1.0], [4.0, 4.0, 1.0], [6.0, 6.0, 6.0]])
        p = s.part.add(pos=pos, type=[0, 0, 0])
        s.integrator.run(0)
        for k in range(3):
            z = pos[k] @ n - 2.0
            np.testing.assert_allclose(p[k].f, wca_force(z, 1.5, 0.8) * n, rtol=1e-12,
                                       atol=1e-14)
        np.testing.assert_allclose(w.total_force(), -p.f.sum(0), atol=1e-12)

    @skipIfMissingFeatures("TUNABLE_SLIP", "DPD")
    def test_friction_kT0(self):
        """kT = 0: F = -gamma w(z) (v - v_wall), with and without offset."""
        for offset in (0.0, 0.8):
            s = make_system()
            L = s.box_l[2]
            vw_lo, vw_hi = np.array([0.3, -0.2, 0.0]), np.array([-0.5, 0.1, 0.0])
            lo = s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0), particle_type=1,
                                   velocity=vw_lo)
            hi = s.constraints.add(shape=Wall(normal=[0, 0, -1], dist=-L), particle_type=2,
                                   velocity=vw_hi)
            prm = {1: (2.5, 1.2), 2: (0.7, 0.9)}  # gamma, r_cut per wall type
            for wt, (g, rc) in prm.items():
                s.non_bonded_inter[wt, 0].tunable_slip.set_params(gamma=g, r_cut=rc,
                                                                  offset=offset)
            self.assertEqual(s.non_bonded_inter[1, 0].tunable_slip.get_params(),
                             {"gamma": 2.5, "r_cut": 1.2, "offset": offset})
            s.thermostat.set_dpd(kT=0.0, seed=4)
            z = np.array([0.1, 0.5, 0.79, 1.0, 1.9, 2.5, L - 0.2, L - 1.0, L - 1.6, L - 2.5])
            n = len(z)
            rng = np.random.default_rng(3)
            v = rng.normal(size=(n, 3))
            pos = np.column_stack([rng.random(n) * 6, rng.random(n) * 6, z])
            p = s.part.add(pos=pos, v=v, type=[0] * n)
            s.integrator.run(0)
            f_lo = np.array([-prm[1][0] * slip_weight(z[k], prm[1][1], offset) * (v[k] - vw_lo)
                             for k in range(n)])
            f_hi = np.array([-prm[2][0] * slip_weight(L - z[k], prm[2][1], offset)
                             * (v[k] - vw_hi) for k in range(n)])
            np.testing.assert_allclose(p.f, f_lo + f_hi, rtol=1e-12, atol=1e-14)
            np.testing.assert_allclose(lo.total_force(), -f_lo.sum(0), rtol=1e-12, atol=1e-14)
            np.testing.assert_allclose(hi.total_force(), -f_hi.sum(0), rtol=1e-12, atol=1e-14)
            # below the offset the weight is 1, beyond offset + r_cut it is 0
            self.assertGreater(abs(f_lo[0]).max(), 0.0)
            self.assertEqual(abs(f_lo[-1]).max(), 0.0)
            # friction is a thermostat force: off without the DPD thermostat
            s.thermostat.turn_off()
            s.integrator.run(0)
            np.testing.assert_array_equal(p.f, np.zeros((n, 3)))

    @skipIfMissingFeatures("TUNABLE_SLIP", "DPD")
    def test_noise_keyed_by_ids(self):
        """F = -gamma w (v - v_wall) + sqrt(24 kT gamma / dt) sqrt(w) xi(seed, counter, id, wall id)."""
        kT, dt, g, rc, off, seed, counter = 1.3, 0.02, 3.0, 1.0, 0.5, 11, 321

        def forces(order):
            s = make_system(dt=dt)
            L = s.box_l[2]
            walls = [s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0), particle_type=1,
                                       velocity=[0.4, 0.0, 0.0]),
                     s.constraints.add(shape=Wall(normal=[0, 0, -1], dist=-L), particle_type=1)]
            s.non_bonded_inter[1, 0].tunable_slip.set_params(gamma=g, r_cut=rc, offset=off)
            s.thermostat.set_dpd(kT=kT, seed=seed)
            s.thermostat.dpd.philox_counter = counter
            ids = np.array([3, 17, 8, 40])[order]
            z = np.array([0.3, 0.9, L - 1.2, L - 0.6])[order]
            v = np.array([[0.1, 0.2, -0.3], [1.0, 0.0, 0.5], [-0.2, 0.3, 0.0],
                          [0.0, -1.0, 0.2]])[order]
            pos = np.column_stack([np.full(4, 2.0), np.arange(4) * 1.3, z])
            s.part.add(id=ids, pos=pos, v=v, type=[0] * 4)
            s.integrator.run(0)
            return s, walls, {int(i): s.part.by_id(int(i)).f.copy() for i in ids}, \
                {int(i): (zz, vv) for i, zz, vv in zip(ids, z, v)}

        s, walls, f1, geo = forces([0, 1, 2, 3])
        L = s.box_l[2]
        pref = np.sqrt(24.0 * kT * g / dt)
        for pid, (z, v) in geo.items():
            expect = np.zeros(3)
            for w, zw, vw in ((walls[0], z, np.array([0.4, 0, 0])), (walls[1], L - z, np.zeros(3))):
                wz = slip_weight(zw, rc, off)
                if wz > 0.0:
                    expect += -g * wz * (v - vw) + pref * np.sqrt(wz) * wall_noise(
                        seed, counter, pid, w._id)
            np.testing.assert_allclose(f1[pid], expect, rtol=1e-11, atol=1e-13)
        # same ids, other insertion order and slots: bit-identical forces per id
        _, _, f2, _ = forces([2, 0, 3, 1])
        for pid in f1:
            np.testing.assert_array_equal(f1[pid], f2[pid])
        # the counter advances with every step: new noise after run(1)
        f_before = s.part.by_id(3).f.copy()
        s.integrator.run(1)
        self.assertEqual(s.thermostat.dpd.philox_counter, counter + 1)
        self.assertFalse(np.allclose(s.part.by_id(3).f, f_before))


class WallErrors(unittest.TestCase):

    @skipIfMissingFeatures("LENNARD_JONES")
    def test_penetration_error(self):
        s = make_system()
        w = s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=1.0), particle_type=1)
        s.non_bonded_inter[1, 0].lennard_jones.set_params(
            epsilon=1.0, sigma=1.0, cutoff=RC_WCA, shift="auto")
        s.part.add(id=0, pos=[1, 1, 4.0], type=0)
        p = s.part.add(id=7, pos=[1, 1, 0.5], type=0)
        with self.assertRaises(RuntimeError) as cm:
            s.integrator.run(1)
        msg = str(cm.exception)
        self.assertIn("particle 7", msg)
        self.assertIn(f"wall {w._id}", msg)
        # consistent state: move it out and continue
        p.pos = [1, 1, 2.5]
        s.integrator.run(2)
        self.assertTrue(np.all(np.isfinite(s.part.all().pos)))

    @skipIfMissingFeatures("LENNARD_JONES")
    def test_no_interaction_through_open_boundary(self):
        """Pairs across z = 0 / z = L interact only with periodic z."""
        for periodic_z, expect_force in ((True, True), (False, False)):
            s = make_system(L=(5.0, 5.0, 6.0), periodic_z=periodic_z)
            s.non_bonded_inter[0, 0].lennard_jones.set_params(
                epsilon=1.0, sigma=1.0, cutoff=RC_WCA, shift="auto")
            p = s.part.add(pos=[[1, 1, 0.3], [1, 1, 5.7]], type=[0, 0])
            s.integrator.run(0)
            if expect_force:
                np.testing.assert_allclose(p[0].f, [0, 0, wca_force(0.6)], rtol=1e-12)
            else:
                np.testing.assert_array_equal(p.f, np.zeros((2, 3)))
                self.assertEqual(s.analysis.energy()["non_bonded"], 0.0)

    def test_open_axis_not_folded(self):
        s = make_system(L=(5.0, 5.0, 6.0))
        np.testing.assert_array_equal(s.periodicity, [True, True, False])
        p = s.part.add(pos=[6.5, 1.0, 6.5], type=0)
        s.integrator.run(0)
        np.testing.assert_allclose(p.pos_folded, [1.5, 1.0, 6.5])

    def test_bad_input(self):
        for normal in ([0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0], [1, 0]):
            with self.assertRaises(ValueError):
                Wall(normal=normal, dist=0.0)
        with self.assertRaises(ValueError):
            Wall(normal=[0, 0, 1], dist=np.nan)
        s = make_system()
        with self.assertRaisesRegex(ValueError, "velocity"):
            s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0), particle_type=1,
                              velocity=[0.1, 0.0, 0.2])
        with self.assertRaisesRegex(ValueError, "velocity"):
            s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0), particle_type=1,
                              velocity=[np.nan, 0.0, 0.0])
        with self.assertRaisesRegex(ValueError, "particle_type"):
            s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0), particle_type=-1)
        with self.assertRaisesRegex(ValueError, "particle_type"):
            s.constraints.add(shape=Wall(normal=[0, 0, 1], dist=0.0))
        with self.assertRaisesRegex(ValueError, "shape"):
            s.constraints.add(shape=None, particle_type=1)
        with self.assertRaisesRegex(ValueError, "colour"):
            s.constraints.add(shape=Wall(), particle_type=1, colour=2)
        # the script interface validates on its own (not only marble.shapes.Wall)
        for normal in ([0, 0, 0], [np.nan, 0, 1], [np.inf, 0, 0]):
            with self.assertRaisesRegex(ValueError, "normal"):
                s._core.add_wall(normal, 0.0, 1, None)
        with self.assertRaisesRegex(ValueError, "dist"):
            s._core.add_wall([0, 0, 1], np.nan, 1, None)
        self.assertEqual(len(s.constraints), 0)
        with self.assertRaises(ValueError):
            s.periodicity = [True, True]
        with self.assertRaises(ValueError):
            s.periodicity = [True, True, 2]

    @skipIfMissingFeatures("TUNABLE_SLIP")
    def test_bad_slip_params(self):
        s = make_system()
        ts = s.non_bonded_inter[1, 0].tunable_slip
        for kw, name in (({"gamma": -1.0, "r_cut": 1.0}, "gamma"),
                         ({"gamma": np.nan, "r_cut": 1.0}, "gamma"),
                         ({"gamma": 1.0, "r_cut": 0.0}, "r_cut"),
                         ({"gamma": 1.0, "r_cut": -1.0}, "r_cut"),
                         ({"gamma": 1.0, "r_cut": np.inf}, "r_cut"),
                         ({"gamma": 1.0, "r_cut": 1.0, "offset": -0.1}, "offset"),
                         ({"gamma": 1.0}, "r_cut"),
                         ({"r_cut": 1.0}, "gamma"),
                         ({"gamma": 1.0, "r_cut": 1.0, "z_c": 1.0}, "z_c")):
            with self.assertRaisesRegex(ValueError, name):
                ts.set_params(**kw)
        self.assertEqual(ts.get_params(), {})
        ts.set_params(gamma=0.0, r_cut=1.0)  # gamma = 0 is allowed (full slip)
        self.assertEqual(ts.get_params()["gamma"], 0.0)
        ts.deactivate()
        self.assertEqual(ts.get_params(), {})

    def test_features_error_without_tunable_slip(self):
        if marble.has_features("TUNABLE_SLIP"):
            self.skipTest("TUNABLE_SLIP is compiled in (only testable in a minimal build)")
        s = make_system()
        with self.assertRaises(marble.FeaturesError):
            s.non_bonded_inter[1, 0].tunable_slip.set_params(gamma=1.0, r_cut=1.0)


if __name__ == "__main__":
    unittest.main()
