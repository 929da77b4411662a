"""The stresslet of one stick colloid in uniform shear (issue 13, doc/suspensions.md
section 7p): is its strain radius R_s the drag radius R_t or the rotational
radius R_r (section 7m: R_r/R_t = 1.053)?

One calibrated stick colloid (bench/stick_colloid_radii.py's scene:
``setup_suspension(boundary="stick")``'s defaults, core a = R/STICK_RADIUS_RATIO,
R = 1) at the centre of a periodic cube of edge L = 4.3756 (phi = 0.05 at radius
R) in seed 004's solvent (rho = 3, kT = 0.1, gamma = 4.5, a_ss = 25 kT, r_c = 1),
Shardlow dt = 0.01, sheared by Lees-Edwards at ``--rate`` (x along y). The
colloid's stresslet is the whole box's shear stress in excess of the same box
without the colloid at the same bulk solvent density (``--reference``: round(3 V)
beads), times the volume:

    S_xy = -V (<P_xy>_colloid - <P_xy>_reference)

(the solvent's stress integrated over the fluid is eta_0 times the whole box's
strain rate for a rigid particle, so everything above it is the particle's).
P_xy is the symmetrised xy element of ``pressure_tensor()``'s total plus its DPD
part, sampled every ``--every`` steps (default every step); errors by blocking.

- ``--part run``: one run, one JSON line (``--json``): <P_xy>, its blocking error,
  100 block means, the solvent kT of the peculiar velocities, the bead density
  farther than 1 from the core (colloid runs; "bulk" in setup_suspension's sense),
  the colloid's spin about z against the vorticity -rate/2.
- ``--part table``: groups the runs by rate, combines the seeds (weighted), and
  gives S_xy, the intrinsic viscosity in the box, the periodic-lattice factor
  (``marble.theory.stresslet_lattice_factor``: Lees-Edwards shear of a simple
  cubic array, one sphere per box) and the strain radius R_s from
  S_xy = (10/3) pi eta_0 R_s^3 rate x lattice(R_s), against R_t (drag, 7d/7m)
  and R_r (rotation, 7m), and Lin, Peery & Schowalter's unbounded inertial
  correction at each rate.

    build/pymarble bench/stick_colloid_stresslet.py --part run --rate 0.05 --time 60000 --seed 1 \\
        --json bench/results/stick_colloid_stresslet.jsonl
    build/pymarble bench/stick_colloid_stresslet.py --part run --reference --rate 0.05 --time 60000 --seed 1 \\
        --json bench/results/stick_colloid_stresslet.jsonl
    build/pymarble bench/stick_colloid_stresslet.py --part table --results bench/results/stick_colloid_stresslet.jsonl
"""
import argparse
import json
import math
import os
import sys
import time
import types

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import marble  # noqa: E402
import marble.lees_edwards as le  # noqa: E402
import marble.suspensions as sus  # noqa: E402
from marble import theory  # noqa: E402
from marble.diffusion import blocking  # noqa: E402
from stick_colloid_radii import weighted as _weighted  # noqa: E402

R, KT, GAMMA, DT = 1.0, 0.1, 4.5, 0.01
L_DEFAULT = 4.3756
RHO = 3.0
N_BLOCKS = 100


