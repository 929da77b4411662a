# labels: python
"""Lennard-Jones in the SIMD pair block (src/core/forces/pair_simd.cpp): the
forces of a jittered-lattice LJ fluid against a brute-force numpy sum over all
minimum-image pairs to 1e-12 (unshifted, shifted, with an offset, with a
min, and together with the hat), a two-type scene with different LJ
parameters per type pair (the generic scalar loop) the same way, and the
energy conservation of a short NVE run on the SIMD path against the same run
on the generic loop (a second type with other parameters and no particles
moves the scene off the SIMD block)."""
import unittest

import numpy as np

import marble

if not marble.has_features("LENNARD_JONES"):
    raise unittest.SkipTest("missing feature LENNARD_JONES")

L = 6.0


def lattice(rng, n_side=7, jitter=0.12):
    g = (np.arange(n_side) + 0.5) * (L / n_side)
    pos = np.array(np.meshgrid(g, g, g, indexing="ij")).reshape(3, -1).T
    return pos + rng.uniform(-jitter, jitter, pos.shape)


def lj_force_over_r(r, p):
    """LennardJones::force_over_r (espressomd convention), vectorised."""
    roff = r - p.get("offset", 0.0)
    inside = (roff < p["cutoff"]) & (roff > p.get("min", 0.0))
    q6 = (p["sigma"] / np.where(inside, roff, 1.0)) ** 6
    return np.where(inside, 48.0 * p["epsilon"] * q6 * (q6 - 0.5) / (np.where(inside, roff, 1.0) * r), 0.0)


def brute_force(pos, types, params, hat=None):
    """Force on every particle: sum over all minimum-image pairs; also the sum
    of the pair force magnitudes per particle (the scale of its round-off)."""
    d = pos[:, None, :] - pos[None, :, :]
    d -= L * np.round(d / L)
    r = np.sqrt(np.sum(d * d, axis=-1))
    np.fill_diagonal(r, np.inf)
    fac = np.zeros_like(r)
    for (a, b), p in params.items():
        sel = ((types[:, None] == a) & (types[None, :] == b)) | ((types[:, None] == b) & (types[None, :] == a))
        fac += np.where(sel, lj_force_over_r(r, p), 0.0)
    if hat is not None:
        with np.errstate(invalid="ignore"):  # inf / inf on the diagonal, not selected
            fac += np.where(r < hat["cutoff"], hat["F_max"] * (1.0 - r / hat["cutoff"]) / r, 0.0)
    f = np.sum(fac[:, :, None] * d, axis=1)
    scale = np.sum(np.abs(fac) * np.where(np.isfinite(r), r, 0.0), axis=1)
    return f, scale


def system(pos, types, params, hat=None, skin=0.3):
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.005
    s.cell_system.skin = skin
    s.part.add(pos=pos, type=types)
    for (a, b), p in params.items():
        s.non_bonded_inter[a, b].lennard_jones.set_params(**p)
    if hat is not None:
        s.non_bonded_inter[0, 0].hat.set_params(**hat)
    return s


class PairSimdLJ(unittest.TestCase):

    def check_forces(self, params, types=None, hat=None, seed=11):
        rng = np.random.default_rng(seed)
        pos = lattice(rng)
        types = np.zeros(len(pos), dtype=int) if types is None else types(len(pos), rng)
        s = system(pos, types, params, hat)
        s.integrator.run(0)
        f = s.part.all().f
        ref, scale = brute_force(pos, types, params, hat)
        self.assertGreater(np.max(np.abs(ref)), 1.0)  # the fluid is not trivially force-free
        err = np.max(np.abs(f - ref) / scale[:, None])
        self.assertLess(err, 1e-12)

    def test_unshifted(self):
        self.check_forces({(0, 0): dict(epsilon=1.0, sigma=0.8, cutoff=2.0, shift=0.0)})

    def test_shifted(self):
        self.check_forces({(0, 0): dict(epsilon=1.3, sigma=0.8, cutoff=2.0, shift="auto")})

    def test_offset(self):
        self.check_forces({(0, 0): dict(epsilon=1.0, sigma=0.6, cutoff=1.5, shift="auto", offset=0.2)})

    def test_min(self):
        self.check_forces({(0, 0): dict(epsilon=1.0, sigma=0.8, cutoff=2.0, shift=0.0, min=0.75)})
        self.check_forces({(0, 0): dict(epsilon=1.0, sigma=0.6, cutoff=1.5, offset=0.1, min=0.6)})

    @unittest.skipUnless(marble.has_features("HAT"), "missing feature HAT")
    def test_with_hat(self):
        self.check_forces({(0, 0): dict(epsilon=1.0, sigma=0.8, cutoff=1.2, shift="auto")},
                          hat=dict(F_max=25.0, cutoff=1.0))

    def test_two_types_different_parameters(self):
        """Different LJ parameters per type pair: the generic scalar loop."""
        params = {(0, 0): dict(epsilon=1.0, sigma=0.8, cutoff=2.0, shift="auto"),
                  (0, 1): dict(epsilon=0.5, sigma=0.7, cutoff=1.6, shift=0.0),
                  (1, 1): dict(epsilon=1.5, sigma=0.6, cutoff=1.4, shift="auto", offset=0.1)}
        self.check_forces(params, types=lambda n, rng: rng.integers(0, 2, n))

    def test_two_types_same_parameters(self):
        """Two types, one parameter set on every type pair: the SIMD block."""
        p = dict(epsilon=1.0, sigma=0.8, cutoff=2.0, shift="auto")
        self.check_forces({(0, 0): p, (0, 1): p, (1, 1): p}, types=lambda n, rng: rng.integers(0, 2, n))

    def nve_energy(self, generic, dt=0.005, time=10.0):
        rng = np.random.default_rng(5)
        pos = lattice(rng, jitter=0.05)
        p = dict(epsilon=1.0, sigma=0.75, cutoff=2.0, shift="auto")
        params = {(0, 0): p}
        if generic:  # a second type (no particles) with other parameters: the generic loop
            params[(1, 1)] = dict(epsilon=0.5, sigma=0.75, cutoff=2.0, shift="auto")
        s = system(pos, np.zeros(len(pos), dtype=int), params)
        s.time_step = dt
        s.part.all().v = rng.normal(0.0, 1.0, pos.shape)
        e = []
        every = int(round(0.05 / dt))
        for _ in range(int(round(time / 0.05))):
            s.integrator.run(every)
            e.append(s.analysis.energy()["total"])
        return np.array(e)

    def test_nve_energy_conservation_unchanged(self):
        """Velocity Verlet conserves a shadow energy: the fluctuation of the
        total energy is ~dt^2 (halving dt divides it by ~4) and does not
        drift; the SIMD block and the generic loop give the same size of
        fluctuation (the runs part by round-off, chaos: not the same bits)."""
        e_simd, e_half, e_gen = self.nve_energy(False), self.nve_energy(False, dt=0.0025), self.nve_energy(True)
        for e in (e_simd, e_gen):
            self.assertLess(np.std(e) / np.abs(np.mean(e)), 3e-4)
            drift = abs(np.mean(e[-50:]) - np.mean(e[:50]))
            self.assertLess(drift, 3.0 * np.std(e))
        self.assertTrue(2.5 < np.std(e_simd) / np.std(e_half) < 6.0, np.std(e_simd) / np.std(e_half))
        self.assertLess(abs(np.log(np.std(e_simd) / np.std(e_gen))), np.log(1.5))


if __name__ == "__main__":
    unittest.main()
