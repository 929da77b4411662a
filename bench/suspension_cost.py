"""Cost of a seed-004 suspension step (doc/suspensions.md): CPU time per step of a
marble.suspensions.setup_suspension scene (R = 1, rho = 3, kT = 0.1, gamma = 4.5,
eta0 = 0.3, lubrication h_cut = 1 and colloid-colloid DPD r_c = 1 on the gap,
Shardlow, dt = 1e-3) against the bare solvent of the same box, with the
colloids on their own cell grid (cell_system.large_range_types = "auto", the
default; doc/architecture.md "Two cell grids") and with one grid for all
(large_range_types = None, the cost before the split).

The three scenes are built once, then timed in turn (interleaved) --repeats
times; the medians are reported with the spread (min-max) since the machine may
be loaded. Also: CPU-seconds per colloid diffusion time tau_D = 6 pi eta R^3/kT
(= 56.5 for the seed's numbers) at dt = 1e-3 and at the larger dt = 5e-3 that
a softer contact force allows (samples/suspension_viscosity.py).

Reference point (reference.md section 7, not comparable one to one): LAMMPS
pair lubricate + pair brownian (implicit solvent) took 1.4 ms CPU per step for
1331 spheres at phi ~ 0.2; here the solvent is explicit (65 000 beads).

    build/pymarble bench/suspension_cost.py [--box 30] [--phi 0.2] [--steps 20] [--repeats 3]

Writes bench/results/suspension_cost.json (--single: suspension_cost_single.json).
"""
import argparse
import json
import os
import time

import numpy as np

import marble
import marble.suspensions as sus
from bench_common import HERE, machine_info

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--box", type=float, default=30.0)
parser.add_argument("--phi", type=float, default=0.2)
parser.add_argument("--h-cut", type=float, default=1.0)
parser.add_argument("--radius", type=float, default=1.0)
parser.add_argument("--single", action="store_true",
                    help="one colloid at the centre (the core colloid of bench/three_solvents.py: "
                         "--single --radius 2 --box 11)")
parser.add_argument("--steps", type=int, default=20)
parser.add_argument("--repeats", type=int, default=3)
parser.add_argument("--out", default=None,
                    help="default bench/results/suspension_cost.json (--single: _single.json)")
args = parser.parse_args()
if args.out is None:
    args.out = os.path.join(HERE, "results", "suspension_cost%s.json" % ("_single" if args.single else ""))

DT = 1e-3


def build(kind):
    s = marble.System(box_l=[args.box] * 3)
    s.time_step = DT
    s.cell_system.skin = 0.4
    if kind == "solvent":  # the same solvent without colloids
        info = sus.setup_suspension(s, phi=1e-9, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1,
                                    positions=[[0.5 * args.box] * 3], h_cut=args.h_cut)
        s.part.by_ids(info["colloid_ids"]).remove()
        info["n_colloids"] = 0
        s.non_bonded_inter.reset()
        s.non_bonded_inter[0, 0].hat.set_params(F_max=2.5, cutoff=1.0)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, r_cut=1.0)
    else:
        s.cell_system.large_range_types = "auto" if kind == "split" else None
        extra = dict(positions=[[0.5 * args.box] * 3]) if args.single else {}
        info = sus.setup_suspension(s, phi=args.phi, radius=args.radius, kT=0.1, gamma=4.5,
                                    eta=0.3, seed=1, h_cut=args.h_cut, colloid_dpd=True, **extra)
    s.integrator.set_shardlow()
    s.integrator.run(5)
    st = s.cell_system.get_state()
    row = dict(scene=kind, n_colloids=int(info["n_colloids"]), n_particles=len(s.part.all()),
               large_range_types=st["large_range_types"], range_small=st["pair_range_small"],
               range_large=st["pair_range_large"], range_large_small=st["pair_range_large_small"],
               n_pairs=len(s._core.verlet_pairs()))
    print(row, flush=True)
    return s, row


scenes = {k: build(k) for k in ("solvent", "split", "one_grid")}
times = {k: [] for k in scenes}
for rep in range(args.repeats):
    for k, (s, _) in scenes.items():
        t0 = time.process_time()
        s.integrator.run(args.steps)
        times[k].append((time.process_time() - t0) / args.steps)
    print({k: f"{1e3 * v[-1]:.1f} ms" for k, v in times.items()}, flush=True)

tau_D = sus.diffusion_time(args.radius, 0.3, 0.1)
rows = []
base = float(np.median(times["solvent"]))
for k, (s, row) in scenes.items():
    t = np.array(times[k])
    med = float(np.median(t))
    row.update(cpu_ms_per_step=1e3 * med, cpu_ms_min=1e3 * t.min(), cpu_ms_max=1e3 * t.max(),
               cost_vs_solvent=med / base,
               cpu_s_per_tau_D_dt1e3=med * tau_D / DT, cpu_s_per_tau_D_dt5e3=med * tau_D / 5e-3)
    rows.append(row)
print(f"box {args.box}, R {args.radius}, phi {args.phi}{' (one colloid)' if args.single else ''}, h_cut {args.h_cut}, {args.steps} steps x {args.repeats}")
for r in rows:
    print(f"{r['scene']:9s} N = {r['n_particles']:6d} ({r['n_colloids']} colloids)  "
          f"{r['cpu_ms_per_step']:8.1f} ms/step [{r['cpu_ms_min']:.1f}-{r['cpu_ms_max']:.1f}]  "
          f"x{r['cost_vs_solvent']:.2f} of solvent  {r['cpu_s_per_tau_D_dt1e3']:.0f} CPU-s per tau_D "
          f"(dt 1e-3), {r['cpu_s_per_tau_D_dt5e3']:.0f} (dt 5e-3)")
os.makedirs(os.path.dirname(args.out), exist_ok=True)
with open(args.out, "w") as f:
    json.dump(dict(machine=machine_info(), box=args.box, phi=args.phi, radius=args.radius,
                   single=args.single, h_cut=args.h_cut,
                   steps=args.steps, repeats=args.repeats, tau_D=tau_D, rows=rows), f, indent=1)
print("wrote", args.out)
