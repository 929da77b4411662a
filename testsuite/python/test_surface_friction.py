# labels: python
"""The stick (tangential) surface friction between rotating spheres
(nonbonded/surface_friction.hpp, doc/suspensions.md section 7c): force and
torques against an independent numpy implementation (friction, spins and the
counter-based noise of reference_noise.py) to 1e-12 at several gaps, for a
colloid with a bead (lever 1), two unequal colloids (levers a_i/(a_i + a_j)),
both orders of the types and of the ids; nothing along e; zero from the
cutoff on; momentum and angular momentum (sum r x p + I omega, about the
origin) conserved to 1e-12 with noise under velocity Verlet and Shardlow; the
dissipated power F . u <= 0 at kT = 0; the noise variance 2 kT gamma w^2/dt
per tangential direction; its virial in dpd_stress(); bad input."""
import itertools
import unittest

import numpy as np

import marble
from reference_noise import pair_uniform3
from unittest_decorators import skipIfMissingFeatures

SALT = 20  # RNGSalt::surface_friction
DT = 0.004
SEED, COUNTER = 5, 11


def ref_force(prm, d, vij, wi, wj, xi, kT, dt):
    """F_i, T_i, T_j of the pair (a1 the radius of i)."""
    r = np.linalg.norm(d)
    h = r - prm["a1"] - prm["a2"]
    if h >= prm["r_cut"]:
        return np.zeros(3), np.zeros(3), np.zeros(3)
    w = 1 - max(h, 0) / prm["r_cut"]
    s = prm["a1"] + prm["a2"]
    li, lj = (prm["a1"] / s, prm["a2"] / s) if s > 0 else (0.5, 0.5)
    e = d / r
    u = vij - np.cross(li * wi + lj * wj, d)
    g = -prm["gamma"] * w * w * u + np.sqrt(24 * kT * prm["gamma"] / dt) * w * xi
    f = g - (e @ g) * e
    return f, -li * np.cross(d, f), -lj * np.cross(d, f)


def make_pair(prm, kT, x1, x2, v1, v2, w1, w2, types=(1, 0), ids=(3, 8), inertia=(2.0, 0.7), L=12.0):
    s = marble.System(box_l=[L] * 3)
    s.time_step = DT
    p1 = s.part.add(id=ids[0], pos=x1, v=v1, type=types[0], rotation=[True] * 3, rinertia=[inertia[0]] * 3,
                    omega_lab=w1, mass=3.0)
    p2 = s.part.add(id=ids[1], pos=x2, v=v2, type=types[1], rotation=[True] * 3, rinertia=[inertia[1]] * 3,
                    omega_lab=w2)
    # a1 belongs to the first type of the index
    s.non_bonded_inter[types[0], types[1]].surface_friction.set_params(**prm)
    s.thermostat.set_dpd(kT=kT, seed=SEED)
    s.thermostat.dpd.philox_counter = COUNTER
    s.integrator.run(0)
    return s, p1, p2


PARAMS = [dict(gamma=45.0, r_cut=0.26, a1=1.0, a2=0.0),   # seed 004 colloid R = 1, bead
          dict(gamma=3.0, r_cut=0.6, a1=1.5, a2=0.5),     # two unequal spheres
          dict(gamma=1.0, r_cut=1.0)]                     # two points (levers 1/2)


