"""One core-modified colloid at volume fraction 0.05 against Hasimoto (issue 13,
doc/suspensions.md section 9).

Seed 004's solvent and colloid (R = 1, rho = 3, kT = 0.1, gamma = 4.5,
a_ss = 25 kT, the mean-field colloid-solvent hat and the colloid-solvent DPD
on the gap with the equal-volume surface cutoff 0.26, colloid mass 12.57), one
colloid in a periodic cube of edge L = (4 pi R^3 / (3 phi))^(1/3) = 4.373, so
its volume fraction is 0.05; Shardlow, dt = 0.01.

- ``--part eta``: the solvent's viscosity by reverse Poiseuille (box 7 x 7 x 10,
  g = 0.02, the same solvent settings and dt).
- ``--part rot`` (with ``--boundary stick``): rotational equipartition
  <I w^2>/3 = kT and the rotational diffusion (1/3) int <w(0).w(t)> dt, blocking errors.
- ``--part drag``: D by drag (marble.diffusion.measure_drag: a constant force
  on the colloid, the opposite force spread over the solvent; D = kT v / F),
  with the error the larger of the blocking error and sqrt(2 D / T).
- Compared with Hasimoto's D(L) = kT/(6 pi eta) [1/R_h - 2.837297/L +
  (4 pi/3) R_h^2/L^3] (marble.theory.hasimoto_D) for R_h = R and
  R_h = R + r'_c/2, and the R_h that fits (theory.hydrodynamic_radius_from_D).

    ./pymarble bench/suspension_hasimoto.py --part eta --time 1500
    ./pymarble bench/suspension_hasimoto.py --part drag --time 3000 --seed 1
    ./pymarble bench/suspension_hasimoto.py --part drag --boundary stick --time 3000 --seed 1
    ./pymarble bench/suspension_hasimoto.py --part rot --boundary stick --time 2000 --seed 2
    ./pymarble bench/suspension_hasimoto.py --part compare --eta 0.3227 0.0069 --D 0.0156 0.0002

Stick colloids: setup_suspension's default takes R = 1 as the hydrodynamic radius
(core 1/STICK_RADIUS_RATIO); ``--radius-calibration none`` builds the core R = 1
(how the ratio was measured, doc/suspensions.md section 7d):

    ./pymarble bench/suspension_hasimoto.py --part drag --boundary stick --radius-calibration none --time 6000 --seed 2
    ./pymarble bench/suspension_hasimoto.py --part ratio --results bench/results/suspension_stick.jsonl --eta 0.3290 0.0030

The runs of doc/suspensions.md section 7b are in bench/results/suspension_hasimoto.jsonl.
"""
import argparse
import json
import math
import os
import time

import numpy as np

import marble
import marble.suspensions as sus
from marble import theory

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--part", choices=["eta", "drag", "rot", "compare", "ratio"], required=True)
parser.add_argument("--boundary", choices=["slip", "stick"], default="slip",
                    help="setup_suspension's boundary (stick: rotating colloids with the surface_friction kernel)")
parser.add_argument("--stick-gamma", type=float, default=None,
                    help="stick: the surface_friction's gamma (default setup_suspension's 45)")
parser.add_argument("--stick-shell", type=float, default=None,
                    help="stick: the friction shell's thickness on the gap (default setup_suspension's r'_c(a))")
parser.add_argument("--radius-calibration", default=None,
                    help="setup_suspension's radius_calibration: 'none' (the core radius is R = 1: how the "
                         "ratio STICK_RADIUS_RATIO was measured), 'stick' (stick's default: R = 1 is the "
                         "hydrodynamic radius, the core R/1.013), 'rotation', 'stresslet' or a number")
parser.add_argument("--solvent-count", choices=["poisson", "exact"], default="poisson",
                    help="setup_suspension's solvent_count (exact: round(rho x free volume) beads)")
