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

This file also holds the helpers that the other marble_* samples import
(make_system, equilibrium_run, drag_run, window choices).
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

KT, RHO, DT, GAMMA_DPD = 1.0, 3.0, 0.01, 5.0
QUICK = os.environ.get("MARBLE_SAMPLE_TEST") == "1"


# ---------------------------------------------------------------- helpers
def make_system(L, R, gamma, seed, coupling="tunable_slip", warmup=10.0):
    """Paper solvent in a cubic box of side L with one marble of radius R at the
    centre; total momentum set to zero; `warmup` tau of equilibration."""
    system = marble.System(box_l=[L] * 3)
    system.time_step = DT
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    n = int(round(RHO * L ** 3))
    system.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)) * np.sqrt(KT), type=0)
    system.thermostat.set_dpd(kT=KT, seed=seed)
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=GAMMA_DPD, k=1,
                                                 r_cut=1.0)
    colloid = add_marble(system, pos=[L / 2] * 3, radius=R, gamma=gamma, coupling=coupling)
    solvent = system.part.select(type=0)
    # zero total momentum: a drifting centre of mass would add a constant to the
    # VACF and a ballistic t^2 term to the MSD
    p = colloid.mass * np.asarray(colloid.v) + np.sum(solvent.v, axis=0)
    solvent.v = np.asarray(solvent.v) - p / len(solvent)
    if warmup > 0:
        system.integrator.run(int(round(warmup / DT)))
    return system, colloid, solvent


def tau_box(L, eta):
    """Decay time of the slowest shear mode of the box, L^2/(4 pi^2 nu): the
    VACF tail is cut off after a few of these, so the Green-Kubo integral has
    converged to D(L)."""
    return L ** 2 / (4 * np.pi ** 2 * eta / RHO)


def gk_window(L, eta):
    tb = tau_box(L, eta)
    return (3.0 * tb, 6.0 * tb)


def msd_window(L, eta, t_max, paper=False):
    """The paper fits t > 25 tau; in small boxes the linear regime starts earlier
    (3 tau_box). The upper end is limited by the statistics of the chunk."""
    lo = 25.0 if paper else min(25.0, 3.0 * tau_box(L, eta))
    return (lo, max(t_max, 2 * lo))


class Progress:
    def __init__(self, total_steps, label=""):
        self.total, self.done, self.t0, self.label = total_steps, 0, time.time(), label

    def advance(self, steps):
        self.done += steps
        el = time.time() - self.t0
        eta = el / self.done * (self.total - self.done)
        print(f"  {self.label}{self.done}/{self.total} steps ({100 * self.done / self.total:5.1f} %)"
              f"  elapsed {el:6.0f} s  ETA {eta:6.0f} s", flush=True)


def equilibrium_run(system, colloid, t_chunk, n_chunks, vacf_tau_max, msd_tau_max,
                    progress=None, on_chunk=None, pieces=4):
    """n_chunks independent correlator runs of t_chunk tau each. Returns a dict
    with lag times and one row per chunk of the VACF (sum over x, y, z), the
    rotational VACF and the MSD (sum over x, y, z)."""
    vel = obs.ParticleVelocities(ids=[colloid.id], system=system)
    omg = obs.ParticleAngularVelocities(ids=[colloid.id], system=system)
    pos = obs.ParticlePositions(ids=[colloid.id], system=system)
    # The total momentum is zero, so the colloid moves with the fraction
    # Ms/(M+Ms) of the colloid-solvent relative coordinate x = r_c - r_s,com.
    # The drag method and Hasimoto's D(L) give the mobility of x (force F on
    # the colloid, -F on the solvent, velocity relative to the solvent), so
    # equilibrium D's of the colloid itself are smaller by frame_factor =
    # (Ms/(M+Ms))^2 (5.5 % at R=1.5, L=8; 2.8 % at R=3, L=20).
    M = float(colloid.mass)
    Ms = float(np.sum(system.part.all().mass)) - M
    out = {"vacf": [], "rvacf": [], "msd": [], "t_chunk": t_chunk,
           "frame_factor": (Ms / (M + Ms)) ** 2}
    steps = int(round(t_chunk / DT))
    for c in range(n_chunks):
        cv = acc.Correlator(obs1=vel, tau_lin=16, tau_max=vacf_tau_max, delta_N=5,
                            corr_operation="scalar_product", compress1="linear")
        cw = acc.Correlator(obs1=omg, tau_lin=16, tau_max=vacf_tau_max, delta_N=5,
                            corr_operation="scalar_product", compress1="linear")
        cm = acc.Correlator(obs1=pos, tau_lin=16, tau_max=msd_tau_max, delta_N=10,
                            corr_operation="square_distance_componentwise",
                            compress1="discard1")
        for k in (cv, cw, cm):
            system.auto_update_accumulators.add(k)
        for i in range(pieces):
            n = steps // pieces + (1 if i < steps % pieces else 0)
            system.integrator.run(n)
            if progress:
                progress.advance(n)
        system.auto_update_accumulators.clear()
        out["t_vacf"] = cv.lag_times()
        out["t_msd"] = cm.lag_times()
        out["vacf"].append(cv.result()[:, 0])
        out["rvacf"].append(cw.result()[:, 0])
        out["msd"].append(cm.result()[:, 0, :].sum(axis=1))
        if on_chunk:
            on_chunk(out, c + 1)
    return out