def parse(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--part", choices=["run", "table"], required=True)
    p.add_argument("--reference", action="store_true", help="run: the solvent alone (round(3 V) beads)")
    p.add_argument("--rate", type=float, default=0.05)
    p.add_argument("--L", type=float, default=L_DEFAULT)
    p.add_argument("--time", type=float, default=1000.0, help="run: sampled time units")
    p.add_argument("--equil", type=float, default=20.0, help="run: time units at rest")
    p.add_argument("--settle", type=float, default=20.0, help="run: sheared time units before sampling")
    p.add_argument("--every", type=int, default=1,
                   help="run: steps between stress samples (default 1: the cheapest per error bar, section 7p)")
    p.add_argument("--dt", type=float, default=None, help="time step (default 0.01; 0.005 with --vv)")
    p.add_argument("--vv", action="store_true", help="run: velocity Verlet instead of Shardlow (a check of the "
                                                     "stress estimator)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--solvent-count", choices=["bulk", "exact"], default="bulk",
                   help="run: setup_suspension's solvent count (bulk: the adsorbed shell added, so that the "
                        "solvent away from the colloid is at density 3 like the reference)")
    p.add_argument("--beads", type=int, default=None,
                   help="run --reference: this many beads instead of round(3 V) (the viscosity's density slope)")
    p.add_argument("--json", help="run: append the result (one JSON line) to this file")
    p.add_argument("--results", nargs="*", help="table: JSONL files of runs")
    p.add_argument("--pool-reference", action="store_true",
                   help="table: one solvent viscosity from the references of every rate (a Newtonian solvent), "
                        "instead of each rate's own")
    args = p.parse_args(argv)
    if args.dt is None:
        args.dt = 0.005 if args.vv else DT
    if args.part == "run":
        for name in ("L", "time", "equil", "settle", "dt", "rate"):
            v = getattr(args, name)
            if not (math.isfinite(v) and v > 0):
                p.error(f"--{name} must be > 0, got {v}")
        if args.time < 10.0:
            p.error(f"--time must be >= 10 (10 blocks of the once-per-time-unit samples), got {args.time}")
        if args.L < 3.0:
            p.error(f"--L must be >= 3 (the colloid's own image), got {args.L}")
        if args.every < 1:
            p.error("--every must be >= 1")
        if args.beads is not None and (args.beads < 1 or not args.reference):
            p.error("--beads must be >= 1 and goes with --reference")
    elif not args.results:
        p.error("--part table needs --results")
    return args


def make_scene(args):
    """The colloid box (stick_colloid_radii's scene) or the reference solvent,
    Shardlow, zero momentum, ``equil`` time units at rest."""
    if args.reference:
        s = marble.System(box_l=[args.L] * 3)
        s.time_step = args.dt
        s.cell_system.skin = 0.4
        rng = np.random.default_rng(args.seed)
        n = int(round(RHO * args.L ** 3)) if args.beads is None else args.beads
        s.part.add(pos=rng.uniform(0, 1, (n, 3)) * args.L, v=rng.normal(size=(n, 3)) * math.sqrt(KT))
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0 * KT, cutoff=1.0)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=GAMMA, r_cut=1.0)
        s.thermostat.set_dpd(kT=KT, seed=args.seed)
        s.integrator.set_shardlow()
        info = dict(n_solvent=n, colloid_ids=[], solvent_ids=list(range(n)))
    else:
        from stick_colloid_radii import colloid_box
        ns = types.SimpleNamespace(L=args.L, dt=args.dt, radius_calibration="stick", trans_gamma=None,
                                   stick_shell=None, seed=args.seed, solvent_count=args.solvent_count)
        s, info = colloid_box(ns)
    if args.vv:
        s.integrator.set_vv()
    s.galilei.galilei_transform()
    s.integrator.run(int(round(args.equil / args.dt)))
    return s, info


