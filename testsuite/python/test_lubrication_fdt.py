# labels: python long
"""Fluctuation-dissipation of the lubrication kernel (doc/suspensions.md).

K independent pairs of spheres (a = 1, m = 1) without solvent: pair k has types
(2k, 2k+1) and only its two spheres interact (squeeze lubrication, h_cut = 0.5,
h_min = 0.001, eta0 = 0.3, and a soft contact force, delta = 0.2), integrated
with the Shardlow sweep (the exact pair OU step carries the stiff near-contact
friction: a_sq/mu reaches 2800 at h_min). The thermostat acts only through
the lubrication, so the pair's equilibrium is canonical only if its noise
satisfies fluctuation-dissipation:
  - <mu v_n^2> = kT in every gap bin (v_n the normal relative velocity) within
    3 %, with the error of the mean from 16 time blocks (asserted < 1 %);
  - the pair's gap distribution g(h) = exp(-U_contact(h)/kT) times the box
    normalisation (flat above delta) within 5 % per bin;
  - seed 004's noise (noise="seed": amplitude times w = 1 - h/h_cut) leaves
    the relative motion colder than kT (the deficit of the variance);
  - the shifted form (form="shifted", friction and noise zero at h_cut; a
    quarter of the samples): <mu v_n^2> = kT in every gap bin within 4 blocking
    errors (asserted < 2.5 %).
"""
import unittest

import numpy as np

import marble
from unittest_decorators import skipIfMissingFeatures

K = 24   # few types: the per-step cost grows with n_types^2
L = 5.4        # > 2 x the pair range 2.5: one image interacts
A = 1.0        # radius
F_C, DELTA = 20.0, 0.2   # U(0) = 1 kT, stiffness 300 kT: dt = 0.004, the first bin gets samples
H_CUT = 0.5
KT = 1.0
DT = 0.004
BINS = np.array([0.0, 0.05, 0.1, 0.2, 0.3, 0.5])


def contact_u(h):
    h = np.asarray(h, float)
    y = np.clip(1 - h / DELTA, 0, None)
    inside = F_C * (DELTA / 4 - h + 1.5 * h * h / DELTA)
    return np.where(h >= DELTA, 0.0, np.where(h >= 0, F_C * DELTA / 4 * y ** 4, inside))


def expected_fractions():
    """P(h in bin) for one pair uniform in the cube with weight exp(-U/kT)."""
    r = np.linspace(1.0, 2 * A + DELTA, 400001)
    w = (1 - np.exp(-contact_u(r - 2 * A) / KT)) * 4 * np.pi * r ** 2
    v_excl = np.sum(0.5 * (w[1:] + w[:-1]) * np.diff(r)) + 4 / 3 * np.pi * 1.0 ** 3
    z = L ** 3 - v_excl
    out = []
    for h1, h2 in zip(BINS[:-1], BINS[1:]):
        rr = np.linspace(2 * A + h1, 2 * A + h2, 20001)
        f = np.exp(-contact_u(rr - 2 * A) / KT) * 4 * np.pi * rr ** 2
        out.append(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(rr)) / z)
    return np.array(out)


def run_pairs(noise, n_samples=96000, every=10, seed=7, form="plain"):
    s = marble.System(box_l=[L] * 3)
    s.time_step = DT
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    pos = []
    for _ in range(K):
        while True:
            x = rng.uniform(0, L, size=(2, 3))
            d = x[0] - x[1]
            d -= L * np.round(d / L)
            if np.linalg.norm(d) > 2 * A + 0.3:
                break
        pos.extend(x)
    types = np.repeat(np.arange(K) * 2, 2) + np.tile([0, 1], K)
    s.part.add(pos=np.array(pos), v=rng.normal(size=(2 * K, 3)) * np.sqrt(KT), type=types)
    for k in range(K):
        ia = s.non_bonded_inter[2 * k, 2 * k + 1]
        ia.lubrication.set_params(eta=0.3, a1=A, a2=A, h_cut=H_CUT, h_min=1e-3, noise=noise, form=form)
        ia.contact.set_params(f_contact=F_C, delta=DELTA, offset=2 * A)
    s.thermostat.set_dpd(kT=KT, seed=seed)
    s.integrator.set_shardlow()
    s.integrator.run(2500)  # equilibrate
    h_all, e_all = [], []
    p = s.part.all()
    for _ in range(n_samples):
        s.integrator.run(every)
        x, v = p.pos.reshape(K, 2, 3), p.v.reshape(K, 2, 3)
        d = x[:, 0] - x[:, 1]
        d -= L * np.round(d / L)
        r = np.linalg.norm(d, axis=1)
        vn = np.sum((v[:, 0] - v[:, 1]) * d, axis=1) / r
        h_all.append(r - 2 * A)
        e_all.append(0.5 * vn ** 2)  # mu v_n^2, mu = 1/2
    return np.array(h_all), np.array(e_all)


