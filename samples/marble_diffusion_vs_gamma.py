"""Diffusion coefficient of a marble colloid vs surface friction gamma
(Zhou & Schmid, Fig. 4): Green-Kubo (VACF), MSD fit and drag, three seeds.

For every gamma and seed: one equilibrium run (VACF and MSD correlators, see
marble_vacf.py) and one drag run (constant force on the colloid, the opposite
force spread over the solvent; marble.diffusion.measure_drag). The value per
method is the mean over the seeds, the error the standard error over the seeds
(as in the paper). Lines: Hasimoto's D(L) for a stick and a perfectly slipping
sphere (marble.theory.hasimoto_D) with the given eta. The runs go seed by seed
(every gamma of the first seed, then the second seed, ...), so a partial run
already has a whole curve.

    build/pymarble samples/marble_diffusion_vs_gamma.py            # R=1.5, L=8, a few minutes
    build/pymarble samples/marble_diffusion_vs_gamma.py --paper    # R=3, L=20 (many hours)
    build/pymarble samples/marble_diffusion_vs_gamma.py --gammas 0.5 5 --seeds 3
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/marble_diffusion_vs_gamma.py   # < 30 s

    # the paper's Fig. 4 in pieces (a batch queue's time limit, or a shared machine):
    build/pymarble samples/marble_diffusion_vs_gamma.py --paper --integrator shardlow \
        --out fig4 --resume --stop-after 7200      # repeat until it says "all runs done"

Writes marble_diffusion_vs_gamma.json (rewritten after every run, so a killed
run leaves its data) and marble_diffusion_vs_gamma.png into --out. Every run
records its CPU and wall time; ``cpu_time_s`` is their sum over all pieces.
``--resume`` keeps the runs already in the JSON file (same settings required)
and does only the missing ones; ``--stop-after S`` starts no new run once S
seconds (wall) have passed or the next run would likely end after S.
"""
import json
import os
import time

import numpy as np

from marble.colloid_runs import (KT, QUICK, analyse_equilibrium, common_args, drag_run,  # noqa: E402
                                equilibrium_run, integration_args, make_system, plot_setup,
                                save_figure, write_json)
from marble import theory as th  # noqa: E402


def mean_err(x):
    x = np.asarray([v for v in x if v is not None and np.isfinite(v)], dtype=float)
    if len(x) == 0:
        return float("nan"), float("nan")
    return float(x.mean()), float(x.std(ddof=1) / np.sqrt(len(x))) if len(x) > 1 else float("nan")


RUN_SETTINGS = ("R", "L", "dt", "integrator", "t_equilibrium", "t_drag", "force", "kT", "equilibrium",
                "marble_coupling")


def marble_coupling(integrator):
    """How the engine integrates the marble coupling: Shardlow updates it in its
    sweep since session 13 (doc/marble.md); earlier pieces (no such key) ran it
    as an explicit force, and --resume must not mix the two."""
    return "shardlow_sweep" if integrator == "shardlow" else "explicit"


def summarise(runs, gammas):
    """Mean and standard error over the seeds of every gamma with runs."""
    out = []
    for g in gammas:
        rs = [r for r in runs if r["gamma"] == g]
        if not rs:
            continue
        summ = dict(gamma=g, n=len(rs))
        for m in ("vacf", "msd", "drag"):
            summ[f"D_{m}"], summ[f"D_{m}_err"] = mean_err([r.get(f"D_{m}") for r in rs])
        out.append(summ)
    return out


def with_totals(data, gammas, seeds):
    """@p data with the summary over its runs, their summed CPU and wall time
    (over all pieces) and whether every (gamma, seed) run is there."""
    runs = data["runs"]
    data.update(summary=summarise(runs, gammas), cpu_time_s=sum(r.get("cpu_s", 0.0) for r in runs),
                wall_time_s=sum(r.get("wall_s", 0.0) for r in runs),
                complete=len(runs) == len(gammas) * len(seeds))
    return data


def resume_runs(jpath, data):
    """The runs of an earlier piece in jpath, after checking that its settings
    are data's (ValueError naming the first that differs)."""
    if not os.path.exists(jpath):
        return []
    with open(jpath) as f:
        old = json.load(f)
    for k in RUN_SETTINGS:
        default = {"integrator": "vv", "marble_coupling": "explicit"}.get(k)
        a, b = old.get(k, default), data[k]
        same = (a == b) if not isinstance(b, float) else (a is not None and abs(a - b) <= 1e-12 * abs(b))
        if not same:
            why = (" (files without the key are from before session 13, which integrated the marble "
                   "coupling explicitly under Shardlow too)" if k == "marble_coupling" and k not in old else "")
            raise ValueError(f"--resume: {jpath} was made with {k} = {a!r}, this run has {b!r}{why}; "
                             f"use another --out or the same settings")
    return [r for r in old.get("runs", []) if r["gamma"] in data["gammas"] and r["seed"] in data["seeds"]]


