"""Velocity autocorrelation functions of a marble colloid (Zhou & Schmid, Fig. 2).

One no-slip marble (gamma = 5, tunable-slip coupling) in the paper's DPD
solvent (rho = 3, gamma_DPD = 5, kT = 1, dt = 0.01). An equilibrium run is cut
into independent chunks; in every chunk multiple-tau correlators
(marble.accumulators.Correlator) sample the translational and rotational VACF
and the MSD of the colloid. The plot shows the normalised
C_v(t) = <v(0).v(t)>/<v^2> and C_w(t) = <w(0).w(t)>/<w^2> on log-log axes with
the mode-coupling tails A_T t^-3/2 and A_R t^-5/2 (marble.theory), and the
script prints the Green-Kubo D (error from the spread over chunks) next to
Hasimoto's D(L).

    build/pymarble samples/marble_vacf.py                 # R=2, L=12, a few minutes
    build/pymarble samples/marble_vacf.py --paper         # R=3, L=20, 20000 tau (hours)
    build/pymarble samples/marble_vacf.py --time 2000 --out results/
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/marble_vacf.py   # quick check (< 30 s)

Writes marble_vacf.json and marble_vacf.png into --out (the JSON is rewritten
after every chunk, so a killed run leaves its data).

The helpers shared with the other marble_* samples and the tests are in
marble.colloid_runs.
"""
import argparse
import json
import os
import time

import numpy as np

import marble
from marble import accumulators as acc
from marble import diffusion as dif
from marble import observables as obs
from marble import theory as th
from marble.colloids import add_marble

from marble.colloid_runs import (  # noqa: F401  (the shared helpers)
    KT, RHO, DT, GAMMA_DPD, integration_args, QUICK, make_system, tau_box, gk_window, msd_window, Progress, equilibrium_run, drag_run, rows, analyse_equilibrium, jsonable, write_json, common_args, plot_setup, save_figure)


