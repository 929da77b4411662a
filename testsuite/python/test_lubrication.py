# labels: python
"""The lubrication kernel (squeeze mode on the surface gap, seed 004 made
fluctuation-dissipation consistent; doc/suspensions.md): the pair force
against an independent implementation (friction and the counter-based noise
of reference_noise.py) to 1e-12 at several gaps, equal and unequal radii, with
and without the log term, both noise variants, both forms ("plain" and
"shifted", zero at h_cut); zero from h_cut on; the shifted form's closed-form
value and its continuity at h_cut; the noise variance along e and nothing
across e; momentum conservation with noise in velocity Verlet and Shardlow;
bad input."""
import itertools
import unittest

import numpy as np

import marble
from reference_noise import pair_uniform3
from unittest_decorators import skipIfMissingFeatures

SALT_LUB = 16  # RNGSalt::lubrication
DT = 0.004


def a_sq(h, eta, a1, a2, h_cut, h_min=1e-3, log_term="off", noise="fdt", form="plain"):
    he = max(h, h_min)
    a_red = a1 * a2 / (a1 + a2)
    c = a1 * a2 * (a1 ** 2 + 7 * a1 * a2 + a2 ** 2) / (5 * (a1 + a2) ** 3)
    if form == "shifted":  # minus the value at h_cut (log part from h_cut too)
        a = a_red ** 2 * (1 / he - 1 / h_cut)
        if log_term == "on":
            a += c * np.log(h_cut / he)
        return max(6 * np.pi * eta * a, 0.0)
    a = a_red ** 2 / he
    if log_term == "on":
        a += c * np.log(0.5 * (a1 + a2) / he)
    return max(6 * np.pi * eta * a, 0.0)


def ref_force(prm, d, v, xi, kT, dt):
    r = np.linalg.norm(d)
    h = r - prm["a1"] - prm["a2"]
    if h >= prm["h_cut"]:
        return np.zeros(3)
    e = d / r
    a = a_sq(h, **prm)
    w = 1.0 if prm.get("noise", "fdt") == "fdt" else 1 - max(h, 0) / prm["h_cut"]
    return (-a * (e @ v) + np.sqrt(24 * kT * a / dt) * w * (e @ xi)) * e


def make_pair(prm, kT, x1, x2, v1, v2, ids=(3, 8), seed=5, counter=11, L=10.0):
    s = marble.System(box_l=[L] * 3)
    s.time_step = DT
    p1 = s.part.add(id=ids[0], pos=x1, v=v1)
    p2 = s.part.add(id=ids[1], pos=x2, v=v2)
    s.non_bonded_inter[0, 0].lubrication.set_params(**prm)
    s.thermostat.set_dpd(kT=kT, seed=seed)
    s.thermostat.dpd.philox_counter = counter
    s.integrator.run(0)
    return s, p1, p2


PARAMS = [dict(eta=0.3, a1=1.0, a2=1.0, h_cut=1.0),
          dict(eta=1.1, a1=1.0, a2=2.5, h_cut=0.6, h_min=0.01, log_term="on"),
          dict(eta=0.7, a1=0.5, a2=1.5, h_cut=1.5, noise="seed"),
          dict(eta=0.3, a1=0.987, a2=0.987, h_cut=0.15, form="shifted"),  # setup_suspension's stick default
          dict(eta=1.1, a1=1.0, a2=2.5, h_cut=0.6, h_min=0.01, log_term="on", form="shifted"),
          dict(eta=0.7, a1=0.5, a2=1.5, h_cut=1.5, noise="seed", form="shifted")]
SHIFTED = [p for p in PARAMS if p.get("form") == "shifted"]


