# labels: python long
"""A sheared DPD fluid under Lees-Edwards boundary conditions
(marble.lees_edwards, doc/lees-edwards.md), integrated with velocity Verlet
and with the Shardlow S1 splitting: Groot-Warren water (rho = 3, a = 25,
gamma = 4.5, w_D = (1 - r)^2, kT = 1, dt = 0.01) in an 8 x 8 x 8 box, 10 time
units at rest, then sheared at rate 0.3 (shear velocity 2.4 across L_y = 8),
20 time units, then 700 time units sampled every 10 steps (a 6 x 8 x 6 box
reads ~2-4 % lower, doc/lees-edwards.md):
(a) the mean velocity profile is linear (chi^2 of a line through 16 bin
    means) with the imposed rate (within 3 error bars of the fitted slope);
(b) the kinetic temperature of the peculiar velocities is kT: velocity Verlet
    within 0.02 (its ~0.7 % hot drift at dt = 0.01 plus viscous heating),
    Shardlow within 0.015 (1.001 at rest, doc/stability.md; the shear adds
    ~0.9 %), each plus 3 error bars;
(c) eta = -<P_xy>/rate (P = kinetic + conservative + DPD pair stress, through
    the Lees-Edwards images) agrees with the reverse-Poiseuille measurement of
    the same fluid (doc/dpd.md: 0.844 +/- 0.012 and 0.851 +/- 0.017, pooled
    0.846 +/- 0.010) within 3 combined error bars.
Measured by marble.viscosity.lees_edwards_viscosity (errors by blocking,
at least 16 blocks). ~35 s (VV) and
~45 s (Shardlow). Measured (seed 11): VV slope 0.2992 +/- 0.0007 (chi^2
10.0 / 14), kT 1.0171 +/- 0.0008, eta 0.857 +/- 0.012; Shardlow slope 0.2995
+/- 0.0005 (chi^2 12.5 / 14), kT 1.0104 +/- 0.0008, eta 0.838 +/- 0.012. `python3 test_lees_edwards_viscosity.py vv
shardlow` prints both."""
import numpy as np
import pytest

import marble
from marble.viscosity import lees_edwards_viscosity

pytestmark = pytest.mark.skipif(not marble.has_features("HAT"), reason="Groot-Warren water needs the HAT feature")

ETA_RP, ETA_RP_ERR = 0.846, 0.010  # doc/dpd.md, pooled reverse Poiseuille of GW water


def sheared_fluid(integrator="shardlow", L=(8.0, 8.0, 8.0), rate=0.3, dt=0.01, t_run=700.0, seed=11):
    L = np.asarray(L, dtype=float)
    rng = np.random.default_rng(seed)
    n = int(round(3.0 * np.prod(L)))
    s = marble.System(box_l=L)
    s.time_step = dt
    s.cell_system.skin = 0.4
    pos = rng.uniform(0, 1, (n, 3)) * L
    v = rng.normal(size=(n, 3))
    s.part.add(pos=pos, v=v - v.mean(axis=0))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    if integrator == "shardlow":
        s.integrator.set_shardlow()
    s.integrator.run(int(round(10.0 / dt)))  # the overlaps of the random start relax at rest
    # the steady profile to start, 20 time units sheared, then sampled every 0.1
    r = lees_edwards_viscosity(s, rate, t_run, equilibration=20.0, sample_every=max(1, int(round(0.1 / dt))),
                               n_bins=16, min_blocks=16)
    return dict(slope=r.slope, slope_err=r.slope_err, chi2=r.chi2, dof=r.dof, kt=r.kT, kt_err=r.kT_err,
                eta=r.eta, eta_err=r.eta_err, rate=rate)


def check(r, kt_tol):
    print(f"\nLE, rate {r['rate']}: slope {r['slope']:.4f} +/- {r['slope_err']:.4f} "
          f"(chi2 {r['chi2']:.1f} / {r['dof']}), kT {r['kt']:.4f} +/- {r['kt_err']:.4f}, "
          f"eta {r['eta']:.4f} +/- {r['eta_err']:.4f} (reverse Poiseuille {ETA_RP} +/- {ETA_RP_ERR})")
    assert abs(r["slope"] - r["rate"]) < 3 * r["slope_err"] + 1e-3
    assert r["chi2"] < r["dof"] + 4 * np.sqrt(2 * r["dof"])  # linear (4 sigma of chi^2)
    assert abs(r["kt"] - 1.0) < kt_tol + 3 * r["kt_err"]
    assert r["eta_err"] < 0.05, "run too short for a meaningful check"
    assert abs(r["eta"] - ETA_RP) < 3 * np.hypot(r["eta_err"], ETA_RP_ERR)


def test_sheared_dpd_fluid_viscosity():
    check(sheared_fluid("vv"), 0.02)


def test_sheared_dpd_fluid_shardlow():
    check(sheared_fluid("shardlow"), 0.015)


if __name__ == "__main__":
    import sys
    import time
    for integ in sys.argv[1:] or ["vv", "shardlow"]:
        t0 = time.time()
        r = sheared_fluid(integ)
        print(integ, {k: round(float(v), 4) for k, v in r.items()}, f"{time.time() - t0:.1f} s", flush=True)