parser.add_argument("--time", type=float, default=1000.0, help="production time")
parser.add_argument("--dt", type=float, default=0.01)
parser.add_argument("--force", type=float, default=0.5, help="drag force on the colloid")
parser.add_argument("--g", type=float, default=0.02, help="reverse Poiseuille body force")
parser.add_argument("--seed", type=int, default=1)
parser.add_argument("--trans-gamma", type=float, default=0.0,
                    help="drag: add TRANS_DPD friction (tangential) on the colloid-solvent pair "
                         "(not in seed 004; tests whether the slip comes from the central friction)")
parser.add_argument("--eta", type=float, nargs=2, help="compare: eta and its error")
parser.add_argument("--D", type=float, nargs=2, help="compare: D and its error")
parser.add_argument("--json", help="append the result (a JSON line) to this file")
parser.add_argument("--results", help="ratio: the JSON lines of drag runs to combine")
args = parser.parse_args()
if args.stick_shell is not None:
    if not (math.isfinite(args.stick_shell) and args.stick_shell > 0):
        parser.error(f"--stick-shell must be > 0, got {args.stick_shell}")
    if args.boundary != "stick":
        parser.error("--stick-shell needs --boundary stick")

marble.assert_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS", "EXTERNAL_FORCE")
R, KT, GAMMA, PHI = 1.0, 0.1, 4.5, 0.05
L = (4.0 * math.pi * R ** 3 / (3.0 * PHI)) ** (1.0 / 3.0)


def colloid_box():
    s = marble.System(box_l=[L] * 3)
    s.time_step = args.dt
    s.cell_system.skin = 0.4
    kw = dict(boundary=args.boundary, solvent_count=args.solvent_count)
    if args.boundary == "stick" and args.stick_gamma is not None:
        kw["trans_gamma"] = args.stick_gamma
    if args.stick_shell is not None:
        kw["stick_shell"] = args.stick_shell
    if args.radius_calibration is not None:
        rc = args.radius_calibration
        kw["radius_calibration"] = sus.radius_calibration_arg(rc)
    info = sus.setup_suspension(s, phi=PHI, radius=R, kT=KT, gamma=GAMMA, eta=0.3, seed=args.seed,
                                positions=[[L / 2] * 3], **kw)
    if args.trans_gamma > 0:
        marble.assert_features("TRANS_DPD")
        s.non_bonded_inter[1, 0].dpd.set_params(
            weight_function=1, gamma=GAMMA, r_cut=info["cutoff_surface"], offset=R,
            trans_weight_function=1, trans_gamma=args.trans_gamma, trans_r_cut=info["cutoff_surface"])
    s.integrator.set_shardlow()
    return s, info


def solvent_box():
    box = np.array([7.0, 7.0, 10.0])
    s = marble.System(box_l=box)
    s.time_step = args.dt
    s.cell_system.skin = 0.4
    info = sus.setup_suspension(s, phi=1e-9, radius=R, kT=KT, gamma=GAMMA, eta=0.3, seed=args.seed,
                                positions=[0.5 * box])
    s.part.by_ids(info["colloid_ids"]).remove()
    s.non_bonded_inter.reset()
    s.non_bonded_inter[0, 0].hat.set_params(F_max=info["a_ss"], cutoff=1.0)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=GAMMA, r_cut=1.0)
    s.integrator.set_shardlow()
    return s


def zero_momentum(s):
    p = s.part.all()
    v, m = np.asarray(p.v), np.asarray(p.mass)
    p.v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)


t0 = time.process_time()
out = dict(part=args.part, dt=args.dt, seed=args.seed, time=args.time, L=L)
if args.part == "eta":
    from marble.viscosity import reverse_poiseuille
    s = solvent_box()
    zero_momentum(s)
    s.integrator.run(int(round(20.0 / args.dt)))
    res = reverse_poiseuille(s, g=args.g, time=args.time, n_blocks=10, margin=1.5)
    out.update(eta=res.eta, eta_err=res.eta_err, kT=res.kT, v_max=res.v_max, g=args.g)
    print(f"eta = {res.eta:.4f} +/- {res.eta_err:.4f} (kT {res.kT:.4f}, v_max {res.v_max:.3f})")