def main():
    p = common_args(__doc__.splitlines()[0], 300.0, 5000.0)
    p.add_argument("--gammas", type=float, nargs="+", default=None)
    p.add_argument("--seeds", type=int, default=3, help="independent runs per gamma")
    p.add_argument("--drag-time", type=float, default=None,
                   help="drag production time per run (default 100, --paper 1000 tau)")
    p.add_argument("--no-equilibrium", action="store_true", help="drag method only")
    p.add_argument("--resume", action="store_true",
                   help="keep the runs already in --out's JSON file, do the missing ones")
    p.add_argument("--stop-after", type=float, default=None, metavar="SECONDS",
                   help="start no run that would likely end after SECONDS (wall) of this invocation")
    args = p.parse_args()
    if args.stop_after is not None and not args.stop_after > 0:
        raise ValueError(f"--stop-after must be > 0 seconds, got {args.stop_after}")
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
    integrator, dt = integration_args(args, R)
    os.makedirs(args.out, exist_ok=True)
    jpath = os.path.join(args.out, "marble_diffusion_vs_gamma.json")
    print(f"marble R={R} L={L}: gammas {gammas}, {len(seeds)} seeds, equilibrium {t_eq} tau, "
          f"drag {t_drag} tau (F = {F:.2f}), {integrator} dt = {dt}; Hasimoto stick {D_stick:.5f}, "
          f"slip {D_slip:.5f}", flush=True)
    data = dict(sample="marble_diffusion_vs_gamma", R=R, L=L, eta=eta, kT=KT, dt=dt,
                integrator=integrator, marble_coupling=marble_coupling(integrator),
                equilibrium=not args.no_equilibrium,
                t_equilibrium=t_eq, t_drag=t_drag, force=F, seeds=seeds, gammas=gammas,
                D_hasimoto_stick=D_stick, D_hasimoto_slip=D_slip, runs=[], summary=[])
    if args.resume:
        data["runs"] = resume_runs(jpath, data)
    done_keys = {(r["gamma"], r["seed"]) for r in data["runs"]}
    todo = [(g, s) for s in seeds for g in gammas if (g, s) not in done_keys]
    print(f"{len(done_keys)} runs already done, {len(todo)} to do", flush=True)
    t_start, longest = time.time(), 0.0
    stopped = False
    for k, (g, s) in enumerate(todo):
        el = time.time() - t_start
        if args.stop_after is not None and (el >= args.stop_after or el + longest > args.stop_after):
            print(f"stopping after {el:.0f} s: {len(todo) - k} runs left (continue with --resume)",
                  flush=True)
            stopped = True
            break
        w0, c0 = time.time(), time.process_time()
        run = dict(gamma=g, seed=s)
        if not args.no_equilibrium:
            system, col, _ = make_system(L, R, g, s, integrator=integrator, dt=dt)
            eq = equilibrium_run(system, col, t_eq, 1, min(50.0, t_eq / 4), t_eq / 4)
            gk, wgk, msd, wmsd = analyse_equilibrium(eq, L, eta, args.paper)
            run.update(D_vacf=gk.value, D_msd=msd.value, gk_window=wgk, msd_window=wmsd)
            del system
        system, col, _ = make_system(L, R, g, s + 7, integrator=integrator, dt=dt)
        res = drag_run(system, col, F, t_drag)
        del system
        run.update(D_drag=res.D, D_drag_err=res.D_err, cpu_s=time.process_time() - c0,
                   wall_s=time.time() - w0)
        longest = max(longest, run["wall_s"])
        data["runs"].append(run)
        el = time.time() - t_start
        print(f"  gamma={g:5.2f} seed={s}: " +
              ("" if args.no_equilibrium else
               f"D_vacf={run['D_vacf']:.5f} D_msd={run['D_msd']:.5f} ") +
              f"D_drag={res.D:.5f}+-{res.D_err:.5f}   [{k + 1}/{len(todo)}, {run['cpu_s']:.0f} CPU-s, "
              f"elapsed {el:.0f} s, ETA {el / (k + 1) * (len(todo) - k - 1):.0f} s]", flush=True)
        write_json(jpath, with_totals(data, gammas, seeds))
    write_json(jpath, with_totals(data, gammas, seeds))
    if not stopped:
        print("all runs done", flush=True)
    if not data["summary"]:
        return
    print(f"{'gamma':>6} {'D_vacf':>17} {'D_msd':>17} {'D_drag':>17}   (stick {D_stick:.5f}, "
          f"slip {D_slip:.5f}, eta {eta}; {data['cpu_time_s'] / 3600:.2f} CPU-h in all)")
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
    ax.set_title(f"marble R={R:g}, L={L:g}, eta={eta}, {len(seeds)} seeds, {integrator} dt={dt:g}",
                 fontsize=9)
    ax.legend(fontsize=8)
    save_figure(fig, args.out, "marble_diffusion_vs_gamma.png", jpath)


if __name__ == "__main__":
    main()
