"""A DPD fluid at number density rho = 3: the solvent of the marble paper.

Pure DPD thermostat, no conservative force (the paper's solvent, reference.md
section 2: gamma = 5, w_D = (1 - r)^2 via weight_function=1, k=1, r_cut=1,
kT = 1), or Groot-Warren "water" with --a 25 --gamma 4.5 (soft repulsion
F = a (1 - r) e). Prints the kinetic temperature and the pressure (kinetic,
conservative virial and the DPD pair-force part from analysis.dpd_stress_split())
with blocking error bars. Expected: kT slightly above 1 (plain velocity Verlet,
doc/dpd.md: 1.007 at dt = 0.01 for the paper solvent); p = rho kT = 3 for the
ideal solvent; p = 23.6 for Groot-Warren water (a rho / kT = 75: the
equation of state of Liyana-Arachchi et al. 2015 gives 23.59, Allen and
Tildesley's DPD example measures 23.64; Groot and Warren's own fit
p = rho kT + 0.101 a rho^2 = 25.7 is too high here).

    build/pymarble samples/dpd_fluid.py [--box 10] [--time 100] [--a 0] [--gamma 5]

With MARBLE_SAMPLE_TEST=1 (the ctest run) it uses a 6^3 box and 5 time units.
"""
import argparse
import os

import numpy as np

import marble
from marble.viscosity import block_average

short = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--box", type=float, default=6.0 if short else 10.0)
parser.add_argument("--time", type=float, default=5.0 if short else 100.0,
                    help="production time (after 5 time units of equilibration)")
parser.add_argument("--a", type=float, default=0.0, help="hat F_max (0: none)")
parser.add_argument("--gamma", type=float, default=5.0)
parser.add_argument("--dt", type=float, default=0.01)
parser.add_argument("--seed", type=int, default=42)
args = parser.parse_args()

marble.assert_features("DPD")
if args.a > 0:
    marble.assert_features("HAT")

RHO, KT = 3.0, 1.0
L = args.box
N = int(round(RHO * L**3))
system = marble.System(box_l=[L, L, L])
system.time_step = args.dt
system.cell_system.skin = 0.4
rng = np.random.default_rng(args.seed)
v = rng.normal(0.0, np.sqrt(KT), size=(N, 3))
system.part.add(pos=rng.uniform(0.0, L, size=(N, 3)), v=v - v.mean(axis=0))
if args.a > 0:
    system.non_bonded_inter[0, 0].hat.set_params(F_max=args.a, cutoff=1.0)
system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=args.gamma, k=1.0,
                                             r_cut=1.0)
system.thermostat.set_dpd(kT=KT, seed=args.seed)

system.integrator.run(int(round(5.0 / args.dt)))
every = max(1, int(round(0.05 / args.dt)))
series = {"kT": [], "p_kin": [], "p_cons": [], "p_dpd": []}
for _ in range(int(round(args.time / args.dt)) // every):
    system.integrator.run(every)
    e = system.analysis.energy()
    p = system.analysis.pressure()
    series["kT"].append(2.0 * e["kinetic"] / (3.0 * N - 3.0))  # total momentum is 0
    series["p_kin"].append(p["kinetic"])
    series["p_cons"].append(p["non_bonded"])
    series["p_dpd"].append(np.trace(system.analysis.dpd_stress_split()["total"]) / 3.0)

print(f"DPD fluid: N = {N}, L = {L}, rho = {RHO}, a = {args.a}, gamma = {args.gamma}, "
      f"dt = {args.dt}, {args.time} time units")
res = {k: block_average(x, min_blocks=8) for k, x in series.items()}
p_tot = np.array(series["p_kin"]) + np.array(series["p_cons"]) + np.array(series["p_dpd"])
res["p_total"] = block_average(p_tot, min_blocks=8)
for k, (m, err) in res.items():
    print(f"  {k:8s} = {m:.4f} +/- {err:.4f}")
