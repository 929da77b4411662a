"""The stick colloid as a core with a graded, anisotropic Brinkman layer: a
continuum model of its translational, rotational and stresslet radii (issue 13,
doc/suspensions.md section 7o).

- ``--part density``: one stick colloid (core a, ``--radius-calibration none``:
  a = 1) held at rest at the centre of a periodic cube in seed 004's solvent
  (rho = 3, kT = 0.1, gamma = 4.5), Shardlow dt = 0.01; after 20 time units the
  bead density n(h) around it is histogrammed on the gap h = r - a every
  ``--every`` steps for ``--time`` time units (10 blocks for the errors). The
  profile depends only on the conservative forces (the hat), not on the friction
  settings, so one run serves every row of section 7n.
- ``--part model``: marble.layered_sphere with that n(h): the friction density
  K_t(h) = n(h) gamma_t w(h)^2 on the tangential, K_n(h) = n(h) gamma_c w_c(h)^2 on
  the radial relative velocity (w = 1 - h/shell), a free-slip, impermeable core at
  h = 0 and the solvent viscosity eta_0 (uniform, or ``--eta-model density``:
  eta_0 n(h)/n_bulk). Prints R_t, R_r, R_s and the ratios for every setting of
  section 7n next to the measured ones.

    build/pymarble bench/stick_colloid_layer.py --part density --time 2000 --seed 1 \\
        --json bench/results/stick_colloid_layer.jsonl
    build/pymarble bench/stick_colloid_layer.py --part model --results bench/results/stick_colloid_layer.jsonl
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


KT, GAMMA, DT = 0.1, 4.5, 0.01
ETA0 = 0.3290  # doc/suspensions.md 7d, exact density 3
RHO = 3.0
DEFAULT_TRANS_GAMMA = 45.0
# section 7n (core a = 1): (trans_gamma, shell or None = r'_c(1), R_r/a, err, R_t/a, err, R_r/R_t, err)
MEASURED = ((15.0, None, 0.9985, 0.0024, 0.9406, 0.0036, 1.0615, 0.0051),
            (45.0, None, 1.0608, 0.0040, 1.0115, 0.0043, 1.0487, 0.0061),
            (135.0, None, 1.0910, 0.0030, 1.0608, 0.0042, 1.0285, 0.0051),
            (45.0, 0.13, 0.8280, 0.0018, 0.8235, 0.0051, 1.0055, 0.0069),
            (45.0, 0.5, 1.2072, 0.0057, 1.1790, 0.0056, 1.0239, 0.0069))


def parse(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--part", choices=["density", "model"], required=True)
    p.add_argument("--L", type=float, default=6.0, help="density: box edge")
    p.add_argument("--time", type=float, default=2000.0, help="density: sampled time units")
    p.add_argument("--every", type=int, default=50, help="density: steps between samples")
    p.add_argument("--bin", type=float, default=0.01, help="density: bin width on the gap")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--json", default=None, help="density: append the profile as one JSON line")
    p.add_argument("--results", nargs="+", default=None, help="model: JSONL files with density profiles")
    p.add_argument("--eta-model", choices=["uniform", "density", "pairs"], default="uniform",
                   help="model: solvent viscosity in the layer (eta_0; eta_0 n(h)/n_bulk; or the DPD pairs "
                        "that straddle a plane near the core, layered_sphere.dpd_pair_viscosity_fraction)")
    p.add_argument("--continuity", choices=["volume", "mass"], default="volume",
                   help="model: div v = 0, or div(n v) = 0 with the equilibrium n(h) (layered_sphere.layer_from_profile)")
    p.add_argument("--eta-kinetic", type=float, default=0.0,
                   help="model, --eta-model pairs: the kinetic part of eta_0, scaled with n(h) instead")
    args = p.parse_args(argv)
    for name in ("L", "time", "bin"):
        v = getattr(args, name)
        if not (math.isfinite(v) and v > 0):
            p.error(f"--{name} must be > 0, got {v}")
    if args.every < 1:
        p.error("--every must be >= 1")
    if args.part == "density" and args.L < 4.0:
        p.error(f"--L must be >= 4 (a bulk region around the colloid), got {args.L}")
    if args.part == "model" and not args.results:
        p.error("--part model needs --results")
    return args


def density(args):
    marble.assert_features("ROTATION", "TRANS_DPD", "DPD")
    t0 = time.process_time()
    s = marble.System(box_l=[args.L] * 3)
    s.time_step = DT
    s.cell_system.skin = 0.4
    centre = np.full(3, args.L / 2)
    info = sus.setup_suspension(s, phi=4.0 * math.pi / (3.0 * args.L ** 3), radius=1.0, kT=KT, gamma=GAMMA,
                                eta=0.3, seed=args.seed, positions=[centre.tolist()], boundary="stick",
                                solvent_count="exact", radius_calibration="none")
    s.integrator.set_shardlow()
    cid = info["colloid_ids"]
    c = s.part.by_ids(cid)
    c.fix = [[True, True, True]]
    c.v = [[0.0, 0.0, 0.0]]
    a = float(info["core_radius"])
    solvent = s.part.by_ids(sorted(set(int(i) for i in s.part.all().id) - set(cid)))
    s.integrator.run(int(round(20.0 / DT)))
    r_max = args.L / 2.0
    edges = np.arange(-a, r_max - a + 1e-12, args.bin)
    nblk = 10
    counts = np.zeros((nblk, len(edges) - 1))
    nsamp = int(round(args.time / (args.every * DT)))
    per = max(1, nsamp // nblk)
    kts = []
    for k in range(per * nblk):
        s.integrator.run(args.every)
        x = np.asarray(solvent.pos) - centre
        x -= args.L * np.round(x / args.L)
        h = np.linalg.norm(x, axis=1) - a
        counts[k // per] += np.histogram(h, bins=edges)[0]
        if k % 20 == 0:
            kts.append(float(np.mean(np.asarray(solvent.v) ** 2)))
    r_lo, r_hi = a + edges[:-1], a + edges[1:]
    shell = 4.0 * math.pi / 3.0 * (np.clip(r_hi, 0, None) ** 3 - np.clip(r_lo, 0, None) ** 3)
    n_blk = counts / (per * shell)
    n = n_blk.mean(axis=0)
    n_err = n_blk.std(axis=0, ddof=1) / math.sqrt(nblk)
    hc = 0.5 * (edges[:-1] + edges[1:])
    far = hc > 1.5
    out = dict(part="density", L=args.L, seed=args.seed, time=per * nblk * args.every * DT, dt=DT,
               every=args.every, core_radius=a, n_solvent=info["n_solvent"],
               hat_F_max=info.get("a_cs"), shell=info.get("stick_shell"),
               h=hc.tolist(), n=n.tolist(), n_err=n_err.tolist(), bin=args.bin,
               n_bulk=float(np.mean(n[far])), kT_solvent=float(np.mean(kts)),
               cpu_s=time.process_time() - t0)
    print(f"L = {args.L}, {info['n_solvent']} beads, core a = {a}, {out['time']:.0f} time units; bulk n "
          f"(h > 1.5) = {out['n_bulk']:.4f}; solvent kT {out['kT_solvent']:.4f}; CPU {out['cpu_s']:.0f} s")
    for lo, hi in ((-0.5, -0.2), (-0.2, -0.1), (-0.1, 0.0), (0.0, 0.05), (0.05, 0.1), (0.1, 0.15), (0.15, 0.2), (0.2, 0.265), (0.265, 0.4),
                   (0.4, 0.6), (0.6, 1.0), (1.0, 1.5)):
        sel = (hc > lo) & (hc < hi)
        print(f"  h in [{lo:5.2f}, {hi:5.2f}): n = {np.mean(n[sel]):.4f}")
    return out


def load_profiles(files):
    prof = []
    for f in files:
        with open(f) as fh:
            for line in fh:
                line = line.strip()
                if line:
                    r = json.loads(line)
                    if r.get("part") == "density":
                        prof.append(r)
    if not prof:
        raise SystemExit("no density profile in --results")
    return prof


def combined_profile(prof):
    h = np.asarray(prof[0]["h"])
    for p in prof:
        if len(p["h"]) < len(h):
            h = np.asarray(p["h"])
    w = np.array([p["time"] for p in prof])
    n = sum(wi * np.asarray(p["n"][:len(h)]) for wi, p in zip(w, prof)) / w.sum()
    return h, n, float(np.average([p["n_bulk"] for p in prof], weights=w)), float(prof[0]["core_radius"])


def model(args):
    from marble import layered_sphere
    prof = load_profiles(args.results)
    h, n, n_bulk, a = combined_profile(prof)
    rc_shell = sus.surface_cutoff(a)
    print(f"density profile: {len(prof)} run(s), core a = {a}, bulk n = {n_bulk:.4f}; "
          f"viscosity {args.eta_model}" + (f" (kinetic part {args.eta_kinetic})" if args.eta_model == "pairs" else "")
          + f"; continuity {args.continuity}; eta_0 = {ETA0}")
    print("| trans_gamma | shell | model R_t/a | model R_r/a | model R_s/a | model R_r/R_t | measured R_t/a | "
          "measured R_r/a | measured R_r/R_t |")
    print("|---|---|---|---|---|---|---|---|---|")
    rows = []
    for g, sh, rr, rre, rt, rte, q, qe in MEASURED:
        shell = rc_shell if sh is None else sh
        lay = layered_sphere.layer_from_profile(h, n, a=a, trans_gamma=g, shell=shell, gamma=GAMMA,
                                                dpd_shell=rc_shell, eta=ETA0,
                                                eta_model=args.eta_model, eta_kinetic=args.eta_kinetic,
                                                continuity=args.continuity,
                                                n_bulk=n_bulk)
        res = layered_sphere.radii(lay)
        rows.append(res)
        print(f"| {g:g} | {shell:.3f} | {res['R_t'] / a:.4f} | {res['R_r'] / a:.4f} | {res['R_s'] / a:.4f} | "
              f"{res['R_r'] / res['R_t']:.4f} | {rt:.4f}({rte * 1e4:.0f}) | {rr:.4f}({rre * 1e4:.0f}) | "
              f"{q:.4f}({qe * 1e4:.0f}) |")
    return rows


def main(argv=None):
    args = parse(argv)
    if args.part == "density":
        out = density(args)
        if args.json:
            os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
            with open(args.json, "a") as f:
                f.write(json.dumps(out) + "\n")
    else:
        model(args)


if __name__ == "__main__":
    sys.exit(main())
