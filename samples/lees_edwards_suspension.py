"""Viscosity of a core-modified DPD colloid suspension under Lees-Edwards
simple shear (doc/lees-edwards.md, doc/suspensions.md).

The scene is built by marble.suspensions.setup_suspension (R = 1, rho = 3,
kT = 0.1, gamma = 4.5, a_ss = 25 kT, squeeze lubrication eta0 = 0.3, the soft
contact of samples/suspension_viscosity.py; the boundary's defaults: "slip" is
seed 004's colloid with the plain kernel to h_cut = 1 and the colloid-colloid
DPD, "stick" the shifted kernel to h_cut = 0.15, no colloid-colloid DPD and the
"bulk" solvent count, doc/suspensions.md 7i) and sheared by
Lees-Edwards boundary conditions (LinearShear in x across y): a uniform shear
rate over the whole box, so colloids cannot migrate to a low-shear region and
no profile fit mixes shear rates, unlike reverse Poiseuille flow. The pure
solvent of the same box and settings gives eta_0 the same way;
eta = -<P_xy> / rate with P = kinetic + conservative + DPD pair stress
(pressure_tensor()'s 'total' + 'dpd'), errors by blocking; the mean velocity
profile is fitted to check the imposed rate.

Integration: Shardlow (the DPD, lubrication and surface-friction pairs
updated exactly in the sweep, across the shear plane with the shear velocity
jump) at dt = 0.01 by default; --vv uses velocity Verlet at dt = 0.005 (the
explicit lubrication friction of close colloid pairs needs the smaller step;
the stability check refuses a too large one).

    build/pymarble samples/lees_edwards_suspension.py [--box 8 8 8] [--rate 0.05]
        [--phi 0.1] [--time 200] [--vv] [--dt DT] [--boundary stick]
        [--no-lubrication] [--no-colloid-dpd | --colloid-dpd] [--h-cut H]
        [--lubrication-form plain|shifted] [--solvent-count exact|bulk]
        [--mass-scale M] [--shared full|split|off]

--mass-scale M multiplies the mass of every particle (solvent beads 1 -> M,
colloids their setup_suspension mass x M, the colloids' rotational inertia x M;
velocities and spins rescaled by 1/sqrt(M) so they stay at kT) at fixed radius,
kT, gamma and rate: the particle Reynolds number Re = 3 M rate R^2/eta_0(M)
changes (eta_0's kinetic part grows with M, so measure eta_0 at every M;
doc/suspensions.md 7l). M = 1 (default) leaves the scene bit for bit unchanged.
Lighter particles need a smaller dt with --vv (friction rates gamma/M).

Options left out take setup_suspension's default for the boundary (for "slip"
the solvent count is "exact", as in this sample before).

Several MPI ranks: `mpiexec -n 2 build/pymarble samples/lees_edwards_suspension.py
--box 8 8 12 --boundary stick ...` (Lees-Edwards splits the vorticity axis z only;
under Shardlow each slab must be at least twice the colloids' pair range
2R + h_cut + skin: 2 x 2.55 for stick colloids of R = 1, hence L_z >= 10.2 on 2
ranks; 2 x 3.4 for the default "slip", L_z >= 13.6; doc/lees-edwards.md).

With MARBLE_SAMPLE_TEST=1 (a smoke test) it uses a 6 x 6 x 6 box and 2 time
units per scene (the numbers are then noise).
"""
import argparse
import os
import time

import numpy as np

import marble
import marble.suspensions as sus
from marble import theory
from marble.viscosity import lees_edwards_viscosity

R, KT, GAMMA, ETA0 = 1.0, 0.1, 4.5, 0.3
SOFT_CONTACT = dict(f_contact=50.0, delta=0.02)