def run(args):
    t0 = time.process_time()
    s, info = make_scene(args)
    L = args.L
    s.lees_edwards.set_boundary_conditions(
        shear_direction="x", shear_plane_normal="y",
        protocol=le.LinearShear(shear_velocity=args.rate * L, time_0=s.time))
    parts = s.part.all()
    s.galilei.galilei_transform()
    v = np.asarray(parts.v)
    v[:, 0] += args.rate * (np.asarray(parts.pos_folded)[:, 1] - 0.5 * L)
    parts.v = v
    s.integrator.run(int(round(args.settle / args.dt)))
    m = np.asarray(parts.mass, dtype=float)
    cid = info["colloid_ids"]
    col = s.part.by_ids(cid) if len(cid) else None
    sol = s.part.by_ids(info["solvent_ids"])
    a = float(info.get("core_radius", 0.0))
    n_samples = int(round(args.time / (args.every * args.dt)))
    per_unit = max(1, int(round(1.0 / (args.every * args.dt))))  # samples per time unit
    pxy = np.empty(n_samples)
    kts, n_far, wz = [], [], []
    if col is not None:  # the volume farther than 1 from the core surface (Monte Carlo)
        x = np.random.default_rng([args.seed, 7]).uniform(-0.5, 0.5, (400000, 3)) * L
        v_far = float(np.count_nonzero(np.linalg.norm(x, axis=1) > a + 1.0)) / len(x) * L ** 3
    for k in range(n_samples):
        s.integrator.run(args.every)
        p = s.analysis.pressure_tensor()
        t = p["total"] + p["dpd"]
        pxy[k] = 0.5 * (t[0, 1] + t[1, 0])
        if k % per_unit == 0:
            y = np.asarray(parts.pos_folded)[:, 1]
            c = np.asarray(parts.v).copy()
            c[:, 0] -= args.rate * (y - 0.5 * L)
            c -= (m[:, None] * c).sum(axis=0) / m.sum()
            kts.append(float((m[:, None] * c ** 2).sum() / (3 * (len(m) - 1))))
            if col is not None:
                cp = np.mod(np.asarray(col.pos, float)[0], L)
                d = np.mod(np.asarray(sol.pos, float) - cp + 0.5 * L, L) - 0.5 * L
                n_far.append(int(np.count_nonzero(np.linalg.norm(d, axis=1) > a + 1.0)))
                wz.append(float(np.asarray(col.omega_lab, float)[0][2]))
    blk = blocking(pxy)
    blocks = [float(b.mean()) for b in np.array_split(pxy, N_BLOCKS)]
    out = dict(part="run", reference=bool(args.reference), rate=args.rate, L=args.L, seed=args.seed,
               integrator="vv" if args.vv else "shardlow",
               time=args.time, dt=args.dt, every=args.every, equil=args.equil, settle=args.settle,
               n_solvent=int(info["n_solvent"]), solvent_count=None if args.reference else args.solvent_count,
               core_radius=a if len(cid) else None, pxy=float(blk.mean), pxy_err=float(blk.error),
               pxy_err_blocks=float(np.std(blocks, ddof=1) / math.sqrt(N_BLOCKS)),
               blocking_converged=bool(blk.converged), blocks=blocks, kT=float(np.mean(kts)),
               cpu_s=time.process_time() - t0)
    if col is not None:
        out["far_density"] = float(np.mean(n_far)) / v_far
        out["far_density_err"] = float(np.std([np.mean(b) for b in np.array_split(n_far, 10)], ddof=1)
                                       / math.sqrt(10)) / v_far
        out["omega_z"] = float(np.mean(wz))
        out["omega_z_err"] = float(np.std([np.mean(b) for b in np.array_split(wz, 10)], ddof=1) / math.sqrt(10))
    kind = "reference" if args.reference else f"colloid ({args.solvent_count}, {info['n_solvent']} beads)"
    print(f"{kind}: rate {args.rate}, L = {L:.4f}, {args.time:g} time units: -<P_xy>/rate = "
          f"{-blk.mean / args.rate:.5f} +/- {blk.error / args.rate:.5f} (blocks {out['pxy_err_blocks'] / args.rate:.5f}); "
          f"kT {out['kT']:.4f}" + (f"; far density {out['far_density']:.4f} +/- {out['far_density_err']:.4f}; "
                                   f"omega_z {out['omega_z']:.4f} (-rate/2 = {-args.rate / 2:.4f})"
                                   if col is not None else "") + f"; CPU {out['cpu_s']:.0f} s")
    return out


def weighted(x, e):
    """(weighted mean, its error scaled by sqrt(chi^2/dof) above 1, chi^2): stick_colloid_radii's."""
    return _weighted(x, e)[:3]


def pxy_mean(rs):
    """Weighted <P_xy> of runs (each with the larger of its two error estimates): (mean, error, chi^2)."""
    return weighted([r["pxy"] for r in rs], [max(r["pxy_err"], r["pxy_err_blocks"]) for r in rs])


def stresslet_over(r, L):
    """S_xy/(eta rate/2) of a no-slip sphere of radius r in the box L: (20/3) pi r^3 x lattice(r, L)."""
    return (20.0 / 3.0) * math.pi * r ** 3 * theory.stresslet_lattice_factor(r, L)


def predictions(R_t, R_r, L):
    return {"R_t": stresslet_over(R_t, L), "R_r": stresslet_over(R_r, L)}


