# labels: python
"""The pair noise of the dissipative pair kernels (Philox4x32-10,
src/utils/include/utils/philox4x32.hpp): the reference implementation of
reference_noise.py against the Random123 known-answer vectors, and the
engine's DPD (+ hat) forces of a 200-particle fluid against a brute-force sum
with it to 1e-12: one type and two types with the same kernels (the SIMD
block loop), two types with different ones (the generic loop), LJ + hat + DPD
in one block, and a seed and
step counter beyond 2^32 (the high key and counter words). The statistics of the generator (mean, variance 1/12,
correlations between components, neighbouring keys and steps) are tested in
testsuite/core/philox4x32_test.cpp."""
import unittest

import numpy as np

import marble

from reference_noise import SALT_DPD, pair_noise, philox4x32

if not marble.has_features("DPD"):
    raise unittest.SkipTest("missing feature DPD")


class PairNoise(unittest.TestCase):
    def test_known_answers(self):
        # Random123 kat_vectors, philox4x32 10 rounds
        kat = [([0, 0, 0, 0], [0, 0], [0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8]),
               ([0xffffffff] * 4, [0xffffffff] * 2, [0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd]),
               ([0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344], [0xa4093822, 0x299f31d0],
                [0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1])]
        for ctr, key, out in kat:
            self.assertEqual(philox4x32(ctr, key), out)

    def fluid_forces(self, seed, counter, n=200, L=4.0, kT=1.3, gamma=4.5, hat=0.0, gamma01=None, lj=None):
        """Forces of n particles against a brute-force sum. With gamma01, half
        the particles are type 1 and the pairs (0, 0), (0, 1), (1, 1) have DPD
        (gamma, gamma01, gamma): equal gammas take the SIMD loop (one set of
        kernels on every type pair), unequal ones the generic loop. With lj (LennardJones parameters with a
        min: random positions overlap), the LJ kernel on every type pair too."""
        rng = np.random.default_rng(3)
        s = marble.System(box_l=[L] * 3)
        s.time_step = 0.01
        s.cell_system.skin = 0.3
        pos, v = rng.random((n, 3)) * L, rng.normal(size=(n, 3))
        types = np.zeros(n, dtype=int) if gamma01 is None else np.arange(n) % 2
        s.part.add(pos=pos, v=v, type=types)
        pairs = [(0, 0)] if gamma01 is None else [(0, 0), (0, 1), (1, 1)]
        g = {}
        for a, b in pairs:
            g[a, b] = g[b, a] = gamma if a == b else gamma01
            s.non_bonded_inter[a, b].dpd.set_params(weight_function=1, gamma=g[a, b], k=1.0, r_cut=1.0)
            if hat > 0 and marble.has_features("HAT"):
                s.non_bonded_inter[a, b].hat.set_params(F_max=hat, cutoff=1.0)
            if lj is not None:
                s.non_bonded_inter[a, b].lennard_jones.set_params(**lj)
        s.thermostat.set_dpd(kT=kT, seed=seed)
        s.thermostat.dpd.philox_counter = counter
        s.integrator.run(0)
        ids = s.part.all().id
        f = s.part.all().f
        # brute force reference over all minimum-image pairs
        ref = np.zeros((n, 3))
        for a in range(n):
            d = pos[a] - pos[a + 1:]
            d -= L * np.round(d / L)
            r = np.linalg.norm(d, axis=1)
            for k in np.nonzero(r < 1.0)[0]:
                if lj is not None:  # LennardJones::force_over_r
                    roff = r[k] - lj.get("offset", 0.0)
                    if lj["min"] < roff < lj["cutoff"]:
                        q6 = (lj["sigma"] / roff) ** 6
                        fl = 48.0 * lj["epsilon"] * q6 * (q6 - 0.5) / (roff * r[k]) * d[k]
                        ref[a] += fl
                        ref[a + 1 + k] -= fl
                b = a + 1 + k
                gab = g[types[a], types[b]]
                pref = np.sqrt(24.0 * kT * gab / s.time_step)
                e = d[k] / r[k]
                w = 1.0 - r[k]
                xi = pair_noise(seed, SALT_DPD, counter, ids[a], ids[b])
                fa = (-gab * w * w * (e @ (v[a] - v[b])) + pref * w * (e @ xi)) * e
                if hat > 0 and marble.has_features("HAT"):
                    fa += hat * (1.0 - r[k]) * e
                ref[a] += fa
                ref[b] -= fa
        np.testing.assert_allclose(f, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))

    def test_fluid_against_reference(self):
        self.fluid_forces(seed=17, counter=5)

    def test_fluid_with_hat(self):
        self.fluid_forces(seed=5, counter=9, hat=25.0)

    def test_two_types_same_kernels(self):
        self.fluid_forces(seed=11, counter=3, hat=25.0, gamma01=4.5)

    def test_two_types_different_kernels(self):
        self.fluid_forces(seed=11, counter=3, hat=25.0, gamma01=2.0)

    @unittest.skipUnless(marble.has_features("LENNARD_JONES", "HAT"), "missing LENNARD_JONES or HAT")
    def test_fluid_with_lj_and_hat(self):
        """LJ + hat + DPD in one SIMD block (LJ from 1/r^2, and with an offset)."""
        self.fluid_forces(seed=7, counter=4, hat=25.0,
                          lj=dict(epsilon=1.0, sigma=0.3, cutoff=0.9, shift="auto", min=0.22))
        self.fluid_forces(seed=7, counter=4, hat=25.0,
                          lj=dict(epsilon=1.0, sigma=0.3, cutoff=0.85, shift="auto", min=0.2, offset=0.05))

    def test_large_seed_and_counter(self):
        self.fluid_forces(seed=(1 << 40) + 12345, counter=(1 << 33) + 7, n=60)


if __name__ == "__main__":
    unittest.main()
