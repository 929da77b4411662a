# labels: python long
"""A sheared DPD fluid under Lees-Edwards boundary conditions integrated with
the Shardlow S1 splitting (doc/lees-edwards.md): the settings of
test_lees_edwards_viscosity.py (Groot-Warren water, rho = 3, a = 25,
gamma = 4.5, w_D = (1 - r)^2, kT = 1, dt = 0.01, 8 x 8 x 8 box, rate 0.3,
10 time units at rest, 20 sheared, then 700 time units sampled every 10 steps):
(a) the mean velocity profile is linear with the imposed rate (chi^2 of a
    line through 16 bin means; slope within 3 error bars);
(b) the kinetic temperature of the peculiar velocities is kT within
    0.015 + 3 error bars (at rest Shardlow runs this fluid at 1.001 at
    dt = 0.01, doc/stability.md; the shear at rate 0.3 adds ~0.9 %, as it
    adds ~0.8 % to velocity Verlet's 1.007: measured 1.0103 and 1.0145);
(c) eta = -<P_xy>/rate agrees with the reverse-Poiseuille value of the same
    fluid (doc/dpd.md, 0.846 +/- 0.010, which the velocity Verlet run also
    matches) within 3 combined error bars.
The DPD part of P_xy is the pair friction + noise of the current velocities
(System::dpd_stress), the same estimator as for velocity Verlet.
Errors: blocking analysis (marble.viscosity.block_average). ~45 s.
Measured (seed 11): slope 0.2994 +/- 0.0006 (chi^2 25.2 / 14), kT 1.0103 +/-
0.0008, eta 0.873 +/- 0.012; velocity Verlet with the same settings
(`python3 test_lees_edwards_shardlow.py vv`): 0.2998, 1.0145, 0.851 +/- 0.012."""
import numpy as np

import marble
import marble.lees_edwards as le
from marble.viscosity import block_average

ETA_RP, ETA_RP_ERR = 0.846, 0.010  # doc/dpd.md, pooled reverse Poiseuille of GW water


def sheared_fluid(integrator="shardlow", L=(8.0, 8.0, 8.0), rate=0.3, dt=0.01, t_run=700.0, seed=11):
    L = np.asarray(L, dtype=float)
    V = rate * L[1]
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
    parts = s.part.all()
    v = np.asarray(parts.v)
    v[:, 0] += rate * (np.asarray(parts.pos_folded)[:, 1] - 0.5 * L[1])  # the steady profile
    parts.v = v
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                           protocol=le.LinearShear(shear_velocity=V))
    s.integrator.run(int(round(20.0 / dt)))
    n_bins = 16
    edges = np.linspace(0, L[1], n_bins + 1)
    pxy, prof, kts = [], [], []
    every = max(1, int(round(0.1 / dt)))
    for _ in range(int(round(t_run / (every * dt)))):
        s.integrator.run(every)
        pt = s.analysis.pressure_tensor()
        p = pt["total"] + pt["dpd"]
        pxy.append(0.5 * (p[0, 1] + p[1, 0]))
        y = np.asarray(parts.pos_folded)[:, 1]
        vel = np.asarray(parts.v)
        idx = np.clip(np.digitize(y, edges) - 1, 0, n_bins - 1)
        prof.append(np.bincount(idx, vel[:, 0], n_bins) / np.maximum(np.bincount(idx, None, n_bins), 1))
        c = vel.copy()
        c[:, 0] -= rate * y
        c -= c.mean(axis=0)
        kts.append((c ** 2).sum() / (3 * (n - 1)))
    prof = np.array(prof)
    yc = 0.5 * (edges[1:] + edges[:-1])
    means, errs = zip(*(block_average(prof[:, k], min_blocks=8) for k in range(n_bins)))
    means, errs = np.array(means), np.array(errs)
    A = np.vstack([yc, np.ones_like(yc)]).T / errs[:, None]
    coef, *_ = np.linalg.lstsq(A, means / errs, rcond=None)
    cov = np.linalg.inv(A.T @ A)
    resid = (means - (coef[0] * yc + coef[1])) / errs
    kt, kt_err = block_average(kts)
    mp, mp_err = block_average(pxy)
    return dict(slope=coef[0], slope_err=np.sqrt(cov[0, 0]), chi2=float((resid ** 2).sum()),
                dof=n_bins - 2, kt=kt, kt_err=kt_err, eta=-mp / rate, eta_err=mp_err / rate, rate=rate)


def test_sheared_dpd_fluid_shardlow():
    r = sheared_fluid("shardlow")
    print(f"\nLE + Shardlow, rate {r['rate']}: slope {r['slope']:.4f} +/- {r['slope_err']:.4f} "
          f"(chi2 {r['chi2']:.1f} / {r['dof']}), kT {r['kt']:.4f} +/- {r['kt_err']:.4f}, "
          f"eta {r['eta']:.4f} +/- {r['eta_err']:.4f} (reverse Poiseuille {ETA_RP} +/- {ETA_RP_ERR})")
    assert abs(r["slope"] - r["rate"]) < 3 * r["slope_err"] + 1e-3
    assert r["chi2"] < r["dof"] + 4 * np.sqrt(2 * r["dof"])
    assert abs(r["kt"] - 1.0) < 0.015 + 3 * r["kt_err"]
    assert r["eta_err"] < 0.05, "run too short for a meaningful check"
    assert abs(r["eta"] - ETA_RP) < 3 * np.hypot(r["eta_err"], ETA_RP_ERR)


if __name__ == "__main__":
    import sys
    import time
    for integ in sys.argv[1:] or ["shardlow"]:
        t0 = time.time()
        r = sheared_fluid(integ)
        print(integ, {k: round(float(v), 4) for k, v in r.items()}, f"{time.time() - t0:.1f} s", flush=True)
