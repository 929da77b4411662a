# labels: python long
"""A sheared DPD fluid under Lees-Edwards boundary conditions
(marble.lees_edwards, doc/lees-edwards.md): Groot-Warren water (rho = 3,
a = 25, gamma = 4.5, w_D = (1 - r)^2, kT = 1, dt = 0.01) in an 8 x 8 x 8 box
sheared at rate 0.3 (shear velocity 2.4 across L_y = 8), 700 time units
(a 6 x 8 x 6 box reads ~2-4 % lower, doc/lees-edwards.md):
(a) the mean velocity profile is linear (chi^2 of a line through 16 bin
    means) with the imposed rate (within 3 error bars of the fitted slope);
(b) the kinetic temperature of the peculiar velocities is kT (within 0.02,
    the ~0.7 % hot drift of plain velocity Verlet at dt = 0.01 plus viscous
    heating, and 3 error bars);
(c) eta = -<P_xy>/rate (P = kinetic + conservative + DPD pair stress, through
    the Lees-Edwards images) agrees with the reverse-Poiseuille measurement of
    the same fluid (doc/dpd.md: 0.844 +/- 0.012 and 0.851 +/- 0.017, pooled
    0.846 +/- 0.010) within 3 combined error bars.
Errors: blocking analysis (marble.viscosity.block_average). ~35 s."""
import numpy as np

import marble
import marble.lees_edwards as le
from marble.viscosity import block_average

ETA_RP, ETA_RP_ERR = 0.846, 0.010  # doc/dpd.md, pooled reverse Poiseuille of GW water


def test_sheared_dpd_fluid_viscosity():
    L = np.array([8.0, 8.0, 8.0])
    rate = 0.3
    V = rate * L[1]
    rng = np.random.default_rng(11)
    n = int(round(3.0 * np.prod(L)))
    s = marble.System(box_l=L)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    pos = rng.uniform(0, 1, (n, 3)) * L
    v = rng.normal(size=(n, 3))
    s.part.add(pos=pos, v=v - v.mean(axis=0))
    s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=11)
    s.integrator.run(1000)  # the overlaps of the random start relax at rest
    parts = s.part.all()
    v = np.asarray(parts.v)
    v[:, 0] += rate * (np.asarray(parts.pos_folded)[:, 1] - 0.5 * L[1])  # the steady profile
    parts.v = v
    s.lees_edwards.set_boundary_conditions(shear_direction="x", shear_plane_normal="y",
                                           protocol=le.LinearShear(shear_velocity=V))
    # 20 time units (a deviation from the linear profile decays in rho L^2 / (pi^2 eta) ~ 23)
    s.integrator.run(2000)
    n_bins = 16
    edges = np.linspace(0, L[1], n_bins + 1)
    pxy, prof, kts = [], [], []
    for _ in range(7000):  # 700 time units
        s.integrator.run(10)
        pt = s.analysis.pressure_tensor()
        p = pt["total"] + pt["dpd"]
        pxy.append(0.5 * (p[0, 1] + p[1, 0]))
        y = np.asarray(parts.pos_folded)[:, 1]
        vel = np.asarray(parts.v)
        idx = np.clip(np.digitize(y, edges) - 1, 0, n_bins - 1)
        vx = np.bincount(idx, vel[:, 0], n_bins) / np.maximum(np.bincount(idx, None, n_bins), 1)
        prof.append(vx)
        c = vel.copy()
        c[:, 0] -= rate * y  # peculiar velocities (profile slope imposed; offset removed below)
        c -= c.mean(axis=0)
        kts.append((c ** 2).sum() / (3 * (n - 1)))
    prof = np.array(prof)
    # (a) linear profile with the imposed rate: fit slope over the bin means
    yc = 0.5 * (edges[1:] + edges[:-1])
    # blocks up to 700/8 time units: longer than the slowest profile mode's
    # relaxation time rho (L / 2 pi)^2 / eta ~ 6
    means, errs = zip(*(block_average(prof[:, k], min_blocks=8) for k in range(n_bins)))
    means, errs = np.array(means), np.array(errs)
    A = np.vstack([yc, np.ones_like(yc)]).T / errs[:, None]
    coef, *_ = np.linalg.lstsq(A, means / errs, rcond=None)
    cov = np.linalg.inv(A.T @ A)
    slope, slope_err = coef[0], np.sqrt(cov[0, 0])
    resid = (means - (coef[0] * yc + coef[1])) / errs
    chi2 = float((resid ** 2).sum())
    # (b) temperature of the peculiar velocities
    kt, kt_err = block_average(kts)
    # (c) viscosity
    mp, mp_err = block_average(pxy)
    eta, eta_err = -mp / rate, mp_err / rate
    comb = np.hypot(eta_err, ETA_RP_ERR)
    print("profile residuals / error:", np.round(resid, 1))
    print(f"\nLE shear rate {rate}: slope {slope:.4f} +/- {slope_err:.4f} (chi2 {chi2:.1f} / "
          f"{n_bins - 2}), kT {kt:.4f} +/- {kt_err:.4f}, eta {eta:.4f} +/- {eta_err:.4f} "
          f"(reverse Poiseuille {ETA_RP} +/- {ETA_RP_ERR})")
    assert abs(slope - rate) < 3 * slope_err + 1e-3
    dof = n_bins - 2
    assert chi2 < dof + 4 * np.sqrt(2 * dof)  # linear (4 sigma of chi^2)
    # plain velocity Verlet at dt = 0.01 runs DPD water ~0.7 % hot (doc/dpd.md), plus viscous heating
    assert abs(kt - 1.0) < 0.02 + 3 * kt_err
    assert eta_err < 0.05, "run too short for a meaningful check"
    assert abs(eta - ETA_RP) < 3 * comb
