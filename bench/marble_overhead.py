"""Cost of one marble colloid on top of its DPD solvent (issue: <= 5 %).

One R=3 marble in an L=20 box of rho=3 solvent (the paper's set-up) against the
same solvent alone; runs are interleaved (A B A B ...) and the ratio of the
medians is reported. Writes bench/results/marble_overhead.json.

    build/pymarble bench/marble_overhead.py [--repeats 5] [--steps 300]
"""
import argparse
import json
import os
import platform
import time

import numpy as np

import marble
from marble.colloids import add_marble

parser = argparse.ArgumentParser()
parser.add_argument("--repeats", type=int, default=5)
parser.add_argument("--steps", type=int, default=300)
parser.add_argument("--L", type=float, default=20.0)
parser.add_argument("--radius", type=float, default=3.0)
args = parser.parse_args()


def make(with_colloid, seed=1):
    L = args.L
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    n = int(3 * L ** 3)
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)), type=0)
    s.thermostat.set_dpd(kT=1.0, seed=seed)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    if with_colloid:
        add_marble(s, pos=[L / 2] * 3, radius=args.radius, gamma=5.0)
    s.integrator.run(200)
    return s


solvent, with_marble = make(False), make(True)
t_s, t_m = [], []
for _ in range(args.repeats):
    for s, acc in ((solvent, t_s), (with_marble, t_m)):
        t = time.perf_counter()
        s.integrator.run(args.steps)
        acc.append((time.perf_counter() - t) / args.steps)
ms, mm = float(np.median(t_s)), float(np.median(t_m))
# per-particle rate of the solvent-only system; the colloid system has fewer beads
n_s, n_m = len(solvent.part), len(with_marble.part)
res = {
    "L": args.L, "radius": args.radius, "steps": args.steps, "repeats": args.repeats,
    "n_solvent_only": n_s, "n_with_marble": n_m,
    "colloid_pairs": with_marble._core.n_colloid_pairs(),
    "s_per_step_solvent": ms, "s_per_step_marble": mm,
    "ratio_time_per_step": mm / ms,
    "ratio_time_per_particle_step": (mm / n_m) / (ms / n_s),
    "all_s_per_step_solvent": t_s, "all_s_per_step_marble": t_m,
    "machine": platform.processor() or platform.machine(), "cpus": os.cpu_count(),
}
print(f"solvent alone: {ms * 1e3:.2f} ms/step ({n_s} beads, {n_s / ms:.3g} particle-steps/s)")
print(f"with marble  : {mm * 1e3:.2f} ms/step ({n_m} particles, "
      f"{res['colloid_pairs']} colloid pairs)")
print(f"overhead: time per step x{res['ratio_time_per_step']:.3f}, "
      f"per particle-step x{res['ratio_time_per_particle_step']:.3f} "
      f"(medians of {args.repeats} interleaved runs)")
os.makedirs(os.path.join(os.path.dirname(__file__), "results"), exist_ok=True)
with open(os.path.join(os.path.dirname(__file__), "results", "marble_overhead.json"), "w") as f:
    json.dump(res, f, indent=1)
