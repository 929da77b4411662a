# labels: python
"""Equilibrium of the DPD thermostat at kT = 2.3: Maxwell distribution of every
velocity component (Kolmogorov-Smirnov, sample-size tolerance) and
equipartition <m v_a^2> = kT per component and per species of different masses
(error bars from blocking). A small dt (0.004) keeps the plain-VV drift
(~0.1 %) well below the statistical resolution (~0.5 %)."""
import math
import unittest

import numpy as np

import marble

if not marble.has_features("DPD"):
    raise unittest.SkipTest("missing feature DPD")
from marble.viscosity import block_average

KT = 2.3
L = 8.0
N = 1536


def ks_normal(u):
    """KS distance of the sample ``u`` from the standard normal distribution."""
    u = np.sort(u)
    n = u.size
    cdf = 0.5 * (1.0 + np.vectorize(math.erf)(u / math.sqrt(2.0)))
    i = np.arange(1, n + 1)
    return max(np.max(i / n - cdf), np.max(cdf - (i - 1) / n))


class DPDMaxwell(unittest.TestCase):

    def test_maxwell_equipartition(self):
        rng = np.random.default_rng(12)
        has_mass = marble.has_features("MASS")
        mass = np.where(np.arange(N) % 2 == 0, 1.0, 3.0) if has_mass else np.ones(N)
        s = marble.System(box_l=[L, L, L])
        s.time_step = 0.004
        s.cell_system.skin = 0.4
        kw = {"mass": mass} if has_mass else {}
        s.part.add(pos=rng.uniform(0, L, size=(N, 3)), v=np.zeros((N, 3)), **kw)
        if marble.has_features("HAT"):
            s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=KT, seed=77)
        s.integrator.run(1000)  # 4 tau from rest: the thermostat heats the fluid up
        parts = s.part.all()
        species = [mass == 1.0, mass == 3.0] if has_mass else [np.ones(N, bool)]
        # velocity-decorrelation time of the heavy beads ~ m / (4 pi gamma rho / 90) ~ 1.6
        n_snap, spacing = 60, 500  # 2 tau apart, 120 tau
        t_series = np.empty((n_snap, len(species), 3))
        u_all = []
        for k in range(n_snap):
            s.integrator.run(spacing)
            v = parts.v
            for q, sel in enumerate(species):
                t_series[k, q] = np.mean(mass[sel, None] * v[sel] ** 2, axis=0)
            u_all.append((v * np.sqrt(mass[:, None] / KT)).ravel())
        # equipartition per species and component
        for q in range(len(species)):
            for a in range(3):
                t, err = block_average(t_series[:, q, a], min_blocks=8)
                with self.subTest(species=q, axis=a):
                    self.assertLess(abs(t - KT), 4.0 * err, f"<m v^2> = {t} +/- {err}")
                    self.assertLess(err, 0.02 * KT)  # resolution ~1 %
        # Maxwell: the scaled components are N(0, 1). Snapshots 2 tau apart are
        # nearly independent; the KS threshold uses half the samples (alpha ~ 1e-4).
        u = np.concatenate(u_all)
        d = ks_normal(u)
        n_eff = u.size / 2
        self.assertLess(d, 2.0 / math.sqrt(n_eff), f"KS distance {d}")
        # a wrong variance by 3 % would be seen
        self.assertGreater(ks_normal(u * 1.03), 2.0 / math.sqrt(n_eff))


if __name__ == "__main__":
    unittest.main()
