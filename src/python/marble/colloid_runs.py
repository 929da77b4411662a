"""Runs of a marble colloid in the marble paper's DPD solvent, shared by the
samples that reproduce Zhou & Schmid's Figs. 2-5 (samples/marble_*.py) and by
the diffusion tests: set-up, equilibrium runs with multiple-tau correlators
(VACF, rotational VACF, MSD), drag runs, the choice of fit windows, and small
I/O helpers. doc/paper-reproduction.md explains the method (incl. the frame
factor (Ms/(M+Ms))^2 between the colloid's own and the relative coordinate).
"""
import argparse
import json
import os
import time

import numpy as np

from . import _marble
from . import accumulators as acc
from . import diffusion as dif
from . import observables as obs
from . import theory as th
from .colloids import add_marble
from .system import System

KT, RHO, DT, GAMMA_DPD = 1.0, 3.0, 0.01, 5.0
QUICK = os.environ.get("MARBLE_SAMPLE_TEST") == "1"


def marble_box(L, R, gamma, seed, rho=RHO, gamma_dpd=GAMMA_DPD, kT=KT, dt=DT, marble_r_cut=1.0,
               coupling="tunable_slip", skin=0.4):
    """The marble paper's solvent (density rho, DPD gamma_dpd, w = 1 - r, r_c = 1,
    no conservative force) in a periodic cube of side L with one neutrally
    buoyant marble (add_marble defaults) of radius R and surface friction
    ``gamma`` at the centre; total momentum zero, no equilibration; Verlet
    ``skin`` of the cell system. The integrator is left at its default
    (velocity Verlet). Returns (system, colloid, solvent)."""
    system = System(box_l=[L] * 3)
    system.time_step = dt
    system.cell_system.skin = skin
    rng = np.random.default_rng(seed)
    n = int(round(rho * L ** 3))
    system.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)) * np.sqrt(kT), type=0)
    system.thermostat.set_dpd(kT=kT, seed=seed)
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma_dpd, k=1,
                                                 r_cut=1.0)
    colloid = add_marble(system, pos=[L / 2] * 3, radius=R, gamma=gamma, r_cut=marble_r_cut,
                         coupling=coupling)
    solvent = system.part.select(type=0)
    # zero total momentum: a drifting centre of mass would add a constant to the
    # VACF and a ballistic t^2 term to the MSD
    p = colloid.mass * np.asarray(colloid.v) + np.sum(solvent.v, axis=0)
    solvent.v = np.asarray(solvent.v) - p / len(solvent)
    return system, colloid, solvent


INTEGRATORS = ("vv", "shardlow")


def default_dt(integrator, R):
    """The samples' time step for @p integrator and a marble of radius @p R:
    the paper's 0.01 for velocity Verlet; for Shardlow the advisor's
    marble_dt(R): 0.04 up to R = 2, and 0.06 with default_substeps = 3 RESPA
    substeps for the marble's wall above (at R = 3, plain Shardlow at dt = 0.04
    lets rare beads hit the WCA wall hard enough to move more than the skin in
    one step; doc/speed-accuracy.md)."""
    if check_integrator(integrator) == "vv":
        return DT
    from .advisor import marble_dt
    return marble_dt(R)


def default_substeps(integrator, R):
    """The RESPA substeps that go with default_dt(integrator, R): 1 for velocity
    Verlet, advisor.marble_substeps(R) for Shardlow (3 above R = 2)."""
    if check_integrator(integrator) == "vv":
        return 1
    from .advisor import marble_substeps
    return marble_substeps(R)


def default_skin(integrator, R, dt=None, substeps=None):
    """The Verlet skin that goes with the step: 0.6 for Shardlow at its RESPA
    step above R = 2 (dt = 0.06 with 3 substeps: at skin 0.4 the lists are
    rebuilt every step there; skin 0.6 is 11-13 % cheaper per tau at L = 12 and
    20, with the same D, doc/speed-accuracy.md), 0.4 (marble_box's) otherwise.
    ``dt``/``substeps`` default to default_dt/default_substeps(integrator, R)."""
    dt = default_dt(integrator, R) if dt is None else float(dt)
    substeps = default_substeps(integrator, R) if substeps is None else int(substeps)
    if check_integrator(integrator) == "shardlow" and substeps > 1 and dt >= 0.05:
        return 0.6
    return 0.4


