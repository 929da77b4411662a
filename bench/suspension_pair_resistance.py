"""Two stick colloids in the DPD solvent: squeeze resistance against the gap (issue 13).

doc/suspensions.md section 7g. Two calibrated stick colloids (setup_suspension's
boundary="stick", hydrodynamic radius R = 1, seed 004's solvent) move with prescribed,
equal and opposite velocities +/-U along their line of centres, so their surface gap h
sweeps a triangle wave between --h-lo and --h-hi (approach at relative speed 2U, then
separation at 2U, ...). The force each colloid receives from the solvent is measured
exactly as its momentum change: the colloids get a huge mass M (and moment of inertia),
so the solvent's impulse J over a chunk of steps changes their velocity by J/M only;
the velocity is reset to +/-U after every chunk and J = M (v_after - v_set).

Why not frozen colloids: a colloid held in place while it "carries" a velocity is
the same Stokes problem only in a continuum; here the colloid-solvent repulsion acts
on the positions, so a frozen colloid is impenetrable where the moving one would push
solvent away (the normal boundary condition), and it would measure something else.
The motion is real, and the measurement is quasi-steady.

The colloid-colloid kernels (squeeze lubrication, seed 004's colloid DPD) are switched
off in the simulation: with prescribed motion they act on the colloids only, so the
solvent's flow does not depend on them and their mean force is added analytically
(a_sq(h_core) 2U and gamma w(h_core)^2 2U). Per gap bin:

    lambda_app, lambda_sep   the resisting force per colloid / (6 pi eta_0 R U), approach and separation
    lambda_odd  = (lambda_app + lambda_sep)/2  the part linear in U (static, inertial O(U^2) and
                   history terms even in U cancel)
    lambda_even = (lambda_app - lambda_sep)/2  what cancelled
    theory      = the exact two-sphere squeeze resistance (marble.theory.two_sphere_squeeze_resistance)

Errors: 10 time blocks (each holds many passes). eta_0 = 0.3290(30) (section 7d, the same solvent
at density 3); R = 1 is the drag radius (section 7d, c = 1.013(10)).

    build/pymarble bench/suspension_pair_resistance.py --time 3000 --seed 1 \
        --json bench/results/suspension_pair_resistance.json

--mode frozen holds the pair at --gap and takes the squeeze and transverse frictions from
the force autocorrelation; --shared full|split|off sets the stick kernel's treatment of a
bead inside both colloids' friction shells (section 7t compares the transverse friction with
bench/two_sphere_stokes.py's no-slip pair for "full" and "off").

--mode slide drives the pair at fixed --gap with +/-U perpendicular to its line of centres and
no rotation, and measures the transverse resistance Y^A_11 - Y^A_12 as the sweep measures the
squeeze (the solvent's impulse on the heavy colloids, velocities reset every chunk), after
--discard time units of steady sliding; it prints the ratio to bench/two_sphere_stokes.py's
stored no-slip value when the gap is one of its rows (section 7v):

    build/pymarble bench/suspension_pair_resistance.py --mode slide --gap 0.1 --time 3000 \
        --shared off --json bench/results/suspension_pair_slide_h010_off.json
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
from marble.accumulators import fft_correlate

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import machine_info  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--L", type=float, default=8.0, help="cubic box edge")
parser.add_argument("--U", type=float, default=0.05, help="speed of each colloid")
parser.add_argument("--h-lo", type=float, default=0.05, help="smallest gap h = r - 2R of the sweep")
parser.add_argument("--h-hi", type=float, default=1.65, help="largest gap of the sweep")
parser.add_argument("--time", type=float, default=1000.0, help="time of the sweeps (after --equil and one discarded period)")
parser.add_argument("--equil", type=float, default=20.0, help="time at rest before the sweeps")
parser.add_argument("--dt", type=float, default=0.01)
parser.add_argument("--chunk", type=int, default=10, help="steps per impulse chunk")
parser.add_argument("--seed", type=int, default=1)
parser.add_argument("--eta0", type=float, nargs=2, default=[0.3290, 0.0030],
                    help="solvent viscosity and its error (section 7d)")
parser.add_argument("--bins", type=float, nargs="+",
                    default=[0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.7, 0.9, 1.2, 1.65],
                    help="gap bin edges")
parser.add_argument("--blocks", type=int, default=10)
parser.add_argument("--raw", help="also save the chunk records (npz) here")
parser.add_argument("--from-raw", help="analyse the chunk records of an earlier run (npz) instead of "
                    "simulating (pass the run's --U, --dt, --chunk, --L, --time, --h-lo, --h-hi, --seed)")
parser.add_argument("--json", help="write the result (JSON) to this file")
parser.add_argument("--mode", choices=["sweep", "frozen", "slide"], default="sweep",
                    help="sweep: prescribed +/-U (triangle wave in h); frozen: the pair held at --gap, "
                    "friction from the force autocorrelation (Green-Kubo, heavy-particle limit); slide: the "
                    "pair at --gap driven at +/-U perpendicular to its line of centres, no rotation (the "
                    "transverse resistance Y^A_11 - Y^A_12, measured as the sweep measures the squeeze)")
parser.add_argument("--gap", type=float, default=0.3, help="frozen, slide: the gap h = r - 2R")
parser.add_argument("--discard", type=float, default=100.0,
                    help="slide: time of steady sliding discarded before the measurement")
parser.add_argument("--t-max", type=float, nargs="+", default=[2.0, 5.0, 10.0, 20.0, 40.0],
                    help="frozen: upper limits of the Green-Kubo integral")
parser.add_argument("--shared", choices=sus.STICK_SHARED_MODES, default=sus.STICK_SHARED_DEFAULT,
                    help="the stick kernel's treatment of a bead in both colloids' friction shells "
                    "(setup_suspension's shared; default its default, off; full in every run before "
                    "session 36 and in the JSON files without the key)")
parser.add_argument("--quiet", action="store_true")
args = parser.parse_args()

for name in ("L", "U", "time", "dt"):
    if not getattr(args, name) > 0:
        raise ValueError(f"parameter '--{name.lower()}' must be > 0")
if not 0 < args.h_lo < args.h_hi:
    raise ValueError("parameters '--h-lo' and '--h-hi' must satisfy 0 < h_lo < h_hi")
if args.chunk < 1:
    raise ValueError("parameter '--chunk' must be >= 1")

R = 1.0          # hydrodynamic radius (setup_suspension's calibrated stick colloid)
KT, GAMMA, ETA_KERNEL = 0.1, 4.5, 0.3   # seed 004; ETA_KERNEL: setup_suspension's default eta
M_BIG = 1e7      # the colloids' mass and moment of inertia during the sweeps
eta0, eta0_err = args.eta0
L = args.L
if L < 2 * R + args.h_hi + 2.5:
    raise ValueError(f"parameter '--L' must be >= 2R + h_hi + 2.5 = {2 * R + args.h_hi + 2.5}")


def new_pair_system(r0):
    """Two calibrated stick colloids at centre distance r0 on the x axis, heavy, at rest,
    the solvent equilibrated for --equil (colloid-colloid kernels off: see the module doc)."""
    s = marble.System(box_l=[L] * 3)
    s.time_step = args.dt
    s.cell_system.skin = 0.4
    c0 = 0.5 * L
    pos = [[c0 - 0.5 * r0, c0, c0], [c0 + 0.5 * r0, c0, c0]]
    info = sus.setup_suspension(s, phi=0.01, radius=R, kT=KT, gamma=GAMMA, eta=ETA_KERNEL, seed=args.seed,
                                positions=pos, boundary="stick", solvent_count="exact",
                                lubrication=False, colloid_dpd=False, shared=args.shared)
    col = s.part.by_ids(info["colloid_ids"])
    col.mass = [M_BIG, M_BIG]
    col.rinertia = np.full((2, 3), M_BIG)
    col.omega_lab = np.zeros((2, 3))
    col.v = np.zeros((2, 3))
    s.integrator.set_shardlow()
    s.integrator.run(int(round(args.equil / args.dt)))
    return s, info, col


def gk_integral(f, tau, t_max):
    """int_0^t_max <f(t) f(0)> dt from chunk means f (mean removed), exact for chunk
    averages: (tau/2) [c_0 + 2 sum_{1<=j<=m} c_j]."""
    f = np.asarray(f, dtype=float)
    c = fft_correlate((f - f.mean())[:, None], max_lag=int(round(t_max / tau)))[:, 0]
    return 0.5 * tau * (c[0] + 2 * np.sum(c[1:]))


def run_at_fixed_gap(v_set, discard_time):
    """The pair at centre distance 2R + --gap, both colloids reset to the velocities v_set
    (2 x 3) and to no rotation before every chunk: after discard_time, the solvent's impulse
    on each colloid per chunk for --time. Returns (forces (n, 2, 3), the gap at the end,
    setup_suspension's info, CPU-s)."""
    if not args.gap > 0:
        raise ValueError("parameter '--gap' must be > 0")
    if not discard_time >= 0:
        raise ValueError("parameter '--discard' must be >= 0")
    t_cpu0 = time.process_time()
    s, info, col = new_pair_system(2 * R + args.gap)
    k = args.chunk
    tau = k * args.dt
    n_discard = int(round(discard_time / tau))
    n = int(round(args.time / tau))
    zero = np.zeros((2, 3))
    J = np.empty((n, 2, 3))
    for i in range(n_discard + n):
        col.v = v_set
        col.omega_lab = zero
        s.integrator.run(k)
        if i >= n_discard:
            J[i - n_discard] = M_BIG * (np.asarray(col.v) - v_set)
        if not args.quiet and i % 5000 == 0:
            print(f"chunk {i}/{n_discard + n}, cpu {time.process_time() - t_cpu0:.0f} s", flush=True)
    x = np.asarray(col.pos)
    return J / tau, float(x[1, 0] - x[0, 0] - 2 * R), info, time.process_time() - t_cpu0


if args.mode == "frozen":
    f, h_run, info, cpu = run_at_fixed_gap(np.zeros((2, 3)), 0.0)
    k = args.chunk
    tau = k * args.dt
    n = len(f)
    # squeeze: f_a = (F1x - F2x)/2, int <f_a f_a> = kT (zeta_11 - zeta_12)/2;
    # tangential (no rotation), y and z: (F1y - F2y)/2 likewise with Y^A_11 - Y^A_12
    f_sq = 0.5 * (f[:, 0, 0] - f[:, 1, 0])
    f_t = [0.5 * (f[:, 0, 1] - f[:, 1, 1]), 0.5 * (f[:, 0, 2] - f[:, 1, 2])]
    zeta0 = 6 * math.pi * eta0 * R
    blocks = np.array_split(np.arange(n), args.blocks)
    res = []
    for tm in args.t_max:
        sq = np.array([2 * gk_integral(f_sq[b], tau, tm) / KT for b in blocks]) / zeta0
        tg = np.array([np.mean([2 * gk_integral(ft[b], tau, tm) / KT for ft in f_t]) for b in blocks]) / zeta0
        res.append(dict(t_max=tm, lambda_squeeze=float(sq.mean()),
                        lambda_squeeze_err=float(sq.std(ddof=1) / math.sqrt(len(sq))),
                        lambda_tangential=float(tg.mean()),
                        lambda_tangential_err=float(tg.std(ddof=1) / math.sqrt(len(tg)))))
    # the mean force along the line of centres (the solvent-mediated static force; > 0: repulsive)
    f_mean = -f_sq
    fm = np.array([f_mean[b].mean() for b in blocks])
    th = theory.two_sphere_squeeze_resistance(h_run / R)
    a = info["core_radius"]
    h_core = h_run + 2 * R - 2 * a
    lam_lub = 1.5 * math.pi * ETA_KERNEL * a * a / max(h_core, info["h_min"]) * 2 / zeta0 if h_core < info["h_cut"] else 0.0
    lam_cdpd = GAMMA * max(1 - h_core, 0.0) ** 2 * 2 / zeta0
    out = dict(bench="suspension_pair_resistance", mode="frozen", L=L, gap=args.gap, gap_end=h_run, dt=args.dt,
               shared=args.shared,
               chunk=k, seed=args.seed, time=args.time, equil=args.equil, R=R, core_radius=a, kT=KT,
               eta0=eta0, eta0_err=eta0_err, n_solvent=info["n_solvent"], blocks=args.blocks,
               gk=res, theory_squeeze=th, theory_squeeze_lubrication=theory.two_sphere_squeeze_lubrication(h_run / R),
               lambda_lubrication_kernel=lam_lub, lambda_colloid_dpd=lam_cdpd,
               mean_force=float(fm.mean()), mean_force_err=float(fm.std(ddof=1) / math.sqrt(len(fm))),
               cpu_s=cpu, machine=machine_info())
    print(f"frozen pair, h = {h_run:.4f} (core gap {h_core:.4f}), L = {L}, {info['n_solvent']} beads, "
          f"{args.time} time units, cpu {cpu:.0f} s; theory lambda = {th:.4f}, lubrication kernel {lam_lub:.3f}, "
          f"colloid DPD {lam_cdpd:.3f}; mean force {fm.mean():+.4f} +/- {out['mean_force_err']:.4f}")
    for r in res:
        print(f"t_max {r['t_max']:5.1f}: squeeze {r['lambda_squeeze']:.3f} +/- {r['lambda_squeeze_err']:.3f} "
              f"(/theory {r['lambda_squeeze'] / th:.3f}), tangential {r['lambda_tangential']:.3f} "
              f"+/- {r['lambda_tangential_err']:.3f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1, default=float)
    sys.exit(0)

def transverse_solve(xi):
    """bench/two_sphere_stokes.py's no-slip Y^A_11 - Y^A_12 at xi (from its stored result), or None."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "two_sphere_stokes.json")
    try:
        rows = json.load(open(path))["rows"]
    except (OSError, KeyError, ValueError):
        return None
    for r in rows:
        if abs(r["xi"] - xi) < 1e-6:
            return r["transverse_extrapolated"], r["transverse_err"]
    return None


def periodic_transverse_correction(d, box, sigma=0.3):
    """The change of the relative transverse mobility (mu_11 - mu_12, units 1/(6 pi eta R)) of two
    point forces +/-F e_y at distance d along x when the unbounded fluid becomes the periodic cube
    of edge box (net force zero): the lattice sum (1/V) sum_k (1 - k_y^2/k^2)/k^2 (1 - cos k_x d)
    minus its unbounded integral, both with the Gaussian regularisation exp(-k^2 sigma^2) (the
    image field is smooth, so sigma << d, box drops out: the same sum without the (1 - cos) term
    gives Hasimoto's self term -2.837 R/box to 1 % at sigma = 0.3). Negative: the box raises the
    resistance; the no-slip pair in the box resists with 1/(1/lambda + correction)."""
    from scipy.integrate import quad
    nmax = int(math.ceil(7.0 / sigma / (2 * math.pi / box)))
    n = np.arange(-nmax, nmax + 1)
    kv = 2 * math.pi / box * np.stack(np.meshgrid(n, n, n, indexing="ij")).reshape(3, -1)
    k2 = (kv ** 2).sum(0)
    m = k2 > 0
    kv, k2 = kv[:, m], k2[m]
    lat = np.sum((1 - kv[1] ** 2 / k2) / k2 * np.exp(-k2 * sigma ** 2) * (1 - np.cos(kv[0] * d))) / box ** 3

    def angular(a):   # the mean over directions of (1 - k_y^2/k^2) cos(k_x d), a = k d
        return quad(lambda u: 0.25 * (1 + u * u) * math.cos(a * u), -1, 1, limit=200)[0]
    free = quad(lambda k: math.exp(-k * k * sigma ** 2) * (2.0 / 3.0 - angular(k * d)), 0, 60 / sigma,
                limit=400)[0] / (2 * math.pi ** 2)
    return float(6 * math.pi * (lat - free))


if args.mode == "slide":
    # Colloid 0 moves at +U e_y, colloid 1 at -U e_y, both held without rotation; their line of
    # centres is x, so the gap stays --gap. The solvent's impulse on each over a chunk is
    # M (v_after - v_set), as in the sweep. The net force on the pair vanishes on average, so the
    # periodic images' leading (Hasimoto, 1/L) term cancels as for the squeeze. Nothing moves along
    # the line of centres, so the squeeze lubrication and seed 004's colloid DPD exert no mean force.
    f, h_run, info, cpu = run_at_fixed_gap(np.array([[0.0, args.U, 0.0], [0.0, -args.U, 0.0]]), args.discard)
    k = args.chunk
    n = len(f)
    zeta0 = 6 * math.pi * eta0 * R
    blocks = np.array_split(np.arange(n), args.blocks)

    def per_block(values):
        b = np.array([values[ix].mean() for ix in blocks])
        return float(b.mean()), float(b.std(ddof=1) / math.sqrt(len(b)))

    # resisting force per colloid along its motion, over 6 pi eta_0 R U
    lam, lam_err = per_block(-0.5 * (f[:, 0, 1] - f[:, 1, 1]) / (zeta0 * args.U))
    # checks that vanish by symmetry: the net force along y, the mean forces along z
    net, net_err = per_block(0.5 * (f[:, 0, 1] + f[:, 1, 1]) / (zeta0 * args.U))
    fz, fz_err = per_block(0.5 * (f[:, 0, 2] - f[:, 1, 2]) / (zeta0 * args.U))
    fx, fx_err = per_block(-0.5 * (f[:, 0, 0] - f[:, 1, 0]))
    solve = transverse_solve(args.gap / R)   # (h_run drifts by ~1e-5 over a run)
    lam_rel = lam_rel_err = box_solve = None
    box_corr = periodic_transverse_correction(2 * R + args.gap, L)
    if solve is not None:
        box_solve = 1.0 / (1.0 / solve[0] + box_corr)
        lam_rel = lam / solve[0]
        # statistical error, eta_0's error and the solve's, in quadrature
        lam_rel_err = abs(lam_rel) * math.sqrt((lam_err / lam) ** 2 + (eta0_err / eta0) ** 2
                                               + (solve[1] / solve[0]) ** 2)
    out = dict(bench="suspension_pair_resistance", mode="slide", L=L, U=args.U, gap=args.gap, gap_end=h_run,
               dt=args.dt, shared=args.shared, chunk=k, seed=args.seed, time=args.time, discard=args.discard,
               equil=args.equil, R=R, core_radius=info["core_radius"], kT=KT, eta0=eta0, eta0_err=eta0_err,
               n_solvent=info["n_solvent"], blocks=args.blocks,
               lambda_transverse=lam, lambda_transverse_err=lam_err,
               transverse_solve=None if solve is None else solve[0],
               transverse_solve_err=None if solve is None else solve[1],
               lambda_over_solve=lam_rel, lambda_over_solve_err=lam_rel_err,
               periodic_mobility_correction=box_corr, transverse_solve_in_box=box_solve,
               net_force_y=net, net_force_y_err=net_err, transverse_force_z=fz, transverse_force_z_err=fz_err,
               mean_force_x=fx, mean_force_x_err=fx_err, cpu_s=cpu, machine=machine_info())
    print(f"sliding pair, h = {h_run:.4f}, U = {args.U}, L = {L}, shared {args.shared}, {info['n_solvent']} beads, "
          f"{args.time} time units after {args.discard}, cpu {cpu:.0f} s")
    print(f"transverse lambda = {lam:.4f} +/- {lam_err:.4f}"
          + ("" if solve is None else f"; no-slip solve {solve[0]:.4f}: ratio {lam_rel:.3f} +/- {lam_rel_err:.3f}; "
             f"in the periodic box (mobility {box_corr:+.4f}) {box_solve:.4f}: ratio {lam / box_solve:.3f}"))
    print(f"checks (0 by symmetry, same units): net y {net:+.4f} +/- {net_err:.4f}, z {fz:+.4f} +/- {fz_err:.4f}; "
          f"mean force along the line of centres {fx:+.4f} +/- {fx_err:.4f} (> 0: repulsive)")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1, default=float)
    sys.exit(0)

k = args.chunk
if args.from_raw:
    raw = np.load(args.from_raw)
    rec_h, rec_dir, rec_J, rec_T = raw["h"], raw["dir"], raw["J"], raw["T"]
    n_discard = int(raw["n_discard"])
    a = float(raw["core_radius"]) if "core_radius" in raw else R / sus.STICK_RADIUS_RATIO
    n_solvent = int(raw["n_solvent"]) if "n_solvent" in raw else None
    cpu = float(raw["cpu"]) if "cpu" in raw else None
    period = 2 * (args.h_hi - args.h_lo) / (2 * args.U)
    info = dict(h_min=0.001, h_cut=1.0)
else:
    t_cpu0 = time.process_time()
    s, info, col = new_pair_system(2 * R + args.h_hi)
    a = info["core_radius"]

    step_gap = 2 * args.U * k * args.dt   # gap change per chunk
    period = 2 * (args.h_hi - args.h_lo) / (2 * args.U)
    n_discard = int(math.ceil(period / (k * args.dt)))
    n_chunks = n_discard + int(round(args.time / (k * args.dt)))
    rec_h = np.empty(n_chunks)
    rec_dir = np.empty(n_chunks, dtype=np.int8)   # +1 approach, -1 separation
    rec_J = np.empty((n_chunks, 2, 3))
    rec_T = np.empty((n_chunks, 2, 3))
    direction = +1
    zero3 = np.zeros((2, 3))
    for i in range(n_chunks):
        x = np.asarray(col.pos)
        h = x[1, 0] - x[0, 0] - 2 * R
        if direction > 0 and h - step_gap < args.h_lo - 1e-12:
            direction = -1
        elif direction < 0 and h + step_gap > args.h_hi + 1e-12:
            direction = +1
        v_set = np.array([[direction * args.U, 0, 0], [-direction * args.U, 0, 0]])
        col.v = v_set
        col.omega_lab = zero3
        s.integrator.run(k)
        rec_J[i] = M_BIG * (np.asarray(col.v) - v_set)
        rec_T[i] = M_BIG * np.asarray(col.omega_lab)
        rec_h[i] = h - direction * 0.5 * step_gap
        rec_dir[i] = direction
        if not args.quiet and i % 2000 == 0:
            print(f"chunk {i}/{n_chunks}: h = {h:.3f}, cpu {time.process_time() - t_cpu0:.0f} s", flush=True)
    cpu = time.process_time() - t_cpu0
    n_solvent = info["n_solvent"]

tau = k * args.dt
keep = slice(n_discard, None)
h_all, d_all, J_all, T_all = rec_h[keep], rec_dir[keep], rec_J[keep], rec_T[keep]
# resisting force per colloid along the line of centres (positive: opposes the motion):
# colloid 0 moves with +direction U along x, colloid 1 with -direction U
f_res = -d_all * 0.5 * (J_all[:, 0, 0] - J_all[:, 1, 0]) / tau
zeta0 = 6 * math.pi * eta0 * R
lam = f_res / (zeta0 * args.U)
# the rest: net force along x (should vanish by symmetry), transverse forces and torques
f_net = 0.5 * (J_all[:, 0, 0] + J_all[:, 1, 0]) / tau
edges = np.asarray(args.bins, float)
nb = len(edges) - 1
blocks = np.array_split(np.arange(len(h_all)), args.blocks)


def block_means(mask_fn, values):
    out = np.full((args.blocks, nb), np.nan)
    for b, idx in enumerate(blocks):
        hb, vb = h_all[idx], values[idx]
        sel = mask_fn(idx)
        for j in range(nb):
            m = sel & (hb >= edges[j]) & (hb < edges[j + 1])
            if np.any(m):
                out[b, j] = np.mean(vb[m])
    return out


def mean_err(x):
    ok = np.isfinite(x)
    n = ok.sum(axis=0)
    m = np.nanmean(x, axis=0)
    e = np.nanstd(x, axis=0, ddof=1) / np.sqrt(np.maximum(n, 1))
    return m, e


app = block_means(lambda idx: d_all[idx] > 0, lam)
sep = block_means(lambda idx: d_all[idx] < 0, lam)
odd = 0.5 * (app + sep)
even = 0.5 * (app - sep)
m_app, e_app = mean_err(app)
m_sep, e_sep = mean_err(sep)
m_odd, e_odd = mean_err(odd)
m_even, e_even = mean_err(even)
m_net, e_net = mean_err(block_means(lambda idx: np.ones(len(idx), bool), f_net / (zeta0 * args.U)))

# gap of each bin: the time-weighted mean gap of its chunks
h_bin = np.array([np.mean(h_all[(h_all >= edges[j]) & (h_all < edges[j + 1])]) for j in range(nb)])
xi = h_bin / R
lam_th = np.array([theory.two_sphere_squeeze_resistance(x) for x in xi])
lam_jo = theory.two_sphere_squeeze_lubrication(xi)
# the colloid-colloid kernels setup_suspension adds (mean force for the prescribed motion,
# relative normal velocity 2U), on the core gap h_c = r - 2a
h_core = h_bin + 2 * R - 2 * a
h_min, h_cut = info["h_min"], info["h_cut"]
a_sq = 1.5 * math.pi * ETA_KERNEL * a * a / np.maximum(h_core, h_min)
a_sq = np.where(h_core < h_cut, a_sq, 0.0)
lam_lub = a_sq * 2 * args.U / (zeta0 * args.U)
w = np.clip(1 - h_core / 1.0, 0, None)
lam_cdpd = GAMMA * w ** 2 * 2 * args.U / (zeta0 * args.U)
rel_eta = eta0_err / eta0
rows = []
for j in range(nb):
    e_tot = math.hypot(e_odd[j], m_odd[j] * rel_eta)
    rows.append(dict(h_lo=edges[j], h_hi=edges[j + 1], h=h_bin[j], xi=xi[j],
                     n_chunks=int(np.sum((h_all >= edges[j]) & (h_all < edges[j + 1]))),
                     lambda_app=m_app[j], lambda_app_err=e_app[j],
                     lambda_sep=m_sep[j], lambda_sep_err=e_sep[j],
                     lambda_odd=m_odd[j], lambda_odd_err=e_odd[j], lambda_odd_err_with_eta0=e_tot,
                     lambda_even=m_even[j], lambda_even_err=e_even[j],
                     theory=lam_th[j], theory_lubrication_asymptote=lam_jo[j],
                     ratio_solvent=m_odd[j] / lam_th[j], ratio_solvent_err=e_tot / lam_th[j],
                     lambda_lubrication_kernel=lam_lub[j], lambda_colloid_dpd=lam_cdpd[j],
                     ratio_solvent_plus_lub=(m_odd[j] + lam_lub[j]) / lam_th[j],
                     ratio_all=(m_odd[j] + lam_lub[j] + lam_cdpd[j]) / lam_th[j]))



def fit_model(kind, y, e, scale=1.0):
    """Least-squares fit of the measured lambda (times scale) with spheres that act larger:
    kind "shift": lambda_th((h - delta)/R); kind "radius": (R'/R) lambda_th((h - 2(R' - R))/R')
    (spheres of radius R' at the same centres). Returns the parameter, its 1-sigma error
    (Delta chi^2 = 1) and chi^2 at the minimum."""
    from scipy.optimize import minimize_scalar
    ok = np.isfinite(y) & np.isfinite(e) & (e > 0)
    hh, yy, ee = h_bin[ok], scale * y[ok], scale * e[ok]

    def model(p):
        if kind == "shift":
            return np.array([theory.two_sphere_squeeze_resistance(max(x - p, 1e-4) / R) for x in hh])
        Rp = R + p
        return np.array([Rp / R * theory.two_sphere_squeeze_resistance(max(x - 2 * p, 1e-4) / Rp) for x in hh])

    def chi2(p):
        return float(np.sum(((yy - model(p)) / ee) ** 2))

    lo, hi = (-1.0, 0.95 * hh.min()) if kind == "shift" else (-0.5, 0.45 * hh.min())
    res = minimize_scalar(chi2, bounds=(lo, hi), method="bounded", options=dict(xatol=1e-5))
    p0, c0 = float(res.x), float(res.fun)
    grid = np.linspace(lo, hi, 801)
    c = np.array([chi2(g) for g in grid])
    inside = grid[c <= c0 + 1.0]
    return dict(value=p0, lo=float(inside.min()), hi=float(inside.max()), chi2=c0, dof=int(ok.sum()) - 1,
                at_bound=bool(abs(p0 - hi) < 1e-3 or abs(p0 - lo) < 1e-3))


lam_lub_all = np.array([r["lambda_lubrication_kernel"] for r in rows])
lam_cdpd_all = np.array([r["lambda_colloid_dpd"] for r in rows])
fits = {}
for label, y in [("solvent", m_odd), ("solvent_plus_lubrication", m_odd + lam_lub_all),
                 ("solvent_plus_lubrication_plus_colloid_dpd", m_odd + lam_lub_all + lam_cdpd_all)]:
    fits[label] = {}
    for kind in ("shift", "radius"):
        f = fit_model(kind, y, e_odd)
        # systematic: eta_0 +/- its error rescales every lambda
        f["eta0_minus"] = fit_model(kind, y, e_odd, scale=eta0 / (eta0 - eta0_err))["value"]
        f["eta0_plus"] = fit_model(kind, y, e_odd, scale=eta0 / (eta0 + eta0_err))["value"]
        fits[label][kind] = f
        print(f"fit {label:45s} {kind:6s}: {f['value']:+.4f} [{f['lo']:+.4f}, {f['hi']:+.4f}] "
              f"chi2 {f['chi2']:.1f}/{f['dof']}; eta0 -/+ 1 sigma: {f['eta0_minus']:+.4f} {f['eta0_plus']:+.4f}")

out = dict(bench="suspension_pair_resistance", mode="squeeze", shared=args.shared, L=L, U=args.U, dt=args.dt, chunk=k,
           seed=args.seed, time=args.time, equil=args.equil, discarded=n_discard * tau, period=period,
           h_lo=args.h_lo, h_hi=args.h_hi, R=R, core_radius=a, kT=KT, eta0=eta0, eta0_err=eta0_err,
           n_solvent=n_solvent, colloid_mass_during_sweeps=M_BIG,
           reynolds=3.0 * args.U * R / eta0, blocks=args.blocks,
           net_force_over_zeta0U=dict(mean=float(np.nanmean(m_net)), max_abs=float(np.nanmax(np.abs(m_net))),
                                      typical_err=float(np.nanmean(e_net))),
           transverse_force_rms_over_zeta0U=float(np.sqrt(np.mean((J_all[:, :, 1:] / tau) ** 2)) / (zeta0 * args.U)),
           cpu_s=cpu, rows=rows, fits=fits, machine=machine_info())
if args.raw:
    np.savez_compressed(args.raw, h=rec_h, dir=rec_dir, J=rec_J, T=rec_T, tau=tau, n_discard=n_discard,
                        core_radius=a, n_solvent=n_solvent, cpu=cpu, U=args.U, L=L, dt=args.dt)
print(f"{n_solvent} beads, L = {L}, U = {args.U}, {args.time} time units, cpu {cpu} s")
print(" h      n     lam_app        lam_sep        lam_odd        even           theory  odd/th   +lub/th  +lub+dpd/th")
for r in rows:
    print(f"{r['h']:.3f} {r['n_chunks']:6d} {r['lambda_app']:6.3f}({r['lambda_app_err']:.3f}) "
          f"{r['lambda_sep']:6.3f}({r['lambda_sep_err']:.3f}) {r['lambda_odd']:6.3f}({r['lambda_odd_err']:.3f}) "
          f"{r['lambda_even']:6.3f}({r['lambda_even_err']:.3f}) {r['theory']:7.3f} "
          f"{r['ratio_solvent']:.3f}({r['ratio_solvent_err']:.3f}) {r['ratio_solvent_plus_lub']:.3f} {r['ratio_all']:.3f}")
if args.json:
    with open(args.json, "w") as f:
        json.dump(out, f, indent=1, default=float)
