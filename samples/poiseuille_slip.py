"""Slip length and hydrodynamic boundary of tunable-slip walls vs gamma_L.

The marble paper's DPD solvent (rho = 3, gamma = 5, w_D = (1 - r)^2, kT = 1,
reference.md section 2) in a channel between two WCA walls (z = 0 and z = L,
periodic in x and y) carrying tunable-slip friction layers of range z_c = 1
starting at the fluid's edge (offset 1.016, doc/walls.md). For each gamma_L a
Poiseuille run (body force on every bead) and a Couette run (walls at -/+ v_w)
give the viscosity eta (parabola curvature), the zero z_P of the Poiseuille
parabola and z_0 of the Couette line (both relative to the wall velocity),
and from them the slip length delta_B and the hydrodynamic boundary z_B
(delta_B^2 = (z_P - z_0)(L - z_P - z_0), z_B = z_0 + delta_B; see
marble.slip). The table compares delta_B with Smiatek's approximation
delta_B / z_c ~ 2 eta / (z_c^2 rho gamma_L) - 7/15 (measured from the layer
start, evaluated with the channel's own eta and rho); the PNG plots both.

    build/pymarble samples/poiseuille_slip.py [--gammas 0.5 1 2 3 5 10] [--steps 200000]
    build/pymarble samples/poiseuille_slip.py --replot poiseuille_slip.json   # table + plot only

The full default run is 6 x 2 x 210000 steps of 864 beads (~9 min on one idle core).

With MARBLE_SAMPLE_TEST=1 (the ctest run) it runs one gamma_L for a few thousand steps.
"""
import argparse
import json
import os
import time

import numpy as np

import marble
from marble import slip

short = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--gammas", type=float, nargs="+",
                    default=[1.0] if short else [0.5, 1.0, 2.0, 3.0, 5.0, 10.0])
parser.add_argument("--steps", type=int, default=4000 if short else 200000,
                    help="production steps per flow and gamma_L")
parser.add_argument("--equil", type=int, default=1000 if short else 10000)
parser.add_argument("--height", type=float, default=10.0, help="wall-to-wall distance L")
parser.add_argument("--box", type=float, default=6.0, help="box edge along x and y")
parser.add_argument("--body-force", type=float, default=0.1)
parser.add_argument("--wall-velocity", type=float, default=3.0)
parser.add_argument("--seed", type=int, default=7)
parser.add_argument("--png", default="poiseuille_slip.png")
parser.add_argument("--json", default="poiseuille_slip.json")
parser.add_argument("--replot", metavar="JSON", help="no runs: table and plot from a saved JSON")
args = parser.parse_args()

marble.assert_features("DPD", "LENNARD_JONES", "TUNABLE_SLIP")

OFFSET, Z_C = slip.WCA_FLUID_EDGE, 1.0
print(f"channel {args.box} x {args.box} x {args.height}, layer [{OFFSET}, {OFFSET + Z_C}], "
      f"g = {args.body_force}, v_w = +-{args.wall_velocity}, {args.steps} steps per flow "
      f"(dt = 0.01)")
rows = []
if args.replot:
    with open(args.replot) as f:
        rows = json.load(f)["rows"]
for k, g in enumerate([] if args.replot else args.gammas):
    t = time.perf_counter()
    r = slip.measure_slip(marble, g, n_steps=args.steps, equil_steps=args.equil,
                          body_force=args.body_force, wall_velocity=args.wall_velocity,
                          height=args.height, box_xy=args.box, seed=args.seed + 10 * k,
                          layer_offset=OFFSET, z_c=Z_C)
    formula = slip.smiatek_slip_length(g, eta=r["eta"], rho=r["rho"], z_c=Z_C)
    row = {"gamma_L": g, "formula": formula, "seconds": time.perf_counter() - t}
    for key in ("eta", "rho", "z_P", "z_0", "d2", "delta_B", "z_B", "v_couette_at_zP"):
        row[key], row[key + "_err"] = r[key], r[key + "_err"]
    row["b_couette"] = OFFSET - r["z_0"]  # apparent slip length from the layer start
    rows.append(row)
    print(f"gamma_L = {g}: done in {row['seconds']:.0f} s")