def strain_radius(S_over, L, lo=0.5, hi=1.5):
    """R_s with stresslet_over(R_s, L) = S_over (S_xy/(eta_0 rate/2))."""
    def f(r):
        return stresslet_over(r, L) - S_over
    if f(lo) > 0 or f(hi) < 0:
        return float("nan")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if f(mid) > 0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def table(args):
    runs = []
    for fn in args.results:
        with open(fn) as f:
            runs += [json.loads(line) for line in f if line.strip()]
    vv = [r for r in runs if r.get("part") == "run" and r.get("integrator") == "vv"]
    for r in vv:
        print(f"velocity Verlet (dt {r['dt']}): {'reference' if r['reference'] else 'colloid'} at rate {r['rate']}, "
              f"{r['n_solvent']} beads: -<P_xy>/rate = {-r['pxy'] / r['rate']:.5f} +/- "
              f"{max(r['pxy_err'], r['pxy_err_blocks']) / r['rate']:.5f} (not in the table below)")
    runs = [r for r in runs if r.get("part") == "run" and r.get("integrator", "shardlow") == "shardlow"]
    R_t = theory_R_t()
    R_r = sus.STICK_ROTATIONAL_RADIUS_RATIO / sus.STICK_RADIUS_RATIO * R
    print(f"radii (R = 1 the calibrated drag radius): R_t = {R_t:.4f}, R_r = {R_r:.4f} (section 7m)")
    out = []
    for (rate, L) in sorted({(r["rate"], r["L"]) for r in runs}):
        grp = [r for r in runs if r["rate"] == rate and r["L"] == L]
        col = [r for r in grp if not r["reference"] and r.get("solvent_count", "bulk") == "bulk"]
        exact = [r for r in grp if not r["reference"] and r.get("solvent_count") == "exact"]
        n_ref = int(round(RHO * L ** 3))
        ref = [r for r in grp if r["reference"] and r["n_solvent"] == n_ref]
        other = [r for r in grp if r["reference"] and r["n_solvent"] != n_ref]
        if other and ref:
            # the solvent viscosity's density slope d ln eta / d ln rho from references at other counts
            for n in sorted({r["n_solvent"] for r in other}):
                o = [r for r in other if r["n_solvent"] == n]
                po, poe, _ = pxy_mean(o)
                pr0, pre0, _ = pxy_mean(ref)
                sl = math.log(po / pr0) / math.log(n / n_ref)
                sle = math.hypot(poe / po, pre0 / pr0) / abs(math.log(n / n_ref))
                print(f"rate {rate}: reference at {n} beads: eta {-po / rate:.5f} +/- {poe / rate:.5f}; "
                      f"d ln eta / d ln rho = {sl:.2f} +/- {sle:.2f}")
        if not col or not ref:
            print(f"rate {rate}, L {L}: needs both colloid and reference runs ({len(col)}, {len(ref)})")
            continue
        V = L ** 3
        pc, pce, chc = pxy_mean(col)
        if args.pool_reference:
            pool = [r for r in runs if r["reference"] and r["L"] == L and r["n_solvent"] == n_ref]
            er, ere, chr_ = weighted([-r["pxy"] / r["rate"] for r in pool],
                                     [max(r["pxy_err"], r["pxy_err_blocks"]) / r["rate"] for r in pool])
            pr, pre = -er * rate, ere * rate
            ref = pool
        else:
            pr, pre, chr_ = pxy_mean(ref)
        S = -V * (pc - pr)
        S_err = V * math.hypot(pce, pre)
        eta_ref = -pr / rate
        S_over = S / (eta_ref * rate / 2.0)       # (20/3) pi R_s^3 x lattice
        S_over_err = S_over * math.hypot(S_err / S, pre / pr)
        Rs = strain_radius(S_over, L)
        Rs_lo, Rs_hi = strain_radius(S_over - S_over_err, L), strain_radius(S_over + S_over_err, L)
        pred = predictions(R_t, R_r, L)
        Re = RHO * rate * R ** 2 / eta_ref
        lps = 1.34 * Re ** 1.5 / 2.5
        tcpu = sum(r["cpu_s"] for r in grp)
        ttime = (sum(r["time"] for r in col), sum(r["time"] for r in ref))
        far = [r for r in col if "far_density" in r]  # (recorded since the campaign's third run)
        row = dict(rate=rate, L=L, S=S, S_err=S_err, eta_ref=eta_ref, eta_ref_err=pre / rate,
                   eta_col=-pc / rate, eta_col_err=pce / rate, S_over=S_over, S_over_err=S_over_err,
                   R_s=Rs, R_s_range=[Rs_lo, Rs_hi], pred=pred, Re=Re, lps=lps, chi2=[chc, chr_],
                   n=[len(col), len(ref)], time=ttime, cpu_s=tcpu,
                   far_density=(weighted([r["far_density"] for r in far], [r["far_density_err"] for r in far])[:2]
                                if far else (float("nan"), float("nan"))),
                   kT=[min(r["kT"] for r in grp), max(r["kT"] for r in grp)],
                   omega=[r["omega_z"] for r in col if "omega_z" in r])
        if exact:
            pe, pee, _ = pxy_mean(exact)
            row["S_exact"], row["S_exact_err"] = -V * (pe - pr), V * math.hypot(pee, pre)
            print(f"rate {rate}: colloid at the exact count ({exact[0]['n_solvent']} beads, {len(exact)} runs): "
                  f"S_xy = {row['S_exact']:.4f} +/- {row['S_exact_err']:.4f} (bulk count: {S:.4f} +/- {S_err:.4f})")
        out.append(row)
        print(f"rate {rate} (Re {Re:.2f}; Lin-Peery-Schowalter unbounded +{100 * lps:.0f} % in S), L = {L:.4f}: "
              f"{len(col)} colloid runs ({ttime[0]:g} tu), {len(ref)} reference runs ({ttime[1]:g} tu), "
              f"CPU {tcpu:.0f} s, kT {row['kT'][0]:.4f}-{row['kT'][1]:.4f}")
        print(f"  eta_box: colloid {-pc / rate:.5f} +/- {pce / rate:.5f} (chi2 {chc:.1f}/{len(col) - 1}), "
              f"reference {eta_ref:.5f} +/- {pre / rate:.5f} (chi2 {chr_:.1f}/{len(ref) - 1}); "
              f"far bead density {row['far_density'][0]:.4f} +/- {row['far_density'][1]:.4f}")
        print(f"  S_xy = {S:.4f} +/- {S_err:.4f}; S/(eta rate/2) = {S_over:.3f} +/- {S_over_err:.3f}; "
              f"predicted (lattice included): R_t {pred['R_t']:.3f}, R_r {pred['R_r']:.3f}; "
              f"R_s = {Rs:.4f} ({Rs_lo:.4f}-{Rs_hi:.4f})")
    if len(out) >= 2:
        extrapolate(out, L_of=lambda r: r["L"], R_t=R_t, R_r=R_r)
    return out