elif args.part == "drag":
    from marble.diffusion import measure_drag
    s, info = colloid_box()
    zero_momentum(s)
    s.integrator.run(int(round(20.0 / args.dt)))
    res = measure_drag(s, info["colloid_ids"], force=[args.force, 0, 0],
                       steps=int(round(args.time / args.dt)), equilibration_steps=int(round(20 / args.dt)),
                       delta_N=10, kT=KT)
    err = max(res.D_err, KT * math.sqrt(2 * max(res.D, 0) / args.time) / args.force)
    out.update(D=res.D, D_err=err, D_err_blocking=res.D_err, force=args.force, trans_gamma=args.trans_gamma,
               boundary=args.boundary, stick_gamma=info.get("trans_gamma"), stick_shell=args.stick_shell,
               stick_shell_used=info.get("stick_shell"),
               n_solvent=info["n_solvent"], core_radius=info["core_radius"],
               radius_calibration=info["radius_calibration"], solvent_count=args.solvent_count)
    print(f"L = {L:.4f}, {info['n_solvent']} beads: D = {res.D:.5f} +/- {err:.5f} "
          f"(blocking {res.D_err:.5f}), v = {res.v:.4f}")
elif args.part == "rot":
    # stick: rotational equipartition <I w^2>/3 = kT and the rotational diffusion
    # D_r = (1/3) int <w(0) . w(t)> dt (to t_max = 10) against kT/(8 pi eta R^3)
    s, info = colloid_box()
    zero_momentum(s)
    s.integrator.run(int(round(20.0 / args.dt)))
    c = s.part.by_ids(info["colloid_ids"])
    every = 5
    n = int(round(args.time / (every * args.dt)))
    w = np.empty((n, 3))
    v = np.empty((n, 3))
    for k in range(n):
        s.integrator.run(every)
        w[k] = c.omega_lab[0]
        v[k] = c.v[0]
    I_rot, M = float(info["rinertia"] or 0.0), float(info["colloid_mass"])
    nb, tmax = 10, 10.0
    lag = int(round(tmax / (every * args.dt)))
    blocks = np.array_split(np.arange(n), nb)
    ke_r = np.array([I_rot * np.mean(w[b] ** 2) / KT for b in blocks])
    ke_t = np.array([M * np.mean(v[b] ** 2) / KT for b in blocks])

    def acf_integral(x):
        x = x - 0.0  # the spin has no mean: no subtraction
        f = np.fft.rfft(x, n=2 * len(x), axis=0)
        acf = np.fft.irfft(f * np.conj(f), axis=0)[:lag + 1].sum(axis=1) / (len(x) - np.arange(lag + 1))
        return every * args.dt * (acf.sum() - 0.5 * acf[0] - 0.5 * acf[-1]) / 3.0

    Dr = np.array([acf_integral(w[b]) for b in blocks])
    sq = math.sqrt(nb)
    out.update(kT_rot=ke_r.mean(), kT_rot_err=ke_r.std(ddof=1) / sq, kT_trans=ke_t.mean(),
               kT_trans_err=ke_t.std(ddof=1) / sq, D_r=Dr.mean(), D_r_err=Dr.std(ddof=1) / sq,
               boundary=args.boundary, rinertia=I_rot, tmax=tmax)
    print(f"<I w^2>/(3 kT) = {out['kT_rot']:.4f} +/- {out['kT_rot_err']:.4f}, <M v^2>/(3 kT) = "
          f"{out['kT_trans']:.4f} +/- {out['kT_trans_err']:.4f}, D_r = {out['D_r']:.5f} +/- {out['D_r_err']:.5f}")
