"""What two processes cost each other on this machine: the ceiling of a
2-rank parallel efficiency before any decomposition work.

One process runs one rank's share of the `mpi_scaling.py` fluid (rho = 3,
a = 0, gamma = 5, kT = 1, skin 0.4; the box L/2 x L x L, periodic) alone,
pinned to core 0, then alone on core 1; then two such processes run at once,
pinned to cores 0 and 1. Alternated (alone, alone, pair, ...) so that the
machine's drifting speed hits both alike. Reported: particle-steps per
CPU-second, and per round the mean over the two cores of the pair's rate
on a core over the alone rate on the same core (since session 28; before,
both against core 0 alone, which a slower core 0 biased): the share of
one core's speed a process keeps when the other core is busy with the same
work (caches and memory bandwidth are shared). A 2-rank efficiency E above
that ratio cannot be expected on this machine (doc/parallel.md). Each
core's speed is probed before and after (bench_common.core_speeds).

Run:  build/pymarble bench/concurrency_cap.py [--integrator vv|shardlow] [--size 40]
                                              [--repeats 3] [--steps N] [--out DIR]
Writes bench/results/concurrency_cap_<integrator>.json.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def worker(L, integrator, steps, rounds, out):
    import time
    import marble
    rng = np.random.default_rng(7)
    box = np.array([L / 2, L, L])
    n = int(round(3.0 * np.prod(box)))
    s = marble.System(box_l=list(box))
    s.time_step = 0.04 if integrator == "shardlow" else 0.01
    s.cell_system.skin = 0.4
    s.part.add(pos=rng.random((n, 3)) * box, v=rng.normal(size=(n, 3)))
    s.thermostat.set_dpd(kT=1.0, seed=7)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1.0, r_cut=1.0)
    if integrator == "shardlow":
        s.integrator.set_shardlow()
    s.integrator.run(30)
    rates = []
    for _ in range(rounds):
        c0 = time.process_time()
        s.integrator.run(steps)
        rates.append(n * steps / (time.process_time() - c0))
    with open(out, "w") as f:
        json.dump(dict(n=n, steps=steps, rate=statistics.median(rates)), f)


def launch(cores, args, tmp, tag):
    """One process per core in @p cores at once; their rates."""
    procs, outs = [], []
    for c in cores:
        out = os.path.join(tmp, f"{tag}_{c}.json")
        cmd = ["taskset", "-c", str(c), sys.executable, os.path.abspath(__file__), "--worker", out,
               "--integrator", args.integrator, "--size", str(args.size), "--steps", str(args.steps)]
        procs.append(subprocess.Popen(cmd, env=os.environ.copy()))
        outs.append(out)
    for p in procs:
        if p.wait() != 0:
            raise RuntimeError(f"worker failed ({tag})")
    return [json.load(open(o))["rate"] for o in outs]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--integrator", default="shardlow", choices=["vv", "shardlow"])
    p.add_argument("--size", type=float, default=40.0, help="L of the full box (the process runs L/2 x L x L)")
    p.add_argument("--repeats", type=int, default=3, help="alone/pair alternations")
    p.add_argument("--steps", type=int, default=60, help="steps per timed round (3 rounds, median)")
    p.add_argument("--out", default=os.path.join(HERE, "results"))
    p.add_argument("--worker", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.worker:
        worker(args.size, args.integrator, args.steps, 3, args.worker)
        return
    if (os.cpu_count() or 1) < 2:
        sys.exit("concurrency_cap.py needs two cores")
    sys.path.insert(0, HERE)
    from bench_common import probe_cores
    speeds = [probe_cores("before")]
    alone, pairs = [], []  # alone: [core 0, core 1] per round
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.repeats):
            alone.append([launch([c], args, tmp, f"a{k}_{c}")[0] for c in (0, 1)])
            pairs.append(launch([0, 1], args, tmp, f"p{k}"))
            r = statistics.mean(q / a for q, a in zip(pairs[-1], alone[-1]))
            print(f"round {k}: alone {alone[-1][0]:.3e} / {alone[-1][1]:.3e}  two at once "
                  f"{pairs[-1][0]:.3e} / {pairs[-1][1]:.3e}  -> {r:.3f} of alone", flush=True)
    speeds.append(probe_cores("after"))
    ratios = [statistics.mean(q / x for q, x in zip(qs, a)) for a, qs in zip(alone, pairs)]
    res = dict(integrator=args.integrator, size=args.size, steps=args.steps, alone=alone, pairs=pairs,
               ratios=ratios, ratio_median=statistics.median(ratios),
               load_after=os.getloadavg()[0], core_speed_before=speeds[0], core_speed_after=speeds[1])
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, f"concurrency_cap_{args.integrator}.json")
    with open(path, "w") as f:
        json.dump(res, f, indent=1)
    print(f"CAP: {args.integrator}, L = {args.size:g} (half box per process): two processes at once keep "
          f"{res['ratio_median']:.3f} (per round {min(ratios):.3f}-{max(ratios):.3f}) of one alone; {path}")


if __name__ == "__main__":
    main()
