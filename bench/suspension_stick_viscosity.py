"""One scene of the suspension viscosity measurement (doc/suspensions.md
sections 7 and 7c): the scene of samples/suspension_viscosity.py (seed 004's
solvent and colloids, R = 1, softer contact f_c = 50, delta = 0.02, squeeze
lubrication eta0 = 0.3 with h_cut = 1, Shardlow dt = 0.01), sheared by the
mass-proportional reverse Poiseuille flow; one scene per call so that the
scenes run side by side, each appending a JSON line. The scene and the
measurement are the sample's (imported).

    ./pymarble bench/suspension_stick_viscosity.py --phi 0 --time 3000 --json out.jsonl   # solvent
    ./pymarble bench/suspension_stick_viscosity.py --phi 0.1 --boundary stick --time 3000 --json out.jsonl

The runs quoted in doc/suspensions.md section 7c are in bench/results/suspension_stick.jsonl,
those of section 7e in bench/results/suspension_excess.jsonl.

Section 7e's options: ``--structure FILE.npz`` records the colloid centres every
``--structure-every`` time units during the measurement (through a wrapper of the
integrator: the trajectory and eta are unchanged) for bench/suspension_structure.py;
``--rest`` runs the scene without the force (structure only); ``--extra-solvent X``
adds X beads per colloid after the setup (the solvent the colloids adsorb, so that the
bulk density stays near rho) and equilibrates again at rest.
"""
import argparse
import json
import os
import sys
import time

import numpy as np

import marble
from marble import theory
import marble.suspensions as sus

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "samples"))
import suspension_viscosity as sample  # noqa: E402

parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
parser.add_argument("--phi", type=float, required=True, help="volume fraction (0: the solvent alone)")
parser.add_argument("--boundary", choices=["slip", "stick"], default="slip")
parser.add_argument("--trans-gamma", type=float, default=None, help="stick: tangential friction (default 45)")
parser.add_argument("--shared", choices=sus.STICK_SHARED_MODES, default=None,
                    help="stick: friction of a bead in several colloids' shells (default setup_suspension's: off)")
parser.add_argument("--stick-shell", type=float, default=None, help="stick: the friction shell's thickness")
parser.add_argument("--radius-calibration", default=None,
                    help="stick: setup_suspension's radius_calibration ('none': the core radius is R = 1, "
                         "as in section 7c; default 'stick': R = 1 is the hydrodynamic radius; 'rotation', "
                         "'stresslet': the rotational or strain radius; or a number)")
parser.add_argument("--solvent-count", choices=["poisson", "exact"], default="poisson",
                    help="setup_suspension's solvent_count (exact: round(rho x free volume) beads)")
parser.add_argument("--box", type=float, nargs=3, default=[7, 7, 10])
parser.add_argument("--time", type=float, default=2000.0, help="production time")
parser.add_argument("--equil", type=float, default=20.0)
parser.add_argument("--g", type=float, default=0.02)
parser.add_argument("--dt", type=float, default=0.01)
parser.add_argument("--seed", type=int, default=11)
parser.add_argument("--no-colloid-dpd", action="store_true", help="no DPD between colloids (seed 004 has it)")
parser.add_argument("--no-lubrication", action="store_true", help="no squeeze lubrication (seed 004 has it)")
parser.add_argument("--structure", help="record the colloid centres during the run into this .npz file "
                    "(bench/suspension_structure.py; the trajectory is unchanged)")
parser.add_argument("--structure-every", type=float, default=1.0, help="time units between recorded frames")
parser.add_argument("--rest", action="store_true", help="no flow (g = 0): only the structure is recorded")
parser.add_argument("--extra-solvent", type=float, default=0.0,
                    help="beads per colloid added after the setup (outside the cores; then --equil more at rest): "
                         "the solvent the colloids adsorb (doc/suspensions.md 7e: ~4 per colloid), so that the "
                         "bulk density stays near rho")
parser.add_argument("--density", type=float, default=None,
                    help="solvent density (default setup_suspension's 3; section 7e: eta_0 at the depleted bulk density)")
