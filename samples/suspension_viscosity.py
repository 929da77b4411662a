"""Relative viscosity of a core-modified DPD colloid suspension (seed 004,
doc/suspensions.md) against the volume fraction, with Batchelor and
Krieger-Dougherty.

Each scene is built by marble.suspensions.setup_suspension (R = 1, rho = 3,
kT = 0.1, gamma = 4.5, a_ss = 25 kT, mean-field colloid-solvent repulsion,
squeeze lubrication eta0 = 0.3, colloid mass rho 4/3 pi R^3; the boundary's
defaults of setup_suspension: "slip" is seed 004's colloid with the plain kernel
to h_cut = 1 on the gap and the colloid-colloid DPD, "stick" the shifted kernel
to h_cut = 0.15, no colloid-colloid DPD, doc/suspensions.md 7i) and sheared by a reverse Poiseuille flow
(marble.viscosity.reverse_poiseuille with ``mass_proportional=True``: the same
body acceleration on solvent beads and colloids, as a pressure gradient gives
neutrally buoyant spheres). The pure solvent of the same box and settings gives
eta_0; eta_r = eta(phi) / eta_0, its error from both blocking error bars.

Integration: Shardlow (lubrication and colloid-solvent friction in the exact
pair update), dt = 0.01 with a softer contact force than the seed's
(f_contact = 50 = 500 kT, delta = 0.02: contact stiffness 3 f_c/delta = 7500,
period 0.18 for the colloid pair's reduced mass) so that the step is set by the
solvent, not by the contact (the seed's f_c = 1e4 kT, delta = 1e-3 needs
dt = 1e-3; --seed-contact uses it).

Prints eta_0, eta(phi), eta_r(phi) with error bars and the two theories, and
writes suspension_viscosity.png.

    build/pymarble samples/suspension_viscosity.py [--box 8 8 12] [--time 1000]
        [--phi 0.05 0.1 0.2 0.3] [--g 0.02] [--boundary stick]

Statistics (doc/suspensions.md section 7): at box 7 x 7 x 10, g = 0.02 and 300
time units per scene eta has a blocking error of about 6 % per scene
(eta_0 = 0.327 +/- 0.019, eta(0.103) = 0.392 +/- 0.025, eta_r = 1.20 +/- 0.10
against Batchelor's 1.32); the error falls as 1/sqrt(time). The default run
(~2300 particles, 1000 time units per scene) takes about 2-3 minutes per scene
on one idle core.

``--boundary stick`` makes the colloids rotating no-slip spheres (setup_suspension's
surface_friction, doc/suspensions.md section 7c) whose hydrodynamic radius is R = 1
(core radius R/1.013, section 7d; ``--radius-calibration none`` builds the core R = 1
as before; ``--radius-calibration rotation``: R = 1 is the rotational radius, core
R/1.0623, section 7m; ``--radius-calibration stresslet``: R = 1 is the strain radius of
Einstein's viscosity, core R/1.032, section 7p); phi is then the volume fraction of spheres of that radius and
the cores' is printed too, with the volume fractions of the rotational and the strain
radius and Krieger-Dougherty there. The solvent has exactly rho x free volume beads for "slip" and the "bulk" count for
"stick" (setup_suspension's stick default; ``--solvent-count poisson``: a
Poisson number, as the runs of sections 7-7c; section 7d: the density scatter of a
Poisson count shifts eta by several %, and eta_0 must be measured at the same density). The default "slip" is seed 004's colloid, whose central colloid-solvent
friction makes it a slipping sphere (section 7b).

Shear-induced migration (doc/suspensions.md section 7e): in the reverse Poiseuille
channel the colloids drift towards the planes of zero shear, where the fit is made;
in the 7 x 7 x 10 box the fitted region's volume fraction is ~9 % above phi (0.214 at
phi = 0.197, 0.327 at 0.299), so eta_r belongs to that higher phi. Compare with theory
at the fitted region's phi (bench/suspension_stick_viscosity.py --structure and
bench/suspension_structure.py measure it). Also: the colloids adsorb ~4 solvent beads
each, so the bulk solvent between them is below the density of the eta_0 scene (2.78
instead of 3 at phi = 0.2) and eta/eta_0 understates the relative viscosity by 4-11 %
(section 7e).

With MARBLE_SAMPLE_TEST=1 (the ctest run) it uses a 7 x 7 x 8 box, phi = 0.05
and 0.1 and 5 time units per scene: a smoke test of the pipeline (the flow has
not developed then; the numbers are noise).

Importable (bench/suspension_stick_viscosity.py reuses ``scene`` and ``measure``):
the run is in ``main()``.
"""
import argparse
import math
import os

