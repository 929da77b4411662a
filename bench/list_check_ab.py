"""cell_system.list_check in one process: (skin, rule) configurations of one
DPD fluid alternated round by round (forwards, then backwards), so the
machine's drifting speed hits every configuration alike (doc/benchmarks.md,
"The pair test under Shardlow").

    build/pymarble bench/list_check_ab.py --integrator shardlow --dt 0.06 \
        --configs 0.6:half_skin,0.5:pairs,0.45:pairs

--scene fig4: the Fig. 4 scene of compare_builds.py (a marble R = 3 in the
paper solvent, L = 20, Shardlow at its default dt = 0.06 with 3 RESPA
substeps; --dt, --a, --gamma and --integrator are then ignored).

Prints, per configuration, the median rate (particle-steps per CPU-second),
the median of its per-round ratios against the first configuration, and the
list's mean life in steps; --out writes them as JSON with the machine record."""
import argparse
import json
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import marble  # noqa: E402
from bench_common import machine_info  # noqa: E402
from dpd_throughput import make_dpd  # noqa: E402


def make(L, a, gamma, dt, integrator, seed=7):
    """dpd_throughput.py's fluid (relaxed under VV), then under @p integrator."""
    s = make_dpd(L, a, gamma, dt, 0.4, seed=seed)
    if integrator == "shardlow":
        s.integrator.set_shardlow()
        s.integrator.run(20)
    return s


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", choices=("fluid", "fig4"), default="fluid")
    ap.add_argument("--integrator", choices=("vv", "shardlow"), default="shardlow")
    ap.add_argument("--dt", type=float, default=0.04)
    ap.add_argument("--a", type=float, default=0.0, help="hat F_max (0: the paper solvent)")
    ap.add_argument("--gamma", type=float, default=None, help="DPD gamma (default 5, or 4.5 with --a > 0)")
    ap.add_argument("--L", type=float, default=20.0)
    ap.add_argument("--configs", default="0.4:half_skin,0.3:pairs", help="skin:rule,... (first: the reference)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    gamma = args.gamma if args.gamma is not None else (4.5 if args.a > 0 else 5.0)
    cfgs = [(float(c.split(":")[0]), c.split(":")[1]) for c in args.configs.split(",")]
    if args.scene == "fig4":
        from marble.colloid_runs import make_system
        s, _, _ = make_system(args.L, 3.0, 1.0, 7, integrator="shardlow", warmup=3.0)
    else:
        s = make(args.L, args.a, gamma, args.dt, args.integrator)
    n = len(s.part)

    def timed(cfg):
        s.cell_system.skin, s.cell_system.list_check = cfg
        s.integrator.run(10)  # (the new skin's first list)
        r0 = s.cell_system.get_state()["verlet_rebuilds"]
        c0 = time.process_time()
        s.integrator.run(args.steps)
        c = time.process_time() - c0
        return n * args.steps / c, args.steps / max(1, s.cell_system.get_state()["verlet_rebuilds"] - r0)

    rate = {c: [] for c in cfgs}
    life = {c: [] for c in cfgs}
    for _ in range(args.rounds):
        for c in cfgs + cfgs[::-1]:
            r, lf = timed(c)
            rate[c].append(r)
            life[c].append(lf)
    rows = []
    for c in cfgs:
        ratios = [x / y for x, y in zip(rate[c], rate[cfgs[0]])]
        rows.append(dict(skin=c[0], rule=c[1], rate_median=statistics.median(rate[c]),
                         ratio_median=statistics.median(ratios), ratio_min=min(ratios), ratio_max=max(ratios),
                         life=statistics.mean(life[c]), rates=rate[c]))
        print(f"skin {c[0]:<5} {c[1]:<9} {statistics.median(rate[c]):.3e} particle-steps/CPU-s  "
              f"x{statistics.median(ratios):.3f} ({min(ratios):.3f}-{max(ratios):.3f})  life {rows[-1]['life']:.2f}",
              flush=True)
    if args.out:
        with open(args.out, "w") as f:
            json.dump(dict(machine=machine_info(), args=vars(args), gamma=gamma, n=n, rows=rows), f, indent=1)
    return rows


if __name__ == "__main__":
    main()
