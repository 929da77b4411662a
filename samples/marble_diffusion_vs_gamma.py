"""Diffusion coefficient of a marble colloid vs surface friction gamma
(Zhou & Schmid, Fig. 4): Green-Kubo (VACF), MSD fit and drag, three seeds.

For every gamma and seed: one equilibrium run (VACF and MSD correlators, see
marble_vacf.py) and one drag run (constant force on the colloid, the opposite
force spread over the solvent; marble.diffusion.measure_drag). The value per
method is the mean over the seeds, the error the standard error over the seeds
(as in the paper). Lines: Hasimoto's D(L) for a stick and a perfectly slipping
sphere (marble.theory.hasimoto_D) with the given eta.

    build/pymarble samples/marble_diffusion_vs_gamma.py            # R=1.5, L=8, a few minutes
    build/pymarble samples/marble_diffusion_vs_gamma.py --paper    # R=3, L=20 (many hours)
    build/pymarble samples/marble_diffusion_vs_gamma.py --gammas 0.5 5 --seeds 3
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/marble_diffusion_vs_gamma.py   # < 30 s

Writes marble_diffusion_vs_gamma.json (rewritten after every run, so a killed
run leaves its data) and marble_diffusion_vs_gamma.png into --out.
"""
import os
import time

import numpy as np

from marble.colloid_runs import (DT, KT, QUICK, analyse_equilibrium, common_args,  # noqa: E402
                         drag_run, equilibrium_run, make_system, plot_setup, save_figure, write_json)
from marble import theory as th  # noqa: E402


def mean_err(x):
    x = np.asarray([v for v in x if v is not None and np.isfinite(v)], dtype=float)
    if len(x) == 0:
        return float("nan"), float("nan")
    return float(x.mean()), float(x.std(ddof=1) / np.sqrt(len(x))) if len(x) > 1 else float("nan")


