"""The phi = 0.3 viscosity of stick suspensions against the colloid radius in
units of the solvent's interaction range (doc/suspensions.md, section 7q;
issue 13).

At R = 1 = r_c the typical surface gap between neighbours at phi = 0.3
(a few tenths of R) is a fraction of the DPD solvent's own interaction range,
so the solvent between neighbours is not a continuum. This bench builds the
same colloid surface on a larger sphere: the core radius a, the
colloid-solvent hat and DPD on the shell and with the F_max of the R = 1 stick
colloid of sections 7d/7k (core a_1 = 1/1.013, shell r'_c(a_1), mean-field
F_max(a_1)), the same friction shell, contact, shifted lubrication to the core
gap 0.15, no colloid DPD, and the bulk solvent count with the adsorbed beads
per unit core area of section 7e. The core sits the R = 1 colloid's drag offset
d_t = a_1 (1.013 - 1) below the given radius, so that ``--radius`` is the
drag radius if the offset is a property of the surface (the first order of a
slip length); the table reports Krieger-Dougherty at the drag, strain and
rotational offsets of the R = 1 colloid (sections 7d, 7p, 7m), d_s = a_1
(1.032 - 1) and d_r = a_1 (1.0623 - 1). Uniform shear by Lees-Edwards, velocity
Verlet, eta = -<P_xy>/rate with blocking errors (samples/lees_edwards_suspension.py's
``measure()``), eta_r = eta/eta_0 with the solvent's eta_0 = 0.3290(30).

    build/pymarble bench/suspension_radius.py run --radius 2 --phi 0.3 --box 16 16 16 \\
        --rate 0.025 --time 1000 --seed 11 --json bench/results/suspension_radius.jsonl
    build/pymarble bench/suspension_radius.py table bench/results/suspension_radius.jsonl

``--radius 1`` builds the 7k scene's colloid (core 1/1.013, its own shell and
F_max), i.e. the R = 1 reference with the same code path.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "samples"))
sys.path.insert(0, HERE)

import marble  # noqa: E402
import marble.suspensions as sus  # noqa: E402
from marble.theory import krieger_dougherty_viscosity as kd  # noqa: E402
from lees_edwards_suspension import measure, zero_momentum, dimensionless, KT, GAMMA, ETA0, SOFT_CONTACT  # noqa: E402
from suspension_shear_diagnosis import weighted  # noqa: E402  (mean, error scaled by sqrt(chi^2/dof) > 1, chi^2)

A1 = 1.0 / sus.STICK_RADIUS_RATIO          # the R = 1 stick colloid's core (7d, 7k)
SHELL1 = sus.surface_cutoff(A1)            # its colloid-solvent and friction shell on the gap
FMAX1 = sus.colloid_solvent_repulsion(A1, a_ss=25.0 * KT / 1.0)  # its hat F_max (a_ss = 25 kT/r_c, as setup_suspension)
OFFSETS = {"drag": A1 * (sus.STICK_RADIUS_RATIO - 1.0),
           "strain": A1 * (sus.STICK_STRESSLET_RADIUS_RATIO - 1.0),
           "rotation": A1 * (sus.STICK_ROTATIONAL_RADIUS_RATIO - 1.0)}
ETA0_REF = (0.3290, 0.0030)  # the solvent (doc/suspensions.md 7d, 7j)


def scene(radius, phi, box, dt, seed, equil=10.0):
    """The stick suspension with the R = 1 colloid's surface on cores of
    radius - d_t; returns (system, info)."""
    a = radius - OFFSETS["drag"]
    s = marble.System(box_l=np.asarray(box, float))
    s.time_step = dt
    s.cell_system.skin = 0.4
    info = sus.setup_suspension(
        s, phi=phi, radius=radius, radius_calibration=radius / a, kT=KT, gamma=GAMMA, eta=ETA0, seed=seed,
        boundary="stick", cs_shell=SHELL1, a_cs=FMAX1, solvent_count="bulk",
        adsorbed=sus.ADSORBED_PER_AREA * 4.0 * math.pi * a * a, colloid_dpd=False, **SOFT_CONTACT)
    s.integrator.set_vv()
    zero_momentum(s)
    s.integrator.run(int(round(equil / dt)))
    return s, info


def run(args):
    t0, w0 = time.process_time(), time.time()
    s, info = scene(args.radius, args.phi, args.box, args.dt, args.seed)
    eta, err, slope, slope_err, kt = measure(s, args.rate, args.time)
    re, pe = dimensionless(args.rate, ETA0_REF[0], radius=args.radius)
    row = dict(radius=args.radius, core_radius=info["core_radius"], shell=info["cutoff_surface"],
               a_cs=info["a_cs"], phi=info["phi"], phi_core=info["phi_core"], n_colloids=info["n_colloids"],
               n_solvent=len(info["solvent_ids"]), box=list(args.box), rate=args.rate, time=args.time, dt=args.dt,
               seed=args.seed, eta=eta, eta_err=err, slope=slope, slope_err=slope_err, kT=kt, Re=re, Pe=pe,
               cpu_s=time.process_time() - t0, wall_s=time.time() - w0)
    print(json.dumps(row))
    if args.json:
        with open(args.json, "a") as f:
            f.write(json.dumps(row) + "\n")
    return row


def table(files, eta0=ETA0_REF):
    rows = [json.loads(line) for f in files for line in open(f) if line.strip()]
    groups = {}
    for r in rows:
        groups.setdefault((r["radius"], r["rate"], tuple(r["box"])), []).append(r)
    print("| R | box | rate | Re, Pe | seeds | eta_r per seed | eta_r | phi (drag) | KD at drag / strain / rotation "
          "offsets | vs KD at the strain offset | CPU-s per scene |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (R, rate, box), g in sorted(groups.items()):
        er = [r["eta"] / eta0[0] for r in g]
        ee = [r["eta_err"] / eta0[0] for r in g]
        m, e, chi2 = weighted(er, ee)
        e = math.hypot(e, m * eta0[1] / eta0[0])  # eta_0's error, common to all scenes
        a = g[0]["core_radius"]
        phi_core = float(np.mean([r["phi_core"] for r in g]))
        kds = {k: float(kd(phi_core * ((a + d) / a) ** 3)) for k, d in OFFSETS.items()}
        dev = m / kds["strain"] - 1.0
        per = ", ".join(f"{x:.3f}({round(1000 * y)}) ({r['seed']})" for x, y, r in zip(er, ee, g))
        print(f"| {R:g} | {'x'.join(f'{b:g}' for b in box)} | {rate:g} | {g[0]['Re']:.2f}, {g[0]['Pe']:.1f} | "
              f"{len(g)} | {per} | **{m:.3f} +/- {e:.3f}** (chi^2 {chi2:.1f}/{len(g) - 1}) | "
              f"{float(np.mean([r['phi'] for r in g])):.4f} | {kds['drag']:.3f} / {kds['strain']:.3f} / "
              f"{kds['rotation']:.3f} | {100 * dev:+.1f} +/- {100 * e / kds['strain']:.1f} % | "
              f"{np.mean([r['cpu_s'] for r in g]):.0f} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--radius", type=float, default=2.0, help="the drag radius (the core is radius - d_t)")
    r.add_argument("--phi", type=float, default=0.3)
    r.add_argument("--box", type=float, nargs=3, default=[16.0, 16.0, 16.0])
    r.add_argument("--rate", type=float, default=0.025)
    r.add_argument("--time", type=float, default=1000.0)
    r.add_argument("--dt", type=float, default=0.005)
    r.add_argument("--seed", type=int, default=11)
    r.add_argument("--json")
    t = sub.add_parser("table")
    t.add_argument("files", nargs="+")
    args = ap.parse_args()
    if args.cmd == "run":
        if args.radius <= OFFSETS["drag"]:
            raise ValueError(f"parameter 'radius' must exceed the drag offset {OFFSETS['drag']:.4f}, "
                             f"got {args.radius}")
        run(args)
    else:
        table(args.files)


if __name__ == "__main__":
    main()