def check_integrator(integrator):
    """@p integrator if it is one of INTEGRATORS, else ValueError."""
    if integrator not in INTEGRATORS:
        raise ValueError(f"integrator must be one of {INTEGRATORS}, got {integrator!r}")
    return integrator


def steps_for(system, t):
    """The number of steps of the system's time step in @p t tau."""
    return int(round(t / system.time_step))


def every(system, t):
    """A sampling interval in steps close to @p t tau (at least one step)."""
    return max(1, int(round(t / system.time_step)))


def make_system(L, R, gamma, seed, coupling="tunable_slip", warmup=10.0, integrator="vv", dt=None,
                substeps=None, skin=None):
    """Paper solvent in a cubic box of side L with one marble of radius R at the
    centre (marble_box); total momentum set to zero; `warmup` tau of equilibration.
    ``integrator`` is "vv" (velocity Verlet, the paper's) or "shardlow" (the DPD
    pairs by Shardlow's exact pair update, doc/dpd.md); ``dt`` defaults to
    default_dt(integrator, R); ``substeps``: the integrator's RESPA substeps for
    the marble's wall (set_vv / set_shardlow(substeps=...), doc/speed-accuracy.md),
    default: default_substeps(integrator, R) when dt is default_dt(integrator, R)
    (given or defaulted), else 1; ``skin``: the Verlet skin, default
    default_skin(integrator, R, dt, substeps) (0.6 at the RESPA step, else 0.4)."""
    check_integrator(integrator)
    if substeps is None:
        substeps = default_substeps(integrator, R) if dt is None or float(dt) == default_dt(integrator, R) \
            else 1
    dt = default_dt(integrator, R) if dt is None else float(dt)
    if not dt > 0:
        raise ValueError(f"dt must be > 0, got {dt}")
    if skin is None:
        skin = default_skin(integrator, R, dt, substeps)
    system, colloid, solvent = marble_box(L, R, gamma, seed, coupling=coupling, dt=dt, skin=skin)
    if integrator == "shardlow":
        system.integrator.set_shardlow(substeps=substeps)
    elif substeps != 1:
        system.integrator.set_vv(substeps=substeps)
    if warmup > 0:
        system.integrator.run(steps_for(system, warmup))
    return system, colloid, solvent


def tau_box(L, eta):
    """Decay time of the slowest shear mode of the box, L^2/(4 pi^2 nu): the
    VACF tail is cut off after a few of these, so the Green-Kubo integral has
    converged to D(L)."""
    return L ** 2 / (4 * np.pi ** 2 * eta / RHO)


def gk_window(L, eta):
    """Green-Kubo integration window (3, 6) x tau_box(L, eta)."""
    tb = tau_box(L, eta)
    return (3.0 * tb, 6.0 * tb)


def msd_window(L, eta, t_max, paper=False):
    """The paper fits t > 25 tau; in small boxes the linear regime starts earlier
    (3 tau_box). The upper end is limited by the statistics of the chunk."""
    lo = 25.0 if paper else min(25.0, 3.0 * tau_box(L, eta))
    return (lo, max(t_max, 2 * lo))