parser.add_argument("--seed004-kernels", action="store_true",
                    help="stick: the kernels of sections 7c-7e (plain lubrication to h_cut = 1; with --no-colloid-dpd/--no-lubrication still honoured) instead of setup_suspension's stick defaults (shifted lubrication to h_cut = 0.15, section 7i)")
parser.add_argument("--json", help="append the result (a JSON line) to this file")
args = parser.parse_args()
if args.rest and not args.structure:
    parser.error("--rest needs --structure")

marble.assert_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS", "EXTERNAL_FORCE")
box = np.array(args.box, dtype=float)

t0 = time.process_time()
kw = dict(solvent_count=args.solvent_count)
if args.density is not None:
    kw["density"] = args.density
if args.phi > 0:
    kw = dict(kw, boundary=args.boundary, colloid_dpd=not args.no_colloid_dpd, lubrication=not args.no_lubrication)
    if args.boundary == "stick" and args.trans_gamma is not None:
        kw["trans_gamma"] = args.trans_gamma
    if args.boundary == "stick":
        kw.update(shared=args.shared, stick_shell=args.stick_shell)
        if args.seed004_kernels:
            kw.update(lubrication_form="plain", h_cut=1.0)
        if args.radius_calibration is not None:
            rc = args.radius_calibration
            kw["radius_calibration"] = sus.radius_calibration_arg(rc)
# the sample's scene and measurement (samples/suspension_viscosity.py)
s, info = sample.scene(args.phi, box, dt=args.dt, seed=args.seed, equil=args.equil, **kw)
if sample.add_extra_solvent(s, info, box, args.extra_solvent, args.seed) is not None:
    p_all = s.part.all()
    v, m = np.asarray(p_all.v), np.asarray(p_all.mass)
    p_all.v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)
    s.integrator.run(int(round(args.equil / args.dt)))
if args.structure:
    from suspension_structure import StructureSampler  # noqa: E402 (bench/)
    sampler = StructureSampler(s, info["colloid_ids"], int(round(args.structure_every / args.dt)))
    if args.rest:
        sampler.run_rest(int(round(args.time / args.dt)))
        res = None
    else:
        res = sample.measure(sampler, args.g, args.time)
    sampler.save(args.structure, seed=args.seed, colloid_dpd=not args.no_colloid_dpd, rest=args.rest,
                 g=0.0 if args.rest else args.g, phi=info["phi"], phi_core=info["phi_core"],
                 core_radius=info["core_radius"], time=args.time, n_colloids=info["n_colloids"])
else:
    res = sample.measure(s, args.g, args.time)
if res is None:
    print(f"--rest: {len(sampler.frames)} frames written to {args.structure}")
    sys.exit(0)
out = dict(phi=info["phi"], phi_nominal=args.phi, n_colloids=info["n_colloids"],
           boundary=args.boundary if args.phi > 0 else "solvent", trans_gamma=info.get("trans_gamma"),
           shared=info.get("shared"), stick_shell=info.get("stick_shell"),
           box=list(box), time=args.time, dt=args.dt, g=args.g, seed=args.seed,
           eta=res.eta, eta_err=res.eta_err, kT=res.kT, v_max=res.v_max,
           colloid_dpd=not args.no_colloid_dpd, lubrication=not args.no_lubrication,
           phi_core=info.get("phi_core", 0.0), phi_hydrodynamic=info.get("phi_hydrodynamic"),
           core_radius=info.get("core_radius"), radius_calibration=info.get("radius_calibration"),
           n_solvent=len(s.part.all()) - info["n_colloids"], solvent_count=args.solvent_count,
           extra_solvent=args.extra_solvent, density=3.0 if args.density is None else args.density)
out["cpu_s"] = time.process_time() - t0
print(json.dumps(out))
print(f"phi = {out['phi']:.4f} (cores {out['phi_core']:.4f}; {out['boundary']}): eta = {res.eta:.4f} +/- {res.eta_err:.4f}; "
      f"Batchelor x eta0 would be {theory.batchelor_viscosity(out['phi']):.3f} eta0")
if args.json:
    with open(args.json, "a") as f:
        f.write(json.dumps(out) + "\n")
