# labels: python
"""The contact kernel (seed 004's contact force, made to grow with overlap;
doc/suspensions.md): force and energy of a pair against an independent
implementation at gaps on both sides of contact, force = -dU/dr, value and
slope continuous at h = 0, zero from h = delta on, the force growing with
overlap (seed 004's f(1 + h) shrinks), and momentum conservation in a run."""
import unittest

import numpy as np

import marble
from unittest_decorators import skipIfMissingFeatures

P = dict(f_contact=50.0, delta=0.2, offset=2.0)


def contact_f(r, f_contact, delta, offset):
    h = r - offset
    if h >= delta:
        return 0.0
    if h >= 0:
        return f_contact * (1 - h / delta) ** 3
    return f_contact * (1 - 3 * h / delta)


def contact_u(r, f_contact, delta, offset):
    h = r - offset
    if h >= delta:
        return 0.0
    if h >= 0:
        return f_contact * delta / 4 * (1 - h / delta) ** 4
    return f_contact * (delta / 4 - h + 1.5 * h * h / delta)


def pair(r, **params):
    s = marble.System(box_l=[12.0] * 3)
    s.time_step = 0.01
    s.part.add(pos=[[3.0, 4.0, 5.0], [3.0 + r, 4.0, 5.0]])
    s.non_bonded_inter[0, 0].contact.set_params(**params)
    s.integrator.run(0)
    return s


@skipIfMissingFeatures("CONTACT")
class Contact(unittest.TestCase):
    GAPS = (-0.3, -0.05, -1e-9, 0.0, 0.03, 0.1, 0.19, 0.2, 0.5)

    def test_values(self):
        for prm in (P, dict(P, offset=0.0), dict(P, delta=0.001, f_contact=1e4)):
            for h in self.GAPS:
                r = prm["offset"] + h * prm["delta"] / 0.2
                if r <= 0:
                    continue
                with self.subTest(prm=prm, h=h):
                    s = pair(r, **prm)
                    r = (3.0 + r) - 3.0  # the distance the engine sees
                    u, f = contact_u(r, **prm), contact_f(r, **prm)
                    self.assertAlmostEqual(s.analysis.energy()["non_bonded"], u,
                                           delta=1e-12 * (1 + abs(u)))
                    np.testing.assert_allclose(s.part.by_id(1).f, [f, 0, 0], rtol=1e-12, atol=1e-12)
                    np.testing.assert_array_equal(s.part.by_id(0).f, -s.part.by_id(1).f)

    def test_force_is_minus_derivative(self):
        eps = 1e-7
        for r in np.linspace(1.6, 2.199, 17):
            du = (contact_u(r + eps, **P) - contact_u(r - eps, **P)) / (2 * eps)
            self.assertAlmostEqual(pair(r, **P).part.by_id(1).f[0], -du,
                                   delta=1e-6 * (1 + abs(du)))

    def test_continuous_at_contact_and_grows_with_overlap(self):
        r0 = P["offset"]
        f = [pair(r0 + dh, **P).part.by_id(1).f[0] for dh in (-1e-8, 0.0, 1e-8)]
        self.assertAlmostEqual(f[0], P["f_contact"], delta=1e-5)
        self.assertAlmostEqual(f[2], P["f_contact"], delta=1e-5)
        # slope -3 f_c / delta on both sides
        for dh in (-1e-6, 1e-6):
            slope = (pair(r0 + dh, **P).part.by_id(1).f[0] - f[1]) / dh
            self.assertAlmostEqual(slope, -3 * P["f_contact"] / P["delta"], delta=1e-2)
        over = [pair(r0 - x, **P).part.by_id(1).f[0] for x in (0.0, 0.1, 0.2, 0.4)]
        self.assertTrue(np.all(np.diff(over) > 0), over)

    def test_zero_beyond_range(self):
        for r in (P["offset"] + P["delta"], P["offset"] + P["delta"] + 1e-9, 3.0):
            s = pair(r, **P)
            self.assertEqual(s.analysis.energy()["non_bonded"], 0.0)
            np.testing.assert_array_equal(s.part.by_id(1).f, [0.0, 0.0, 0.0])
        self.assertAlmostEqual(pair(2.2 - 1e-9, **P).analysis.energy()["non_bonded"], 0.0, delta=1e-12)

    def test_momentum_conserved(self):
        s = marble.System(box_l=[8.0] * 3)
        s.time_step = 0.002
        rng = np.random.default_rng(7)
        grid = np.stack(np.meshgrid(*[np.arange(4) * 2.0] * 3), -1).reshape(-1, 3)
        s.part.add(pos=grid + 0.2 * rng.random(grid.shape), v=rng.normal(size=grid.shape))
        s.non_bonded_inter[0, 0].contact.set_params(f_contact=50.0, delta=0.3, offset=1.9)
        p0 = np.array(s.analysis.linear_momentum())
        s.integrator.run(300)
        np.testing.assert_allclose(s.analysis.linear_momentum(), p0, atol=1e-12)

    def test_bad_input(self):
        s = pair(2.1, **P)
        h = s.non_bonded_inter[0, 0].contact
        for bad, key in ((dict(P, delta=-0.001), "delta"), (dict(P, delta=0.0), "delta"),
                         (dict(P, offset=-1.0), "offset"), (dict(P, f_contact=-1.0), "f_contact")):
            with self.assertRaisesRegex(ValueError, key):
                h.set_params(**bad)
            self.assertEqual(h.get_params(), P)


if __name__ == "__main__":
    unittest.main()