import numpy as np

import marble
import marble.suspensions as sus
from marble import theory
from marble.viscosity import reverse_poiseuille

R, KT, GAMMA, ETA0 = 1.0, 0.1, 4.5, 0.3
SOFT_CONTACT = dict(f_contact=50.0, delta=0.02)  # contact stiffness 7500, period 0.18: dt = 0.01


def scene(phi, box, dt=0.01, seed=11, equil=20.0, contact=None, **suspension_kw):
    """The scene at volume fraction ``phi`` (0: the solvent alone, setup_suspension's
    solvent without the colloid) in a box ``box``: seed 004's colloids and solvent,
    ``contact`` the contact parameters (default SOFT_CONTACT), ``suspension_kw``
    more setup_suspension parameters (boundary, trans_gamma, shared, colloid_dpd, ...);
    Shardlow at ``dt``, zero total momentum, ``equil`` time units at rest.
    Returns (system, info)."""
    box = np.asarray(box, dtype=float)
    contact = SOFT_CONTACT if contact is None else contact
    s = marble.System(box_l=box)
    s.time_step = dt
    s.cell_system.skin = 0.4
    if phi > 0:
        info = sus.setup_suspension(s, phi=phi, radius=R, kT=KT, gamma=GAMMA, eta=ETA0,
                                    seed=seed, **contact, **suspension_kw)
    else:  # the solvent alone: setup_suspension's solvent without the colloid
        count = suspension_kw.get("solvent_count", "poisson")
        # "exact": a point-sized placeholder colloid, so that no hole is cut from the solvent
        info = sus.setup_suspension(s, phi=1e-9, radius=R if count == "poisson" else 1e-3, kT=KT,
                                    gamma=GAMMA, eta=ETA0, seed=seed, positions=[0.5 * box],
                                    solvent_count=count, density=suspension_kw.get("density", 3.0), **contact)
        s.part.by_ids(info["colloid_ids"]).remove()
        s.non_bonded_inter.reset()
        s.non_bonded_inter[0, 0].hat.set_params(F_max=info["a_ss"], cutoff=1.0)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=GAMMA, r_cut=1.0)
        info["n_colloids"], info["phi"], info["phi_core"] = 0, 0.0, 0.0
    s.integrator.set_shardlow()
    p = s.part.all()
    v = np.asarray(p.v)
    m = np.asarray(p.mass)
    p.v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)  # no drift of the centre of mass
    s.integrator.run(int(round(equil / dt)))
    return s, info


def add_extra_solvent(s, info, box, per_colloid, seed, kT=KT):
    """Add round(per_colloid x colloids) solvent beads at random outside the
    cores (Maxwellian velocities at kT; the stream keyed by [seed, 7]), to
    restore the bulk density the colloids' adsorbed layers take away
    (doc/suspensions.md section 7e). Returns the added particles (or None)."""
    n_extra = int(round(per_colloid * info["n_colloids"]))
    if n_extra <= 0:
        return None
    box = np.asarray(box, float)
    rng = np.random.default_rng([seed, 7])
    cp = np.mod(np.asarray(s.part.by_ids(info["colloid_ids"]).pos, float), box)
    new = np.empty((0, 3))
    while len(new) < n_extra:
        x = rng.uniform(0, 1, (4 * n_extra, 3)) * box
        keep = np.ones(len(x), bool)
        for c in cp:
            d = x - c
            d -= box * np.round(d / box)
            keep &= np.linalg.norm(d, axis=1) >= info["core_radius"]
        new = np.vstack([new, x[keep]])
    return s.part.add(pos=new[:n_extra], type=[0] * n_extra, v=rng.normal(size=(n_extra, 3)) * np.sqrt(kT))