def scene(phi, box, dt, seed=11, equil=10.0, boundary="slip", shardlow=True, solvent_count=None,
          lubrication=True, colloid_dpd=None, h_cut=None, lubrication_form=None, mass_scale=1.0,
          shared=None):
    """The scene at volume fraction ``phi`` (0: the solvent alone), ``equil`` time
    units at rest. None for ``solvent_count``, ``colloid_dpd``, ``h_cut`` and
    ``lubrication_form``: setup_suspension's default for ``boundary``, except
    that the solvent count of "slip" is "exact" (this sample's). ``mass_scale``
    multiplies every mass and rotational inertia (see scale_masses). ``shared``
    (stick only; None: setup_suspension's, "off"): the stick kernel's treatment of a
    bead in the friction shells of two colloids. Returns (system, info)."""
    mass_scale = check_mass_scale(mass_scale)
    if solvent_count is None and boundary == "slip":
        solvent_count = "exact"
    box = np.asarray(box, dtype=float)
    s = marble.System(box_l=box)
    s.time_step = dt
    s.cell_system.skin = 0.4
    if phi > 0:
        info = sus.setup_suspension(s, phi=phi, radius=R, kT=KT, gamma=GAMMA, eta=ETA0,
                                    seed=seed, h_cut=h_cut, solvent_count=solvent_count, boundary=boundary,
                                    lubrication=lubrication, colloid_dpd=colloid_dpd,
                                    lubrication_form=lubrication_form,
                                    **({} if shared is None else dict(shared=shared)), **SOFT_CONTACT)
    else:  # the solvent alone: the same solvent interactions and thermostat
        rng = np.random.default_rng(seed)
        n = int(round(3.0 * np.prod(box)))
        s.part.add(pos=rng.uniform(0, 1, (n, 3)) * box)
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0 * KT, cutoff=1.0)
        s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=GAMMA, k=1.0, r_cut=1.0)
        s.thermostat.set_dpd(kT=KT, seed=seed)
        info = {"n_colloids": 0}
    if mass_scale != 1.0:
        scale_masses(s, mass_scale, info)
    info["mass_scale"] = mass_scale
    if shardlow:
        s.integrator.set_shardlow()
    else:
        s.integrator.set_vv()
    zero_momentum(s)
    s.integrator.run(int(round(equil / dt)))
    return s, info


def check_mass_scale(mass_scale):
    """``mass_scale`` as a float; ValueError unless finite and > 0."""
    try:
        m = float(mass_scale)
    except (TypeError, ValueError):
        raise ValueError(f"parameter 'mass_scale' must be a number > 0, got {mass_scale!r}") from None
    if not (np.isfinite(m) and m > 0):
        raise ValueError(f"parameter 'mass_scale' must be finite and > 0, got {mass_scale!r}")
    if m != 1.0 and not marble.has_features("MASS"):
        raise marble.FeaturesError("missing feature MASS (needed for mass_scale != 1)")
    return m


def scale_masses(s, mass_scale, info=None):
    """Multiply the mass of every particle by ``mass_scale`` (beads 1 -> M,
    colloids M_c -> M M_c) and the rotational inertia of the rotating ones too;
    velocities and spins are divided by sqrt(M) so that the kinetic energy (kT)
    is unchanged. Radius, kT and every friction (gamma, trans_gamma, the
    lubrication's eta) stay: DPD's friction and noise do not depend on the mass
    in the default build (no DPD_MASS_RED/LIN), so only the inertia changes.
    ``info`` (setup_suspension's dict) gets the new colloid mass and inertia."""
    m = check_mass_scale(mass_scale)
    parts = s.part.all()
    if len(parts) == 0:
        return
    f = 1.0 / np.sqrt(m)
    parts.mass = np.asarray(parts.mass, dtype=float) * m
    parts.v = np.asarray(parts.v, dtype=float) * f
    if marble.has_features("ROTATION"):
        rot = np.asarray(parts.rotation, dtype=bool).any(axis=1)
        if rot.any():
            ids = np.asarray(parts.id)[rot]
            r = s.part.by_ids(ids)
            r.rinertia = np.asarray(r.rinertia, dtype=float) * m
            r.omega_lab = np.asarray(r.omega_lab, dtype=float) * f
    if info is not None:
        for k in ("colloid_mass", "rinertia"):
            if info.get(k) is not None:
                info[k] = info[k] * m


def dimensionless(rate, eta0, mass_scale=1.0, radius=R, density=3.0, kT=KT):
    """(Re, Pe) of a colloid of ``radius`` in the solvent of viscosity ``eta0``:
    Re = rho_mass rate R^2 / eta_0 with rho_mass = density x mass_scale (bead
    mass 1 x M), Pe = 6 pi eta_0 R^3 rate / kT."""
    return (density * mass_scale * rate * radius ** 2 / eta0,
            6.0 * np.pi * eta0 * radius ** 3 * rate / kT)