def pm(row, key, fmt="{:.3f}"):
    return (fmt + " +- " + fmt).format(row[key], row[key + "_err"])


print()
print(f"{'gamma_L':>7} | {'eta':>15} | {'z_P':>15} | {'z_0':>15} | {'d2':>15} | "
      f"{'delta_B':>15} | {'z_B':>15} | {'formula':>7} | {'b = off - z_0':>13}")
for row in rows:
    print(f"{row['gamma_L']:7.2f} | {pm(row, 'eta'):>15} | {pm(row, 'z_P'):>15} | "
          f"{pm(row, 'z_0'):>15} | {pm(row, 'd2'):>15} | {pm(row, 'delta_B'):>15} | "
          f"{pm(row, 'z_B'):>15} | {row['formula']:7.3f} | {row['b_couette']:13.3f}")
print("z in units of r_c from the wall plane; layer starts at", OFFSET,
      "; d2 < 0: no real (z_B, delta_B), reported delta_B = -sqrt(-d2), z_B = (z_P + z_0)/2")

if not args.replot and marble.mpi_rank() == 0:  # under MPI one rank writes
    with open(args.json, "w") as f:
        json.dump({"params": vars(args), "offset": OFFSET, "z_c": Z_C, "rows": rows}, f,
                  indent=1)

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib not available: no plot")
else:
    gam = np.array([r["gamma_L"] for r in rows])
    eta = np.mean([r["eta"] for r in rows])
    rho = np.mean([r["rho"] for r in rows])
    gg = np.geomspace(min(0.4, gam.min()), max(12.0, gam.max()), 200)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].errorbar(gam, [r["delta_B"] for r in rows], [r["delta_B_err"] for r in rows],
                   fmt="o", label=r"$\delta_B$ (Poiseuille + Couette)")
    ax[0].errorbar(gam, [r["b_couette"] for r in rows], [r["z_0_err"] for r in rows],
                   fmt="s", mfc="none", label=r"offset $- z_0$ (Couette, from layer start)")
    ax[0].plot(gg, slip.smiatek_slip_length(gg, eta=eta, rho=rho, z_c=Z_C), "k-",
               label=rf"Smiatek: $2\eta/(\rho\gamma_L z_c) - 7z_c/15$, $\eta$={eta:.3f}")
    gc = np.geomspace(gg[0], gg[-1], 25)
    cont = [slip.continuum_slip(x, eta=eta, rho=rho, z_c=Z_C, height=args.height - 2 * OFFSET,
                                n=801) for x in gc]
    ax[0].plot(gc, [-c["z_0"] for c in cont], "k--", lw=1,
               label=r"continuum model, exact: offset $- z_0$")
    ax[0].axhline(0.0, color="grey", lw=0.5)
    ax[0].set_xscale("log")
    ax[0].set_xlabel(r"$\gamma_L$")
    ax[0].set_ylabel("slip length")
    ax[0].legend(fontsize=8)
    ax[1].errorbar(gam, [r["z_B"] for r in rows], [r["z_B_err"] for r in rows], fmt="o",
                   label=r"$z_B$")
    ax[1].errorbar(gam, [r["z_P"] for r in rows], [r["z_P_err"] for r in rows], fmt="^",
                   mfc="none", label=r"$z_P$ (Poiseuille zero)")
    ax[1].errorbar(gam, [r["z_0"] for r in rows], [r["z_0_err"] for r in rows], fmt="v",
                   mfc="none", label=r"$z_0$ (Couette zero)")
    ax[1].axhspan(OFFSET, OFFSET + Z_C, color="C2", alpha=0.15, label="friction layer")
    ax[1].set_xscale("log")
    ax[1].set_xlabel(r"$\gamma_L$")
    ax[1].set_ylabel("distance from the wall")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    if marble.mpi_rank() == 0:
        fig.savefig(args.png, dpi=120)
        print("wrote", args.png, "and", args.json)