def extrapolate(rows, L_of, R_t, R_r):
    """Weighted fit S/(eta rate/2) = S0 + b rate^p through the rates of one box (p = 2:
    S/rate is even in the rate, so a periodic box's inertial correction is O(Re^2);
    p = 1.5: the unbounded sphere's Re^(3/2) form), and R_s of S0. Returns the fits."""
    fits = []
    for L in sorted({L_of(r) for r in rows}):
        g = [r for r in rows if L_of(r) == L]
        if len(g) < 2:
            continue
        y = np.array([r["S_over"] for r in g])
        w = 1.0 / np.array([r["S_over_err"] for r in g]) ** 2
        pred = predictions(R_t, R_r, L)
        for p in (2.0, 1.5):
            x = np.array([r["rate"] for r in g]) ** p
            A = np.vstack([np.ones_like(x), x]).T
            C = np.linalg.inv(A.T @ (A * w[:, None]))
            b = C @ (A.T @ (w * y))
            chi2 = float(np.sum(w * (y - A @ b) ** 2))
            e0 = math.sqrt(C[0, 0])
            Rs = strain_radius(b[0], L)
            Rs_lo, Rs_hi = strain_radius(b[0] - e0, L), strain_radius(b[0] + e0, L)
            fits.append(dict(L=L, p=p, S0=float(b[0]), S0_err=e0, slope=float(b[1]), slope_err=math.sqrt(C[1, 1]),
                             chi2=chi2, dof=len(g) - 2, R_s=Rs, R_s_range=[Rs_lo, Rs_hi]))
            print(f"rate -> 0 (L = {L:.4f}, S/(eta rate/2) = S0 + b rate^{p:g} over {len(g)} rates): S0 = {b[0]:.3f} "
                  f"+/- {e0:.3f}, b = {b[1]:.1f} +/- {math.sqrt(C[1, 1]):.1f} (chi2 {chi2:.2f}/{len(g) - 2}); "
                  f"R_s = {Rs:.4f} ({Rs_lo:.4f}-{Rs_hi:.4f}); S0 - R_t's: {(b[0] - pred['R_t']) / e0:+.1f} sigma, "
                  f"- R_r's: {(b[0] - pred['R_r']) / e0:+.1f} sigma")
            # the core radius a = R / STICK_RADIUS_RATIO by construction (the colloid's calibration)
            to_a = sus.STICK_RADIUS_RATIO / R
            print(f"  R_s/a = {Rs * to_a:.4f} +/- {0.5 * (Rs_hi - Rs_lo) * to_a:.4f} "
                  f"(marble.suspensions.STICK_STRESSLET_RADIUS_RATIO = {sus.STICK_STRESSLET_RADIUS_RATIO} "
                  f"+/- {sus.STICK_STRESSLET_RADIUS_RATIO_ERR})")
    return fits


def theory_R_t():
    """The drag radius of the calibrated colloid in units of R (section 7m: R_t/a =
    1.009 +/- 0.007 with a = R/STICK_RADIUS_RATIO)."""
    return 1.009 / sus.STICK_RADIUS_RATIO * R


def main(argv=None):
    args = parse(argv)
    if args.part == "run":
        out = run(args)
        if args.json:
            with open(args.json, "a") as f:
                f.write(json.dumps(out) + "\n")
    else:
        table(args)


if __name__ == "__main__":
    main()