def zero_momentum(s):
    """Remove the mass-weighted mean velocity: total momentum 0. Under
    Lees-Edwards a net momentum normal to the shear plane (P_y = M V_y, conserved)
    carries the material across the shear plane, each crossing changes v_x by
    the shear velocity, so the mean flow drifts as U_0(t) = -rate V_y t and the
    kinetic stress gains M U_0 V_y / V: eta biased by +M V_y^2 t / V
    (doc/suspensions.md section 7k). Colloids heavier than the beads make an
    unweighted mean leave such a P_y."""
    s.galilei.galilei_transform()


def measure(s, rate, time, sample_every=10, equil=10.0):
    """Shear at ``rate`` for ``equil`` then ``time`` time units
    (``marble.viscosity.lees_edwards_viscosity``: mass-weighted zero momentum,
    the linear profile to start, 8 bins, blocking with at least 8 blocks);
    returns (eta, eta_err, slope, slope_err, kT of the peculiar velocities)."""
    r = lees_edwards_viscosity(s, rate, time, equilibration=equil, sample_every=sample_every,
                               n_bins=8, min_blocks=8)
    return r.eta, r.eta_err, r.slope, r.slope_err, r.kT


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--box", type=float, nargs=3, default=[8.0, 8.0, 8.0])
    ap.add_argument("--rate", type=float, default=0.05)
    ap.add_argument("--phi", type=float, default=0.1)
    ap.add_argument("--time", type=float, default=200.0)
    ap.add_argument("--dt", type=float, default=None,
                    help="time step (default 0.01 with Shardlow, 0.005 with --vv)")
    ap.add_argument("--vv", action="store_true", help="velocity Verlet instead of Shardlow")
    ap.add_argument("--boundary", choices=["slip", "stick"], default="slip",
                    help="setup_suspension's colloid surface (slip: seed 004's colloid; stick: section 7c/7d)")
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--solvent-count", choices=["exact", "bulk"], default=None,
                    help="default: exact for slip, setup_suspension's bulk for stick; exact: rho x free volume beads (the colloids' adsorbed shells then deplete the "
                         "solvent between them, doc/suspensions.md 7e); bulk: plus the ~4 beads per colloid "
                         "they adsorb, so the bulk solvent is at rho")
    ap.add_argument("--no-lubrication", action="store_true",
                    help="without seed 004's squeeze lubrication kernel (the resolved solvent carries the "
                         "near field of stick colloids: doc/suspensions.md section 7g)")
    dpd = ap.add_mutually_exclusive_group()
    dpd.add_argument("--no-colloid-dpd", dest="colloid_dpd", action="store_false", default=None,
                     help="without seed 004's colloid-colloid DPD (the default for stick)")
    dpd.add_argument("--colloid-dpd", dest="colloid_dpd", action="store_true",
                     help="with seed 004's colloid-colloid DPD (the default for slip)")
    ap.add_argument("--h-cut", type=float, default=None,
                    help="the lubrication kernel's range on the core gap (default setup_suspension's: 1.0 = r_c "
                         "for slip and the plain form, 0.15 for stick's shifted form, doc/suspensions.md 7g/7i)")
    ap.add_argument("--shared", choices=sus.STICK_SHARED_MODES, default=None,
                    help="stick only: the friction of a bead in two colloids' shells (setup_suspension's "
                         "shared; default off, full before session 36; doc/suspensions.md 7c, 7t, 7u)")
    ap.add_argument("--lubrication-form", choices=["plain", "shifted"], default=None,
                    help="the lubrication kernel's form (default setup_suspension's: plain for slip, shifted, "
                         "i.e. zero at h_cut, for stick)")
    ap.add_argument("--eta0", type=float, nargs=2, metavar=("ETA0", "ERR"),
                    help="use this solvent viscosity and error instead of measuring it")
    ap.add_argument("--mass-scale", type=float, default=1.0,
                    help="multiply every particle's mass and rotational inertia by this (default 1: unchanged); "
                         "Re = 3 M rate R^2/eta_0(M), doc/suspensions.md 7l")
    ap.add_argument("--json", help="append the results (a JSON line) to this file")
    args = ap.parse_args()
    if args.shared is not None and args.boundary != "stick":
        ap.error("--shared applies to --boundary stick only")
    if args.dt is None:
        args.dt = 0.005 if args.vv else 0.01
    if os.environ.get("MARBLE_SAMPLE_TEST"):
        args.box, args.time = [6.0, 6.0, 6.0], 2.0
    results = {}
    # the solvent reference first, unless given or the scene is the solvent itself
    runs = (args.phi,) if args.eta0 or args.phi == 0 else (0.0, args.phi)
    if args.eta0:
        results[0.0] = tuple(args.eta0)
    for phi in runs:
        s, info = scene(phi, args.box, args.dt, seed=args.seed, boundary=args.boundary, shardlow=not args.vv,
                        solvent_count=args.solvent_count, lubrication=not args.no_lubrication,
                        colloid_dpd=args.colloid_dpd, h_cut=args.h_cut, lubrication_form=args.lubrication_form,
                        mass_scale=args.mass_scale, shared=args.shared, equil=2.0 if os.environ.get("MARBLE_SAMPLE_TEST") else 10.0)
        eta, err, slope, slope_err, kt = measure(
            s, args.rate, args.time, equil=1.0 if os.environ.get("MARBLE_SAMPLE_TEST") else 10.0)
        results[phi] = (eta, err)
        if marble.mpi_rank() != 0:  # (under mpiexec every rank has the same numbers)
            continue
        print(f"phi = {phi:.3f} ({info.get('n_colloids', 0)} colloids): eta = {eta:.4f} +/- {err:.4f}, "
              f"profile slope {slope:.4f} +/- {slope_err:.4f} (imposed {args.rate}), kT {kt:.4f}")
        if args.json:
            import json
            extra = {} if args.mass_scale == 1.0 else dict(mass_scale=args.mass_scale)
            if phi and args.boundary == "stick":  # (lines without it: "full", the default before session 36)
                extra["shared"] = info["shared"]
            if marble.mpi_size() > 1:  # (cpu_s is rank 0's)
                extra["ranks"] = marble.mpi_size()
            with open(args.json, "a") as f:
                f.write(json.dumps(dict(**extra, phi=info.get("phi", 0.0), phi_nominal=phi, boundary=args.boundary if phi else "solvent",
                                        n_colloids=info.get("n_colloids", 0), box=list(args.box), rate=args.rate,
                                        time=args.time, dt=args.dt,
                                        integrator="vv" if args.vv else "shardlow", seed=args.seed, eta=eta, eta_err=err,
                                        solvent_count=info["solvent_count"] if phi else "exact",
                                        lubrication=info["lubrication"] if phi else None,
                                        colloid_dpd=info["colloid_dpd"] if phi else None,
                                        h_cut=info["h_cut"] if phi and info["lubrication"] else None,
                                        lubrication_form=info["lubrication_form"] if phi else None,
                                        n_solvent=len(info["solvent_ids"]) if phi else None,
                                        cpu_s=time.process_time(), slope=slope, slope_err=slope_err, kT=kt)) + "\n")
    if args.phi == 0:
        return
    (e0, s0), (e1, s1) = results[0.0], results[args.phi]
    er = e1 / e0
    if marble.mpi_rank() == 0:
        ph = args.phi
        print(f"eta_r({ph}) = {er:.3f} +/- {abs(er) * np.hypot(s0 / e0, s1 / e1):.3f} "
              f"(Batchelor 1 + 2.5 phi + 6.2 phi^2 = {theory.batchelor_viscosity(ph):.3f}, "
              f"Krieger-Dougherty phi_m 0.63 = {theory.krieger_dougherty_viscosity(ph):.3f}, hard spheres "
              f"(de Kruif et al. 1985) at low shear {theory.quemada_viscosity(ph, 0.63):.3f}, "
              f"at high shear {theory.quemada_viscosity(ph, 0.71):.3f}; doc/suspensions.md 7s)")


if __name__ == "__main__":
    main()