def binned(h, e, n_blocks=16):
    """Per gap bin: <mu v_n^2>/kT, its blocking error, and the fraction of pair samples."""
    nb = len(BINS) - 1
    blocks = np.array_split(np.arange(len(h)), n_blocks)
    mean_b = np.zeros((n_blocks, nb))
    frac_b = np.zeros((n_blocks, nb))
    for b, idx in enumerate(blocks):
        hb, eb = h[idx].ravel(), e[idx].ravel()
        k = np.digitize(hb, BINS) - 1
        for j in range(nb):
            sel = k == j
            mean_b[b, j] = eb[sel].mean() / KT if sel.any() else np.nan
            frac_b[b, j] = sel.sum() / hb.size
    err = lambda a: a.std(axis=0, ddof=1) / np.sqrt(n_blocks)  # noqa: E731
    return mean_b.mean(0), err(mean_b), frac_b.mean(0), err(frac_b)


@skipIfMissingFeatures("LUBRICATION", "CONTACT", "MASS")
class LubricationFDT(unittest.TestCase):

    def test_fdt_noise(self):
        h, e = run_pairs("fdt")
        T, T_err, frac, frac_err = binned(h, e)
        want = expected_fractions()
        g = frac / want
        g_err = frac_err / want
        print("\nfdt   bins", BINS)
        print("  mu v_n^2/kT", np.round(T, 4), "+-", np.round(T_err, 4))
        print("  g(h)/theory", np.round(g, 4), "+-", np.round(g_err, 4))
        for j in range(len(T)):
            self.assertLess(T_err[j], 0.012, f"bin {j}: too few samples for a 3 % test")
            self.assertLess(g_err[j], 0.02, f"bin {j}: too few samples for a 5 % test")
            self.assertLess(abs(T[j] - 1), 0.03, f"bin {j}: <mu v_n^2> = {T[j]:.4f} kT")
            self.assertLess(abs(g[j] - 1), 0.05, f"bin {j}: g/theory = {g[j]:.4f}")

    def test_fdt_shifted(self):
        h, e = run_pairs("fdt", n_samples=24000, form="shifted")
        T, T_err, _, _ = binned(h, e)
        print("\nshifted mu v_n^2/kT", np.round(T, 4), "+-", np.round(T_err, 4))
        for j in range(len(T)):
            self.assertLess(T_err[j], 0.025, f"bin {j}: too few samples")
            self.assertLess(abs(T[j] - 1), 4 * T_err[j], f"bin {j}: <mu v_n^2> = {T[j]:.4f} kT")

    def test_seed_noise_deficit(self):
        h, e = run_pairs("seed", n_samples=10000)
        T, T_err, _, _ = binned(h, e)
        print("\nseed  mu v_n^2/kT", np.round(T, 4), "+-", np.round(T_err, 4))
        # without other thermostat the pairs cool far below kT (pairs that slow
        # down stay out of the inner bins: those may be empty)
        sel = (h < H_CUT) & (h >= 0)
        self.assertGreater(sel.sum(), 1000)
        self.assertLess(e[sel].mean() / KT, 0.5)
        for j in np.flatnonzero(np.isfinite(T)):
            self.assertLess(T[j], 0.95, f"bin {j}")


if __name__ == "__main__":
    unittest.main()
