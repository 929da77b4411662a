# labels: python
"""The Morse kernel (espressomd's morse: eps, alpha, rmin, cutoff; plus an
optional surface offset for seed 004): energy and force of a particle pair
against an independent implementation of the formula at several distances,
force = -dU/dr, zero beyond the cutoff, the energy shift making U continuous
at the cutoff, and momentum conservation in a run."""
import unittest

import numpy as np

import marble
from unittest_decorators import skipIfMissingFeatures


def morse_u(r, eps, alpha, rmin, cutoff, offset=0.0):
    def bare(x):
        return eps * (np.exp(-2 * alpha * (x - rmin)) - 2 * np.exp(-alpha * (x - rmin)))
    x = r - offset
    return bare(x) - bare(cutoff) if x < cutoff else 0.0


def morse_f(r, eps, alpha, rmin, cutoff, offset=0.0):
    x = r - offset
    if x >= cutoff:
        return 0.0
    return 2 * alpha * eps * (np.exp(-2 * alpha * (x - rmin)) - np.exp(-alpha * (x - rmin)))


@skipIfMissingFeatures("MORSE")
class Morse(unittest.TestCase):
    P = dict(eps=1.7, alpha=3.0, rmin=1.1, cutoff=2.2)

    def pair(self, r, **params):
        s = marble.System(box_l=[12.0] * 3)
        s.time_step = 0.01
        s.part.add(pos=[[3.0, 4.0, 5.0], [3.0 + r, 4.0, 5.0]])
        s.non_bonded_inter[0, 0].morse.set_params(**params)
        s.integrator.run(0)
        return s

    def check_pair(self, params):
        for r in (0.8, 1.0, params["rmin"] + params.get("offset", 0.0), 1.6, 2.0, 2.5, 3.5):
            s = self.pair(r, **params)
            u = morse_u(r, **params)
            f = morse_f(r, **params)
            self.assertAlmostEqual(s.analysis.energy()["non_bonded"], u, delta=1e-12 * (1 + abs(u)))
            np.testing.assert_allclose(s.part.by_id(1).f, [f, 0.0, 0.0], rtol=1e-12, atol=1e-12)
            np.testing.assert_allclose(s.part.by_id(0).f, [-f, 0.0, 0.0], rtol=1e-12, atol=1e-12)

    def test_values(self):
        self.check_pair(self.P)

    def test_values_with_offset(self):
        self.check_pair({**self.P, "offset": 0.7})

    def test_force_is_minus_derivative(self):
        h = 1e-6
        for r in np.linspace(0.9, 2.19, 9):
            du = (morse_u(r + h, **self.P) - morse_u(r - h, **self.P)) / (2 * h)
            s = self.pair(r, **self.P)
            self.assertAlmostEqual(s.part.by_id(1).f[0], -du, delta=1e-6 * (1 + abs(du)))

    def test_continuous_at_cutoff_and_zero_beyond(self):
        c = self.P["cutoff"]
        self.assertAlmostEqual(self.pair(c - 1e-9, **self.P).analysis.energy()["non_bonded"], 0.0,
                               delta=1e-8)
        s = self.pair(c + 1e-9, **self.P)
        self.assertEqual(s.analysis.energy()["non_bonded"], 0.0)
        np.testing.assert_array_equal(s.part.by_id(1).f, [0.0, 0.0, 0.0])

    def test_minimum_depth(self):
        # U(rmin) = -eps - U_bare(cutoff), where the force vanishes
        eps, alpha, rmin, c = (self.P[k] for k in ("eps", "alpha", "rmin", "cutoff"))
        u_c = eps * (np.exp(-2 * alpha * (c - rmin)) - 2 * np.exp(-alpha * (c - rmin)))
        s = self.pair(rmin, **self.P)
        self.assertAlmostEqual(s.analysis.energy()["non_bonded"], -eps - u_c, delta=1e-12)
        self.assertAlmostEqual(s.part.by_id(1).f[0], 0.0, delta=1e-12)

    def test_momentum_conserved(self):
        s = marble.System(box_l=[6.0] * 3)
        s.time_step = 0.005
        rng = np.random.default_rng(4)
        grid = np.stack(np.meshgrid(*[np.arange(4) * 1.5] * 3), -1).reshape(-1, 3)
        s.part.add(pos=grid + 0.1 * rng.random(grid.shape), v=rng.normal(size=grid.shape))
        s.non_bonded_inter[0, 0].morse.set_params(**self.P)
        p0 = s.analysis.linear_momentum()
        s.integrator.run(200)
        np.testing.assert_allclose(s.analysis.linear_momentum(), p0, atol=1e-11)


if __name__ == "__main__":
    unittest.main()
