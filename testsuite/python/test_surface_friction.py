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
per tangential direction; its virial in dpd_stress(); the shared-shell
option (a bead inside the shells of n colloids: gamma, gamma/n or nothing per
pair) against numpy with noise, with conservation and the virial; bad input."""
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

    # -- shared shells (option shared) ---------------------------------------------
    SH_PRM = dict(gamma=45.0, r_cut=0.4, a1=1.0, a2=0.0)

    def shared_scene(self, shared, kT, shardlow=False, L=12.0):
        """Three colloids (R = 1) with gaps 0.3 and beads in 0, 1, 2 and 3 shells."""
        rng = np.random.default_rng(5)
        s = marble.System(box_l=[L] * 3)
        s.time_step = DT
        c = np.array([[5.0, 5.0, 5.0], [7.3, 5.0, 5.0], [6.15, 5.0 + 2.3 * np.sqrt(0.75), 5.0]])
        for x in c:
            s.part.add(pos=x, type=1, mass=4.0, rotation=[True] * 3, rinertia=[1.6] * 3,
                       v=0.3 * rng.normal(size=3), omega_lab=rng.normal(size=3))
        centre = c.mean(axis=0)
        beads = [centre + [0, 0, 0.1],                 # in the three shells
                 0.5 * (c[0] + c[1]) + [0, -0.05, 0.2],  # between two colloids
                 0.5 * (c[1] + c[2]) + [0.05, 0, -0.3],
                 c[0] + [-1.2, 0.1, 0.0],               # one shell
                 c[2] + [0.0, 1.1, 0.2],
                 c[1] + [0.3, -0.2, 1.1],
                 c[0] + [0.0, -2.0, 0.0]]               # none
        for b in beads:
            s.part.add(pos=b, type=0, v=rng.normal(size=3))
        s.non_bonded_inter[1, 0].surface_friction.set_params(**self.SH_PRM, shared=shared)
        s.thermostat.set_dpd(kT=kT, seed=SEED)
        s.thermostat.dpd.philox_counter = COUNTER
        if shardlow:
            s.integrator.set_shardlow()
        return s

    @staticmethod
    def ref_shared(s, shared, kT):
        """Forces and torques of the scene by numpy: n shells per bead, gamma s(n)."""
        p = s.part.all()
        x, v, w = np.asarray(p.pos), np.asarray(p.v), np.asarray(p.omega_lab)
        ids, typ = np.asarray(p.id), np.asarray(p.type)
        prm = SurfaceFriction.SH_PRM
        col, bead = np.where(typ == 1)[0], np.where(typ == 0)[0]
        h = np.linalg.norm(x[col][:, None] - x[bead][None], axis=2) - prm["a1"]
        n = np.sum(h < prm["r_cut"], axis=0)
        f, t = np.zeros_like(x), np.zeros_like(x)
        for a, ci in enumerate(col):
            for b, bi in enumerate(bead):
                if h[a, b] >= prm["r_cut"]:
                    continue
                sc = 1.0 if shared == "full" or n[b] <= 1 else (1.0 / n[b] if shared == "split" else 0.0)
                if sc == 0.0:
                    continue
                sign = 1.0 if ids[ci] < ids[bi] else -1.0
                xi = sign * pair_uniform3(SEED, SALT, COUNTER, min(ids[ci], ids[bi]), max(ids[ci], ids[bi]))
                q = dict(prm, gamma=prm["gamma"] * sc)
                fi, ti, tj = ref_force(q, x[ci] - x[bi], v[ci] - v[bi], w[ci], w[bi], xi, kT, DT)
                f[ci] += fi
                f[bi] -= fi
                t[ci] += ti
                t[bi] += tj
        return f, t, n

    def test_shared_force_and_torque(self):
        for shared, kT in itertools.product(("full", "split", "off"), (0.0, 0.4)):
            with self.subTest(shared=shared, kT=kT):
                s = self.shared_scene(shared, kT)
                s.integrator.run(0)
                f, t, n = self.ref_shared(s, shared, kT)
                self.assertEqual(sorted(n.tolist()), [0, 1, 1, 1, 2, 2, 3])
                p = s.part.all()
                scale = np.max(np.abs(f))
                np.testing.assert_allclose(p.f, f, rtol=0, atol=1e-12 * scale)
                np.testing.assert_allclose(p.torque_lab, t, rtol=0, atol=1e-12 * np.max(np.abs(t)))
                self.assertEqual(s.non_bonded_inter[1, 0].surface_friction.get_params()["shared"], shared)
                if shared == "off":  # the beads in 2 and 3 shells feel nothing
                    np.testing.assert_array_equal(np.asarray(p.f)[3:6], 0.0)
                # the virial of the scaled pairs
                st = s.analysis.dpd_stress_split()
                tot = np.asarray(st["friction"]) + np.asarray(st["noise"])
                x = np.asarray(p.pos)  # sum over pairs (x_c - x_b) (x) F_cb = sum_k x_k (x) f_k
                vir = np.einsum("ka,kb->ab", x, f) / s.volume()
                np.testing.assert_allclose(tot.reshape(3, 3), vir, rtol=0, atol=1e-12 * np.max(np.abs(vir)))
        # "full" is the kernel without the option
        s = self.shared_scene("full", 0.4)
        s.non_bonded_inter[1, 0].surface_friction.set_params(**self.SH_PRM)
        self.assertEqual(s.non_bonded_inter[1, 0].surface_friction.get_params()["shared"], "full")

    def test_shared_conservation(self):
        """split and off with noise, VV and Shardlow: P and L to 1e-12 over 300 steps."""
        for shared, shardlow in itertools.product(("split", "off"), (False, True)):
            with self.subTest(shared=shared, shardlow=shardlow):
                s = self.shared_scene(shared, 1.0, shardlow=shardlow, L=30.0)
                s.time_step = 0.002
                p = s.part.all()

                def momenta():
                    m = np.asarray(p.mass)[:, None]
                    x, v = np.asarray(p.pos), np.asarray(p.v)
                    return np.sum(m * v, axis=0), (np.sum(np.cross(x, m * v), axis=0)
                                                   + np.sum(np.asarray(p.rinertia) * np.asarray(p.omega_lab), axis=0))
                P0, L0 = momenta()
                w0 = np.asarray(p.omega_lab).copy()
                s.integrator.run(300)
                P1, L1 = momenta()
                self.assertGreater(np.max(np.abs(np.asarray(p.omega_lab) - w0)), 1e-2)
                np.testing.assert_allclose(P1, P0, rtol=0, atol=1e-12)
                np.testing.assert_allclose(L1, L0, rtol=0, atol=1e-12 * max(1.0, np.max(np.abs(L0))))

    def test_shared_shardlow_step(self):
        """Shardlow at kT = 0: a bead only in shells with "off" keeps its velocity."""
        s = self.shared_scene("off", 0.0, shardlow=True)
        p = s.part.all()
        v0 = np.asarray(p.v).copy()
        s.integrator.run(1)
        v1 = np.asarray(p.v)
        np.testing.assert_allclose(v1[3:6], v0[3:6], rtol=0, atol=1e-12)
        self.assertGreater(np.max(np.abs(v1[6:9] - v0[6:9])), 1e-3)

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
        with self.assertRaisesRegex(ValueError, "shared"):
            ia[1, 0].surface_friction.set_params(gamma=1.0, r_cut=0.3, a1=1.0, shared="half")
        self.assertEqual(ia[1, 0].surface_friction.get_params(), {})
        import marble.suspensions as sus
        for kw, key in ((dict(boundary="stick", shared="half"), "shared"),
                        (dict(boundary="stick", stick_shell=0.0), "stick_shell"),
                        (dict(shared="off"), "shared"), (dict(stick_shell=0.1), "stick_shell")):
            s2 = marble.System(box_l=[6] * 3)
            with self.assertRaisesRegex(ValueError, key):
                sus.setup_suspension(s2, phi=0.05, radius=1.0, seed=1, **kw)
            self.assertEqual(len(s2.part.all()), 0)


if __name__ == "__main__":
    unittest.main()
