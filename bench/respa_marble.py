"""Shardlow with RESPA substeps for the marble's wall (issue 15; doc/speed-accuracy.md,
"RESPA substeps for the marble's wall"): drag runs of samples/marble_hasimoto.py's
L = 12, R = 3 scene (gamma = 5, F = 24.2, 10 + 20 tau warm-up; marble.colloid_runs
make_system + drag_run), the settings interleaved per seed, one JSON line per run:

    nice -n 10 build/pymarble bench/respa_marble.py --settings 0.03:1,0.06:3 --seeds 1,2,3 \
        --time 1000 > respa.jsonl

Each line: dt, substeps, seed, ok (False: the run stopped; 'stopped_at' tau and the message),
D, D_err (drag_run: blocking or the floor sqrt(2D/T)/v), cpu_s (process time of the
drag run, 20 + T tau), cpu_per_1000 (cpu_s per 1000 tau of it), and the solvent's kT
(mean m v^2 / 3 with the solvent's mean velocity removed, sampled every 0.5 tau
over --kt_time tau after the drag run, force still on; error: std / sqrt(n)).
--gamma G: another surface friction (default 5). --scene20 N: time N steps of the paper's L = 20 scene per setting instead (CPU-s per tau).
"""
import argparse
import json
import sys
import time

import numpy as np

from marble.colloid_runs import drag_run, make_system

L, R, GAMMA, FORCE = 12.0, 3.0, 5.0, 24.2


def kT_solvent(system, t, every_tau=0.5):
    solv = system.part.select(type=0)
    n_every = max(1, int(round(every_tau / system.time_step)))
    vals = []
    for _ in range(int(round(t / every_tau))):
        system.integrator.run(n_every)
        v = np.asarray(solv.v)
        m = np.asarray(solv.mass)
        v = v - np.average(v, axis=0, weights=m)
        vals.append(np.sum(m[:, None] * v * v) / (3 * len(v)))
    vals = np.asarray(vals)
    return float(vals.mean()), float(vals.std(ddof=1) / np.sqrt(len(vals)))


def one_run(dt, n, seed, t_prod, kt_time, gamma=GAMMA):
    out = dict(dt=dt, substeps=n, seed=seed, t_prod=t_prod, gamma=gamma)
    t0 = time.process_time()
    system = None
    try:
        system, col, _ = make_system(L, R, gamma, seed, integrator="shardlow", dt=dt, substeps=n)
        t1 = time.process_time()
        res = drag_run(system, col, FORCE, t_prod)
        cpu = time.process_time() - t1
        out.update(ok=True, D=float(res.D), D_err=float(res.D_err), cpu_s=cpu,
                   cpu_per_1000=cpu * 1000.0 / (t_prod + 20.0), warmup_cpu_s=t1 - t0)
        if kt_time > 0:
            out["kT"], out["kT_err"] = kT_solvent(system, kt_time)
    except RuntimeError as err:
        out.update(ok=False, stopped_at=(system.time if system is not None else None),
                   message=str(err)[:300], cpu_s=time.process_time() - t0)
    return out


def scene20(dt, n, steps, seed=1):
    """CPU-s per tau of the L = 20 scene (Fig. 4 --paper: R = 3, gamma given)."""
    system, _, _ = make_system(20.0, R, GAMMA, seed, integrator="shardlow", dt=dt, substeps=n,
                               warmup=2.0)
    t0 = time.process_time()
    system.integrator.run(steps)
    cpu = time.process_time() - t0
    return dict(scene="L20", dt=dt, substeps=n, steps=steps, cpu_s=cpu, cpu_per_tau=cpu / (steps * dt))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--settings", default="0.03:1,0.06:3")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--time", type=float, default=1000.0)
    ap.add_argument("--kt_time", type=float, default=50.0)
    ap.add_argument("--scene20", type=int, default=0)
    ap.add_argument("--gamma", type=float, default=GAMMA, help="the marble's surface friction")
    a = ap.parse_args()
    settings = [(float(x.split(":")[0]), int(x.split(":")[1])) for x in a.settings.split(",")]
    seeds = [int(s) for s in a.seeds.split(",")]
    for seed in seeds:
        for dt, n in settings:
            r = scene20(dt, n, a.scene20, seed) if a.scene20 else one_run(dt, n, seed, a.time, a.kt_time, a.gamma)
            print(json.dumps(r), flush=True)
            sys.stderr.write(f"{r}\n")


if __name__ == "__main__":
    main()