def drag_run(system, colloid, force, t_prod, t_equil=20.0, delta_N=10):
    """Drag method via marble.diffusion.measure_drag; returns the Result
    (D, D_err, v, v_err attributes).

    The error is the larger of the blocking error and the statistical floor
    sqrt(2 D / t_prod) for the time average of the velocity (its variance is
    2 D_x / T for a run much longer than the velocity correlation time): in
    runs of a few hundred tau the blocking analysis has no plateau and
    underestimates the error (we saw 3-sigma "outliers" with it alone).
    The blocking values are kept as D_err_blocking, v_err_blocking."""
    res = dif.measure_drag(system, [colloid], force=[force, 0.0, 0.0],
                           steps=int(round(t_prod / DT)),
                           equilibration_steps=int(round(t_equil / DT)), delta_N=delta_N, kT=KT)
    v_floor = np.sqrt(2.0 * max(res.D, 0.0) / t_prod)
    res.D_err_blocking, res.v_err_blocking = res.D_err, res.v_err
    if v_floor > res.v_err:
        res.v_err = v_floor
        res.D_err = KT * v_floor / np.linalg.norm(res.force)
    return res


def rows(a):
    return np.atleast_2d(np.asarray(a, dtype=float))


def analyse_equilibrium(eq, L, eta, paper=False, relative=True):
    """Green-Kubo and MSD-fit D with errors over the chunks (needs >= 2).
    relative=True divides by eq["frame_factor"]: D of the colloid-solvent
    relative coordinate, the quantity that the drag method and Hasimoto's
    D(L) describe (see equilibrium_run)."""
    f = 1.0 / eq["frame_factor"] if relative else 1.0
    t, V = np.asarray(eq["t_vacf"]), rows(eq["vacf"]) * f
    tm, M = np.asarray(eq["t_msd"]), rows(eq["msd"]) * f
    win_gk = gk_window(L, eta)
    win_gk = (min(win_gk[0], 0.5 * t[-1]), min(win_gk[1], t[-1]))
    gk = dif.green_kubo(t, V, window=win_gk)
    win_msd = msd_window(L, eta, 0.5 * tm[-1], paper)
    win_msd = (min(win_msd[0], 0.25 * tm[-1]), min(win_msd[1], tm[-1]))
    msd = dif.msd_fit(tm, M, window=win_msd)
    return gk, win_gk, msd, win_msd


def jsonable(x):
    if isinstance(x, dict):
        return {k: jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (np.floating, float)):
        return None if not np.isfinite(x) else float(x)
    if isinstance(x, np.integer):
        return int(x)
    return x


def write_json(path, data):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(jsonable(data), f, indent=1)
    os.replace(tmp, path)


def common_args(description, default_time, paper_time):
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--paper", action="store_true", help="paper size: R=3, L=20, paper run lengths")
    p.add_argument("--time", type=float, default=None,
                   help=f"production time per run in tau (default {default_time}, "
                        f"--paper {paper_time})")
    p.add_argument("--eta", type=float, default=1.24,
                   help="solvent viscosity for the theory (the engine's measured value)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", default=".", help="output directory")
    return p


def plot_setup():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


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
    os.makedirs(args.out, exist_ok=True)
    jpath = os.path.join(args.out, "marble_vacf.json")

    system, col, _ = make_system(L, R, args.gamma, args.seed)
    M, I = col.mass, col.rinertia[0]
    print(f"marble R={R} L={L} gamma={args.gamma}: M={M:.1f}, {n_chunks} chunks x {t_chunk} tau",
          flush=True)
    D_th = th.hasimoto_D(eta, R, L)
    Dr_th = th.rotational_diffusion_coefficient(eta, R, L)
    A_T = th.vacf_tail_amplitude(eta, RHO)
    A_R = th.rotational_vacf_tail_amplitude(eta, RHO)
    meta = dict(sample="marble_vacf", R=R, L=L, gamma=args.gamma, eta=eta, kT=KT, rho=RHO,
                dt=DT, mass=M, rinertia=I, seed=args.seed, t_chunk=t_chunk,
                n_chunks_planned=n_chunks, D_hasimoto_stick=D_th, Dr_hasimoto_stick=Dr_th,
                tail_amplitude_T=A_T, tail_amplitude_R=A_R)
    t_start = time.time()

    def save(eq, done):
        data = dict(meta, n_chunks_done=done, cpu_time_s=time.time() - t_start,
                    t_vacf=eq["t_vacf"], vacf_rows=eq["vacf"], rvacf_rows=eq["rvacf"])
        write_json(jpath, data)

    prog = Progress(n_chunks * int(round(t_chunk / DT)))
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
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "marble_vacf.png"), dpi=120)
    print(f"wrote {jpath} and marble_vacf.png")


if __name__ == "__main__":
    main()
