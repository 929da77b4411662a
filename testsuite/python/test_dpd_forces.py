# labels: python
"""DPD pair forces against an independent Python implementation of
reference.md section 1 (incl. the Philox4x32-10 pair noise), to 1e-11 relative:
both weight functions, k != 1, transverse part, pairs across the periodic
boundary, exact antisymmetry, DPD_MASS_* factors, momentum conservation."""
import itertools
import unittest

import numpy as np

import marble

if not marble.has_features("DPD"):
    raise unittest.SkipTest("missing feature DPD")
from unittest_decorators import skipIfMissingFeatures

from reference_noise import SALT_DPD, pair_uniform3


def noise(seed, counter, a, b):
    """Uniform 3-vector in (-1/2, 1/2) of the unordered pair (a, b), sign by id order."""
    a, b = int(a), int(b)
    lo, hi = min(a, b), max(a, b)
    xi = pair_uniform3(seed, SALT_DPD, counter, lo, hi)
    return xi if a < b else -xi


def weight(wf, k, rc, r):
    if r >= rc:
        return 0.0
    return 1.0 if wf == 0 else 1.0 - (r / rc) ** k


def mass_factor(mi, mj):
    if marble.has_features("DPD_MASS_RED"):
        return 2.0 * mi * mj / (mi + mj)
    if marble.has_features("DPD_MASS_LIN"):
        return 0.5 * (mi + mj)
    return 1.0


def ref_force(prm, d, v, xi, kT, dt, mfac=1.0):
    """reference.md section 1: F_i for d = r_i - r_j, v = v_i - v_j."""
    r = np.linalg.norm(d)
    e = d / r
    P = np.outer(e, e)
    out = np.zeros(3)
    parts = [("", P)]
    if prm.get("trans_gamma", 0.0) > 0.0:
        parts.append(("trans_", np.eye(3) - P))
    for pre, proj in parts:
        g = prm.get(pre + "gamma", 0.0)
        w = weight(prm.get(pre + "weight_function", 0), prm.get("k", 1.0),
                   prm.get(pre + "r_cut", 0.0), r)
        s = np.sqrt(24.0 * kT * g / dt)
        out += proj @ (-g * mfac * w * w * v + s * np.sqrt(mfac) * w * xi)
    return out


def make_system(L=5.0, dt=0.01):
    s = marble.System(box_l=[L, L, L])
    s.time_step = dt
    s.cell_system.skin = 0.3
    return s


PARAM_SETS = [
    dict(weight_function=0, gamma=1.7, r_cut=1.1),
    dict(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0),
    dict(weight_function=1, gamma=2.5, k=0.5, r_cut=1.2),
    dict(weight_function=1, gamma=3.0, k=2.25, r_cut=0.9),
]
TRANS_SETS = [
    dict(weight_function=1, gamma=2.0, k=1.5, r_cut=1.0,
         trans_weight_function=0, trans_gamma=3.3, trans_r_cut=0.8),
    dict(weight_function=0, gamma=0.7, r_cut=0.95,
         trans_weight_function=1, trans_gamma=1.9, trans_r_cut=1.15),
    dict(trans_weight_function=1, trans_gamma=1.1, trans_r_cut=1.0, k=3.0),
]


