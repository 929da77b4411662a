"""A stick colloid in an SRD solvent (seed 003: Padding et al. 2005).

Measures the colloid's translational diffusion coefficient by the drag method
(a constant force F on the colloid and -F/N on the SRD particles, so the net
force is zero; D = kT v_rel / F with v_rel the colloid's velocity relative to
the fluid: the total momentum stays zero, so v_rel = V (1 + M/(N m))) and
compares it with Hasimoto's finite-box law at the SRD viscosity, alone and
with the kinetic (Enskog) friction of the boundary rule added in parallel
(seed 003 eq. 11: 1/zeta = 1/zeta_kin + 1/zeta_h, i.e.
D = kT/(M zeta_kin) + D_Hasimoto), see doc/srd.md. Also reports the
equipartition of V and Omega.

    build/pymarble samples/srd_colloid.py                 # a = 2, L = 16, a few minutes
    build/pymarble samples/srd_colloid.py --rule rough    # seed 003's Enskog collision
    build/pymarble samples/srd_colloid.py --a 3 --L 24 --eta 2.60   # M = 125 (a/2)^3: same colloid density
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/srd_colloid.py   # quick check
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
from marble.theory import hasimoto_D
from marble.viscosity import block_average

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--rule", default="stochastic", choices=["stochastic", "rough", "bounce_back", "slip"])
parser.add_argument("--time", type=float, default=None, help="production time")
parser.add_argument("--L", type=float, default=16.0)
parser.add_argument("--seed", type=int, default=3)
parser.add_argument("--dt", type=float, default=0.025)
parser.add_argument("--v-rel", type=float, default=0.05, help="target relative velocity (sets F)")
parser.add_argument("--eta", type=float, default=None,
                    help="viscosity for Hasimoto (default: the formula, 2.496; measured 2.60 +/- 0.03)")
parser.add_argument("--coupling", default="pair", choices=["pair", "fixed_surface", "seed003"])
parser.add_argument("--a", type=float, default=2.0, help="colloid radius")
parser.add_argument("--M", type=float, default=None,
                    help="colloid mass (default 125 (a/2)^3: the density of the a = 2, M = 125 colloid)")
parser.add_argument("--warmup", type=float, default=50.0, help="equilibration time before sampling")
parser.add_argument("--json", default=None, help="append the results as one JSON line to this file")
args = parser.parse_args()

quick = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
L = 8.0 if quick else args.L
a, rho, kT, dt, tau, angle = args.a, 5, 1.0, args.dt, 0.1, 90.0
M = args.M if args.M is not None else 125.0 * (a / 2.0) ** 3
t_prod = args.time or (5.0 if quick else 2000.0)
eta = args.eta or srd.eta(rho, angle, tau)  # measured: 2.60 +/- 0.03 (doc/srd.md)
D_h = hasimoto_D(eta, a, L, kT, "stick" if args.rule != "slip" else "slip")
zeta_kin = srd.kinetic_friction(a, M, rho, args.rule, coupling=args.coupling)[0]
D_par = kT / (M * zeta_kin) + D_h
F = args.v_rel / D_par  # relative velocity ~ v_rel

system = marble.System(box_l=[L] * 3, time_step=dt)
system.cell_system.skin = 0.5
system.srd = srd.SRDFluid(types=[0], tau=tau, angle=angle, kT=kT, seed=args.seed, thermostat="mbs")
srd.add_fluid(system, density=rho, type=0, kT=kT, seed=args.seed + 1)
col = srd.add_colloid(system, pos=[L / 2] * 3, radius=a, mass=M, type=1, rule=args.rule,
                      coupling=args.coupling)
N = system.srd.n
col.ext_force = [F, 0.0, 0.0]
system.srd.acceleration = [-F / N, 0.0, 0.0]
system.integrator.run(int(round((2.0 if quick else args.warmup) / dt)))

t0 = time.time()
c0 = time.process_time()
every = 4
tv = acc.TimeSeries(obs=obs.ParticleVelocities(ids=[col.id], system=system), delta_N=every)
tw = acc.TimeSeries(obs=obs.ParticleAngularVelocities(ids=[col.id], system=system), delta_N=every)
system.auto_update_accumulators.add(tv)
system.auto_update_accumulators.add(tw)
P = M * np.asarray(col.v) + system.srd.v.sum(axis=0)  # 0 (add_fluid: zero momentum)
system.integrator.run(int(round(t_prod / dt)))
V = np.array(tv.time_series()).reshape(-1, 3)
W = np.array(tw.time_series()).reshape(-1, 3)
# M V + N m u = P: the relative velocity V - u = V (1 + M/(N m)) - P/(N m)
v_rel = V[:, 0] * (1.0 + M / N) - P[0] / N
mv2 = M * np.mean(V[:, 1:] ** 2, axis=1)  # transverse components: no drift
iw2 = 0.4 * M * a ** 2 * np.mean(W ** 2, axis=1)
v_mean, v_err = block_average(v_rel, min_blocks=8 if quick else 16)
D, D_err = kT * v_mean / F, kT * v_err / F
e_v = block_average(mv2, min_blocks=8)
e_w = block_average(iw2, min_blocks=8)
print(f"rule {args.rule} ({args.coupling}), a = {a}, M = {M}, L = {L}, N = {N}, dt = {dt}, F = {F:.3f}, "
      f"t = {t_prod}, wall {time.time() - t0:.1f} s, CPU {time.process_time() - c0:.1f} s")
print(f"D (drag)                         = {D:.5f} +/- {D_err:.5f}")
print(f"Hasimoto (eta = {eta:.3f})           = {D_h:.5f}   ratio {D / D_h:.3f}")
print(f"kT/(M zeta_kin) + Hasimoto       = {D_par:.5f}   ratio {D / D_par:.3f}")
print(f"<M V^2>/kT (y, z) = {e_v[0]:.3f} +/- {e_v[1]:.3f}, <I W^2>/kT = {e_w[0]:.3f} +/- {e_w[1]:.3f}")
if args.json:
    with open(args.json, "a") as f:
        f.write(json.dumps(dict(rule=args.rule, coupling=args.coupling, a=a, M=M, L=L, N=N, dt=dt, seed=args.seed,
                                F=F, v_rel=float(v_mean), time=t_prod, warmup=args.warmup, eta=eta, D=D, D_err=D_err,
                                D_hasimoto=D_h, D_kinetic=kT / (M * zeta_kin), D_parallel=D_par,
                                equipartition_V=list(e_v), equipartition_W=list(e_w),
                                cpu_s=round(time.process_time() - c0, 1))) + "\n")
assert np.isfinite(D)
