"""Summary of bench/results/srd_drag_size.jsonl (doc/srd.md, "D by drag against the
colloid size"): rows of `samples/srd_colloid.py --json` grouped by (rule, a, M, L,
v_rel target); D = mean of the runs weighted by their length, error = the larger
of the combined block errors and the scatter between runs / sqrt(n); ratios to
Hasimoto alone (eta as given to the sample) and to the parallel estimate
kT/(M zeta_kin) + Hasimoto; `hydro part` = (D - kT/(M zeta_kin)) / Hasimoto.

    build/pymarble bench/srd_drag_size_summary.py
"""
import collections
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "results", "srd_drag_size.jsonl")
groups = collections.defaultdict(list)
for line in open(path):
    r = json.loads(line)
    groups[(r["rule"], r["a"], r["M"], r["L"], round(r["F"] * r["D_parallel"], 4))].append(r)
print("| a | M | L | runs x t0 | Re | D (drag) | Hasimoto | D / Hasimoto | parallel | D / parallel | "
      "(D - kT/(M zeta_kin)) / Hasimoto | CPU |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for (rule, a, M, L, v), rows in sorted(groups.items()):
    t = np.array([r["time"] for r in rows])
    D = np.array([r["D"] for r in rows])
    e = np.array([r["D_err"] for r in rows])
    Dm = float(np.sum(t * D) / np.sum(t))
    err = float(np.sqrt(np.sum((t * e) ** 2)) / np.sum(t))
    if len(rows) > 1:
        err = max(err, float(np.std(D, ddof=1) / np.sqrt(len(D))))
    r0 = rows[0]
    Dh, Dp, Dk = r0["D_hasimoto"], r0["D_parallel"], r0["D_kinetic"]
    Re = v * a / (r0["eta"] / 5.0)
    print(f"| {a:g} | {M:g} | {L:g} | {len(rows)} x {t[0]:g} | {Re:.2f} | {Dm:.5f} +/- {err:.5f} | {Dh:.5f} | "
          f"{Dm / Dh:.3f} +/- {err / Dh:.3f} | {Dp:.5f} | {Dm / Dp:.3f} +/- {err / Dp:.3f} | "
          f"{(Dm - Dk) / Dh:.3f} +/- {err / Dh:.3f} | {sum(r['cpu_s'] for r in rows):.0f} s |")