class DPDForces(unittest.TestCase):
    rng = np.random.default_rng(2024)

    def pair_check(self, prm, kT, x1, x2, v1, v2, m=(1.0, 1.0), seed=17, counter=5,
                   ids=(3, 8)):
        L = 5.0
        dt = 0.013
        s = make_system(L, dt)
        mkw = [{}, {}] if m == (1.0, 1.0) else [{"mass": m[0]}, {"mass": m[1]}]
        p1 = s.part.add(id=ids[0], pos=x1, v=v1, **mkw[0])
        p2 = s.part.add(id=ids[1], pos=x2, v=v2, **mkw[1])
        s.non_bonded_inter[0, 0].dpd.set_params(**prm)
        s.thermostat.set_dpd(kT=kT, seed=seed)
        s.thermostat.dpd.philox_counter = counter
        s.integrator.run(0)
        d = np.asarray(x1, float) - np.asarray(x2, float)
        d -= L * np.round(d / L)
        xi = noise(seed, counter, ids[0], ids[1])
        f_ref = ref_force(prm, d, np.asarray(v1) - np.asarray(v2), xi, kT, dt,
                          mass_factor(*m))
        f1, f2 = p1.f, p2.f
        scale = max(np.max(np.abs(f_ref)), 1e-300)
        np.testing.assert_allclose(f1, f_ref, rtol=0, atol=1e-11 * scale)
        np.testing.assert_array_equal(f2, -f1)  # exact antisymmetry
        return f1

    def random_pair(self, r, straddle=False):
        e = self.rng.normal(size=3)
        e /= np.linalg.norm(e)
        x2 = self.rng.uniform(1.5, 3.5, size=3)
        if straddle:  # x2 just inside the lower face, x1 across it (folded to the top)
            x2[0] = 0.1
            e[0] = -abs(e[0]) - 0.5
            e /= np.linalg.norm(e)
        x1 = x2 + r * e
        return x1, x2, self.rng.normal(size=3), self.rng.normal(size=3)

    def test_friction_kT0(self):
        for prm, straddle in itertools.product(PARAM_SETS, (False, True)):
            for r in (0.05, 0.37, 0.8):
                with self.subTest(prm=prm, r=r, straddle=straddle):
                    f = self.pair_check(prm, 0.0, *self.random_pair(r, straddle))
                    self.assertGreater(np.linalg.norm(f), 0.0)

    def test_beyond_cutoff(self):
        for prm in PARAM_SETS:
            x1, x2, v1, v2 = self.random_pair(prm["r_cut"] + 0.01)
            f = self.pair_check(prm, 1.0, x1, x2, v1, v2)
            np.testing.assert_array_equal(f, 0.0)

    def test_with_noise(self):
        for prm, straddle in itertools.product(PARAM_SETS, (False, True)):
            with self.subTest(prm=prm, straddle=straddle):
                self.pair_check(prm, 1.3, *self.random_pair(0.6, straddle), seed=99, counter=123)
        # noise only (v = 0): the prefactor sqrt(24 kT gamma / dt) alone
        x1, x2, _, _ = self.random_pair(0.5)
        self.pair_check(PARAM_SETS[1], 2.0, x1, x2, np.zeros(3), np.zeros(3))
        # id order reversed: same unordered-pair noise, sign by id order
        self.pair_check(PARAM_SETS[1], 2.0, x1, x2, np.zeros(3), np.zeros(3), ids=(8, 3))

    @skipIfMissingFeatures("TRANS_DPD")
    def test_transverse(self):
        for prm, straddle in itertools.product(TRANS_SETS, (False, True)):
            for kT in (0.0, 1.1):
                for r in (0.3, 0.85, 1.05):
                    with self.subTest(prm=prm, kT=kT, r=r, straddle=straddle):
                        self.pair_check(prm, kT, *self.random_pair(r, straddle))
        # pure transverse friction is orthogonal to d
        x1, x2, v1, v2 = self.random_pair(0.5)
        f = self.pair_check(TRANS_SETS[2], 0.0, x1, x2, v1, v2)
        self.assertLess(abs(np.dot(f, x1 - x2)), 1e-13 * np.linalg.norm(f))

    @skipIfMissingFeatures("MASS")
    def test_mass_factor(self):
        """gamma -> gamma M_ij, s -> s sqrt(M_ij) with DPD_MASS_*, unchanged otherwise."""
        prm = TRANS_SETS[0] if marble.has_features("TRANS_DPD") else PARAM_SETS[1]
        for kT in (0.0, 1.0):
            x1, x2, v1, v2 = self.random_pair(0.55)
            f_unit = self.pair_check(prm, kT, x1, x2, v1, v2)
            f_m = self.pair_check(prm, kT, x1, x2, v1, v2, m=(0.7, 3.1))
            if kT == 0.0:
                np.testing.assert_allclose(f_m, mass_factor(0.7, 3.1) * f_unit,
                                           rtol=1e-12, atol=0)
        if marble.has_features("DPD_MASS_RED"):
            self.assertAlmostEqual(mass_factor(0.7, 3.1), 2 * 0.7 * 3.1 / 3.8)
        elif marble.has_features("DPD_MASS_LIN"):
            self.assertAlmostEqual(mass_factor(0.7, 3.1), 1.9)

    def test_many_particles(self):
        """Every force of a random 150-particle system (pairs across all faces,
        ghosts, Verlet list) equals the brute-force O(N^2) reference."""
        L, N, dt, kT, seed, counter = 3.2, 150, 0.01, 1.4, 5, 77
        prm = TRANS_SETS[0] if marble.has_features("TRANS_DPD") else PARAM_SETS[2]
        rc = max(prm.get("r_cut", 0), prm.get("trans_r_cut", 0))
        rng = np.random.default_rng(7)
        s = make_system(L, dt)
        pos = rng.uniform(0, L, size=(N, 3))
        vel = rng.normal(size=(N, 3))
        ids = rng.permutation(1000)[:N]  # arbitrary, non-contiguous ids
        mass = rng.uniform(0.5, 2.0, size=N) if marble.has_features("MASS") else np.ones(N)
        for i in range(N):
            kw = {"mass": mass[i]} if marble.has_features("MASS") else {}
            s.part.add(id=int(ids[i]), pos=pos[i], v=vel[i], **kw)
        s.non_bonded_inter[0, 0].dpd.set_params(**prm)
        s.thermostat.set_dpd(kT=kT, seed=seed)
        s.thermostat.dpd.philox_counter = counter
        s.integrator.run(0)
        f_ref = np.zeros((N, 3))
        for i in range(N):
            for j in range(i + 1, N):
                d = pos[i] - pos[j]
                d -= L * np.round(d / L)
                if np.linalg.norm(d) >= rc:
                    continue
                f = ref_force(prm, d, vel[i] - vel[j], noise(seed, counter, ids[i], ids[j]),
                              kT, dt, mass_factor(mass[i], mass[j]))
                f_ref[i] += f
                f_ref[j] -= f
        f = s.part.by_ids(ids).f
        np.testing.assert_allclose(f, f_ref, rtol=0, atol=1e-11 * np.max(np.abs(f_ref)))
        self.assertLess(np.max(np.abs(f.sum(axis=0))), 1e-12 * np.max(np.abs(f)) * N)

    def test_momentum_conservation(self):
        """Pair forces are exactly antisymmetric: total momentum stays constant
        (to round-off) over a thermostatted run, also with unequal masses."""
        L, N = 4.0, 192
        rng = np.random.default_rng(11)
        s = make_system(L, 0.01)
        has_mass = marble.has_features("MASS")
        kw = {"mass": rng.choice([0.5, 1.0, 4.0], size=N)} if has_mass else {}
        s.part.add(pos=rng.uniform(0, L, size=(N, 3)), v=rng.normal(size=(N, 3)), **kw)
        prm = TRANS_SETS[0] if marble.has_features("TRANS_DPD") else PARAM_SETS[1]
        s.non_bonded_inter[0, 0].dpd.set_params(**prm)
        if marble.has_features("HAT"):
            s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        s.thermostat.set_dpd(kT=1.0, seed=3)
        p0 = np.array(s.analysis.linear_momentum())
        for _ in range(5):
            s.integrator.run(100)
            dp = np.array(s.analysis.linear_momentum()) - p0
            self.assertLess(np.max(np.abs(dp)), 1e-12, dp)  # |p| ~ 40, sum |m v| ~ 400


if __name__ == "__main__":
    unittest.main()
