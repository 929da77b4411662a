"""Is the stick colloid one no-slip sphere? Its rotational radius against its drag
radius (issue 13, doc/suspensions.md section 7m).

One calibrated stick colloid (``setup_suspension(boundary="stick")``'s defaults:
core a = R/STICK_RADIUS_RATIO, ``trans_gamma`` 45, the default shell; R = 1;
``solvent_count="exact"``) at the centre of a periodic cube of edge L in seed
004's solvent (rho = 3, kT = 0.1, gamma = 4.5, a_ss = 25 kT, r_c = 1), Shardlow
dt = 0.01 (section 7d's drag scene; L = 4.3756 puts the sphere of radius R at
phi = 0.05).

- ``--part drive``: a constant external torque T e_z on the colloid (particle
  ``ext_torque``, feature ROTATION + EXTERNAL_FORCE); after ``--settle`` time units
  the spin omega(t) is sampled every ``--every`` steps for ``--time``. The
  rotational friction in the box is zeta_L = T/<omega_z>; the error of <omega_z>
  is the larger of the blocking error and sqrt(2 D_r/t) with D_r = kT/zeta_L (the
  thermal angle's diffusion). The fluctuations delta omega = omega - <omega> give
  a Green-Kubo cross-check D_r = (1/3) int_0^tmax <delta omega(0) . delta omega(t)> dt
  (10 blocks) and the spin's equipartition <I delta omega^2>/(3 kT), and the colloid's
  translational D from its MSD (lags 20-100, 10 blocks; a torque about z does not
  move a sphere at linear order), in the lab frame.
- ``--part table``: groups the drive runs of ``--results`` by (L, T), combines
  the seeds (weighted, error scaled by sqrt(chi^2/dof) when above 1), removes
  the periodic images (theory.rotational_friction_unbounded: 1/zeta_0 =
  1/zeta_L + 1/(6 eta L^3)), gives R_r = (zeta_0/(8 pi eta_0))^(1/3) with eta_0 =
  0.3290(30) (section 7d), compares it with the drag radius R_t = c a (c =
  STICK_RADIUS_RATIO = 1.013(10), section 7d), fits the Navier-slip sphere
  (a, beta) to (R_t, R_r) where one exists (R_r <= R_t), converts the MSD D to the
  motion relative to the solvent (x (1 + M/M_s)^2, zero total momentum) for a
  second, force-free R_t, and gives Krieger-Dougherty at phi and at phi (R_r/R)^3
  against the measured uniform-shear eta_r.
- The stick colloid's settings (section 7n): ``--trans-gamma`` and ``--stick-shell``
  (drive; default None = setup_suspension's 45 and r'_c(a)) are passed to
  setup_suspension and recorded; ``table`` groups by them too (runs without the keys
  are the defaults, whose rows and combined blocks stay those of section 7m) and,
  when ``--results`` holds stick drag runs (bench/suspension_hasimoto.py --part drag
  --boundary stick --solvent-count exact [--stick-gamma G] [--stick-shell S]) or
  other settings, adds one row per (core a, trans_gamma, shell): R_r/a (torque),
  R_t/a (drag; MSD) and R_r/R_t.

    build/pymarble bench/stick_colloid_radii.py --part drive --torque 0.85 --time 10000 --seed 1 \\
        --json bench/results/stick_colloid_radii.jsonl
    build/pymarble bench/stick_colloid_radii.py --part drive --L 6 --torque 0.85 --time 10000 --seed 1 \\
        --json bench/results/stick_colloid_radii.jsonl
    build/pymarble bench/stick_colloid_radii.py --part table --results bench/results/stick_colloid_radii.jsonl
    build/pymarble bench/stick_colloid_radii.py --part drive --radius-calibration none --trans-gamma 15 \
        --time 10000 --seed 1 --json bench/results/stick_colloid_radii_scan.jsonl
    build/pymarble bench/stick_colloid_radii.py --part table --results bench/results/stick_colloid_radii_scan.jsonl \
        bench/results/stick_colloid_radii_drag.jsonl

Runs append one JSON line each (``--json``); ``table`` reads them back.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

import marble
import marble.suspensions as sus
from marble import theory

R, KT, GAMMA, DT = 1.0, 0.1, 4.5, 0.01
L_PHI05 = (4.0 * math.pi * R ** 3 / (3.0 * 0.05)) ** (1.0 / 3.0)  # 4.3756
ETA0, ETA0_ERR = 0.3290, 0.0030  # doc/suspensions.md section 7d, exact density 3
# the drag radius of section 7d: R_t/a = c with the core a; its error without
# eta_0's (the runs' D only, 0.0092) and with it (0.010); D of the a = 1 runs
C_T, C_T_ERR = sus.STICK_RADIUS_RATIO, 0.010
D_CORE1, D_CORE1_ERR, L_CORE1 = 0.00628, 0.00014, L_PHI05
# uniform-shear eta_r of the stick defaults (doc/suspensions.md 7k: 9, 14, 11 seeds) and
# the values quoted in issue 13 (7j's phi = 0.098 over five seeds, 7e's bulk-solvent 0.2)
MEASURED_ETA_R = ((0.098, "1.322(27) (7k); 1.391(58) (7j)"), (0.196, "2.043(34) (7k)"),
                  (0.1966, "2.40(9) (7e, reverse Poiseuille)"), (0.303, "3.695(54) (7k)"))


def parse(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--part", choices=["drive", "table"], required=True)
    p.add_argument("--L", type=float, default=L_PHI05, help="box edge (default 4.3756: phi = 0.05)")
    p.add_argument("--torque", type=float, default=0.85,
                   help="external torque on the colloid along z (0.85: omega R ~ 0.1)")
    p.add_argument("--time", type=float, default=10000.0, help="production time (time units)")
    p.add_argument("--settle", type=float, default=50.0, help="time with the torque on before sampling")
    p.add_argument("--equil", type=float, default=20.0, help="time at rest before the torque")
    p.add_argument("--every", type=int, default=5, help="sample the spin every this many steps")
    p.add_argument("--tmax", type=float, default=10.0, help="Green-Kubo integration limit")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--dt", type=float, default=DT)
    p.add_argument("--solvent-count", choices=["exact", "poisson", "bulk"], default="exact")
    p.add_argument("--radius-calibration", default="stick",
                   help="setup_suspension's radius_calibration ('stick', 'rotation', 'stresslet', 'none' or a number)")
    p.add_argument("--trans-gamma", type=float, default=None,
                   help="drive: the surface_friction's gamma (default None: setup_suspension's 45)")
    p.add_argument("--stick-shell", type=float, default=None,
                   help="drive: the friction shell's thickness on the gap (default None: setup_suspension's r'_c(a))")
    p.add_argument("--json", help="append the result (one JSON line) to this file")
    p.add_argument("--results", nargs="+", help="table: JSON-lines files of drive runs")
    p.add_argument("--eta0", type=float, nargs=2, default=[ETA0, ETA0_ERR], help="table: eta_0 and its error")
    args = p.parse_args(argv)
    if args.part == "drive":
        for name in ("L", "time", "settle", "tmax", "dt"):
            v = getattr(args, name)
            if not (math.isfinite(v) and v > 0):
                p.error(f"--{name} must be > 0, got {v}")
        if args.L < 3.0:
            p.error(f"--L must be >= 3 (the colloid's own image), got {args.L}")
        if not math.isfinite(args.torque):
            p.error("--torque must be finite")
        if args.every < 1:
            p.error("--every must be >= 1")
        for name in ("trans_gamma", "stick_shell"):
            v = getattr(args, name)
            if v is not None and not (math.isfinite(v) and v > 0):
                p.error(f"--{name.replace('_', '-')} must be > 0, got {v}")
    elif not args.results:
        p.error("--part table needs --results")
    return args


def colloid_box(args):
    """One calibrated stick colloid at the box centre, Shardlow, zero momentum."""
    s = marble.System(box_l=[args.L] * 3)
    s.time_step = args.dt
    s.cell_system.skin = 0.4
    rc = args.radius_calibration
    rc = sus.radius_calibration_arg(rc)
    phi = 4.0 * math.pi * R ** 3 / (3.0 * args.L ** 3)
    kw = {k: v for k, v in (("trans_gamma", args.trans_gamma), ("stick_shell", args.stick_shell)) if v is not None}
    info = sus.setup_suspension(s, phi=phi, radius=R, kT=KT, gamma=GAMMA, eta=0.3, seed=args.seed,
                                positions=[[args.L / 2] * 3], boundary="stick",
                                solvent_count=args.solvent_count, radius_calibration=rc, **kw)
    s.integrator.set_shardlow()
    p = s.part.all()
    v, m = np.asarray(p.v), np.asarray(p.mass)
    p.v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)
    return s, info


def acf_integral(x, lag, dt):
    """(1/3) int_0^{lag dt} <x(0) . x(t)> dt (trapezoid) of a (n, 3) series."""
    n = len(x)
    f = np.fft.rfft(x, n=2 * n, axis=0)
    acf = np.fft.irfft(f * np.conj(f), n=2 * n, axis=0)[:lag + 1].sum(axis=1) / (n - np.arange(lag + 1))
    return dt * (acf.sum() - 0.5 * acf[0] - 0.5 * acf[-1]) / 3.0, acf / 3.0


def msd_D(x, dt, lo=20.0, hi=100.0):
    """D = slope/6 of the MSD of a (n, 3) unfolded trajectory sampled every dt,
    fitted over lags lo..hi (on a 1-time-unit grid)."""
    k = max(1, int(round(1.0 / dt)))
    p = x[::k]
    h = dt * k
    lags = np.arange(int(round(lo / h)), int(round(hi / h)) + 1)
    msd = np.array([np.mean(np.sum((p[l:] - p[:-l]) ** 2, axis=1)) for l in lags])
    return float(np.polyfit(lags * h, msd, 1)[0] / 6.0)


def drive(args):
    from marble.accumulators import TimeSeries
    from marble.diffusion import blocking
    from marble.observables import ParticleAngularVelocities, ParticlePositions
    marble.assert_features("ROTATION", "EXTERNAL_FORCE", "TRANS_DPD", "DPD")
    t0 = time.process_time()
    s, info = colloid_box(args)
    cid = info["colloid_ids"]
    c = s.part.by_ids(cid)
    s.integrator.run(int(round(args.equil / args.dt)))
    c.ext_torque = [0.0, 0.0, args.torque]
    s.integrator.run(int(round(args.settle / args.dt)))
    ts = TimeSeries(obs=ParticleAngularVelocities(ids=cid, system=s), delta_N=args.every)
    tp = TimeSeries(obs=ParticlePositions(ids=cid, system=s), delta_N=args.every)
    s.auto_update_accumulators.add(ts)
    s.auto_update_accumulators.add(tp)
    steps = int(round(args.time / args.dt))
    chunk = max(args.every, int(round(100.0 / args.dt)) // args.every * args.every)
    kts, done = [], 0
    solvent = s.part.by_ids(sorted(set(int(i) for i in s.part.all().id) - set(cid)))
    while done < steps:
        n = min(chunk, steps - done)
        s.integrator.run(n)
        done += n
        v = np.asarray(solvent.v)
        kts.append(float(np.mean(v ** 2)))  # bead mass 1
    s.auto_update_accumulators.remove(ts)
    s.auto_update_accumulators.remove(tp)
    w = np.asarray(ts.time_series()).reshape(-1, 3)
    pos = np.asarray(tp.time_series()).reshape(-1, 3)
    wz = w[:, 2]
    blk = blocking(wz)
    omega = float(blk.mean)
    zeta_L = args.torque / omega if omega != 0 else float("nan")
    Dr_est = KT / zeta_L if zeta_L > 0 else KT / (8 * math.pi * ETA0 * R ** 3)
    err_diff = math.sqrt(2.0 * Dr_est / args.time)
    err = max(blk.error, err_diff)
    zeta_err = abs(args.torque) * err / omega ** 2 if omega != 0 else float("nan")
    # Green-Kubo of the fluctuations and equipartition, 10 blocks
    dw = w - w.mean(axis=0)
    tau = args.every * args.dt
    lag = int(round(args.tmax / tau))
    blocks = np.array_split(np.arange(len(dw)), 10)
    I_rot = float(np.asarray(c.rinertia)[0][0]) if np.ndim(c.rinertia) == 2 else float(info["rinertia"])
    gk = np.array([acf_integral(dw[b], lag, tau)[0] for b in blocks])
    gk_perp = np.array([acf_integral(np.c_[dw[b][:, :2], np.zeros(len(b))], lag, tau)[0] * 1.5 for b in blocks])
    ke = np.array([I_rot * np.mean(dw[b] ** 2) / KT for b in blocks])
    sq = math.sqrt(len(blocks))
    # the colloid's translational D (equilibrium: a torque along z does not move a
    # sphere at linear order) from the MSD slope over lags 20-100 per block, in the lab frame
    # (the table converts it to the motion relative to the solvent, as Hasimoto's D(L))
    Dm = np.array([msd_D(pos[b], tau) for b in blocks])
    rho = float(info["n_solvent"]) / (args.L ** 3 - 4.0 / 3.0 * math.pi * info["core_radius"] ** 3)
    out = dict(part="drive", L=args.L, torque=args.torque, seed=args.seed, time=args.time, dt=args.dt,
               settle=args.settle, every=args.every, n_solvent=info["n_solvent"], rho_free=rho,
               core_radius=info["core_radius"], radius_ratio=info["radius_ratio"], rinertia=I_rot,
               solvent_count=args.solvent_count, radius_calibration=info["radius_calibration"],
               trans_gamma=info.get("trans_gamma"), stick_shell=args.stick_shell,
               stick_shell_used=info.get("stick_shell"),
               omega=[float(x) for x in w.mean(axis=0)], omega_z=omega, omega_err=err,
               omega_err_blocking=float(blk.error), omega_err_diffusion=err_diff,
               blocking_converged=bool(blk.converged), zeta_L=zeta_L, zeta_L_err=zeta_err,
               surface_speed=omega * R, Re_rot=3.0 * omega * R ** 2 / ETA0,
               D_r_gk=float(gk.mean()), D_r_gk_err=float(gk.std(ddof=1) / sq),
               D_r_gk_perp=float(gk_perp.mean()), D_r_gk_perp_err=float(gk_perp.std(ddof=1) / sq),
               tmax=args.tmax, kT_rot=float(ke.mean()), kT_rot_err=float(ke.std(ddof=1) / sq),
               D_msd=float(Dm.mean()), D_msd_err=float(Dm.std(ddof=1) / sq), msd_window=[20.0, 100.0],
               kT_solvent=float(np.mean(kts)), cpu_s=time.process_time() - t0)
    print(f"L = {args.L:.4f}, {info['n_solvent']} beads (free-volume density {rho:.4f}), core a = "
          f"{info['core_radius']:.4f}, T = {args.torque}: <omega> = ({out['omega'][0]:+.5f}, "
          f"{out['omega'][1]:+.5f}, {omega:.5f} +/- {err:.5f}) (blocking {blk.error:.5f}, "
          f"sqrt(2 D_r/t) {err_diff:.5f}); zeta_L = {zeta_L:.4f} +/- {zeta_err:.4f}; "
          f"Re_rot = {out['Re_rot']:.3f}")
    print(f"Green-Kubo D_r (to t = {args.tmax}) = {out['D_r_gk']:.5f} +/- {out['D_r_gk_err']:.5f} "
          f"(x, y only {out['D_r_gk_perp']:.5f} +/- {out['D_r_gk_perp_err']:.5f}); kT/zeta_L = {KT / zeta_L:.5f}; "
          f"<I dw^2>/(3 kT) = {out['kT_rot']:.4f} +/- {out['kT_rot_err']:.4f}; D (MSD) = {out['D_msd']:.5f} +/- "
          f"{out['D_msd_err']:.5f}; solvent kT {out['kT_solvent']:.4f}; "
          f"CPU {out['cpu_s']:.0f} s")
    return out


def weighted(x, e):
    x, e = np.asarray(x, float), np.asarray(e, float)
    w = 1.0 / e ** 2
    m = float(np.sum(w * x) / np.sum(w))
    err = float(1.0 / math.sqrt(np.sum(w)))
    chi2 = float(np.sum(w * (x - m) ** 2))
    dof = len(x) - 1
    if dof > 0 and chi2 > dof:
        err *= math.sqrt(chi2 / dof)
    return m, err, chi2, dof


def table(args):
    eta, eta_err = args.eta0
    lines = []
    for fn in args.results:
        with open(fn) as f:
            lines += [json.loads(line) for line in f if line.strip()]
    runs = [r for r in lines if r.get("part") == "drive"]
    if not runs:
        sys.exit("no drive runs in --results")
    groups = {}
    for r in runs:
        groups.setdefault((round(r["L"], 4), r["torque"], round(r["core_radius"], 6)) + setting(r)
                          + (r.get("dt", DT),), []).append(r)
    print(f"eta_0 = {eta} +/- {eta_err}; drag radius R_t = c a, c = {C_T} +/- {C_T_ERR} (section 7d)")
    print("| L | T | core a | seeds | time units | <omega> R | Re_rot | zeta_L (chi^2/dof) | zeta_0 | "
          "R_r | R_r/a | GK D_r / (kT/zeta_L) | <I dw^2>/3kT | CPU-s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    out = dict(part="table", eta0=eta, eta0_err=eta_err, groups=[])
    for (L, T, a, g, sh, dt), rs in sorted(groups.items(), key=lambda kv: _sort_key(kv[0])):
        z, ze, chi2, dof = weighted([r["zeta_L"] for r in rs], [r["zeta_L_err"] for r in rs])
        z0, z0e = theory.rotational_friction_unbounded(z, eta, L, zeta_err=ze)
        Rr, Rre = theory.rotational_radius(z0, eta, zeta_err=z0e, eta_err=0.0)
        _, Rre_eta = theory.rotational_radius(z0, eta, zeta_err=0.0, eta_err=eta_err)
        om = float(np.mean([r["omega_z"] for r in rs]))
        gk = weighted([r["D_r_gk"] * r["zeta_L"] / KT for r in rs], [r["D_r_gk_err"] * r["zeta_L"] / KT for r in rs])
        ke = weighted([r["kT_rot"] for r in rs], [r["kT_rot_err"] for r in rs])
        seeds = ",".join(str(r["seed"]) for r in rs)
        tt = sum(r["time"] for r in rs)
        cpu = sum(r.get("cpu_s", 0.0) for r in rs)
        print(f"| {L:.4f} | {T} | {a:.4f}{setting_label(g, sh, dt)} | {seeds} | {tt:.0f} | {om * R:.4f} | {3 * om * R ** 2 / eta:.2f} | "
              f"{z:.4f} +/- {ze:.4f} ({chi2:.1f}/{dof}) | {z0:.4f} +/- {z0e:.4f} | {Rr:.4f} +/- {Rre:.4f} "
              f"(eta_0: {Rre_eta:.4f}) | {Rr / a:.4f} +/- {Rre / a:.4f} | {gk[0]:.3f} +/- {gk[1]:.3f} | "
              f"{ke[0]:.4f} +/- {ke[1]:.4f} | {cpu:.0f} |")
        dm = [r for r in rs if "D_msd" in r]
        if len(dm) >= 2:
            Dm = weighted([r["D_msd"] for r in dm], [r["D_msd_err"] for r in dm])
            fac = (1.0 + 4.0 * math.pi * a ** 3 / dm[0]["n_solvent"]) ** 2  # to the solvent's frame (below)
            Dm = (Dm[0] * fac, Dm[1] * fac, Dm[2], Dm[3])
            Rt_m, Rt_me = theory.hydrodynamic_radius_from_D(Dm[0], eta, L, D_err=Dm[1], kT=KT)
            print(f"|   | equilibrium D (MSD, {len(dm)} runs) = {Dm[0]:.5f} +/- {Dm[1]:.5f} (chi^2 {Dm[2]:.1f}/{Dm[3]}): "
                  f"Hasimoto stick R_t = {Rt_m:.3f} +/- {Rt_me:.3f} (R_t/a {Rt_m / a:.3f}) |")
        else:
            Dm, Rt_m, Rt_me = (None, None, None, None), None, None
        out["groups"].append(dict(L=L, torque=T, core_radius=a, trans_gamma=g, stick_shell=sh, dt=dt, n=len(rs), time=tt, zeta_L=z, zeta_L_err=ze,
                                  D_msd=Dm[0], D_msd_err=Dm[1], R_t_msd=Rt_m, R_t_msd_err=Rt_me,
                                  chi2=chi2, dof=dof, zeta_0=z0, zeta_0_err=z0e, R_r=Rr, R_r_err=Rre,
                                  R_r_err_eta=Rre_eta, omega=om, gk_ratio=gk[0], gk_ratio_err=gk[1],
                                  kT_rot=ke[0], kT_rot_err=ke[1], cpu_s=cpu))
    # all calibrated groups together: zeta_0 (box-corrected) per group, weighted
    # other cores (e.g. --radius-calibration none: a = 1, the core of section 7d's drag runs)
    # (setup_suspension's default trans_gamma and shell only; other settings: the scan block at the end)
    dflt = [g for g in out["groups"] if is_default(g["trans_gamma"], g["stick_shell"]) and g["dt"] == DT]
    for a in sorted({g["core_radius"] for g in dflt}):
        if abs(a - R / C_T) < 1e-4:
            continue
        gs = [g for g in dflt if g["core_radius"] == a]
        z0, z0e, chi2, dof = weighted([g["zeta_0"] for g in gs], [g["zeta_0_err"] for g in gs])
        Rr, Rre = theory.rotational_radius(z0, eta, zeta_err=z0e)
        Rt_a = theory.hydrodynamic_radius_from_D(D_CORE1, eta, L_CORE1, kT=KT)[0]
        print(f"\ncore a = {a:.4f}: zeta_0 = {z0:.4f} +/- {z0e:.4f}; R_r/a = {Rr / a:.4f} +/- {Rre / a:.4f} "
              f"(zeta; eta_0 cancels in the ratio); R_r/R_t = {Rr / a / Rt_a:.4f} with section 7d's a = 1 drag")
        out.setdefault("other_cores", []).append(dict(core_radius=a, zeta_0=z0, zeta_0_err=z0e,
                                                      R_r_over_a=Rr / a, R_r_over_a_err=Rre / a))
    cal = [g for g in dflt if abs(g["core_radius"] - R / C_T) < 1e-4]
    if cal:
        z0, z0e, chi2, dof = weighted([g["zeta_0"] for g in cal], [g["zeta_0_err"] for g in cal])
        a = cal[0]["core_radius"]
        Rr, Rre = theory.rotational_radius(z0, eta, zeta_err=z0e)
        _, Rre_eta = theory.rotational_radius(z0, eta, eta_err=eta_err)
        print(f"\nall calibrated groups (core a = {a:.4f}): zeta_0 = {z0:.4f} +/- {z0e:.4f} "
              f"(chi^2 {chi2:.1f}/{dof}); R_r = {Rr:.4f} +/- {Rre:.4f} (zeta) +/- {Rre_eta:.4f} (eta_0); "
              f"R_r/a = {Rr / a:.4f} +/- {math.hypot(Rre, Rre_eta) / a:.4f}")
        # the ratio R_r/R_t with eta_0 varied jointly (both radii fall with eta_0)
        def radii(e):
            Rt = theory.hydrodynamic_radius_from_D(D_CORE1, e, L_CORE1, kT=KT)[0]  # a = 1 runs: R_t/a
            Rr_ = theory.rotational_radius(z0, e)[0] / a
            return Rt, Rr_
        Rt_a, Rr_a = radii(eta)
        Rt_D = theory.hydrodynamic_radius_from_D(D_CORE1, eta, L_CORE1, D_err=D_CORE1_ERR, kT=KT)[1]
        q = Rr_a / Rt_a
        qe_eta = abs(radii(eta + eta_err)[1] / radii(eta + eta_err)[0] - q)
        qe = math.sqrt((Rre / a / Rt_a) ** 2 + (q * Rt_D / Rt_a) ** 2 + qe_eta ** 2)
        print(f"R_t/a (section 7d's a = 1 runs at this eta_0) = {Rt_a:.4f} +/- {Rt_D:.4f} (D); "
              f"R_r/R_t = {q:.4f} +/- {qe:.4f} (eta_0's part {qe_eta:.4f}: it cancels)")
        out.update(zeta_0=z0, zeta_0_err=z0e, chi2=chi2, dof=dof, R_r=Rr, R_r_err=Rre, R_r_err_eta=Rre_eta,
                   core_radius=a, R_r_over_a=Rr / a, R_t_over_a=Rt_a, R_t_over_a_err=Rt_D,
                   ratio_r_t=q, ratio_r_t_err=qe)
        # the drag-free R_t: the equilibrium MSD D of the calibrated runs in the L = 4.3756 box
        # with T <= 0.85 (a spinning sphere feels the lift pi a^3 rho Omega x v, Rubinow & Keller,
        # J. Fluid Mech. 11, 447 (1961), which turns its x-y velocity: D_xy falls by
        # 1/(1 + (rho a^2 Omega/(6 eta))^2), 1.6 % at T = 0.85, 6 % at T = 1.7)
        dm = [r for r in runs if "D_msd" in r and abs(r["core_radius"] - a) < 1e-6 and abs(r["L"] - L_CORE1) < 1e-3
              and r["torque"] <= 0.85 and is_default(*setting(r)) and r.get("dt", DT) == DT]
        if len(dm) >= 2:
            Dm, Dme, chi2m, dofm = weighted([r["D_msd"] for r in dm], [r["D_msd_err"] for r in dm])
            # the MSD is the colloid's lab (= centre-of-mass) frame displacement; Hasimoto's D(L), like the
            # drag (measure_drag: velocity relative to the solvent's centre of mass), is that of
            # X = r_c - R_solvent = r_c (1 + M/M_s) at zero total momentum: D_X = (1 + M/M_s)^2 D_lab
            # (colloid mass M = rho 4/3 pi a^3, setup_suspension's default; beads of mass 1)
            fac = (1.0 + 4.0 * math.pi * a ** 3 / dm[0]["n_solvent"]) ** 2
            print(f"equilibrium D (MSD, lab frame) = {Dm:.5f} +/- {Dme:.5f}; relative to the solvent x {fac:.4f}")
            Dm, Dme = Dm * fac, Dme * fac
            Rt_m, Rt_me = theory.hydrodynamic_radius_from_D(Dm, eta, L_CORE1, D_err=Dme, kT=KT)
            qm = Rr_a / (Rt_m / a)
            qme = qm * math.hypot(Rt_me / Rt_m, Rre / Rr)
            print(f"equilibrium D (MSD) of the {len(dm)} calibrated runs at L = {L_CORE1:.4f}: {Dm:.5f} +/- {Dme:.5f} "
                  f"(chi^2 {chi2m:.1f}/{dofm}): R_t = {Rt_m:.4f} +/- {Rt_me:.4f} (R_t/a {Rt_m / a:.4f}); "
                  f"R_r/R_t(MSD) = {qm:.4f} +/- {qme:.4f}")
            out.update(D_msd=Dm, D_msd_err=Dme, R_t_msd=Rt_m, R_t_msd_err=Rt_me, ratio_r_t_msd=qm,
                       ratio_r_t_msd_err=qme)
        # slip sphere through (R_t, R_r), and what it predicts
        try:
            asl, beta = theory.slip_sphere_from_radii(Rt_a, Rr_a)
            ie = theory.slip_sphere_intrinsic_viscosity(beta) * (asl / Rt_a) ** 3
            print(f"Navier-slip sphere through (R_t, R_r): a_slip = {asl:.4f} a, beta = {beta:.4f}; "
                  f"[eta] per phi(R_t) = {ie:.4f}")
            out.update(slip_a=asl, slip_beta=beta, intrinsic=ie)
        except ValueError as exc:
            print(f"no Navier-slip sphere through (R_t, R_r): {exc}")
            out.update(slip_a=None, slip_beta=None)
        # eta_r of Krieger-Dougherty for spheres of the drag radius (phi as built: R = c a)
        # and of the rotational radius (phi (R_r/R)^3), against the uniform-shear values
        Rr_tot = math.hypot(Rre, Rre_eta)
        print("\n| phi | measured eta_r | KD, radius R_t = R | KD, radius R_r: phi_eff | eta_r |")
        print("|---|---|---|---|---|")
        out["predictions"] = []
        for phi, meas in MEASURED_ETA_R:
            kd_t = theory.krieger_dougherty_viscosity(phi)
            pe = phi * Rr ** 3
            kd_r = theory.krieger_dougherty_viscosity(pe)
            kd_r_err = 0.5 * abs(theory.krieger_dougherty_viscosity(phi * (Rr + Rr_tot) ** 3)
                                 - theory.krieger_dougherty_viscosity(phi * (Rr - Rr_tot) ** 3))
            print(f"| {phi} | {meas} | {kd_t:.3f} | {pe:.4f} | {kd_r:.3f} +/- {kd_r_err:.3f} |")
            out["predictions"].append(dict(phi=phi, measured=meas, kd_R=kd_t, phi_eff=pe, kd_Rr=kd_r,
                                           kd_Rr_err=kd_r_err))
    scan = settings_scan(runs, drag_runs(lines), out["groups"], eta, eta_err)
    if scan:
        out["settings"] = scan
    return out


# --- the stick colloid's settings (trans_gamma, stick_shell): doc/suspensions.md section 7n ---
DEFAULT_TRANS_GAMMA = 45.0  # setup_suspension's default surface_friction gamma


def setting(r, gamma_key="trans_gamma"):
    """(trans_gamma, stick_shell) of a run; a run without the keys (or with None) has
    setup_suspension's defaults (45, None = the shell r'_c(a)). Drag runs of
    bench/suspension_hasimoto.py keep the surface_friction's gamma under 'stick_gamma'."""
    g = r.get(gamma_key)
    sh = r.get("stick_shell")
    return (DEFAULT_TRANS_GAMMA if g is None else float(g), None if sh is None else round(float(sh), 6))


