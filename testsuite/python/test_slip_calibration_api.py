"""marble.slip.gamma_for_slip_length / slip_length_for_gamma / calibrate: the
API around the slip calibration curves (doc/walls.md "Slip length on request").
Quick: synthetic curves and the shipped ones, no simulation except a tiny
calibrate() smoke run."""
import copy
import json
import os
import tempfile
import unittest

import numpy as np

import marble
from marble import slip


def synthetic_curve(surface="wall"):
    """b = 0.93 / gamma - 0.49 (the shape of Smiatek's formula) at 5 points, 10 % errors."""
    g = np.array([0.25, 0.35, 0.5, 0.7, 1.0])
    b = 0.93 / g - 0.49
    cond = slip.WALL_CONDITIONS if surface == "wall" else slip.MARBLE_CONDITIONS
    return {"format": slip.FORMAT, "surface": surface,
            "parameter": "gamma_L" if surface == "wall" else "gamma",
            "conditions": dict(cond), "measurement": {},
            "points": [{"gamma": float(x), "b": float(y), "b_err": float(0.1 * y), "use": True}
                       for x, y in zip(g, b)]}


class SlipCalibrationAPI(unittest.TestCase):

    def setUp(self):
        self.curve = synthetic_curve()

    def test_round_trip_of_the_interpolation(self):
        for p in self.curve["points"]:  # nodes are reproduced exactly
            g, _ = slip.gamma_for_slip_length(p["b"], curve=self.curve)
            self.assertAlmostEqual(g, p["gamma"], places=8)
            b, berr = slip.slip_length_for_gamma(p["gamma"], curve=self.curve)
            self.assertAlmostEqual(b, p["b"], places=10)
            self.assertAlmostEqual(berr, p["b_err"], places=8)
        for b in (0.5, 0.9, 2.0, 2.9):
            g, gerr = slip.gamma_for_slip_length(b, curve=self.curve)
            self.assertAlmostEqual(slip.slip_length_for_gamma(g, curve=self.curve)[0], b, places=8)
            self.assertGreater(gerr, 0.0)
            # between the nodes the monotone cubic follows the smooth curve closely
            self.assertLess(abs(g - 0.93 / (b + 0.49)) / g, 0.02)

    def test_monotone(self):
        lo, hi, glo, ghi = slip.calibrated_range(curve=self.curve)
        bs = np.linspace(lo, hi, 200)
        gs = [slip.gamma_for_slip_length(b, curve=self.curve).gamma for b in bs]
        self.assertTrue(np.all(np.diff(gs) < 0))
        gg = np.geomspace(glo, ghi, 200)
        bb = [slip.slip_length_for_gamma(g, curve=self.curve)[0] for g in gg]
        self.assertTrue(np.all(np.diff(bb) < 0))

    def test_noisy_points_are_made_monotone(self):
        c = copy.deepcopy(self.curve)
        c["points"][2]["b"] = c["points"][1]["b"] * 1.05  # a noise-induced inversion
        lo, hi, _, _ = slip.calibrated_range(curve=c)
        gs = [slip.gamma_for_slip_length(b, curve=c).gamma for b in np.linspace(lo, hi, 100)]
        self.assertTrue(np.all(np.diff(gs) < 0))

    def test_uncertainty_grows_between_points(self):
        nodes = slip._nodes(self.curve)
        X = nodes[0]
        for j in range(len(X) - 1):
            xm = 0.5 * (X[j] + X[j + 1])
            y, _, s_tot = slip._curve_at(nodes, xm)
            # data part alone (the nodes' errors propagated), and at the nodes
            s_data = np.sqrt(s_tot ** 2 - (y - np.interp(xm, X, nodes[1])) ** 2)
            self.assertGreater(s_tot, s_data)
            for xn, sn in ((X[j], nodes[2][j]), (X[j + 1], nodes[2][j + 1])):
                self.assertAlmostEqual(float(slip._curve_at(nodes, xn)[2]), sn, places=8)
        # error bars scale the answer's error
        big = copy.deepcopy(self.curve)
        for p in big["points"]:
            p["b_err"] *= 3
        self.assertGreater(slip.gamma_for_slip_length(1.0, curve=big).gamma_err,
                           2 * slip.gamma_for_slip_length(1.0, curve=self.curve).gamma_err)

    def test_out_of_range(self):
        lo, hi, _, _ = slip.calibrated_range(curve=self.curve)
        for b in (0.9 * lo, 1.1 * hi, -1.0, float("nan"), float("inf")):
            with self.assertRaisesRegex(ValueError, r"'b'.*calibrated range"):
                slip.gamma_for_slip_length(b, curve=self.curve)
        with self.assertRaisesRegex(ValueError, "'b'"):
            slip.gamma_for_slip_length("x", curve=self.curve)
        with self.assertRaisesRegex(ValueError, "'gamma'.*calibrated range"):
            slip.slip_length_for_gamma(10.0, curve=self.curve)

    def test_conditions(self):
        g = slip.gamma_for_slip_length(1.0, curve=self.curve, rho=3, gamma_dpd=5.0, kT=1.0,
                                       dt=0.01).gamma
        self.assertGreater(g, 0)
        for key, val in (("rho", 4.0), ("kT", 1.5), ("gamma_dpd", 4.5), ("dt", 0.005),
                         ("a", 25.0), ("z_c", 0.5)):
            with self.assertRaisesRegex(ValueError, rf"{key}=.*calibrate\(") as cm:
                slip.gamma_for_slip_length(1.0, curve=self.curve, **{key: val})
            self.assertIn("measured at", str(cm.exception))
        with self.assertRaisesRegex(ValueError, "unknown condition 'colour'"):
            slip.gamma_for_slip_length(1.0, curve=self.curve, colour=1)
        m = synthetic_curve("marble")
        with self.assertRaisesRegex(ValueError, "radius="):
            slip.gamma_for_slip_length(1.0, "marble", curve=m, radius=3.0)

    def test_bad_surface_and_curve(self):
        for s in ("walls", "", None, "colloid"):
            with self.assertRaisesRegex(ValueError, "'surface'"):
                slip.gamma_for_slip_length(1.0, surface=s)
        with self.assertRaisesRegex(ValueError, "'curve'"):
            slip.gamma_for_slip_length(1.0, surface="marble", curve=self.curve)
        with self.assertRaisesRegex(ValueError, "'curve'"):
            slip.gamma_for_slip_length(1.0, curve={"format": "x"})
        with self.assertRaisesRegex(ValueError, "'surface'"):
            slip.calibrate(surface="wal", gammas=[1.0])
        with self.assertRaisesRegex(ValueError, "'gammas'"):
            slip.calibrate(surface="wall", gammas=[-1.0])
        with self.assertRaisesRegex(ValueError, "unknown run parameter"):
            slip.calibrate(surface="wall", gammas=[1.0], radius=2.0)
        with self.assertRaisesRegex(ValueError, "'n_steps'"):
            slip.calibrate(surface="wall", gammas=[1.0, 2.0], n_steps=[100])

    def test_file_round_trip(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "c.json")
            with open(path, "w") as f:
                json.dump(self.curve, f)
            self.assertEqual(slip.gamma_for_slip_length(1.0, curve=path),
                             slip.gamma_for_slip_length(1.0, curve=self.curve))

    def test_common_boundary_fit(self):
        """Zeros generated from one z_B and known slip lengths (exact two-flow relations) give
        back z_B and every delta_B, chi^2 ~ 0; a single run at a given z_B likewise."""
        L, zb = 10.0, 1.05
        pts = []
        for d in (3.0, 1.2, 0.5):
            z0 = zb - d
            zp = L / 2 - np.sqrt(L * L / 4 - (z0 * (L - z0) + d * d))
            pts.append({"z_P": zp, "z_P_err": 0.01, "z_0": z0, "z_0_err": 0.02})
        fit = slip.common_boundary_fit(pts, L)
        self.assertAlmostEqual(fit["z_B"], zb, places=5)
        self.assertLess(fit["chi2"], 1e-8)
        self.assertEqual(fit["dof"], 2)
        np.testing.assert_allclose(fit["delta_B"], [3.0, 1.2, 0.5], atol=1e-5)
        self.assertTrue(all(e > s for e, s in zip(fit["delta_B_err"], fit["delta_B_err_stat"])))
        d, e, dc, dp = slip.slip_length_at_boundary(pts[2]["z_P"], 0.01, pts[2]["z_0"], 0.02, zb, L)
        self.assertAlmostEqual(dc, 0.5, places=10)
        self.assertAlmostEqual(dp, 0.5, places=10)
        self.assertLess(e, 0.02)
        with self.assertRaisesRegex(ValueError, ">= 2 points"):
            slip.common_boundary_fit(pts[:1], L)
        # the refit keeps the two-flow values and is idempotent
        curve = slip.load_curve("wall")
        again = slip.refit_common_boundary(curve)
        self.assertEqual([p["b"] for p in again["points"]], [p["b"] for p in curve["points"]])
        self.assertIn("b_two_flow", again["points"][0])

    def test_shipped_curves(self):
        """The package curves load, cover the targets of issue 14 and record
        their conditions and how they were measured."""
        for surface, targets in (("wall", (0.5, 2.0)), ("marble", (0.5,))):
            data = slip.load_curve(surface)
            for key in ("rho", "gamma_dpd", "a", "kT", "dt", "r_cut"):
                self.assertIn(key, data["conditions"])
            for key in ("seed", "marble_git"):
                self.assertIn(key, data["measurement"])
            for p in data["points"]:
                self.assertIn("b_err", p)
            for b in targets:
                g, gerr = slip.gamma_for_slip_length(b, surface)
                self.assertTrue(0 < gerr < g, (surface, b, g, gerr))


@unittest.skipIf(not marble.has_features("DPD", "LENNARD_JONES", "TUNABLE_SLIP",
                                         "EXTERNAL_FORCE"),
                 "needs DPD, LENNARD_JONES, TUNABLE_SLIP, EXTERNAL_FORCE")
class CalibrateSmoke(unittest.TestCase):

    def test_calibrate_writes_and_resumes(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "wall.json")
            kw = dict(n_steps=200, equil_steps=10, box_xy=4.0, n_blocks=2, seed=5)
            data = slip.calibrate("wall", [0.3], out=path, **kw)
            self.assertEqual(len(data["points"]), 1)
            with open(path) as f:
                on_disk = json.load(f)
            self.assertEqual(on_disk["conditions"]["rho"], 3.0)
            self.assertEqual(on_disk["measurement"]["n_steps"], [200])
            self.assertEqual(on_disk["points"][0]["n_steps"], 200)
            self.assertIn("marble_git", on_disk["measurement"])
            cpu = on_disk["points"][0]["cpu_s"]
            again = slip.calibrate("wall", [0.3], out=path, **kw)  # resumed: not rerun
            self.assertEqual(again["points"][0]["cpu_s"], cpu)


if __name__ == "__main__":
    unittest.main()
