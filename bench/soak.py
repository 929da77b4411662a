"""Soak test (doc/reliability.md): a marble colloid in a DPD solvent for a given
wall time, with a checkpoint every N steps (each one loaded back into a second
System and checked), reporting as JSON

- RSS growth (resident memory of this process, /proc/self/status VmRSS):
  after the first checkpoint vs the end, and the slope of a straight-line fit;
- kT drift: kinetic temperature of the first vs the last tenth of the run,
  and the fitted slope per 1e5 steps, with the standard error of the blocks;
- momentum drift: max |P(t) - P(0)| of the total linear momentum (DPD and the
  marble coupling conserve it exactly up to round-off).

Run by hand, not in CI:

    nice -n 19 build/pymarble bench/soak.py                       # 1 hour
    nice -n 19 build/pymarble bench/soak.py --time 1800 --out soak.json
    build/pymarble bench/soak.py --time 60                        # smoke test
"""
import argparse
import gc
import json
import os
import sys
import tempfile
import time

import numpy as np

import marble
import marble.checkpointing
from marble.colloids import add_marble

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_common import machine_info  # noqa: E402


def rss_mib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--time", type=float, default=3600.0, help="wall time in seconds (default 1 h)")
    ap.add_argument("--every", type=int, default=2000, help="steps between checkpoints")
    ap.add_argument("--sample", type=int, default=100, help="steps between measurements")
    ap.add_argument("--L", type=float, default=8.0, help="box length (solvent density 3)")
    ap.add_argument("--radius", type=float, default=1.5, help="marble radius")
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--out", default=None, help="JSON file (default: stdout only)")
    ap.add_argument("--dir", default=None, help="checkpoint directory (default: a temp dir)")
    ap.add_argument("--no-gc", action="store_true",
                    help="do not gc.collect() after dropping each loaded System")
    args = ap.parse_args()
    if args.every % args.sample:
        ap.error("--every must be a multiple of --sample")

    L, kT, dt = args.L, 1.0, 0.01
    system = marble.System(box_l=[L] * 3)
    system.time_step = dt
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(args.seed)
    n = int(3 * L ** 3)
    system.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)) * np.sqrt(kT), type=0)
    system.thermostat.set_dpd(kT=kT, seed=args.seed)
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1, r_cut=1.0)
    system.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    add_marble(system, pos=[L / 2] * 3, radius=args.radius, gamma=5.0)
    system.integrator.run(500)  # equilibrate the insertion

    tmp = None
    cp_dir = args.dir
    if cp_dir is None:
        tmp = tempfile.TemporaryDirectory(prefix="marble_soak_")
        cp_dir = tmp.name
    ns = {"system": system}
    cp = marble.checkpointing.Checkpoint(checkpoint_id="soak", checkpoint_path=cp_dir, namespace=ns)
    cp.register("system")

    p0 = np.asarray(system.analysis.linear_momentum(), dtype=float)
    t_start = time.time()
    steps, kts, p_dev, rss, rss_t = [], [], [], [], []
    n_checkpoints = n_verified = 0
    cp_seconds = 0.0
    while time.time() - t_start < args.time:
        for _ in range(args.every // args.sample):
            system.integrator.run(args.sample)
            steps.append(int(system.step))
            kts.append(float(system.analysis.kinetic_temperature()))
            p = np.asarray(system.analysis.linear_momentum(), dtype=float)
            p_dev.append(float(np.abs(p - p0).max()))
        t0 = time.time()
        cp.save(n_checkpoints % 2)  # two files in rotation
        # load it back into a second System and compare
        other = {}
        cp2 = marble.checkpointing.Checkpoint(checkpoint_id="soak", checkpoint_path=cp_dir,
                                              namespace=other)
        cp2.load(n_checkpoints % 2)
        s2 = other["system"]
        assert int(s2.step) == int(system.step) and len(s2.part.all()) == len(system.part.all())
        assert np.array_equal(s2.part.all().pos, system.part.all().pos)
        n_verified += 1
        del other, s2, cp2
        if not args.no_gc:
            # A System sits in reference cycles (System <-> its part/analysis/...
            # wrappers), so a dropped one is only freed by the cyclic collector;
            # collect now so that RSS measures leaks, not the GC's schedule.
            gc.collect()
        cp_seconds += time.time() - t0
        n_checkpoints += 1
        rss.append(rss_mib())
        rss_t.append(time.time() - t_start)
    wall = time.time() - t_start

    steps = np.asarray(steps, dtype=float)
    kts = np.asarray(kts)
    tenth = max(1, len(kts) // 10)
    nb = 10
    blocks = kts[: len(kts) // nb * nb].reshape(nb, -1).mean(axis=1) if len(kts) >= nb else kts
    slope_kt = float(np.polyfit(steps, kts, 1)[0] * 1e5) if len(kts) > 2 else float("nan")
    rss = np.asarray(rss)
    rss_slope = float(np.polyfit(np.asarray(rss_t) / 3600.0, rss, 1)[0]) if len(rss) > 2 \
        else float("nan")
    result = dict(
        bench="soak",
        machine=machine_info(),
        parameters=dict(wall_time_requested_s=args.time, every=args.every, sample=args.sample,
                        L=L, radius=args.radius, n_particles=len(system.part.all()), dt=dt,
                        kT=kT, seed=args.seed, gc_collect=not args.no_gc),
        wall_time_s=round(wall, 1),
        steps=int(system.step),
        steps_per_s=round(float(steps[-1] - 500) / wall, 1) if len(steps) else 0.0,
        checkpoints=dict(saved=n_checkpoints, loaded_and_verified=n_verified,
                         seconds_total=round(cp_seconds, 2),
                         file_bytes=os.path.getsize(os.path.join(cp_dir, "soak", "0.checkpoint"))
                         if n_checkpoints else 0),
        rss_mib=dict(first_checkpoint=round(float(rss[0]), 1) if len(rss) else None,
                     end=round(float(rss[-1]), 1) if len(rss) else None,
                     max=round(float(rss.max()), 1) if len(rss) else None,
                     growth=round(float(rss[-1] - rss[0]), 2) if len(rss) else None,
                     slope_per_hour=round(rss_slope, 3),
                     series=[[round(float(t), 1), round(float(r), 1)] for t, r in
                             list(zip(rss_t, rss))[::max(1, len(rss) // 20)]]),
        kT=dict(target=kT, mean=float(kts.mean()) if len(kts) else None,
                stderr_blocks=float(blocks.std(ddof=1) / np.sqrt(len(blocks)))
                if len(blocks) > 1 else None,
                first_tenth=float(kts[:tenth].mean()) if len(kts) else None,
                last_tenth=float(kts[-tenth:].mean()) if len(kts) else None,
                slope_per_1e5_steps=slope_kt),
        momentum=dict(initial=p0.tolist(),
                      max_abs_drift=float(max(p_dev)) if p_dev else None,
                      final_abs_drift=float(p_dev[-1]) if p_dev else None),
    )
    text = json.dumps(result, indent=2)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")
    if tmp is not None:
        tmp.cleanup()


if __name__ == "__main__":
    main()
