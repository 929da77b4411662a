"""Temperature of a light stochastic stick colloid in the SRD fluid (doc/srd.md,
"Finite colloid mass"): <M V^2>/3kT and <I Omega^2>/3kT against the colloid
mass M and the time step dt, for the boundary couplings "pair" (default),
"fixed_surface" and "seed003". Scene: a = 1.5, L = 10, density 5,
alpha = 90 deg, tau = 0.1, MBS cell thermostat, stochastic rule; V and Omega
sampled every 0.25 t0 after 20 t0; error from 20 blocks.
Writes bench/results/srd_colloid_temperature.json (appends rows).
With --walls: the same in a walled channel (stochastic SRD walls at rest at
z = 0 and L); the colloid is kept away from them by two WCA constraint
walls (epsilon = kT, sigma = 1) placed so that the gap between its surface
and an SRD wall stays above about --gap (centre at least a + gap from the
walls, the LJ range crossed only with energies of several kT). --tag labels
the rows (e.g. the build: run another build's package with
PYTHONPATH=<its build/src/python> /usr/bin/python3 bench/srd_colloid_temperature.py).

    build/pymarble bench/srd_colloid_temperature.py --M 20 70 --dt 0.05 0.0125 --time 800
    build/pymarble bench/srd_colloid_temperature.py --M 20 --dt 0.05 --time 1600 --walls --gap 1.5
"""
import argparse
import json
import os
import time

import numpy as np

import marble
import marble.srd as srd
import marble.observables as obs
import marble.accumulators as acc
from marble.viscosity import block_average
from bench_common import HERE

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--M", type=float, nargs="+", default=[20.0, 70.0, 125.0])
p.add_argument("--dt", type=float, nargs="+", default=[0.05, 0.0125])
p.add_argument("--coupling", nargs="+", default=["pair"])
p.add_argument("--time", type=float, default=800.0)
p.add_argument("--seed", type=int, default=11)
p.add_argument("--walls", action="store_true", help="walled channel along z (stochastic walls at rest)")
p.add_argument("--gap", type=float, default=1.5,
               help="with --walls: smallest gap (about) between the colloid surface and an SRD wall")
p.add_argument("--tag", default="", help="a label stored with the rows (e.g. the build)")
p.add_argument("--out", default=os.path.join(HERE, "results", "srd_colloid_temperature.json"))
args = p.parse_args()

a, L, rho, tau = 1.5, 10.0, 5, 0.1
rows = []
for coupling in args.coupling:
    for M in args.M:
        for dt in args.dt:
            t0 = time.process_time()
            s = marble.System(box_l=[L] * 3, time_step=dt)
            s.cell_system.skin = 0.5
            wall_kw = dict(wall_axis=2, wall_rule="stochastic") if args.walls else {}
            s.srd = srd.SRDFluid(types=[0], tau=tau, angle=90, kT=1.0, seed=args.seed, thermostat="mbs",
                                 **wall_kw)
            srd.add_fluid(s, density=rho, type=0, kT=1.0, seed=args.seed + 1)
            c = srd.add_colloid(s, pos=[L / 2] * 3, radius=a, mass=M, type=1, coupling=coupling)
            if args.walls:
                # WCA walls for the colloid: its centre stays beyond ~0.95 sigma of
                # the planes at a + gap - 1 and L - (a + gap - 1)
                from marble.shapes import Wall
                zc = a + args.gap - 1.0
                for nrm, dist in (([0, 0, 1], zc), ([0, 0, -1], -(L - zc))):
                    s.constraints.add(shape=Wall(normal=nrm, dist=dist), particle_type=2)
                s.non_bonded_inter[2, 1].lennard_jones.set_params(epsilon=1.0, sigma=1.0, cutoff=2 ** (1 / 6),
                                                                  shift="auto")
            s.integrator.run(int(round(20.0 / dt)))
            every = max(1, int(round(0.25 / dt)))
            tv = acc.TimeSeries(obs=obs.ParticleVelocities(ids=[c.id], system=s), delta_N=every)
            tw = acc.TimeSeries(obs=obs.ParticleAngularVelocities(ids=[c.id], system=s), delta_N=every)
            s.auto_update_accumulators.add(tv)
            s.auto_update_accumulators.add(tw)
            s.integrator.run(int(round(args.time / dt)))
            V = np.array(tv.time_series()).reshape(-1, 3)
            W = np.array(tw.time_series()).reshape(-1, 3)
            I = 0.4 * M * a ** 2
            ev = block_average((M * V ** 2).mean(axis=1), min_blocks=20)
            ew = block_average((I * W ** 2).mean(axis=1), min_blocks=20)
            kT_f = float(np.mean(s.srd.v.var(axis=0)))
            row = dict(coupling=coupling, M=M, dt=dt, time=args.time, seed=args.seed,
                       walls=bool(args.walls), gap=args.gap if args.walls else None, tag=args.tag,
                       MV2=ev[0], MV2_err=ev[1], IW2=ew[0], IW2_err=ew[1], kT_fluid=kT_f,
                       cpu_s=time.process_time() - t0)
            rows.append(row)
            print(f"{coupling:13s} M = {M:5.0f} dt = {dt:.4f}: <MV^2>/3kT = {ev[0]:.3f} +/- {ev[1]:.3f}, "
                  f"<I W^2>/3kT = {ew[0]:.3f} +/- {ew[1]:.3f}  (fluid kT {kT_f:.3f}, {row['cpu_s']:.0f} CPU-s)",
                  flush=True)

old = []
if os.path.exists(args.out):
    with open(args.out) as f:
        old = json.load(f)
with open(args.out, "w") as f:
    json.dump(old + rows, f, indent=1)