@skipIfMissingFeatures("LUBRICATION")
class Lubrication(unittest.TestCase):
    rng = np.random.default_rng(31)

    def check(self, prm, h, kT, ids=(3, 8), v=True):
        e = self.rng.normal(size=3)
        e /= np.linalg.norm(e)
        x2 = np.array([4.0, 5.0, 5.5])
        x1 = x2 + (prm["a1"] + prm["a2"] + h) * e
        v1, v2 = (self.rng.normal(size=3), self.rng.normal(size=3)) if v else (np.zeros(3),) * 2
        s, p1, p2 = make_pair(prm, kT, x1, x2, v1, v2, ids=ids)
        sign = 1.0 if ids[0] < ids[1] else -1.0
        xi = sign * pair_uniform3(5, SALT_LUB, 11, min(ids), max(ids))
        f_ref = ref_force(prm, x1 - x2, v1 - v2, xi, kT, DT)
        scale = max(np.max(np.abs(f_ref)), 1e-300)
        np.testing.assert_allclose(p1.f, f_ref, rtol=0, atol=1e-12 * scale)
        np.testing.assert_array_equal(p2.f, -p1.f)
        return p1.f, e

    def test_friction_and_noise(self):
        for prm, kT in itertools.product(PARAMS, (0.0, 0.1, 1.3)):
            for h in (-0.05, 0.0005, 0.001, 0.02, 0.1, 0.3, 0.55):
                if h >= prm["h_cut"]:
                    continue
                with self.subTest(prm=prm, kT=kT, h=h):
                    f, e = self.check(prm, h, kT)
                    self.assertGreater(np.linalg.norm(f), 0.0)
                    # along e only
                    np.testing.assert_allclose(f - (f @ e) * e, 0.0, atol=1e-12 * np.linalg.norm(f))
        # id order reversed: same unordered-pair noise, sign by id order
        self.check(PARAMS[0], 0.2, 1.0, ids=(8, 3), v=False)

    def test_stress_virial(self):
        """dpd_stress_split() and pressure_tensor()['dpd'] carry the lubrication's
        virial (1/V) d (x) F, friction and noise apart (issue 13: the virial of
        every kernel), checked against the independent force above."""
        for prm in PARAMS:
            for h in (0.0005, 0.1, 0.3):
                if h >= prm["h_cut"]:
                    continue
                with self.subTest(prm=prm, h=h):
                    kT, ids = 1.3, (3, 8)
                    e = self.rng.normal(size=3)
                    e /= np.linalg.norm(e)
                    x2 = np.array([4.0, 5.0, 5.5])
                    x1 = x2 + (prm["a1"] + prm["a2"] + h) * e
                    v1, v2 = self.rng.normal(size=3), self.rng.normal(size=3)
                    s, p1, p2 = make_pair(prm, kT, x1, x2, v1, v2, ids=ids)
                    xi = pair_uniform3(5, SALT_LUB, 11, min(ids), max(ids))
                    d = x1 - x2
                    V = 10.0 ** 3
                    fric = np.outer(d, ref_force(prm, d, v1 - v2, np.zeros(3), kT, DT)) / V
                    noise = np.outer(d, ref_force(prm, d, np.zeros(3), xi, kT, DT)) / V
                    st = s.analysis.dpd_stress_split()
                    for got, ref in ((st["friction"], fric), (st["noise"], noise), (st["total"], fric + noise)):
                        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))
                    np.testing.assert_allclose(s.analysis.pressure_tensor()["dpd"], fric + noise, rtol=0,
                                               atol=1e-12 * np.max(np.abs(fric + noise)))
                    self.assertGreater(np.max(np.abs(fric)), 0.0)

    def test_leading_term_equal_spheres(self):
        """(3 pi/2) eta a^2 / h for equal spheres: seed 004's and Ball-Melrose's form."""
        for h in (0.01, 0.1, 0.4):
            self.assertAlmostEqual(a_sq(h, **PARAMS[0]), 1.5 * np.pi * 0.3 / h, delta=1e-12 / h)
            f, e = self.check(PARAMS[0], h, 0.0)

    def test_shifted_closed_form(self):
        """form="shifted": a_sq = 6 pi eta [a_red^2 (1/h_e - 1/h_cut) + c_log ln(h_cut/h_e)],
        written out here for each case (not through a_sq above), the kernel's force at
        kT = 0 against it to 1e-12; it is the plain form minus its value at h_cut
        (without the log term); zero at h_cut and beyond; continuous at h_cut (the
        force at h_cut - eps is O(eps))."""
        a = 0.987
        for h in (0.0005, 0.001, 0.01, 0.05, 0.1, 0.149):
            want = 6 * np.pi * 0.3 * (0.25 * a * a) * (1 / max(h, 1e-3) - 1 / 0.15)
            self.assertAlmostEqual(a_sq(h, **SHIFTED[0]), want, delta=1e-12 * want)
            plain = dict(SHIFTED[0], form="plain")
            self.assertAlmostEqual(a_sq(h, **SHIFTED[0]), a_sq(h, **plain) - a_sq(0.15, **plain),
                                   delta=1e-12 * want)
        a1, a2 = 1.0, 2.5
        c = a1 * a2 * (a1 ** 2 + 7 * a1 * a2 + a2 ** 2) / (5 * (a1 + a2) ** 3)
        for h in (0.005, 0.01, 0.2, 0.59):
            he = max(h, 0.01)
            want = 6 * np.pi * 1.1 * ((a1 * a2 / (a1 + a2)) ** 2 * (1 / he - 1 / 0.6) + c * np.log(0.6 / he))
            self.assertAlmostEqual(a_sq(h, **SHIFTED[1]), want, delta=1e-12 * want)
        for prm in SHIFTED:
            for h in (0.0005, 0.3 * prm["h_cut"], 0.9 * prm["h_cut"]):
                with self.subTest(prm=prm, h=h):
                    f, e = self.check(prm, h, 0.0)
                    self.assertGreater(np.linalg.norm(f), 0.0)
            # continuity: |F| at h_cut - eps against the slope of a_sq at h_cut
            v = np.array([0.3, -0.2, 0.1])
            hc = prm["h_cut"]
            a1, a2 = prm["a1"], prm["a2"]
            c = a1 * a2 * (a1 ** 2 + 7 * a1 * a2 + a2 ** 2) / (5 * (a1 + a2) ** 3)
            slope = 6 * np.pi * prm["eta"] * ((a1 * a2 / (a1 + a2)) ** 2 / hc ** 2
                                              + (c / hc if prm.get("log_term") == "on" else 0.0))
            for eps in (1e-3, 1e-6):
                x2 = np.array([4.0, 5.0, 5.5])
                s, p1, _ = make_pair(prm, 0.0, x2 + [a1 + a2 + hc - eps, 0, 0], x2, v, -v)
                # |F| = a_sq(h_cut - eps) |2 v_x| = slope eps |2 v_x| (1 + O(eps/h_cut))
                self.assertAlmostEqual(np.linalg.norm(p1.f) / (slope * eps * 2 * abs(v[0])), 1.0,
                                       delta=2 * eps / hc + 1e-6)
            self.assertEqual(a_sq(hc, **prm), 0.0)

    def test_form_params(self):
        """"plain" is the default (seed 004's kernel unchanged); get_params round-trips the form."""
        s, _, _ = make_pair(PARAMS[0], 1.0, [6.1, 5, 5], [4.0, 5, 5], [0] * 3, [0] * 3)
        handle = s.non_bonded_inter[0, 0].lubrication
        self.assertEqual(handle.get_params()["form"], "plain")
        handle.set_params(**SHIFTED[1])
        got = handle.get_params()
        self.assertEqual(got["form"], "shifted")
        self.assertEqual(got["log_term"], "on")
        handle.set_params(**got)
        self.assertEqual(handle.get_params(), got)

    def test_zero_beyond_cutoff(self):
        for prm in PARAMS:
            for h in (prm["h_cut"] + 1e-9, prm["h_cut"] + 0.01, prm["h_cut"] + 0.5):
                f, _ = self.check(prm, h, 1.0)
                np.testing.assert_array_equal(f, 0.0)

    def test_noise_variance(self):
        """v = 0: <F_e^2> = 2 kT a_sq / dt over counters (uniform noise, var 1/12 x 24);
        no component across e. 4000 draws: 5 sigma of the variance estimate is 5 sqrt(0.8/4000) ~ 7 %."""
        prm, h, kT = PARAMS[0], 0.05, 0.7
        s, p1, p2 = make_pair(prm, kT, [4.0 + 2.05, 5.0, 5.0], [4.0, 5.0, 5.0], [0] * 3, [0] * 3)
        f = []
        for c in range(4000):
            s.thermostat.dpd.philox_counter = c
            s.integrator.run(0, recalc_forces=True)
            f.append(p1.f)
        f = np.array(f)
        np.testing.assert_array_equal(f[:, 1:], 0.0)
        var = np.mean(f[:, 0] ** 2)
        want = 2 * kT * a_sq(h, **prm) / DT
        # the variance of u^2 for uniform u is (1/80 - 1/144)/(1/12)^2 = 0.8 of var^2
        self.assertLess(abs(var / want - 1), 5 * np.sqrt(0.8 / len(f)))

    def check_momentum(self, shardlow, form="plain"):
        L, N = 12.0, 27
        rng = np.random.default_rng(12)
        s = marble.System(box_l=[L] * 3)
        s.time_step = 0.002
        grid = np.stack(np.meshgrid(*[np.arange(3) * 4.0] * 3), -1).reshape(-1, 3)
        s.part.add(pos=grid + 0.2 * rng.random(grid.shape), v=rng.normal(size=(N, 3)),
                   mass=rng.choice([1.0, 4.0], size=N))
        s.non_bonded_inter[0, 0].lubrication.set_params(eta=0.5, a1=1.8, a2=1.8, h_cut=0.8,
                                                        log_term="on", form=form)
        s.non_bonded_inter[0, 0].contact.set_params(f_contact=20.0, delta=0.05, offset=3.6)
        s.thermostat.set_dpd(kT=1.0, seed=3)
        if shardlow:
            s.integrator.set_shardlow()
        p0 = np.array(s.analysis.linear_momentum())
        s.integrator.run(500)
        np.testing.assert_allclose(s.analysis.linear_momentum(), p0, atol=1e-12)

    @skipIfMissingFeatures("CONTACT", "MASS")
    def test_momentum_vv(self):
        self.check_momentum(False)

    @skipIfMissingFeatures("CONTACT", "MASS")
    def test_momentum_shardlow(self):
        self.check_momentum(True)

    @skipIfMissingFeatures("CONTACT", "MASS")
    def test_momentum_shifted(self):
        self.check_momentum(False, "shifted")
        self.check_momentum(True, "shifted")

    def drainage(self, shardlow, dt):
        """kT = 0, two equal spheres approaching at u0: mu du = -(A/h) dh, so
        u(h) = u0 + (A/mu) ln(h0/h) exactly, the gap stops at
        h_stop = h0 exp(u0 mu/A), and t(h) = int_h^h0 dh'/|u(h')| (quadrature)."""
        prm = dict(eta=0.3, a1=1.0, a2=1.0, h_cut=1.0, h_min=1e-4)
        A = 6 * np.pi * 0.3 * 0.25
        m, u0, h0 = 1.0, -3.0, 0.6
        mu = m / 2
        s = marble.System(box_l=[10.0] * 3)
        s.time_step = dt
        s.part.add(pos=[[4.0, 5.0, 5.0], [6.0 + h0, 5.0, 5.0]], v=[[-u0 / 2, 0, 0], [u0 / 2, 0, 0]])
        s.non_bonded_inter[0, 0].lubrication.set_params(**prm)
        s.thermostat.set_dpd(kT=0.0, seed=1)
        if shardlow:
            s.integrator.set_shardlow()
        h_stop = h0 * np.exp(u0 * mu / A)
        # t(h): substitute h = h0 exp(-y) to resolve the end, trapezoid on a fine grid
        y_stop = -np.log(h_stop / h0)

        def t_of_h(h):
            y = np.linspace(0, -np.log(h / h0), 200001)
            f = h0 * np.exp(-y) / (-u0 - A / mu * y)
            return np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(y))
        samples = []
        steps = int(round(0.05 / dt))
        for _ in range(40):
            s.integrator.run(steps)
            p = s.part.all()
            h = p.pos[1][0] - p.pos[0][0] - 2.0
            u = p.v[1][0] - p.v[0][0]
            samples.append((s.time, h, u))
        for t, h, u in samples:
            # u(h) to 1 % of u0
            self.assertAlmostEqual(u, u0 + A / mu * np.log(h0 / h), delta=0.01 * abs(u0))
            if h > h_stop * (1 + 0.05):  # away from the end, where t(h) diverges
                self.assertAlmostEqual(t, t_of_h(h), delta=0.01 * t)
        self.assertAlmostEqual(samples[-1][1], h_stop, delta=0.01 * h_stop)
        self.assertLess(y_stop, np.log(h0 / prm["h_min"]))  # the 1/h law holds all the way

    def test_drainage_vv(self):
        self.drainage(False, 1e-4)

    def test_drainage_shardlow(self):
        self.drainage(True, 2e-5)

    def test_bad_input(self):
        s, _, _ = make_pair(PARAMS[0], 1.0, [6.1, 5, 5], [4.0, 5, 5], [0] * 3, [0] * 3)
        handle = s.non_bonded_inter[0, 0].lubrication
        good = handle.get_params()
        cases = [({k: v for k, v in PARAMS[0].items() if k != "eta"}, "eta"),  # no viscosity
                 (dict(PARAMS[0], eta=0.0), "eta"),
                 (dict(PARAMS[0], h_min=-0.001), "h_min"),
                 (dict(PARAMS[0], h_min=0.0), "h_min"),
                 (dict(PARAMS[0], h_min=1.0), "h_min"),  # not below h_cut
                 (dict(PARAMS[0], h_cut=-0.5), "h_cut"),
                 (dict(PARAMS[0], a1=0.0), "a1"),
                 (dict(PARAMS[0], noise="weak"), "noise"),
                 (dict(PARAMS[0], form="linear"), "form"),
                 (dict(PARAMS[0], form=1), "form")]
        for prm, key in cases:
            with self.subTest(key=key, prm=prm):
                with self.assertRaisesRegex(ValueError, key):
                    handle.set_params(**prm)
                self.assertEqual(handle.get_params(), good)


if __name__ == "__main__":
    unittest.main()