def measure(s, g, time, equilibration=None):
    """eta of the scene by the mass-proportional reverse Poiseuille flow (10 blocks,
    margin 1.5): marble.viscosity.reverse_poiseuille's result."""
    return reverse_poiseuille(s, g=g, time=time, n_blocks=10, margin=1.5,
                              equilibration=equilibration, mass_proportional=True)


def main():
    short = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--box", type=float, nargs=3, default=[7, 7, 8] if short else [8, 8, 12])
    parser.add_argument("--phi", type=float, nargs="+",
                        default=[0.05, 0.1] if short else [0.05, 0.1, 0.2, 0.3])
    parser.add_argument("--time", type=float, default=5.0 if short else 1000.0,
                        help="production time per scene")
    parser.add_argument("--equil", type=float, default=2.0 if short else 20.0,
                        help="equilibration at rest before the flow (time units)")
    parser.add_argument("--g", type=float, default=0.02,
                        help="body force per particle of mean mass (mass_proportional)")
    parser.add_argument("--dt", type=float, default=0.01)
    parser.add_argument("--seed-contact", action="store_true",
                        help="seed 004's contact force (f_c = 1e4 kT, delta = 1e-3; use dt = 1e-3)")
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--boundary", choices=["slip", "stick"], default="slip",
                        help="slip: seed 004's colloids (central friction); stick: rotating colloids with "
                             "the tangential surface_friction (doc/suspensions.md section 7c)")
    parser.add_argument("--trans-gamma", type=float, default=None,
                        help="stick: the tangential friction (default setup_suspension's 45)")
    parser.add_argument("--shared", choices=sus.STICK_SHARED_MODES, default=None,
                        help="stick: the friction of a bead inside several colloids' shells "
                             "(default setup_suspension's)")
    parser.add_argument("--radius-calibration", default=None,
                        help="stick: which radius R = 1 is: 'stick' (default: the hydrodynamic radius, core "
                             "R/1.013, doc/suspensions.md section 7d), 'rotation' (the rotational radius, core "
                             "R/1.0623, section 7m), 'stresslet' (the strain radius, core R/1.032, section "
                             "7p), 'none' (the core) or a ratio")
    parser.add_argument("--solvent-count", choices=["exact", "poisson", "bulk"], default=None,
                        help="solvent beads: exactly rho x free volume (default for slip; stick: "
                             "setup_suspension's default 'bulk'), a Poisson number as "
                             "seed 004 (and doc/suspensions.md sections 7-7c): its density scatter between "
                             "scenes shifts eta by several %% (section 7d), or 'bulk': the exact count plus "
                             "the ~4 beads each colloid adsorbs, so the solvent between the colloids is at "
                             "rho (section 7e)")
    parser.add_argument("--lubrication-form", choices=["plain", "shifted"], default=None,
                        help="the squeeze lubrication kernel's form (default setup_suspension's: plain for slip, "
                             "shifted for stick, doc/suspensions.md 7i)")
    parser.add_argument("--h-cut", type=float, default=None,
                        help="the lubrication range on the core gap (default setup_suspension's: 1 for the plain "
                             "form, 0.15 for stick's shifted form)")
    parser.add_argument("--colloid-dpd", choices=["on", "off"], default=None,
                        help="seed 004's colloid-colloid DPD (default setup_suspension's: on for slip, off for stick)")
    parser.add_argument("--png", default="suspension_viscosity.png")
    args = parser.parse_args()

    marble.assert_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS", "EXTERNAL_FORCE")
    box = np.array(args.box, dtype=float)
    contact = {} if args.seed_contact else SOFT_CONTACT
    stick = dict(boundary=args.boundary)
    if args.lubrication_form is not None:
        stick["lubrication_form"] = args.lubrication_form
    if args.h_cut is not None:
        stick["h_cut"] = args.h_cut
    if args.colloid_dpd is not None:
        stick["colloid_dpd"] = args.colloid_dpd == "on"
    # None: "exact" for slip (this sample's), setup_suspension's "bulk" for stick (the
    # solvent-alone scene has no colloids, so its "bulk" count is the exact count)
    count = args.solvent_count or ("bulk" if args.boundary == "stick" else "exact")
    if args.boundary == "stick":
        marble.assert_features("TRANS_DPD", "ROTATION")
        if args.trans_gamma is not None:
            stick["trans_gamma"] = args.trans_gamma
        if args.shared is not None:
            stick["shared"] = args.shared
        if args.radius_calibration is not None:
            rc = args.radius_calibration
            stick["radius_calibration"] = sus.radius_calibration_arg(rc)

    def run(phi):
        s, info = scene(phi, box, dt=args.dt, seed=args.seed, equil=args.equil, contact=contact,
                        solvent_count=count, **(stick if phi > 0 else {}))
        res = measure(s, args.g, args.time, equilibration=0.5 * args.equil if short else None)
        print(f"phi = {info['phi']:.4f} (cores {info['phi_core']:.4f}; {info['n_colloids']} colloids, "
              f"{len(s.part.all())} "
              f"particles): eta = {res.eta:.4f} +/- {res.eta_err:.4f}, kT = {res.kT:.4f}, "
              f"v_max = {res.v_max:.3f}", flush=True)
        return info["phi"], info["phi_core"], res, (info.get("phi_rotational"), info.get("phi_stresslet"))

    phi0, _, res0, _ = run(0.0)
    rows = []
    for phi in args.phi:
        ph, ph_core, res, radii = run(phi)
        er = res.eta / res0.eta
        er_err = er * math.hypot(res.eta_err / res.eta, res0.eta_err / res0.eta)
        rows.append((ph, er, er_err, ph_core, radii))
    print(f"box {box}, dt = {args.dt}, g = {args.g}, {args.time} time units per scene")
    print(f"eta_0 = {res0.eta:.4f} +/- {res0.eta_err:.4f}")
    print(" phi (given radius)  phi (cores)  eta_r            Batchelor  Krieger-Dougherty")
    for ph, er, e, ph_core, _ in rows:
        print(f" {ph:.3f}               {ph_core:.3f}        {er:.3f} +/- {e:.3f}   "
              f"{theory.batchelor_viscosity(ph):.3f}      {theory.krieger_dougherty_viscosity(ph):.3f}")
    if args.boundary == "stick":
        # the stick colloid is ~5 % larger in rotation than in drag (doc/suspensions.md 7m);
        # its stresslet's (strain) radius lies between the two (7p)
        print(" phi of the rotational radius (7m)   Krieger-Dougherty there   "
              "phi of the strain radius (7p)   Krieger-Dougherty there")
        for ph, er, e, ph_core, (ph_rot, ph_s) in rows:
            print(f" {ph_rot:.3f}                              {theory.krieger_dougherty_viscosity(ph_rot):.3f}"
                  f"                     {ph_s:.3f}                           "
                  f"{theory.krieger_dougherty_viscosity(ph_s):.3f}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    ph = np.linspace(0.0, max(0.35, max(r[0] for r in rows)), 100)
    ax.plot(ph, theory.batchelor_viscosity(ph), "-", label="Batchelor 1 + 2.5 phi + 6.2 phi^2")
    ax.plot(ph, theory.krieger_dougherty_viscosity(ph), "--", label="Krieger-Dougherty, phi_m = 0.63")
    # measured hard spheres (de Kruif et al. 1985): (1 - phi/phi_m)^-2, low and high shear
    ax.plot(ph, theory.quemada_viscosity(ph, 0.63), ":", label="hard spheres, low shear (1 - phi/0.63)^-2")
    ax.plot(ph, theory.quemada_viscosity(ph, 0.71), "-.", label="hard spheres, high shear (1 - phi/0.71)^-2")
    ax.errorbar([r[0] for r in rows], [r[1] for r in rows], yerr=[r[2] for r in rows], fmt="o",
                label=f"core-modified DPD, {args.boundary} colloids (reverse Poiseuille)")
    ax.set_xlabel("phi")
    ax.set_ylabel("eta / eta_0")
    ax.set_title("Suspension viscosity, seed 004 model")
    ax.legend()
    fig.tight_layout()
    if marble.mpi_rank() == 0:
        fig.savefig(args.png, dpi=120)
        print(f"wrote {args.png}")


if __name__ == "__main__":
    main()