# ---------------------------------------------------------------- Fig. 2
def main():
    p = common_args(__doc__.splitlines()[0], 1000.0, 20000.0)
    p.add_argument("--gamma", type=float, default=5.0, help="surface friction (5: no slip)")
    args = p.parse_args()
    R, L = (3.0, 20.0) if args.paper else (2.0, 12.0)
    t_total = args.time or (20000.0 if args.paper else 1000.0)
    if QUICK:
        R, L, t_total = 1.5, 6.0, 60.0
    eta = args.eta
    t_chunk = min(t_total, 500.0 if args.paper else 200.0)
    if QUICK:
        t_chunk = 20.0
    n_chunks = max(1, int(round(t_total / t_chunk)))
    tau_max = min(100.0 if args.paper else 50.0, t_chunk / 4)
    integrator, dt = integration_args(args, R)
    os.makedirs(args.out, exist_ok=True)
    jpath = os.path.join(args.out, "marble_vacf.json")

    system, col, _ = make_system(L, R, args.gamma, args.seed, integrator=integrator, dt=dt)
    M, I = col.mass, col.rinertia[0]
    print(f"marble R={R} L={L} gamma={args.gamma}: M={M:.1f}, {n_chunks} chunks x {t_chunk} tau",
          flush=True)
    D_th = th.hasimoto_D(eta, R, L)
    Dr_th = th.rotational_diffusion_coefficient(eta, R, L)
    A_T = th.vacf_tail_amplitude(eta, RHO)
    A_R = th.rotational_vacf_tail_amplitude(eta, RHO)
    meta = dict(sample="marble_vacf", R=R, L=L, gamma=args.gamma, eta=eta, kT=KT, rho=RHO,
                dt=dt, integrator=integrator, mass=M, rinertia=I, seed=args.seed, t_chunk=t_chunk,
                n_chunks_planned=n_chunks, D_hasimoto_stick=D_th, Dr_hasimoto_stick=Dr_th,
                tail_amplitude_T=A_T, tail_amplitude_R=A_R)
    t_start = time.time()

    def save(eq, done):
        data = dict(meta, n_chunks_done=done, cpu_time_s=time.time() - t_start,
                    t_vacf=eq["t_vacf"], vacf_rows=eq["vacf"], rvacf_rows=eq["rvacf"])
        write_json(jpath, data)

    prog = Progress(n_chunks * int(round(t_chunk / dt)))
    eq = equilibrium_run(system, col, t_chunk, n_chunks, tau_max, tau_max, prog, save)
    t = np.asarray(eq["t_vacf"])
    V, W = rows(eq["vacf"]), rows(eq["rvacf"])
    Cv, Cw = V.mean(axis=0), W.mean(axis=0)
    win = gk_window(L, eta)
    win = (min(win[0], 0.5 * t[-1]), min(win[1], t[-1]))
    ff = eq["frame_factor"]
    gk_lab = dif.green_kubo(t, V, window=win)
    gk = dif.green_kubo(t, V / ff, window=win)      # relative coordinate (see equilibrium_run)
    # the rotational VACF decays within ~tau_nu = R^2/nu (t^-5/2 tail): a short
    # window keeps the noise of the long-time part out of the integral
    tau_nu = R ** 2 * RHO / eta
    win_r = (min(0.5 * tau_nu, 0.5 * t[-1]), min(tau_nu, t[-1]))
    gkr = dif.green_kubo(t, W, window=win_r)
    print(f"<M v^2>/3 = {M * Cv[0] / 3:.3f}, <I w^2>/3 = {I * Cw[0] / 3:.3f} (kT = {KT})")
    print(f"Green-Kubo D = {gk.value:.5f} +- {gk.error:.5f} (window {win[0]:.1f}-{win[1]:.1f} tau,"
          f" {gk.method}; colloid in the lab frame {gk_lab.value:.5f}, frame factor {ff:.4f});"
          f" Hasimoto stick D(L) = {D_th:.5f} (eta = {eta})")
    print(f"Green-Kubo D_r = {gkr.value:.3e} +- {gkr.error:.1e} (window {win_r[0]:.1f}-"
          f"{win_r[1]:.1f} tau); theory (stick) D_r(L) = {Dr_th:.3e}")
    data = dict(meta, n_chunks_done=len(eq["vacf"]), cpu_time_s=time.time() - t_start,
                t_vacf=t, vacf_rows=V, rvacf_rows=W, vacf_norm=Cv / Cv[0], rvacf_norm=Cw / Cw[0],
                D_green_kubo=gk.value, D_green_kubo_err=gk.error, gk_window=win,
                frame_factor=ff, D_green_kubo_lab=gk_lab.value,
                Dr_green_kubo=gkr.value, Dr_green_kubo_err=gkr.error, gk_window_rot=win_r)
    write_json(jpath, data)

    plt = plot_setup()
    fig, axes = plt.subplots(2, 1, figsize=(5.5, 7))
    ok = t > 0
    for ax, C, A, ex, lab in ((axes[0], Cv, A_T * 3, 1.5, r"$C_v(t)$"),
                              (axes[1], Cw, A_R * 3, 2.5, r"$C_\omega(t)$")):
        y = C / C[0]
        pos = ok & (y > 0)
        neg = ok & (y < 0)
        ax.loglog(t[pos], y[pos], "o", ms=3, label=lab + " (simulation)")
        if neg.any():
            ax.loglog(t[neg], -y[neg], "x", ms=3, color="gray", label="negative values")
        tt = np.geomspace(1.0, t[-1], 50)
        ax.loglog(tt, A * tt ** -ex / C[0], "g-", label=rf"theory $\propto t^{{-{ex}}}$")
        ax.set_ylim(1e-5, 1.5)
        ax.set_xlabel(r"$t/\tau$")
        ax.legend(fontsize=8)
    axes[0].set_title(f"marble R={R:g}, L={L:g}, gamma={args.gamma:g}, "
                      f"{len(V)}x{t_chunk:g} tau", fontsize=9)
    save_figure(fig, args.out, "marble_vacf.png", jpath)


if __name__ == "__main__":
    main()
