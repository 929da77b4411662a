"""Summary of bench/results/srd_short_time_friction.jsonl (doc/srd.md, "Short-time
friction: the fit window"): for every (rule, a, M, dt) the mean over the seeds
of each estimator divided by the kinetic value, with the standard error from
the scatter between seeds; `extrap`: each seed's window rates (1, 2, 4, 8 lags)
fitted linearly in the window width n dt and taken at zero width; `fluct OU`:
the one-step fluctuation estimate m<dX^2>/(2 kT dt) = (1 - exp(-zeta dt))/dt
solved for zeta (exact for an exponential decay; removes the O(zeta dt)
bias of the raw form); `one step/free`: `marble.srd.one_step_friction` with the
fluid's temperature over the kinetic value at the free-volume density and that
temperature (rows that have it).

    python3 bench/srd_short_time_friction_summary.py
"""
import collections
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "results", "srd_short_time_friction.jsonl")
groups = collections.defaultdict(list)
for line in open(path):
    r = json.loads(line)
    groups[(r["rule"], r["a"], r["M"], r["L"], r["dt"], r["time"])].append(r)
keys = ["window 1", "window 2", "window 4", "window 8", "window 16", "quad 8", "quad 16", "impulse", "extrap",
        "fluct", "fluct OU", "one step/free"]
for (rule, a, M, L, dt, T), rows in sorted(groups.items()):
    print(f"{rule}, a = {a:g}, M = {M:g}, L = {L:g}, dt = {dt:g}, {len(rows)} seeds x {T:g} t0 "
          f"(CPU {sum(r['cpu_s'] for r in rows):.0f} s)")
    for k, name in enumerate("VW"):
        th = rows[0]["kinetic"][k]
        vals = collections.defaultdict(list)
        for r in rows:
            e = r[name]
            for key in keys:
                if key == "extrap":
                    n = np.array([1, 2, 4, 8])
                    z = np.array([e[f"window {i}"][0] for i in n])
                    vals[key].append(np.polyfit(n * dt, z, 1)[1])
                elif key == "fluct OU":
                    vals[key].append(-np.log(1 - e["fluct"][0] * dt) / dt)
                elif key == "one step/free":
                    if "one step" in e:  # relative to the free-volume value at the fluid's kT
                        vals[key].append(e["one step"][0] * th / r["kinetic_free"][k])
                else:
                    vals[key].append(e[key][0])
            vals["<m x^2>/kT"].append(e["equipartition"] * th)
        out = []
        for key, v in vals.items():
            if not v:
                continue
            v = np.array(v) / th
            out.append(f"{key} {v.mean():.3f}({1000 * v.std(ddof=1) / np.sqrt(len(v)):.0f})")
        print(f"  {name} (kinetic {th:.4f}): " + ", ".join(out))