def main():
    p = common_args(__doc__.splitlines()[0], 300.0, 5000.0)
    p.add_argument("--gammas", type=float, nargs="+", default=None)
    p.add_argument("--seeds", type=int, default=3, help="independent runs per gamma")
    p.add_argument("--drag-time", type=float, default=None,
                   help="drag production time per run (default 100, --paper 1000 tau)")
    p.add_argument("--no-equilibrium", action="store_true", help="drag method only")
    args = p.parse_args()
    if args.paper:
        R, L, t_eq, t_drag = 3.0, 20.0, 5000.0, 1000.0
        gammas = [0.1, 0.5, 1.0, 2.0, 3.0, 5.0, 10.0]
    else:
        R, L, t_eq, t_drag = 1.5, 8.0, 300.0, 100.0
        gammas = [0.5, 2.0, 5.0]
    if QUICK:
        R, L, t_eq, t_drag, gammas = 1.5, 6.0, 20.0, 10.0, [0.5, 5.0]
    t_eq = args.time or t_eq
    t_drag = args.drag_time or t_drag
    gammas = args.gammas or gammas
    seeds = [args.seed + 100 * k for k in range(2 if QUICK else args.seeds)]
    eta = args.eta
    D_stick, D_slip = th.hasimoto_D(eta, R, L), th.hasimoto_D(eta, R, L, boundary="slip")
    F = 0.1 / D_stick * KT          # colloid speed ~ 0.1 (no slip)
    os.makedirs(args.out, exist_ok=True)
    jpath = os.path.join(args.out, "marble_diffusion_vs_gamma.json")
    per_run = t_drag + 20.0 + (0.0 if args.no_equilibrium else t_eq)
    total = len(gammas) * len(seeds) * (per_run + 10.0)
    print(f"marble R={R} L={L}: gammas {gammas}, {len(seeds)} seeds, equilibrium {t_eq} tau, "
          f"drag {t_drag} tau (F = {F:.2f}); Hasimoto stick {D_stick:.5f}, slip {D_slip:.5f}",
          flush=True)
    data = dict(sample="marble_diffusion_vs_gamma", R=R, L=L, eta=eta, kT=KT, dt=DT,
                t_equilibrium=t_eq, t_drag=t_drag, force=F, seeds=seeds, gammas=gammas,
                D_hasimoto_stick=D_stick, D_hasimoto_slip=D_slip, runs=[], summary=[])
    t_start, done = time.time(), 0.0
    for g in gammas:
        for s in seeds:
            run = dict(gamma=g, seed=s)
            if not args.no_equilibrium:
                system, col, _ = make_system(L, R, g, s)
                eq = equilibrium_run(system, col, t_eq, 1, min(50.0, t_eq / 4), t_eq / 4)
                gk, wgk, msd, wmsd = analyse_equilibrium(eq, L, eta, args.paper)
                run.update(D_vacf=gk.value, D_msd=msd.value, gk_window=wgk, msd_window=wmsd)
                del system
            system, col, _ = make_system(L, R, g, s + 7)
            res = drag_run(system, col, F, t_drag)
            del system
            run.update(D_drag=res.D, D_drag_err=res.D_err)
            data["runs"].append(run)
            done += per_run + 10.0
            el = time.time() - t_start
            print(f"  gamma={g:5.2f} seed={s}: " +
                  ("" if args.no_equilibrium else
                   f"D_vacf={run['D_vacf']:.5f} D_msd={run['D_msd']:.5f} ") +
                  f"D_drag={res.D:.5f}+-{res.D_err:.5f}   [{done / total * 100:5.1f} %, "
                  f"elapsed {el:.0f} s, ETA {el / done * (total - done):.0f} s]", flush=True)
            data["cpu_time_s"] = el
            write_json(jpath, data)
        rs = [r for r in data["runs"] if r["gamma"] == g]
        summ = dict(gamma=g, n=len(rs))
        for m in ("vacf", "msd", "drag"):
            summ[f"D_{m}"], summ[f"D_{m}_err"] = mean_err([r.get(f"D_{m}") for r in rs])
        data["summary"].append(summ)
        write_json(jpath, data)
    data["cpu_time_s"] = time.time() - t_start
    write_json(jpath, data)
    print(f"{'gamma':>6} {'D_vacf':>17} {'D_msd':>17} {'D_drag':>17}   (stick {D_stick:.5f}, "
          f"slip {D_slip:.5f}, eta {eta})")
    for s in data["summary"]:
        print(f"{s['gamma']:6.2f} " + " ".join(f"{s['D_' + m]:.5f}+-{s['D_' + m + '_err']:.5f}"
                                               for m in ("vacf", "msd", "drag")))

    plt = plot_setup()
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    gs = np.array([s["gamma"] for s in data["summary"]])
    for k, (m, mk) in enumerate((("vacf", "s"), ("msd", "^"), ("drag", "o"))):
        y = np.array([s[f"D_{m}"] for s in data["summary"]])
        e = np.array([s[f"D_{m}_err"] for s in data["summary"]])
        if np.all(np.isnan(y)):
            continue
        ax.errorbar(gs * (1 + 0.04 * (k - 1)), y, yerr=np.nan_to_num(e), fmt=mk, capsize=3,
                    label=m if m != "drag" else "force")
    ax.axhline(D_stick, color="k", ls="-", label="Hasimoto stick")
    ax.axhline(D_slip, color="k", ls="--", label="Hasimoto slip")
    ax.set_xscale("log")
    ax.set_xlabel(r"$\gamma\ [m/\tau]$")
    ax.set_ylabel(r"$D\ [\sigma^2/\tau]$")
    ax.set_title(f"marble R={R:g}, L={L:g}, eta={eta}, {len(seeds)} seeds", fontsize=9)
    ax.legend(fontsize=8)
    save_figure(fig, args.out, "marble_diffusion_vs_gamma.png", jpath)


if __name__ == "__main__":
    main()