def is_default(g, sh):
    return g == DEFAULT_TRANS_GAMMA and sh is None


def setting_label(g, sh, dt=DT):
    """'' for the defaults (the rows of section 7m unchanged), else ', trans_gamma G, shell S, dt D'."""
    return ((f", trans_gamma {g:g}" if g != DEFAULT_TRANS_GAMMA else "")
            + (f", shell {sh:g}" if sh is not None else "") + (f", dt {dt:g}" if dt != DT else ""))


def _sort_key(k):
    return tuple(-1.0 if x is None else x for x in k)


def drag_runs(lines):
    """The stick drag runs (bench/suspension_hasimoto.py --part drag --boundary stick, exact solvent
    count, no extra TRANS_DPD) among the JSON lines."""
    return [r for r in lines if r.get("part") == "drag" and r.get("boundary") == "stick" and not r.get("trans_gamma")
            and r.get("solvent_count") == "exact" and "core_radius" in r]


def _combine(vals):
    """Weighted mean of (value, error) pairs (error scaled by sqrt(chi^2/dof) when above 1)."""
    vals = [(v, e) for v, e in vals if v is not None and e is not None and e > 0]
    if not vals:
        return None, None
    m, e, _, _ = weighted([v for v, _ in vals], [e for _, e in vals])
    return m, e


