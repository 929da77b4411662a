"""Short-time friction of a stick colloid in the SRD fluid (doc/srd.md, "Short-time
friction: the fit window"): the initial decay rate of the VACF and the RVACF
against the width of the fit window, and the instantaneous (one-step) friction
from the colloid's velocity changes.

Scene: that of test_srd_colloid.py (a = 2, M = 125, L = 16, density 5,
alpha = 90 deg, tau = 0.1, no thermostat, dt = 0.025, 20 t0 of equilibration,
then V and Omega sampled every MD step); --a, --M, --L, --dt change it.

Estimates, for X = V (mass M) and X = Omega (moment of inertia I):
* `window n`: `marble.srd.short_time_friction(X, dt, n_lags=n)` (least-squares
  slope of -ln C(t)/C(0) over the first n lags), n = 1, 2, 4, 8, 16;
* `quad 8`, `quad 16`: the same with a quadratic in t (slope at t = 0,
  `order=2`);
* `impulse`: the regression of the one-step change on the value at the start of
  the step, -<X(t).dX>/<X^2> / dt, dX = X(t + dt) - X(t); with no external force
  or torque dX is the impulse of the SRD collisions of that step divided by M
  (I), so this is the friction at the shortest lag (stationarity gives
  <X.dX> = -<dX^2>/2 exactly);
* `fluct`: m <dX^2> / (2 kT dt) per component (the same with <X^2> replaced
  by its equipartition value kT/m: less noisy);
* `one step`: `marble.srd.one_step_friction` (the same solved for the rate as
  for an exponential, -ln(1 - m <dX^2>/(2 kT))/dt, with the fluid's measured
  temperature), compared with `kinetic_friction` at the free-volume density
  (`add_colloid` moves the particles inside the colloid out: +0.8 % at a = 2,
  L = 16) and that temperature (`kinetic_free` in the rows).
Errors: jackknife over 16 blocks. Appends one JSON row per run to --out.

    build/pymarble bench/srd_short_time_friction.py --seeds 8 9 10 11 12 13 14 15
    build/pymarble bench/srd_short_time_friction.py --rule rough --seeds 8 9 10 11
    build/pymarble bench/srd_short_time_friction.py --dt 0.0125 --seeds 8 9 10 11
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

HERE = os.path.dirname(os.path.abspath(__file__))

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--rule", default="stochastic", choices=["stochastic", "rough", "bounce_back"])
p.add_argument("--seeds", type=int, nargs="+", default=[8])
p.add_argument("--time", type=float, default=600.0, help="production time (t0)")
p.add_argument("--dt", type=float, default=0.025)
p.add_argument("--a", type=float, default=2.0)
p.add_argument("--M", type=float, default=125.0)
p.add_argument("--L", type=float, default=16.0)
p.add_argument("--save", default="", help="directory for the raw series (npz), optional")
p.add_argument("--out", default=os.path.join(HERE, "results", "srd_short_time_friction.jsonl"))
args = p.parse_args()

A, M, L, DT, RHO, KT = args.a, args.M, args.L, args.dt, 5.0, 1.0
I = 0.4 * M * A ** 2
NB = 16


def jackknife(f, parts):
    """f(list of per-block arrays) on all blocks and on all-but-one."""
    full = f(parts)
    jack = np.array([f(parts[:b] + parts[b + 1:]) for b in range(len(parts))])
    return float(full), float(np.sqrt((len(parts) - 1) / len(parts) * np.sum((jack - jack.mean()) ** 2)))


def one_step(X, m):
    dX = X[1:] - X[:-1]
    Xs = X[:-1]
    nb = len(dX) // NB
    xd = [np.sum(Xs[b * nb:(b + 1) * nb] * dX[b * nb:(b + 1) * nb]) for b in range(NB)]
    xx = [np.sum(Xs[b * nb:(b + 1) * nb] ** 2) for b in range(NB)]
    dd = [np.sum(dX[b * nb:(b + 1) * nb] ** 2) for b in range(NB)]
    n = [3 * nb] * NB
    parts = [np.array([xd[b], xx[b], dd[b], n[b]]) for b in range(NB)]
    imp = jackknife(lambda ps: -sum(q[0] for q in ps) / sum(q[1] for q in ps) / DT, parts)
    flu = jackknife(lambda ps: m * sum(q[2] for q in ps) / sum(q[3] for q in ps) / (2 * KT * DT), parts)
    return imp, flu


def analyse(X, m, kT_f):
    res = {}
    for n in (1, 2, 4, 8, 16):
        res[f"window {n}"] = srd.short_time_friction(X, DT, n_lags=n)
    for n in (8, 16):
        res[f"quad {n}"] = srd.short_time_friction(X, DT, n_lags=n, order=2)
    res["impulse"], res["fluct"] = one_step(X, m)
    res["one step"] = srd.one_step_friction(X, DT, m, kT=kT_f)
    res["equipartition"] = float(m * np.mean(X ** 2) / KT)
    return res


theory = srd.kinetic_friction(A, M, RHO, args.rule)
for seed in args.seeds:
    c0 = time.process_time()
    s = marble.System(box_l=[L] * 3, time_step=DT)
    s.cell_system.skin = 0.5
    s.srd = srd.SRDFluid(types=[0], tau=0.1, angle=90, kT=KT, seed=seed)
    srd.add_fluid(s, density=RHO, type=0, kT=KT, seed=seed + 1)
    c = srd.add_colloid(s, pos=[L / 2] * 3, radius=A, mass=M, type=1, rule=args.rule)
    s.integrator.run(int(round(20 / DT)))
    tv = acc.TimeSeries(obs=obs.ParticleVelocities(ids=[c.id], system=s), delta_N=1)
    tw = acc.TimeSeries(obs=obs.ParticleAngularVelocities(ids=[c.id], system=s), delta_N=1)
    s.auto_update_accumulators.add(tv)
    s.auto_update_accumulators.add(tw)
    s.integrator.run(int(round(args.time / DT)))
    V = np.array(tv.time_series()).reshape(-1, 3)
    W = np.array(tw.time_series()).reshape(-1, 3)
    cpu = time.process_time() - c0
    kT_f = float(np.mean(s.srd.v ** 2))  # the fluid's temperature (no thermostat: its initial draw)
    rho_free = RHO * L ** 3 / (L ** 3 - 4.0 / 3.0 * np.pi * A ** 3)  # add_colloid moved the particles inside out
    if args.save:
        os.makedirs(args.save, exist_ok=True)
        np.savez(os.path.join(args.save, f"{args.rule}_a{A:g}_M{M:g}_dt{DT:g}_s{seed}.npz"), V=V, W=W)
    row = dict(rule=args.rule, a=A, M=M, L=L, dt=DT, seed=seed, time=args.time, cpu_s=round(cpu, 1),
               kinetic=list(theory), kT_fluid=kT_f, density_free=rho_free,
               kinetic_free=list(srd.kinetic_friction(A, M, rho_free, args.rule, kT=kT_f)),
               V=analyse(V, M, kT_f), W=analyse(W, I, kT_f))
    for k in "VW":
        r = row[k]
        th = theory["VW".index(k)]
        print(f"{args.rule} seed {seed} dt {DT} {k}: " + ", ".join(
            f"{key} {v[0] / th:.3f}({1000 * v[1] / th:.0f})" for key, v in r.items() if key != "equipartition")
            + f"; <m x^2>/kT {r['equipartition']:.3f}", flush=True)
    with open(args.out, "a") as f:
        f.write(json.dumps(row) + "\n")