elif args.part == "ratio":
    # R_h / core radius of the stick colloid (setup_suspension's STICK_RADIUS_RATIO):
    # the drag runs of --results with --boundary stick (trans_gamma 45, no TRANS_DPD),
    # grouped by core radius; D weighted by 1/err^2 (error scaled by sqrt(chi^2/dof)
    # when above 1), R_h from Hasimoto's stick D(L) at eta (its error added in quadrature)
    eta, eta_err = args.eta
    runs = [json.loads(line) for line in open(args.results) if line.strip()]
    runs = [r for r in runs if r.get("part") == "drag" and r.get("boundary") == "stick"
            and r.get("stick_gamma") in (None, 45.0) and not r.get("trans_gamma") and r.get("stick_shell") is None
            and r.get("force") == args.force]
    groups = {}
    for r in runs:
        groups.setdefault((round(r.get("core_radius", R), 6), r.get("solvent_count", "poisson")), []).append(r)
    for (a, count), rs in sorted(groups.items()):
        D = np.array([r["D"] for r in rs])
        e = np.array([r["D_err"] for r in rs])
        w = 1 / e ** 2
        Dm, De = np.sum(w * D) / np.sum(w), 1 / math.sqrt(np.sum(w))
        chi2 = float(np.sum(w * (D - Dm) ** 2))
        dof = len(D) - 1
        if dof > 0 and chi2 > dof:
            De *= math.sqrt(chi2 / dof)
        Rh, Rh_e = theory.hydrodynamic_radius_from_D(Dm, eta, L, D_err=De, kT=KT)
        Rh_eta = abs(theory.hydrodynamic_radius_from_D(Dm, eta * (1 + eta_err / eta), L, kT=KT)[0] - Rh)
        err = math.hypot(Rh_e, Rh_eta)
        print(f"core a = {a:.4f}, {count} solvent count: {len(D)} runs, {sum(r['time'] for r in rs):.0f} time units: "
              f"D = {Dm:.5f} +/- {De:.5f} (chi^2 {chi2:.1f} for {dof} dof); R_h = {Rh:.4f} +/- {err:.4f} "
              f"(D {Rh_e:.4f}, eta {Rh_eta:.4f}); R_h / a = {Rh / a:.4f} +/- {err / a:.4f}")
        out.setdefault("groups", []).append(dict(core_radius=a, solvent_count=count, n=len(D), D=Dm, D_err=De, chi2=chi2, R_h=Rh,
                                                  R_h_err=err, ratio=Rh / a, ratio_err=err / a))
else:
    eta, eta_err = args.eta
    D, D_err = args.D
    rel = math.hypot(D_err / D, eta_err / eta)
    rp = sus.surface_cutoff(R)
    for bc in ("stick", "slip"):
        for name, Rh in (("R", R), ("R + r'_c/2", R + rp / 2)):
            Dh = theory.hasimoto_D(eta, Rh, L, kT=KT, boundary=bc)
            print(f"Hasimoto {bc:5s} with R_h = {name} = {Rh:.3f}: D = {Dh:.5f}; measured/Hasimoto = "
                  f"{D / Dh:.3f} +/- {D / Dh * rel:.3f}")
    Rh, _ = theory.hydrodynamic_radius_from_D(D, eta, L, kT=KT)
    Rh_hi, _ = theory.hydrodynamic_radius_from_D(D * (1 - rel), eta, L, kT=KT)
    print(f"stick radius that fits: R_h = {Rh:.3f} +/- {abs(Rh_hi - Rh):.3f}")
    # slip: D = kT/(4 pi eta R) - 2.837297 kT/(6 pi eta L)
    def slip_radius(d):
        return KT / (4 * math.pi * eta * (d + theory.HASIMOTO_XI * KT / (6 * math.pi * eta * L)))
    Rs = slip_radius(D)
    print(f"perfect-slip radius that fits: R_s = {Rs:.3f} +/- {abs(slip_radius(D * (1 - rel)) - Rs):.3f}")
    out.update(eta=eta, eta_err=eta_err, D=D, D_err=D_err, R_stick=Rh, R_slip=Rs)
out["cpu_s"] = time.process_time() - t0
print(f"CPU {out['cpu_s']:.0f} s")
if args.json:
    with open(args.json, "a") as f:
        f.write(json.dumps(out) + "\n")
