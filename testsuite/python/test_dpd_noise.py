# labels: python
"""DPD noise: reproducible (same seed -> bit-identical trajectory), different for
another seed or another step, independent of particle insertion order and of
which particle of a pair the loop sees first; variance of the pair noise force
2 kT gamma w^2 / dt (chi^2 bound)."""
import unittest

import numpy as np

import marble

if not marble.has_features("DPD"):
    raise unittest.SkipTest("missing feature DPD")
from test_dpd_forces import noise

L = 4.0
N = 150
PRM = dict(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)


def make(seed=42, order=None, counter=0):
    rng = np.random.default_rng(5)
    pos = rng.uniform(0, L, size=(N, 3))
    vel = rng.normal(size=(N, 3))
    ids = np.arange(N)
    if order is not None:
        pos, vel, ids = pos[order], vel[order], ids[order]
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.cell_system.skin = 0.3
    for p, v, i in zip(pos, vel, ids):  # one by one: insertion order matters to the store
        s.part.add(id=int(i), pos=p, v=v)
    s.non_bonded_inter[0, 0].dpd.set_params(**PRM)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    s.thermostat.dpd.philox_counter = counter
    return s


def state(s):
    p = s.part.all()  # ascending id order
    return p.pos, p.v, p.f


class DPDNoise(unittest.TestCase):

    def test_same_seed_same_trajectory(self):
        a, b = make(), make()
        a.integrator.run(200)
        b.integrator.run(120)
        b.integrator.run(80)  # split runs continue the same stream
        for x, y in zip(state(a), state(b)):
            np.testing.assert_array_equal(x, y)

    def test_other_seed_or_step_differs(self):
        a, b, c = make(), make(seed=43), make(counter=1000)
        for s in (a, b, c):
            s.integrator.run(0)
        fa, fb, fc = (state(s)[2] for s in (a, b, c))
        self.assertGreater(np.abs(fa - fb).max(), 1.0)
        self.assertGreater(np.abs(fa - fc).max(), 1.0)
        for s in (a, b, c):
            s.integrator.run(50)
        self.assertGreater(np.abs(state(a)[0] - state(b)[0]).max(), 1e-3)
        self.assertGreater(np.abs(state(a)[0] - state(c)[0]).max(), 1e-3)
        # consecutive steps draw independent noise: correlation of successive forces ~ 0
        a.part.all().v = np.zeros((N, 3))
        forces = []
        for _ in range(2):
            a.integrator.run(0)
            forces.append(state(a)[2].ravel())
            a.thermostat.dpd.philox_counter += 1
        r = np.corrcoef(forces[0], forces[1])[0, 1]
        self.assertLess(abs(r), 5.0 / np.sqrt(forces[0].size))

    def test_insertion_order(self):
        """Shuffled insertion (other storage and loop order): same forces up to the
        summation order, and the same trajectory up to round-off."""
        a = make()
        b = make(order=np.random.default_rng(9).permutation(N))
        a.integrator.run(0)
        b.integrator.run(0)
        fa, fb = state(a)[2], state(b)[2]
        np.testing.assert_allclose(fb, fa, rtol=0, atol=1e-12 * np.abs(fa).max())
        a.integrator.run(30)
        b.integrator.run(30)
        np.testing.assert_allclose(state(b)[0], state(a)[0], rtol=0, atol=1e-9)

    def test_pair_noise_is_unordered(self):
        """Swapping the ids of the two particles of a pair: the force on the particle
        at each position is unchanged up to the id-order sign: F_i(ids a, b) uses
        xi(min, max) * sign(b - a)."""
        forces = []
        for ids in ((2, 9), (9, 2)):
            s = marble.System(box_l=[L, L, L])
            s.time_step = 0.01
            s.part.add(id=ids[0], pos=[1.0, 1.0, 1.0])
            s.part.add(id=ids[1], pos=[1.4, 1.3, 0.9])
            s.non_bonded_inter[0, 0].dpd.set_params(**PRM)
            s.thermostat.set_dpd(kT=1.0, seed=4)
            s.integrator.run(0)
            forces.append(s.part.by_id(ids[0]).f)
        np.testing.assert_array_equal(forces[0], -forces[1])
        np.testing.assert_array_equal(np.sign(forces[0]), np.sign(
            np.outer([-0.4, -0.3, 0.1], [-0.4, -0.3, 0.1]) @ noise(4, 0, 2, 9)))

    def test_noise_variance(self):
        """A pair at rest, along x: F_x = s w xi_x with var 2 kT gamma w^2 / dt
        (s = sqrt(24 kT gamma / dt), var xi = 1/12). Sample variance over M counters
        against its chi^2 bound (5 sigma); F_y = F_z = 0."""
        kT, gamma, dt, r, M = 1.7, 3.0, 0.02, 0.4, 4000
        s = marble.System(box_l=[L, L, L])
        s.time_step = dt
        s.part.add(pos=[[1.0, 1.0, 1.0], [1.0 + r, 1.0, 1.0]])
        s.non_bonded_inter[0, 0].dpd.set_params(**dict(PRM, gamma=gamma))
        s.thermostat.set_dpd(kT=kT, seed=8)
        fx = np.empty(M)
        p0 = s.part.by_id(0)
        for c in range(M):
            s.thermostat.dpd.philox_counter = c
            s.integrator.run(0)
            f = p0.f
            self.assertEqual(f[1], 0.0)
            self.assertEqual(f[2], 0.0)
            fx[c] = f[0]
        w = 1.0 - r
        var = 2.0 * kT * gamma * w**2 / dt
        # uniform noise: var of the sample variance = (mu4 - var^2)/M, mu4 = 9/5 var^2
        self.assertLess(abs(np.var(fx) / var - 1.0), 5.0 * np.sqrt(0.8 / M))
        self.assertLess(abs(np.mean(fx)), 5.0 * np.sqrt(var / M))
        self.assertLessEqual(np.abs(fx).max(), np.sqrt(3.0 * var) + 1e-12)  # bounded support


if __name__ == "__main__":
    unittest.main()