@skipIfMissingFeatures("TRANS_DPD", "ROTATION", "MASS")
class SurfaceFriction(unittest.TestCase):
    rng = np.random.default_rng(17)

    def check(self, prm, h, kT, ids=(3, 8), swap_types=False):
        e = self.rng.normal(size=3)
        e /= np.linalg.norm(e)
        x2 = np.array([5.0, 6.0, 5.5])
        x1 = x2 + (prm.get("a1", 0) + prm.get("a2", 0) + h) * e
        v1, v2, w1, w2 = (self.rng.normal(size=3) for _ in range(4))
        if swap_types:
            # the same physical pair, set as non_bonded_inter[0, 1] with the radii swapped
            q = dict(prm, a1=prm.get("a2", 0), a2=prm.get("a1", 0))
            s, p1, p2 = make_pair(q, kT, x1, x2, v1, v2, w1, w2, types=(0, 1), ids=ids)
            p1.type, p2.type = 1, 0
            s.integrator.run(0, recalc_forces=True)
        else:
            s, p1, p2 = make_pair(prm, kT, x1, x2, v1, v2, w1, w2, ids=ids)
        sign = 1.0 if ids[0] < ids[1] else -1.0
        xi = sign * pair_uniform3(SEED, SALT, COUNTER, min(ids), max(ids))
        full = {"a1": 0.0, "a2": 0.0, **prm}
        f, ti, tj = ref_force(full, x1 - x2, v1 - v2, w1, w2, xi, kT, DT)
        scale = max(np.max(np.abs(f)), 1e-300)
        np.testing.assert_allclose(p1.f, f, rtol=0, atol=1e-12 * scale)
        np.testing.assert_array_equal(p2.f, -p1.f)
        tscale = max(np.max(np.abs(ti)), np.max(np.abs(tj)), 1e-300)
        np.testing.assert_allclose(p1.torque_lab, ti, rtol=0, atol=1e-12 * tscale)
        np.testing.assert_allclose(p2.torque_lab, tj, rtol=0, atol=1e-12 * tscale)
        return np.asarray(p1.f), e

    def test_force_and_torque(self):
        for prm, kT in itertools.product(PARAMS, (0.0, 0.1, 1.3)):
            for h in (-0.05, 0.0, 0.01, 0.1, 0.25, 0.5, 0.9):
                if h >= prm["r_cut"] or prm.get("a1", 0) + prm.get("a2", 0) + h < 0.005:
                    continue
                with self.subTest(prm=prm, kT=kT, h=h):
                    f, e = self.check(prm, h, kT)
                    self.assertGreater(np.linalg.norm(f), 0.0)
                    self.assertLess(abs(f @ e), 1e-12 * np.linalg.norm(f))  # tangential only
        # id order reversed; the types of the index reversed (mirrored radii)
        self.check(PARAMS[1], 0.2, 1.0, ids=(8, 3))
        for prm in PARAMS[:2]:
            self.check(prm, 0.1, 0.5, swap_types=True)
        self.assertEqual(marble.System(box_l=[5] * 3).non_bonded_inter[1, 0].surface_friction.get_params(), {})

    def test_mirrored_params(self):
        s = marble.System(box_l=[5] * 3)
        s.non_bonded_inter[1, 0].surface_friction.set_params(**PARAMS[1])
        self.assertAlmostEqual(s.non_bonded_inter[0, 1].surface_friction.get_params()["a1"], 0.5)
        self.assertAlmostEqual(s.non_bonded_inter[1, 0].surface_friction.get_params()["a1"], 1.5)

    def test_zero_beyond_cutoff(self):
        for prm in PARAMS:
            for h in (prm["r_cut"] + 1e-9, prm["r_cut"] + 0.01, prm["r_cut"] + 0.3):
                f, _ = self.check(prm, h, 1.0)
                np.testing.assert_array_equal(f, 0.0)

    def test_dissipation(self):
        """kT = 0: the power F_i . v_i + F_j . v_j + T_i . w_i + T_j . w_j = F . u <= 0."""
        for prm in PARAMS:
            for _ in range(5):
                x2 = np.array([5.0, 6.0, 5.5])
                e = self.rng.normal(size=3)
                e /= np.linalg.norm(e)
                x1 = x2 + (prm.get("a1", 0) + prm.get("a2", 0) + 0.3 * prm["r_cut"]) * e
                v1, v2, w1, w2 = (self.rng.normal(size=3) for _ in range(4))
                s, p1, p2 = make_pair(prm, 0.0, x1, x2, v1, v2, w1, w2)
                power = p1.f @ v1 + p2.f @ v2 + p1.torque_lab @ w1 + p2.torque_lab @ w2
                self.assertLess(power, 0.0)

    def test_noise_variance(self):
        """v = omega = 0: <F_t^2> = 2 kT gamma w^2/dt per tangential direction (over
        counters; uniform noise), nothing along e. 4000 draws: 5 sigma ~ 7 %."""
        prm, h, kT = PARAMS[0], 0.1, 0.7
        s, p1, p2 = make_pair(prm, kT, [5.0 + 1.1, 6.0, 5.0], [5.0, 6.0, 5.0], *[[0, 0, 0]] * 4)
        f = []
        for c in range(4000):
            s.thermostat.dpd.philox_counter = c
            s.integrator.run(0, recalc_forces=True)
            f.append(p1.f)
        f = np.array(f)
        np.testing.assert_array_equal(f[:, 0], 0.0)
        w = 1 - h / prm["r_cut"]
        want = 2 * kT * prm["gamma"] * w * w / DT
        for k in (1, 2):
            self.assertLess(abs(np.mean(f[:, k] ** 2) / want - 1), 5 * np.sqrt(0.8 / len(f)))

    def conservation(self, shardlow):
        """Colloids of two radii and beads in a box large enough that nothing
        crosses the boundary: P and L = sum m r x v + I omega (about the origin)."""
        L = 40.0
        rng = np.random.default_rng(12)
        s = marble.System(box_l=[L] * 3)
        s.time_step = 0.005
        centres = np.array([[18.0, 18.0, 18.0], [22.0, 18.5, 19.0], [19.0, 22.0, 21.0]])
        radii = [1.0, 1.0, 1.5]
        types = [1, 1, 2]
        for c, a, t in zip(centres, radii, types):
            s.part.add(pos=c, type=t, mass=5.0 * a ** 3, rotation=[True] * 3, rinertia=[2.0 * a ** 5] * 3,
                       v=0.3 * rng.normal(size=3), omega_lab=rng.normal(size=3))
            # beads in the colloid's shell
            n = rng.normal(size=(25, 3))
            n /= np.linalg.norm(n, axis=1)[:, None]
            s.part.add(pos=c + (a + 0.3 * rng.random((25, 1))) * n, type=0, v=rng.normal(size=(25, 3)))
        ia = s.non_bonded_inter
        ia[1, 0].surface_friction.set_params(gamma=20.0, r_cut=0.4, a1=1.0)
        ia[2, 0].surface_friction.set_params(gamma=10.0, r_cut=0.4, a1=1.5)
        ia[1, 1].surface_friction.set_params(gamma=5.0, r_cut=1.0, a1=1.0, a2=1.0)
        ia[1, 2].surface_friction.set_params(gamma=5.0, r_cut=1.0, a1=1.0, a2=1.5)
        s.thermostat.set_dpd(kT=1.0, seed=3)
        if shardlow:
            s.integrator.set_shardlow()
        p = s.part.all()

        def momenta():
            m = np.asarray(p.mass)[:, None]
            x, v = np.asarray(p.pos), np.asarray(p.v)
            lin = np.sum(m * v, axis=0)
            ang = np.sum(np.cross(x, m * v), axis=0) + np.sum(np.asarray(p.rinertia) * np.asarray(p.omega_lab), axis=0)
            return lin, ang

        P0, L0 = momenta()
        w0 = np.asarray(p.omega_lab).copy()
        s.integrator.run(300)
        P1, L1 = momenta()
        self.assertGreater(np.max(np.abs(np.asarray(p.omega_lab) - w0)), 1e-2)  # torques acted
        np.testing.assert_allclose(P1, P0, rtol=0, atol=1e-12)
        np.testing.assert_allclose(L1, L0, rtol=0, atol=1e-12 * max(1.0, np.max(np.abs(L0))))

    def test_conservation_vv(self):
        self.conservation(False)

    def test_conservation_shardlow(self):
        self.conservation(True)

    def test_dpd_stress(self):
        """dpd_stress() adds sum d (x) F_i / V of the friction and the noise."""
        prm, kT = PARAMS[0], 0.3
        x1, x2 = np.array([5.0, 6.0, 5.5]), np.array([5.0, 6.0, 5.5]) + np.array([0.6, 0.7, 0.4])
        v1, v2, w1, w2 = (self.rng.normal(size=3) for _ in range(4))
        s, p1, p2 = make_pair(prm, kT, x1, x2, v1, v2, w1, w2)
        st = s.analysis.dpd_stress_split()
        d = x1 - x2
        xi = pair_uniform3(SEED, SALT, COUNTER, 3, 8)
        ff, _, _ = ref_force(prm, d, v1 - v2, w1, w2, 0 * xi, kT, DT)
        fn, _, _ = ref_force(prm, d, 0 * v1, 0 * w1, 0 * w2, xi, kT, DT)
        V = 12.0 ** 3
        fric = np.asarray(st["friction"]).reshape(3, 3)
        noise = np.asarray(st["noise"]).reshape(3, 3)
        np.testing.assert_allclose(fric, np.outer(d, ff) / V, rtol=0, atol=1e-12 * np.max(np.abs(ff)) / V)
        np.testing.assert_allclose(noise, np.outer(d, fn) / V, rtol=0, atol=1e-12 * np.max(np.abs(fn)) / V)

    def test_bad_input(self):
        s = marble.System(box_l=[5] * 3)
        ia = s.non_bonded_inter
        for kw, key in ((dict(gamma=-1.0, r_cut=0.3), "gamma"), (dict(gamma=1.0, r_cut=0.0), "r_cut"),
                        (dict(gamma=1.0, r_cut=0.3, a1=-1.0), "a1"), (dict(gamma=1.0), "r_cut")):
            with self.assertRaisesRegex(ValueError, key):
                ia[1, 0].surface_friction.set_params(**kw)
        with self.assertRaisesRegex(ValueError, "a1 == a2"):
            ia[1, 1].surface_friction.set_params(gamma=1.0, r_cut=0.3, a1=1.0, a2=0.5)
        self.assertEqual(ia[1, 1].surface_friction.get_params(), {})


if __name__ == "__main__":
    unittest.main()
