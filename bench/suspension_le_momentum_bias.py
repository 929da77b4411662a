"""The momentum bias of the Lees-Edwards suspension viscosities measured
before the fix of samples/lees_edwards_suspension.py (doc/suspensions.md
section 7k), and the corrected values.

Before the fix the sample's scene() removed the unweighted mean velocity, which
leaves a total momentum P when the colloids are heavier than the beads. Its
component normal to the shear plane, P_y = M V_y, is conserved; the material
then crosses the shear plane at V_y, every crossing changes v_x by the shear
velocity, and the mean flow drifts as U_0(t) = U_0(0) - rate V_y t (t from the
start of the shear). The kinetic stress gains M U_0 V_y / V, so

    eta_measured - eta = M V_y^2 <t> / V - P_x(0) V_y / (rate V),

<t> = equil + time/2 the mean time since the shear began over the sampling.
This script rebuilds each scene of the given result files (the same seed and
settings, the old unweighted mean: the draws are deterministic), reads P and M
(P is conserved through the scene's equilibration; P_x(0) also takes the
initial shear profile the sample adds, evaluated at the rebuilt positions,
before the equilibration: an approximation for that small second term), and
writes the rows with ``eta`` corrected (``eta_uncorrected``, ``momentum_bias``,
``V_y`` added) to OUT.

    build/pymarble bench/suspension_le_momentum_bias.py --out OUT.jsonl FILES...
"""
import argparse
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "samples"))
import lees_edwards_suspension as les  # noqa: E402


def old_zero_momentum(s):
    """The sample's removal before the fix: the unweighted mean velocity."""
    v = np.asarray(s.part.all().v)
    s.part.all().v = v - v.mean(axis=0)


def momentum(row, equil_measure=10.0):
    les.zero_momentum, saved = old_zero_momentum, les.zero_momentum
    try:
        kw = dict(boundary=row.get("boundary", "slip"), shardlow=row.get("integrator", "vv") != "vv",
                  solvent_count=row.get("solvent_count"),
                  lubrication=row.get("lubrication", True) is not False,
                  colloid_dpd=row.get("colloid_dpd") is not False,
                  h_cut=row.get("h_cut", 1.0), lubrication_form=row.get("lubrication_form", "plain"))
        s, _ = les.scene(row["phi_nominal"], row["box"], row["dt"], seed=row["seed"], equil=0.0, **kw)
    finally:
        les.zero_momentum = saved
    p = s.part.all()
    m = np.asarray(p.mass, dtype=float)
    v = np.asarray(p.v)
    L = np.asarray(row["box"], dtype=float)
    y = np.asarray(p.pos_folded)[:, 1]
    P = (m[:, None] * v).sum(axis=0)
    M = m.sum()
    Px0 = P[0] + row["rate"] * np.sum(m * (y - 0.5 * L[1]))
    V = float(np.prod(L))
    Vy = P[1] / M
    t_mean = equil_measure + 0.5 * row["time"]
    bias = M * Vy ** 2 * t_mean / V - Px0 * Vy / (row["rate"] * V)
    return dict(P=P.tolist(), M=float(M), V_y=float(Vy), momentum_bias=float(bias))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    with open(args.out, "w") as out:
        for f in args.files:
            for line in open(f):
                row = json.loads(line)
                if not row.get("n_colloids"):  # the solvent alone: one mass, P = 0 exactly
                    row.update(momentum_bias=0.0, V_y=0.0, eta_uncorrected=row["eta"])
                else:
                    b = momentum(row)
                    row.update(eta_uncorrected=row["eta"], V_y=b["V_y"], momentum_bias=b["momentum_bias"])
                    row["eta"] = row["eta"] - b["momentum_bias"]
                row["source"] = os.path.basename(f)
                out.write(json.dumps(row) + "\n")
                print(f"{os.path.basename(f)} phi {row['phi']:.3f} seed {row['seed']} rate {row['rate']} "
                      f"box {row['box'][0]:g}: V_y {row['V_y']:+.2e}, bias {row['momentum_bias']:+.4f}, "
                      f"eta {row['eta_uncorrected']:.4f} -> {row['eta']:.4f}", flush=True)


if __name__ == "__main__":
    main()
