"""Mean squared displacement of a marble colloid (Zhou & Schmid, Fig. 3).

One no-slip marble (gamma = 5) in the paper's DPD solvent. An equilibrium run
is cut into independent chunks; a multiple-tau correlator (discard1
compression) measures the MSD <|r(t) - r(0)|^2> of the colloid centre in each.
D comes from a straight-line fit a + 6 D t (marble.diffusion.msd_fit) to the
MSD of the colloid-solvent relative coordinate (the colloid's own MSD divided
by (Ms/(M+Ms))^2, see marble.colloid_runs.equilibrium_run); the
paper fits t > 25 tau (--paper does too; the reduced box starts at
min(25, 3 L^2/(4 pi^2 nu)) tau). Error: spread of the per-chunk fits.
The plot shows the MSD on log-log axes with the fitted 6 D t line and
Hasimoto's 6 D(L) t.

    build/pymarble samples/marble_msd.py                 # R=2, L=12, a few minutes
    build/pymarble samples/marble_msd.py --paper         # R=3, L=20, 20000 tau (hours)
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/marble_msd.py   # quick check (< 30 s)

Writes marble_msd.json and marble_msd.png into --out (the JSON after every chunk).
"""
import os
import time

import numpy as np

from marble.colloid_runs import (KT, QUICK, Progress, common_args, equilibrium_run,  # noqa: E402
                                integration_args, make_system, msd_window, plot_setup, rows, save_figure, write_json)
from marble import diffusion as dif  # noqa: E402
from marble import theory as th  # noqa: E402


def main():
    p = common_args(__doc__.splitlines()[0], 1000.0, 20000.0)
    p.add_argument("--gamma", type=float, default=5.0, help="surface friction (5: no slip)")
    args = p.parse_args()
    R, L = (3.0, 20.0) if args.paper else (2.0, 12.0)
    t_total = args.time or (20000.0 if args.paper else 1000.0)
    t_chunk = 500.0 if args.paper else 200.0
    if QUICK:
        R, L, t_total, t_chunk = 1.5, 6.0, 60.0, 20.0
    t_chunk = min(t_chunk, t_total)
    n_chunks = max(1, int(round(t_total / t_chunk)))
    msd_tau_max = t_chunk / 4
    eta = args.eta
    integrator, dt = integration_args(args, R)
    os.makedirs(args.out, exist_ok=True)
    jpath = os.path.join(args.out, "marble_msd.json")
    system, col, _ = make_system(L, R, args.gamma, args.seed, integrator=integrator, dt=dt)
    D_th = th.hasimoto_D(eta, R, L)
    win = msd_window(L, eta, msd_tau_max, args.paper)
    if win[1] > msd_tau_max:   # very short runs (MARBLE_SAMPLE_TEST)
        win = (0.4 * msd_tau_max, msd_tau_max)
    print(f"marble R={R} L={L} gamma={args.gamma}: {n_chunks} chunks x {t_chunk} tau, "
          f"fit window {win[0]:.1f}-{win[1]:.1f} tau", flush=True)
    meta = dict(sample="marble_msd", R=R, L=L, gamma=args.gamma, eta=eta, kT=KT, dt=dt,
                integrator=integrator,
                seed=args.seed, t_chunk=t_chunk, n_chunks_planned=n_chunks, fit_window=win,
                D_hasimoto_stick=D_th)
    t_start = time.time()

    def save(eq, done):
        write_json(jpath, dict(meta, n_chunks_done=done, cpu_time_s=time.time() - t_start,
                               t_msd=eq["t_msd"], msd_rows=eq["msd"]))

    prog = Progress(n_chunks * int(round(t_chunk / dt)))
    eq = equilibrium_run(system, col, t_chunk, n_chunks, min(10.0, t_chunk / 4), msd_tau_max,
                         prog, save)
    ff = eq["frame_factor"]
    t, M = np.asarray(eq["t_msd"]), rows(eq["msd"])
    fit_lab = dif.msd_fit(t, M, window=win)
    # relative coordinate colloid - solvent (what drag and Hasimoto describe;
    # see marble.colloid_runs.equilibrium_run)
    fit = dif.msd_fit(t, M / ff, window=win)
    err = fit.error if len(M) > 1 else float("nan")
    print(f"MSD fit ({win[0]:.1f}-{win[1]:.1f} tau, {fit.method}): D = {fit.value:.5f} +- {err:.5f};"
          f" Hasimoto stick D(L) = {D_th:.5f} (eta = {eta}); colloid in the lab frame "
          f"{fit_lab.value:.5f} (frame factor {ff:.4f})")
    write_json(jpath, dict(meta, n_chunks_done=len(M), cpu_time_s=time.time() - t_start,
                           t_msd=t, msd_rows=M, msd_mean=M.mean(axis=0), D_msd=fit.value,
                           D_msd_err=err, intercept=fit.intercept, frame_factor=ff,
                           D_msd_lab=fit_lab.value))

    plt = plot_setup()
    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ok = t > 0
    m = M.mean(axis=0) / ff
    ax.loglog(t[ok], m[ok], "o", ms=3, label="simulation")
    tt = np.geomspace(max(t[ok][0], 0.1), t[-1], 100)
    tf = np.geomspace(0.5 * win[0], t[-1], 50)      # the fit line where it applies
    ax.loglog(tf, fit.intercept + 6 * fit.value * tf, "r-",
              label=f"fit t>{win[0]:.0f}: D={fit.value:.4f}")
    ax.loglog(tt, 6 * D_th * tt, "g--", label=f"6 D_Hasimoto t, D={D_th:.4f}")
    ax.axvspan(win[0], win[1], color="0.9")
    ax.set_xlabel(r"$t/\tau$")
    ax.set_ylabel(r"MSD of $r_c - r_{solvent}$")
    ax.set_title(f"marble R={R:g}, L={L:g}, gamma={args.gamma:g}, {len(M)}x{t_chunk:g} tau",
                 fontsize=9)
    ax.legend(fontsize=8)
    save_figure(fig, args.out, "marble_msd.png", jpath)


if __name__ == "__main__":
    main()
