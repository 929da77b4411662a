"""Finite-size effect on the diffusion of a marble colloid (Zhou & Schmid, Fig. 5):
D from the drag method vs 1/L, with Hasimoto's law.

For each box size L: a no-slip marble (gamma = 5) in the paper's DPD solvent,
a constant force F on the colloid and -F/N_s on every solvent bead; the
steady velocity relative to the solvent gives D = kT v/F (marble.diffusion.measure_drag;
error: blocking or the floor sqrt(2D/T)/v, whichever is larger). The force is chosen for a colloid speed of
about 0.12 (Reynolds number R v/nu <~ 0.9). The line is Hasimoto's
D(L) = kT/(6 pi eta) [1/R - 2.837297/L + (4 pi/3) R^2/L^3] (and its
perfect-slip counterpart, dashed). A weighted fit of the stick law to the
points gives the hydrodynamic radius R_h (marble.theory).

    build/pymarble samples/marble_hasimoto.py            # R=2, L=8..12, 500 tau each (~4 CPU min)
    build/pymarble samples/marble_hasimoto.py --paper    # R=3, L=12..30, 1000 tau each (hours)
    build/pymarble samples/marble_hasimoto.py --L 10 14 20 --time 400
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/marble_hasimoto.py   # < 30 s

Writes marble_hasimoto.json (after every box size) and marble_hasimoto.png into --out.
"""
import os
import time

import numpy as np

from marble.colloid_runs import (KT, QUICK, common_args, drag_run, integration_args,  # noqa: E402
                                make_system, plot_setup, save_figure, write_json)
from marble import theory as th  # noqa: E402


def main():
    p = common_args(__doc__.splitlines()[0], 500.0, 1000.0)
    p.add_argument("--L", type=float, nargs="+", default=None, help="box sizes")
    p.add_argument("--gamma", type=float, default=5.0)
    p.add_argument("--speed", type=float, default=0.12, help="target colloid speed (sets F)")
    args = p.parse_args()
    if args.paper:
        R, Ls, t_prod = 3.0, [12.0, 16.0, 20.0, 24.0, 30.0], 1000.0
    else:
        R, Ls, t_prod = 2.0, [8.0, 10.0, 12.0], 500.0
    if QUICK:
        R, Ls, t_prod = 1.5, [6.0, 8.0], 10.0
    Ls = args.L or Ls
    t_prod = args.time or t_prod
    eta = args.eta
    integrator, dt = integration_args(args, R)
    os.makedirs(args.out, exist_ok=True)
    jpath = os.path.join(args.out, "marble_hasimoto.json")
    data = dict(sample="marble_hasimoto", R=R, gamma=args.gamma, eta=eta, kT=KT, dt=dt,
                integrator=integrator,
                t_prod=t_prod, t_equil=20.0, seed=args.seed, points=[])
    cost = np.array(Ls) ** 3 * (t_prod + 30.0)
    t_start = time.time()
    for i, L in enumerate(Ls):
        D_th = th.hasimoto_D(eta, R, L)
        F = args.speed / D_th * KT
        c0 = time.process_time()
        system, col, solvent = make_system(L, R, args.gamma, args.seed + i, integrator=integrator, dt=dt)
        res = drag_run(system, col, F, t_prod)
        cpu_s = time.process_time() - c0
        n_solvent = len(solvent)
        del system
        pt = dict(L=L, n_solvent=n_solvent, force=F, D=res.D, D_err=res.D_err, v=res.v,
                  v_err=res.v_err, D_hasimoto_stick=D_th,
                  D_hasimoto_slip=th.hasimoto_D(eta, R, L, boundary="slip"), cpu_s=cpu_s)
        data["points"].append(pt)
        el = time.time() - t_start
        eta_s = el / cost[: i + 1].sum() * cost[i + 1:].sum()
        print(f"  L={L:5.1f} (N={n_solvent}): D = {res.D:.5f} +- {res.D_err:.5f}, Hasimoto "
              f"{D_th:.5f}, ratio {res.D / D_th:.3f} +- {res.D_err / D_th:.3f}   "
              f"[elapsed {el:.0f} s, ETA {eta_s:.0f} s]", flush=True)
        data["cpu_time_s"] = sum(q["cpu_s"] for q in data["points"])
        data["wall_time_s"] = el
        write_json(jpath, data)
    L_arr = np.array([q["L"] for q in data["points"]])
    D_arr = np.array([q["D"] for q in data["points"]])
    E_arr = np.array([q["D_err"] for q in data["points"]])
    try:
        Rh, Rh_err = th.hydrodynamic_radius_from_D(D_arr, eta, L_arr, D_err=E_arr)
        print(f"hydrodynamic radius (weighted fit of Hasimoto stick, eta = {eta}): "
              f"R_h = {Rh:.3f} +- {Rh_err:.3f} (R = {R})")
    except ValueError as e:
        Rh, Rh_err = float("nan"), float("nan")
        print(f"no hydrodynamic-radius fit: {e}")
    chi2 = float(np.sum(((D_arr - th.hasimoto_D(eta, R, L_arr)) / E_arr) ** 2))
    print(f"chi^2 vs Hasimoto stick (no free parameter) = {chi2:.2f} for {len(L_arr)} points")
    data.update(R_h=Rh, R_h_err=Rh_err, chi2_stick=chi2, wall_time_s=time.time() - t_start)
    write_json(jpath, data)

    plt = plot_setup()
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.errorbar(1 / L_arr, D_arr, yerr=E_arr, fmt="o", capsize=3, label="force (drag)")
    x = np.linspace(0, 1.1 / min(L_arr), 100)
    Lx = np.where(x > 0, 1 / np.maximum(x, 1e-12), np.inf)
    ax.plot(x, th.hasimoto_D(eta, R, Lx), "k-", label=f"Hasimoto stick, eta={eta}")
    ax.plot(x, th.hasimoto_D(eta, R, Lx, boundary="slip"), "k--", label="Hasimoto slip")
    ax.set_xlabel(r"$1/L\ [\sigma^{-1}]$")
    ax.set_ylabel(r"$D\ [\sigma^2/\tau]$")
    ax.set_title(f"marble R={R:g}, gamma={args.gamma:g}, {t_prod:g} tau per point", fontsize=9)
    ax.legend(fontsize=8)
    save_figure(fig, args.out, "marble_hasimoto.png", jpath)


if __name__ == "__main__":
    main()
