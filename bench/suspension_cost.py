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

Peer (timed in the same interleaved rounds when Debian's ``lmp`` is on the PATH,
skipped otherwise, or with --no-lammps): LAMMPS ``pair lubricate`` + ``pair
brownian`` (package COLLOID/FLD, implicit solvent: Ball-Melrose squeeze, shear and
pump lubrication with the log terms, FLD's isotropic one-body drag, and the
matching Brownian forces; fix nve/sphere) for the same spheres: the same
positions (marble.suspensions.place_colloids with the same seed), R = 1, mass
12.57, mu = 0.3, kT = 0.1, inner cutoff 2.001 (the gap h_min = 1e-3), outer
cutoff 2.5, dt = 1e-3, seeded, 200 steps of equilibration before each timed run.
Its CPU time per step is LAMMPS's loop time times its reported CPU use (so a
loaded machine's waiting is not counted, as process_time does for Marble). The
two models are not the same computation: the explicit solvent carries the full
many-body hydrodynamics, LAMMPS's pairwise lubrication only the near field plus
a mean-field drag.

    build/pymarble bench/suspension_cost.py [--box 30] [--phi 0.2] [--steps 20] [--repeats 3]

Writes bench/results/suspension_cost.json (--single: suspension_cost_single.json).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import tempfile
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
parser.add_argument("--lammps-steps", type=int, default=500, help="timed LAMMPS steps per round")
parser.add_argument("--no-lammps", action="store_true", help="do not run LAMMPS even if lmp is found")
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


LAMMPS_INPUT = """# pair lubricate + pair brownian (implicit solvent) for the spheres of bench/suspension_cost.py
units lj
atom_style sphere
boundary p p p
newton off
comm_modify vel yes
read_data {data}
velocity all create {kT} {seed} loop geom
pair_style hybrid/overlay lubricate {mu} 1 1 {cut_in} {cut_out} brownian {mu} 1 1 {cut_in} {cut_out} {kT} {seed}
pair_coeff * * lubricate
pair_coeff * * brownian
neighbor 0.3 bin
neigh_modify every 1 delay 0 check yes
fix 1 all nve/sphere
timestep {dt}
thermo {steps}
run {equil}
run {steps}
"""


def lammps_setup(workdir):
    """The LAMMPS data file of the same colloids as the 'split' scene (same
    placement and seed); returns (input path, n spheres)."""
    R, L = args.radius, args.box
    n = int(round(args.phi * L ** 3 / (4.0 / 3.0 * np.pi * R ** 3)))
    pos = sus.place_colloids(np.array([L] * 3), n, R, np.random.default_rng(1), min_gap=1e-3)
    data = os.path.join(workdir, "colloids.data")
    with open(data, "w") as f:
        f.write(f"colloids of bench/suspension_cost.py\n\n{n} atoms\n1 atom types\n\n"
                f"0 {L} xlo xhi\n0 {L} ylo yhi\n0 {L} zlo zhi\n\nAtoms # sphere\n\n")
        for i, p in enumerate(pos):  # id type diameter density x y z (density 3: mass 12.57)
            f.write(f"{i + 1} 1 {2 * R} 3.0 {p[0]:.10f} {p[1]:.10f} {p[2]:.10f}\n")
    inp = os.path.join(workdir, "in.lubricate")
    with open(inp, "w") as f:
        f.write(LAMMPS_INPUT.format(data=data, kT=0.1, mu=0.3, seed=4928, cut_in=2 * R + 1e-3,
                                    cut_out=2.5 * R, dt=DT, equil=200, steps=args.lammps_steps))
    return inp, n


def lammps_round(lmp, inp):
    """CPU seconds per step of one LAMMPS run (loop time x CPU use of the timed run)."""
    env = dict(os.environ, OMP_NUM_THREADS="1")
    out = subprocess.run([lmp, "-in", inp, "-log", "none", "-echo", "none"], capture_output=True,
                         text=True, env=env, cwd=os.path.dirname(inp), timeout=1800)
    if out.returncode != 0:
        raise RuntimeError("lmp failed:\n" + out.stdout[-2000:] + out.stderr[-2000:])
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", out.stdout)
    cpu = re.findall(r"([0-9.]+)% CPU use", out.stdout)
    wall, steps = float(loops[-1][0]), int(loops[-1][1])
    return wall * float(cpu[-1]) / 100.0 / steps


scenes = {k: build(k) for k in ("solvent", "split", "one_grid")}
times = {k: [] for k in scenes}
lmp = None if args.no_lammps else shutil.which("lmp")
tmp = tempfile.TemporaryDirectory(prefix="suspension_cost_lammps_")
if lmp:
    lmp_input, n_lmp = lammps_setup(tmp.name)
    times["lammps"] = []
    print(f"LAMMPS: {lmp}, {n_lmp} spheres", flush=True)
else:
    print("LAMMPS (lmp) not found or --no-lammps: the LAMMPS column is skipped", flush=True)
for rep in range(args.repeats):
    for k, (s, _) in scenes.items():
        t0 = time.process_time()
        s.integrator.run(args.steps)
        times[k].append((time.process_time() - t0) / args.steps)
    if lmp:
        times["lammps"].append(lammps_round(lmp, lmp_input))
    print({k: f"{1e3 * v[-1]:.2f} ms" for k, v in times.items()}, flush=True)

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
if lmp:
    t = np.array(times["lammps"])
    med = float(np.median(t))
    rows.append(dict(scene="lammps_lubricate_brownian", n_colloids=n_lmp, n_particles=n_lmp,
                     cpu_ms_per_step=1e3 * med, cpu_ms_min=1e3 * t.min(), cpu_ms_max=1e3 * t.max(),
                     cost_vs_solvent=med / base, cpu_s_per_tau_D_dt1e3=med * tau_D / DT,
                     cpu_s_per_tau_D_dt5e3=med * tau_D / 5e-3, lammps=lmp,
                     lammps_steps=args.lammps_steps))
tmp.cleanup()
print(f"box {args.box}, R {args.radius}, phi {args.phi}{' (one colloid)' if args.single else ''}, h_cut {args.h_cut}, {args.steps} steps x {args.repeats}")
for r in rows:
    print(f"{r['scene']:26s} N = {r['n_particles']:6d} ({r['n_colloids']} colloids)  "
          f"{r['cpu_ms_per_step']:8.2f} ms/step [{r['cpu_ms_min']:.2f}-{r['cpu_ms_max']:.2f}]  "
          f"x{r['cost_vs_solvent']:.2f} of solvent  {r['cpu_s_per_tau_D_dt1e3']:.0f} CPU-s per tau_D "
          f"(dt 1e-3), {r['cpu_s_per_tau_D_dt5e3']:.0f} (dt 5e-3)")
os.makedirs(os.path.dirname(args.out), exist_ok=True)
with open(args.out, "w") as f:
    json.dump(dict(machine=machine_info(), box=args.box, phi=args.phi, radius=args.radius,
                   single=args.single, h_cut=args.h_cut,
                   steps=args.steps, repeats=args.repeats, tau_D=tau_D, rows=rows), f, indent=1)
print("wrote", args.out)