def settings_scan(runs, drags, groups, eta, eta_err):
    """Per (core a, trans_gamma, stick_shell): R_r/a from the driven rotation (zeta_0 of the
    (L, T) groups at dt = 0.01 and T <= 0.85, weighted), R_t/a from the drag runs (Hasimoto's stick
    D(L)) and, as a check, from the drive runs' equilibrium MSD (L = 4.3756, T <= 0.85, x (1 +
    M/M_s)^2; a few % per setting, and the spin's lift lowers it by ~1-2 %), and R_r/R_t with
    the drag's R_t (the MSD's where a setting has no drag run) and eta_0 varied jointly.
    Printed only when there are drag runs or non-default settings."""
    # other time steps and larger torques: their own rows above only
    groups = [x for x in groups if x["dt"] == DT and x["torque"] <= 0.85]
    runs = [r for r in runs if r.get("dt", DT) == DT and r["torque"] <= 0.85]
    keys = {(g["core_radius"], g["trans_gamma"], g["stick_shell"]) for g in groups}
    keys |= {(round(r["core_radius"], 6),) + setting(r, "stick_gamma") for r in drags}
    if not drags and all(is_default(g, sh) for _, g, sh in keys):
        return []
    print("\nsettings (dt = 0.01, T <= 0.85; R_r by the torque, R_t by the drag (by the equilibrium MSD "
          f"without drag runs); eta_0 = {eta} +/- {eta_err}, its part of R_r/R_t included):")
    print("| core a | trans_gamma | shell (used) | drive: runs, time units | R_r/a | drag: runs (F), time units | "
          "R_t/a drag | R_t/a MSD (check) | R_r/R_t | CPU-s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    res = []
    for a, g, sh in sorted(keys, key=_sort_key):
        gs = [x for x in groups if (x["core_radius"], x["trans_gamma"], x["stick_shell"]) == (a, g, sh)]
        rs = [r for r in runs if (round(r["core_radius"], 6),) + setting(r) == (a, g, sh)]
        ds = [r for r in drags if (round(r["core_radius"], 6),) + setting(r, "stick_gamma") == (a, g, sh)]
        used = [r.get("stick_shell_used") for r in rs + ds if r.get("stick_shell_used") is not None]
        shell_used = used[0] if used else (sus.surface_cutoff(a) if sh is None else sh)

        def radii(e):
            """(R_r/a, its zeta error), (R_t/a drag, err), (R_t/a MSD, err) at eta_0 = e."""
            rr = (None, None)
            if gs:
                z0s = [theory.rotational_friction_unbounded(x["zeta_L"], e, x["L"], zeta_err=x["zeta_L_err"])
                       for x in gs]
                z0, z0e = _combine(z0s)
                Rr, Rre = theory.rotational_radius(z0, e, zeta_err=z0e, eta_err=0.0)
                rr = (Rr / a, Rre / a)
            rt_d = _combine([tuple(x / a for x in theory.hydrodynamic_radius_from_D(
                D, e, L, D_err=De, kT=KT)) for D, De, L in _drag_D(ds)])
            dm = [r for r in rs if "D_msd" in r and abs(r["L"] - L_PHI05) < 1e-3]
            rt_m = (None, None)
            if dm:
                Dm, Dme = _combine([(r["D_msd"], r["D_msd_err"]) for r in dm])
                fac = (1.0 + 4.0 * math.pi * a ** 3 / dm[0]["n_solvent"]) ** 2
                Rt, Rte = theory.hydrodynamic_radius_from_D(Dm * fac, e, dm[0]["L"], D_err=Dme * fac, kT=KT)
                rt_m = (Rt / a, Rte / a)
            return rr, rt_d, rt_m

        (Rr, Rre), (Rtd, Rtde), (Rtm, Rtme) = radii(eta)
        Rt, Rte = (Rtd, Rtde) if Rtd is not None else (Rtm, Rtme)
        q = qe = None
        if Rr is not None and Rt is not None:
            q = Rr / Rt
            (Rr2, _), rtd2, rtm2 = radii(eta + eta_err)
            q_eta = abs(Rr2 / (rtd2[0] if Rtd is not None else rtm2[0]) - q)
            qe = math.sqrt((q * Rre / Rr) ** 2 + (q * Rte / Rt) ** 2 + q_eta ** 2)

        def f(v, e, n=4):
            return "-" if v is None else f"{v:.{n}f} +/- {e:.{n}f}"
        forces = ",".join(sorted({f"{r['force']:g}" for r in ds}))
        cpu = sum(r.get("cpu_s", 0.0) for r in rs + ds)
        print(f"| {a:.4f} | {g:g} | {'default' if sh is None else f'{sh:g}'} ({shell_used:.4f}) | {len(rs)}, "
              f"{sum(r['time'] for r in rs):.0f} | {f(Rr, Rre)} | {len(ds)} ({forces or '-'}), "
              f"{sum(r['time'] for r in ds):.0f} | {f(Rtd, Rtde)} | {f(Rtm, Rtme)} | {f(q, qe)} | "
              f"{cpu:.0f} |")
        res.append(dict(core_radius=a, trans_gamma=g, stick_shell=sh, stick_shell_used=shell_used, n_drive=len(rs),
                        n_drag=len(ds), R_r_over_a=Rr, R_r_over_a_err=Rre, R_t_drag_over_a=Rtd,
                        R_t_drag_over_a_err=Rtde, R_t_msd_over_a=Rtm, R_t_msd_over_a_err=Rtme, R_t_over_a=Rt,
                        R_t_over_a_err=Rte, ratio_r_t=q, ratio_r_t_err=qe, cpu_s=cpu))
    return res


def _drag_D(ds):
    """(D, D_err, L) per box size of drag runs (weighted, error scaled by sqrt(chi^2/dof) when above 1)."""
    out = []
    for L in sorted({round(r["L"], 4) for r in ds}):
        rl = [r for r in ds if round(r["L"], 4) == L]
        D, De = _combine([(r["D"], r["D_err"]) for r in rl])
        out.append((D, De, rl[0]["L"]))
    return out


def main(argv=None):
    args = parse(argv)
    out = drive(args) if args.part == "drive" else table(args)
    if args.json:
        d = os.path.dirname(args.json)
        if d:
            os.makedirs(d, exist_ok=True)
        with open(args.json, "a") as f:
            f.write(json.dumps(out) + "\n")


if __name__ == "__main__":
    main()