class Progress:
    """Prints steps done, elapsed time and ETA of a long run."""
    def __init__(self, total_steps, label=""):
        self.total, self.done, self.t0, self.label = total_steps, 0, time.time(), label

    def advance(self, steps):
        """Count ``steps`` more steps and print the progress line."""
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
    steps = steps_for(system, t_chunk)
    # samples every ~0.05 tau (VACF) and ~0.1 tau (MSD): 5 and 10 steps at dt = 0.01
    n_v, n_m = every(system, 0.05), every(system, 0.1)
    for c in range(n_chunks):
        cv = acc.Correlator(obs1=vel, tau_lin=16, tau_max=vacf_tau_max, delta_N=n_v,
                            corr_operation="scalar_product", compress1="linear")
        cw = acc.Correlator(obs1=omg, tau_lin=16, tau_max=vacf_tau_max, delta_N=n_v,
                            corr_operation="scalar_product", compress1="linear")
        cm = acc.Correlator(obs1=pos, tau_lin=16, tau_max=msd_tau_max, delta_N=n_m,
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


def drag_run(system, colloid, force, t_prod, t_equil=20.0, delta_N=None):
    """Drag method via marble.diffusion.measure_drag; returns the Result
    (D, D_err, v, v_err attributes).

    The error is the larger of the blocking error and the statistical floor
    sqrt(2 D / t_prod) for the time average of the velocity (its variance is
    2 D_x / T for a run much longer than the velocity correlation time): in
    runs of a few hundred tau the blocking analysis has no plateau and
    underestimates the error (we saw 3-sigma "outliers" with it alone).
    The blocking values are kept as D_err_blocking, v_err_blocking. The
    velocity is sampled every ``delta_N`` steps (default: ~0.1 tau)."""
    if delta_N is None:
        delta_N = every(system, 0.1)
    res = dif.measure_drag(system, [colloid], force=[force, 0.0, 0.0],
                           steps=steps_for(system, t_prod),
                           equilibration_steps=steps_for(system, t_equil), delta_N=delta_N, kT=KT)
    v_floor = np.sqrt(2.0 * max(res.D, 0.0) / t_prod)
    res.D_err_blocking, res.v_err_blocking = res.D_err, res.v_err
    if v_floor > res.v_err:
        res.v_err = v_floor
        res.D_err = KT * v_floor / np.linalg.norm(res.force)
    return res


def rows(a):
    """``a`` as a 2D float array (one row per chunk)."""
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
    """numpy scalars/arrays -> plain JSON types; non-finite floats -> None."""
    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, (np.floating, float)):
        return None if not np.isfinite(x) else float(x)
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    return x


def write_json(path, data):
    """Write atomically (temp file + rename); under MPI only rank 0 writes."""
    if _marble.mpi_rank() != 0:
        return
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(jsonable(data), f, indent=1)
    os.replace(tmp, path)


def common_args(description, default_time, paper_time):
    """Argument parser with the options the paper samples share."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--paper", action="store_true", help="paper size: R=3, L=20, paper run lengths")
    p.add_argument("--time", type=float, default=None,
                   help=f"production time per run in tau (default {default_time}, "
                        f"--paper {paper_time})")
    p.add_argument("--eta", type=float, default=1.24,
                   help="solvent viscosity for the theory (the engine's measured value)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--out", default=".", help="output directory")
    p.add_argument("--integrator", choices=INTEGRATORS, default="vv",
                   help="vv: velocity Verlet (the paper's); shardlow: Shardlow's exact DPD pair "
                        "update (doc/speed-accuracy.md's choice at dt = 0.04)")
    p.add_argument("--dt", type=float, default=None,
                   help="time step (default 0.01 with vv; with shardlow 0.04 up to R = 2, "
                        "0.06 with 3 RESPA substeps for the marble's wall above; a non-default "
                        "dt runs without substeps)")
    return p


def integration_args(args, R):
    """(integrator, dt) from the parsed common_args for a marble of radius R,
    dt defaulted (default_dt; make_system checks it)."""
    return args.integrator, default_dt(args.integrator, R) if args.dt is None else args.dt


def save_figure(fig, out_dir, name, json_path):
    """Lay out @p fig and write it as out_dir/name (under MPI rank 0 writes,
    like write_json); report it with the JSON file."""
    fig.tight_layout()
    if _marble.mpi_rank() == 0:
        fig.savefig(os.path.join(out_dir, name), dpi=120)
    print(f"wrote {json_path} and {name}")


def plot_setup():
    """matplotlib.pyplot with the non-interactive Agg backend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


