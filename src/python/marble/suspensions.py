"""Core-modified DPD colloid suspensions (seed 004; doc/suspensions.md).

Colloids are single DPD particles of radius R in a DPD solvent; every
colloid interaction acts on the surface gap h = r - (a_i + a_j):

- solvent-solvent: hat (a_ss = 25 kT/r_c) + DPD, cutoff r_c;
- colloid-solvent: hat and DPD with offset R and the equal-volume surface
  cutoff r'_c = (r_c^3 + R^3)^(1/3) - R;
- colloid-colloid: contact force, squeeze lubrication (FDT-consistent noise),
  optional Morse attraction, and DPD on the gap (cutoff r_c);
- boundary="stick" (not seed 004): rotating colloids and the tangential
  surface_friction kernel on the colloid-solvent pair (no-slip spheres); by
  default the given radius is the colloid's HYDRODYNAMIC radius, the core
  radius being radius / STICK_RADIUS_RATIO (doc/suspensions.md section 7d).

    import marble, marble.suspensions as sus
    s = marble.System(box_l=[12.0] * 3)
    s.time_step = 0.001
    info = sus.setup_suspension(s, phi=0.1, radius=1.0, kT=0.1, gamma=4.5, eta=0.3, seed=1)
"""
import math

import numpy as np

from .code_features import assert_features

#: Random close packing of monodisperse spheres: no random placement above it.
PHI_RCP = 0.64

#: Hydrodynamic radius / core radius of setup_suspension's stick colloid
#: (boundary="stick", trans_gamma = 45, friction shell r'_c, seed 004's solvent:
#: rho = 3, kT = 0.1, gamma = 4.5, a_ss = 25 kT, r_c = 1; core radius ~1), measured by
#: the drag of one colloid in a periodic box against Hasimoto's stick D(L)
#: (doc/suspensions.md section 7d; error STICK_RADIUS_RATIO_ERR).
STICK_RADIUS_RATIO = 1.013
STICK_RADIUS_RATIO_ERR = 0.010

#: Rotational radius / core radius of the same stick colloid: R_r = (zeta_r /
#: (8 pi eta_0))^(1/3) from its rotational friction under a constant torque,
#: box-corrected (doc/suspensions.md section 7m; error STICK_ROTATIONAL_RADIUS_RATIO_ERR).
#: It is 5 % above the drag radius: the colloid is not one no-slip sphere.
STICK_ROTATIONAL_RADIUS_RATIO = 1.0623
STICK_ROTATIONAL_RADIUS_RATIO_ERR = 0.0035

#: Strain (stresslet) radius / core radius of the same stick colloid: R_s from the
#: stresslet S = (20/3) pi eta R_s^3 rate/2 of one colloid in uniform shear (Lees-Edwards,
#: the whole box's shear stress against the solvent alone, the periodic lattice's
#: factor included), extrapolated to rate 0 with S0 + b rate^2 over rates 0.05, 0.1
#: and 0.2 (doc/suspensions.md section 7p; error STICK_STRESSLET_RADIUS_RATIO_ERR, the
#: fit's; the rate^1.5 fit gives 0.5 % less; 68 runs, session 20). The radius of
#: Einstein's viscosity 1 + 2.5 phi: 1.9 % above the drag radius (2.8 sigma) and 2.8 %
#: below the rotational radius (3.8 sigma, which it excludes).
STICK_STRESSLET_RADIUS_RATIO = 1.032
STICK_STRESSLET_RADIUS_RATIO_ERR = 0.008

# radius / core radius of each named stick calibration (setup_suspension's radius_calibration)
_STICK_CALIBRATIONS = {"stick": STICK_RADIUS_RATIO, "rotation": STICK_ROTATIONAL_RADIUS_RATIO,
                       "stresslet": STICK_STRESSLET_RADIUS_RATIO}

#: Solvent beads adsorbed per unit core area (beads within 1.0 of a core surface in
#: excess of the bulk density), measured for seed 004's conservative forces
#: (rho = 3, a_ss = 25 kT/r_c, r_c = 1, the mean-field colloid-solvent hat; core
#: radius 0.987): 4.3 beads around one colloid, 4.0 per colloid at phi = 0.1, 3.8
#: at 0.2 (doc/suspensions.md section 7e). The dilute value 4.0 / (4 pi 0.987^2).
#: Only the conservative forces set it (the DPD, lubrication and surface
#: friction are dissipative and leave the equilibrium structure alone).
ADSORBED_PER_AREA = 4.0 / (4.0 * math.pi * 0.987 ** 2)

#: setup_suspension's default squeeze-lubrication range for boundary="stick" (on the
#: core gap, in units of the solvent's r_c = 1; the kernel's form="shifted", so the
#: friction goes to zero there). The resolved solvent of two stick colloids gives the
#: exact two-sphere squeeze resistance down to a hydrodynamic gap ~0.1 (core gap 0.126)
#: and only 0.79 +/- 0.05 of it in the bin 0.05-0.1 below (doc/suspensions.md 7g); the
#: shifted kernel with h_cut = 0.15 supplies 1.5 of the missing 1.95 +/- 0.45 there
#: and adds only 2 % in the resolved bin 0.1-0.15 (section 7i).
STICK_LUBRICATION_H_CUT = 0.15
#: setup_suspension's treatment of a solvent bead inside the friction shells of
#: several stick colloids (doc/suspensions.md 7t-7v; "full" before session 36)
STICK_SHARED_DEFAULT = "off"
#: the values of ``shared`` (the surface_friction kernel's option)
STICK_SHARED_MODES = ("full", "split", "off")


def radius_calibration_arg(text):
    """A command line's ``--radius-calibration`` for setup_suspension: a named
    calibration ("none", "stick", "rotation", "stresslet") as it is, anything else
    as a number (ValueError naming radius_calibration if it is neither)."""
    if text in ("none", *_STICK_CALIBRATIONS):
        return text
    try:
        return float(text)
    except (TypeError, ValueError):
        raise _bad_radius_calibration(text) from None


def _bad_radius_calibration(value):
    return ValueError("parameter 'radius_calibration' must be 'none', "
                      f"{', '.join(repr(k) for k in _STICK_CALIBRATIONS)} or a ratio > 0, got {value!r}")


def equal_volume_cutoff(R, r_cut=1.0):
    """Centre-centre colloid-solvent cutoff (r_c^3 + R^3)^(1/3): the shell
    R < r < cutoff has the volume of a solvent bead's sphere of radius r_c (seed 004)."""
    _positive("R", R, allow_zero=True)
    _positive("r_cut", r_cut)
    return (r_cut ** 3 + R ** 3) ** (1.0 / 3.0)


def surface_cutoff(R, r_cut=1.0):
    """The same cutoff measured from the colloid surface: (r_c^3 + R^3)^(1/3) - R."""
    return equal_volume_cutoff(R, r_cut) - R


def _hat_shell_integral(R, rc):
    """int_R^{R+rc} (rc - (r - R))^2 r^2 dr (closed form)."""
    c = R + rc
    return c * c * rc ** 3 / 3.0 - c * rc ** 4 / 2.0 + rc ** 5 / 5.0


def colloid_solvent_repulsion(R, a_ss=25.0, r_cut=1.0, rule="mean_field", shell=None):
    """F_max of the colloid-solvent hat on the gap (cutoff ``shell``, default
    surface_cutoff(R)).

    rule="seed": seed 004's 25 kT / r'_c (a_ss / r'_c; 96 at R = 1, 683 at R = 3);
    rule="mean_field" (default): the F_max for which a solvent bead's mean-field
    interaction integral int U dV over the colloid's shell equals that over a
    solvent bead's sphere, int U_ss dV = pi a_ss r_c^4 / 15 (doc/suspensions.md;
    32.6 at R = 1, 95.5 at R = 2, 206 at R = 3 for a_ss = 25). For a ``shell``
    other than the equal-volume one, both rules use that shell in place of r'_c."""
    _positive("R", R, allow_zero=True)
    rp = surface_cutoff(R, r_cut) if shell is None else _positive("shell", shell)
    if rule == "seed":
        return a_ss * r_cut / rp
    if rule != "mean_field":
        raise ValueError(f"parameter 'rule' must be 'mean_field' or 'seed', got {rule!r}")
    return a_ss * (_hat_shell_integral(0.0, r_cut) / r_cut) / (_hat_shell_integral(R, rp) / rp)


def stokes_einstein_D(R, eta, kT):
    """D = kT / (6 pi eta R)."""
    _positive("R", R)
    _positive("eta", eta)
    _positive("kT", kT)
    return kT / (6.0 * math.pi * eta * R)


def diffusion_time(R, eta, kT):
    """tau_D = R^2 / D = 6 pi eta R^3 / kT (seed 004 writes "D = tau": they are not
    the same quantity; 56.5 for R = 1, eta = 0.3, kT = 0.1)."""
    return R * R / stokes_einstein_D(R, eta, kT)


def _positive(name, x, allow_zero=False):
    try:
        x = float(x)
    except (TypeError, ValueError):
        raise ValueError(f"parameter '{name}' must be a number, got {x!r}") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        raise ValueError(f"parameter '{name}' must be a finite number {'>=' if allow_zero else '>'} 0, "
                         f"got {x}")
    return x


def _min_image(d, L):
    return d - L * np.round(d / L)


#: Random sequential addition is used up to this volume fraction of the spheres of
#: diameter 2R + min_gap; denser scenes are compressed (place_colloids)
PHI_RSA = 0.33
#: The densest scene place_colloids builds (a fluid: hard spheres freeze at 0.494,
#: coexist with the crystal up to 0.545; beyond, the compression stalls near a glass)
PHI_PLACE_MAX = 0.55
#: Dense scenes of up to this many colloids are compressed by Monte Carlo (one move
#: at a time, slow for many colloids); larger ones by overlap removal
PLACE_MC_MAX_N = 150


def place_colloids(L, n, radius, rng, min_gap=0.0, max_tries=200000, max_sweeps=20000):
    """n non-overlapping spheres in the periodic box L (no two centres closer than
    2R + min_gap), at random.

    Up to a volume fraction PHI_RSA = 0.33 of the spheres of diameter 2R + min_gap:
    random sequential addition (the scenes of every earlier version, bit for bit).
    Above it, where addition slows and then jams (near 0.38), addition of smaller
    spheres at 0.3, then:

    - n <= PLACE_MC_MAX_N = 150: a hard-sphere Monte Carlo compression: sweeps of
      random single-sphere moves that keep every centre distance above the current
      diameter, which after each sweep grows to the smallest centre distance (never
      above the target), until it reaches 2R + min_gap (~3 s for 108 colloids);
    - more colloids: overlap removal: the spheres take the target diameter at once
      and every overlapping pair is pushed apart along its line of centres (each
      sphere by half the overlap plus 1e-3 of the diameter), all pairs at once,
      until none overlaps (pairs by scipy's periodic k-d tree; ~1 s for 1000
      colloids at 0.45).

    The result is a random, amorphous packing of the target spheres (not an
    equilibrated fluid: run the system at rest for a while before measuring); up to
    PHI_PLACE_MAX = 0.55."""
    L = np.asarray(L, float)
    V = float(np.prod(L))
    d_target = 2.0 * radius + min_gap
    phi_d = n * math.pi / 6.0 * d_target ** 3 / V
    if phi_d <= PHI_RSA:
        return _place_rsa(L, n, d_target, rng, max_tries)
    if phi_d > PHI_PLACE_MAX:
        raise ValueError(f"parameter 'phi': {n} spheres of diameter 2R + gap = {d_target:.4g} fill "
                         f"{phi_d:.3f} of the box; place_colloids builds random scenes up to "
                         f"{PHI_PLACE_MAX} (place denser ones yourself: positions=...)")
    d = d_target * (0.3 / phi_d) ** (1.0 / 3.0)
    pos = _place_rsa(L, n, d, rng, max_tries)
    if n > PLACE_MC_MAX_N:
        return _remove_overlaps(L, pos, d_target, rng, max_sweeps)
    step = 0.5 * d

    def min_dist(i, x):
        r = np.linalg.norm(_min_image(np.delete(pos, i, axis=0) - x, L), axis=1)
        return r.min()

    def all_min():
        dd = _min_image(pos[:, None, :] - pos[None, :, :], L)
        r = np.linalg.norm(dd, axis=2)
        r[np.diag_indices(n)] = np.inf
        return r.min()

    for _ in range(max_sweeps):
        accepted = 0
        for i in rng.permutation(n):
            x = np.mod(pos[i] + rng.uniform(-step, step, 3), L)
            if min_dist(i, x) >= d:
                pos[i] = x
                accepted += 1
        d = min(d_target, all_min())
        if d >= d_target:
            return pos
        # keep about a third of the moves accepted
        step = float(np.clip(step * (1.2 if accepted > 0.4 * n else 0.8), 1e-4 * d_target, 0.5 * d_target))
    raise ValueError(f"parameter 'phi': the compression reached only diameter {d:.4g} of "
                     f"{d_target:.4g} in {max_sweeps} sweeps; place the colloids yourself (positions=...)")


def _remove_overlaps(L, pos, d, rng, max_iter):
    """Push the spheres of diameter d at ``pos`` apart until no two centres are
    closer than d (place_colloids)."""
    from scipy.spatial import cKDTree

    def wrap(p):
        p = np.mod(p, L)
        return np.where(p >= L, p - L, p)  # np.mod may round up to L

    pos = wrap(pos)
    for _ in range(max_iter):
        pairs = cKDTree(pos, boxsize=L).query_pairs(d, output_type="ndarray")
        if len(pairs) == 0:
            return pos
        i, j = pairs[:, 0], pairs[:, 1]
        dv = _min_image(pos[i] - pos[j], L)
        r = np.linalg.norm(dv, axis=1)
        same = r < 1e-12 * d
        if np.any(same):  # coincident centres: a random direction
            dv[same] = rng.normal(size=(int(same.sum()), 3))
            r[same] = np.linalg.norm(dv[same], axis=1)
        push = (0.5 * (d - np.where(same, 0.0, r)) + 1e-3 * d)[:, None] * dv / r[:, None]
        np.add.at(pos, i, push)
        np.add.at(pos, j, -push)
        pos = wrap(pos)
    raise ValueError(f"parameter 'phi': overlaps remain after {max_iter} rounds of overlap removal; "
                     "place the colloids yourself (positions=...)")


def _place_rsa(L, n, d, rng, max_tries):
    """Random sequential addition of n centres at least d apart."""
    pos = np.empty((0, 3))
    tries = 0
    while len(pos) < n:
        tries += 1
        if tries > max_tries:
            raise ValueError(
                f"parameter 'phi': could place only {len(pos)} of {n} colloids without overlap by "
                "random sequential addition (jams near phi = 0.38); place them yourself "
                "(positions=...) or compress a dilute suspension")
        x = rng.uniform(0, 1, size=3) * L
        if len(pos) and np.min(np.linalg.norm(_min_image(pos - x, L), axis=1)) < d:
            continue
        pos = np.vstack([pos, x])
    return pos


def setup_suspension(system, phi, radius, density=3.0, kT=0.1, gamma=4.5, eta=0.3, seed=None,
                     r_cut=1.0, a_ss=None, a_cs=None, a_cs_rule="mean_field",
                     f_contact=None, delta=0.001, lubrication=True, h_cut=None, h_min=0.001,
                     log_term="off", morse=None, colloid_dpd=None,
                     solvent_type=0, colloid_type=1, colloid_mass=None, positions=None,
                     boundary="slip", trans_gamma=None, rinertia=None, shared=None, stick_shell=None,
                     radius_calibration=None, solvent_count=None, adsorbed=None, lubrication_form=None,
                     cs_shell=None):
    """Fill ``system`` (empty) with a colloid suspension at volume fraction ``phi``.

    - Colloids: N = round(phi V / (4/3 pi R^3)), placed at random without
      overlap (place_colloids: random sequential addition, or above a volume
      fraction 0.33 of the spheres of diameter 2R + delta a compression or an
      overlap removal, up to 0.55) or at ``positions``, mass ``density (4/3) pi R^3``
      (seed 004).
    - Solvent: ``density`` beads per unit volume outside the colloid cores
      (beads drawn uniformly over the box, those inside a core removed).
      ``solvent_count`` (default None: ``"poisson"`` for "slip", ``"bulk"`` for
      "stick"): ``"poisson"`` (seed 004's scenes bit for bit):
      a Poisson number of draws with mean ``density V``, so the solvent density of
      a small box scatters between seeds (+/- 6 % for one colloid in L = 4.4,
      +/- 2.6 % in 7 x 7 x 10), and with it the viscosity; ``"exact"``:
      exactly round(density x free volume) beads (doc/suspensions.md section 7d);
      ``"bulk"``: the exact count plus ``adsorbed`` beads per colloid, so that
      the solvent between the colloids (farther than 1 from every core) is at
      ``density`` once the colloids have adsorbed their shells (about 4 beads
      each; with "exact" the bulk is depleted to 2.78 at phi = 0.2, section 7e).
      ``adsorbed`` defaults to ADSORBED_PER_AREA x 4 pi a^2 (a the core radius;
      4.00 at a = 0.987), measured for seed 004's conservative forces at a ~ 1
      (a flatter surface adsorbs more: 0.42 per unit area at a = 2 with the
      R = 1 shell, doc/suspensions.md 7q); with
      another density, a_ss, a_cs, a_cs_rule or r_cut give ``adsorbed``
      yourself (measure it with ``solvent_structure``), or pass
      ``solvent_count="exact"`` (the stick default "bulk" needs it too).
    - Interactions (module doc): a_ss = 25 kT/r_c, the colloid-solvent hat
      F_max from ``colloid_solvent_repulsion(R, a_ss, r_c, a_cs_rule)`` unless
      ``a_cs`` is given; the colloid-solvent hat and DPD act on the gap up to
      ``cs_shell`` (default None: the equal-volume surface cutoff r'_c(a) of
      seed 004; a given shell is also the rule's shell and the stick friction
      shell unless ``stick_shell`` is given: e.g. the shell of an R = 1 colloid
      on a larger one, so that the surface is the same in the solvent's units,
      doc/suspensions.md 7q); contact (f_contact = 1e4 kT/r_c, delta), lubrication
      (eta, h_cut, h_min, log_term, ``lubrication_form`` the kernel's form),
      ``morse`` a dict of the Morse kernel's eps, alpha, rmin, cutoff (offset 2R
      added), DPD with ``gamma`` on the solvent-solvent and colloid-solvent pairs
      and, with ``colloid_dpd``, on the colloid-colloid pairs.
    - Defaults that depend on ``boundary`` (None = the boundary's default; an
      explicit value always wins):

      ============================  =====================  =================================
      parameter                     "slip" (seed 004)      "stick"
      ============================  =====================  =================================
      ``lubrication_form``          ``"plain"``            ``"shifted"``
      ``h_cut`` (core gap)          ``r_cut``              ``r_cut`` if the form is "plain",
                                                           else STICK_LUBRICATION_H_CUT (0.15)
      ``colloid_dpd``               True                   False
      ``solvent_count``             ``"poisson"``          ``"bulk"``
      ============================  =====================  =================================

      The stick colloid's resolved solvent carries the squeeze resistance of a pair
      down to a hydrodynamic gap ~0.1 (doc/suspensions.md 7g), so seed 004's plain
      kernel to h_cut = r_c and its colloid-colloid DPD count it twice; the shifted
      kernel supplies only the part the solvent misses below h_cut (section 7i).
      ``boundary="stick", lubrication_form="plain", colloid_dpd=True,
      solvent_count="poisson"`` is the stick suspension of sections 7c-7h (before
      these defaults) bit for bit.
    - ``boundary``: ``"slip"`` (default, seed 004 unchanged: the colloid-solvent
      friction is central, so the colloids are slipping spheres, doc/suspensions.md
      section 7b) or ``"stick"``: the colloids rotate (moment of inertia
      ``rinertia``, default the uniform sphere's 2/5 M R^2, spins drawn at kT) and
      the colloid-solvent pair gets the ``surface_friction`` kernel (tangential
      friction ``trans_gamma``, default 45, on the same shell, relative velocity of
      the colloid's rigid-body motion at the bead, torques on the colloid; needs
      TRANS_DPD and ROTATION): no-slip spheres of radius R (section 7c).
      ``shared`` (stick only): the kernel's treatment of a bead inside the
      friction shells of several colloids: ``"off"`` (default since session 36:
      no friction with any of them), ``"split"`` (gamma/n with each of n) or
      ``"full"`` (gamma with each, the default before). With ``"off"`` the
      suspension meets Batchelor at phi = 0.05 and 0.1 within 4 % and
      Krieger-Dougherty at phi = 0.2 and 0.3 within 10 %, and shear-thins; with
      ``"full"`` it is 32 % more viscous than Krieger-Dougherty at phi = 0.3 (the
      two agree at phi = 0.1). Driven at a fixed gap, a close pair slides as two
      no-slip spheres within 8 % with ``"full"`` at every gap, with ``"off"`` 8 %
      below them at h = 0.1: ``"full"`` is the more faithful pair near contact
      (doc/suspensions.md 7t-7v).
      A single colloid is the same in every mode; pass ``shared="full"`` to
      reproduce the numbers of sections 7c-7s.
      ``stick_shell`` (stick only): the shell's thickness on the gap (default
      the colloid-solvent DPD cutoff r'_c).
    - ``radius_calibration`` (which radius ``radius`` is): ``"none"`` (the
      default for "slip", seed 004): the core radius a = radius; ``"stick"`` (the
      default for "stick"): ``radius`` is the hydrodynamic (no-slip) radius and the
      core radius is a = radius / STICK_RADIUS_RATIO (1.013 +/- 0.010, measured
      by the drag of one stick colloid, doc/suspensions.md section 7d);
      ``"rotation"`` (stick only): ``radius`` is the rotational radius and
      a = radius / STICK_ROTATIONAL_RADIUS_RATIO (1.0623 +/- 0.0035, section 7m);
      ``"stresslet"`` (stick only): ``radius`` is the strain radius, that of the
      stresslet of one colloid in shear (the radius in Einstein's 1 + 2.5 phi),
      and a = radius / STICK_STRESSLET_RADIUS_RATIO (1.032 +/- 0.008, section 7p):
      the choice for viscosity work (it lies between the drag and the rotational
      radius); or a number c > 0 (your own measured ratio): a = radius / c. Everything of the
      colloid is then built on the core a: the offsets of the colloid-solvent
      hat, DPD and surface friction, the equal-volume surface cutoff r'_c(a)
      (also the friction shell), the solvent removed from r < a, the mass
      ``density (4/3) pi a^3``, the inertia 2/5 M a^2, and the colloid-colloid
      contact, lubrication, DPD and Morse on the core gap r - 2a. The number of
      colloids is N = round(phi V / (4/3 pi radius^3)) and random placement
      keeps the spheres of radius ``radius`` apart, so ``phi`` is the
      hydrodynamic volume fraction; ``positions`` may come as close as 2a. The
      ratio was measured at the seed's settings and a ~ 1 only (another
      trans_gamma, stick_shell or solvent needs its own: bench/suspension_hasimoto.py).
      "none" with "stick" reproduces the uncalibrated colloid bit for bit. The
      drag correction is small (one colloid's drag radius is its core radius
      within ~1 %), but its rotational radius is 5 % larger (section 7m) and its
      strain radius ~2 % larger (section 7p); spheres of the strain radius account
      for about 40 % of the suspension's viscosity excess over Krieger-Dougherty at
      phi = 0.3 (those of the rotational radius would for 87 %). Compare viscosities with an
      eta_0 measured at the same solvent density (``solvent_count="exact"``).
    - The DPD thermostat at ``kT`` with ``seed``.

    The random solvent carries hat energy (about 8 kT per bead at kT = 0.1):
    equilibrate a few time units before measuring (doc/suspensions.md).
    The velocities are drawn at kT without zeroing the total momentum: remove
    the mass-weighted mean velocity before a flow measurement (under
    Lees-Edwards a net momentum normal to the shear plane biases the viscosity:
    doc/lees-edwards.md, doc/suspensions.md section 7k).

    Every parameter is checked before anything changes (ValueError naming
    it). Returns a dict of what was set (counts, cutoffs, parameters, ids;
    ``radius`` the given radius, ``core_radius`` a, ``radius_ratio`` radius/a,
    ``phi`` the volume fraction of spheres of the given radius and ``phi_core``
    that of the cores; ``hydrodynamic_radius`` and ``phi_hydrodynamic`` for
    "stick": a x STICK_RADIUS_RATIO for "stick", "none", "rotation" and "stresslet", a x c
    for your c; ``rotational_radius`` and ``phi_rotational`` for "stick": a x
    STICK_ROTATIONAL_RADIUS_RATIO; ``stresslet_radius`` and ``phi_stresslet`` for "stick":
    a x STICK_STRESSLET_RADIUS_RATIO;
    the effective ``solvent_count``, ``h_cut``, ``lubrication``, ``lubrication_form``
    and ``colloid_dpd`` after the boundary's defaults).
    Colloid-colloid pairs (range 2R + h_cut) go through the main Verlet list
    but the colloids get their own coarse cell grid (``system.cell_system.
    large_range_types``, "auto" by default), so the solvent's cells keep the
    solvent's range (doc/architecture.md, "Two cell grids").
    """
    if boundary not in ("slip", "stick"):
        raise ValueError(f"parameter 'boundary' must be 'slip' or 'stick', got {boundary!r}")
    if boundary == "slip" and any(x is not None for x in (trans_gamma, rinertia, shared, stick_shell)):
        raise ValueError("parameters 'trans_gamma', 'rinertia', 'shared' and 'stick_shell' apply to "
                         "boundary='stick' only")
    stick_default = boundary == "stick"
    if lubrication_form is None:
        lubrication_form = "shifted" if stick_default else "plain"
    if lubrication_form not in ("plain", "shifted"):
        raise ValueError(f"parameter 'lubrication_form' must be 'plain' or 'shifted', got {lubrication_form!r}")
    if colloid_dpd is None:
        colloid_dpd = not stick_default
    if solvent_count is None:
        solvent_count = "bulk" if stick_default else "poisson"
    if h_cut is None:
        h_cut = STICK_LUBRICATION_H_CUT if (stick_default and lubrication_form == "shifted") else r_cut
    if boundary == "stick":
        trans_gamma = 45.0 if trans_gamma is None else _positive("trans_gamma", trans_gamma, allow_zero=True)
        shared = STICK_SHARED_DEFAULT if shared is None else shared
        if shared not in STICK_SHARED_MODES:
            raise ValueError(f"parameter 'shared' must be 'full', 'split' or 'off', got {shared!r}")
        if stick_shell is not None:
            stick_shell = _positive("stick_shell", stick_shell)
    assert_features("DPD", "HAT", "CONTACT", "MASS")
    if boundary == "stick":
        assert_features("TRANS_DPD", "ROTATION")
    if lubrication:
        assert_features("LUBRICATION")
    if morse:
        assert_features("MORSE")
    phi = _positive("phi", phi)
    if phi > PHI_RCP:
        raise ValueError(f"parameter 'phi' must be <= {PHI_RCP} (random close packing), got {phi}")
    R_user = _positive("radius", radius)
    if radius_calibration is None:
        radius_calibration = "stick" if boundary == "stick" else "none"
    if radius_calibration == "none":
        ratio = 1.0
    elif isinstance(radius_calibration, str) and radius_calibration in _STICK_CALIBRATIONS:
        if boundary != "stick":
            raise ValueError(f"parameter 'radius_calibration': {radius_calibration!r} applies to "
                             "boundary='stick' only (use 'none' or your own ratio)")
        ratio = _STICK_CALIBRATIONS[radius_calibration]
    elif isinstance(radius_calibration, str):
        raise _bad_radius_calibration(radius_calibration)
    else:
        ratio = _positive("radius_calibration", radius_calibration)
    # the core radius: every colloid interaction, the solvent removal and the mass use it
    R = R_user / ratio if ratio != 1.0 else R_user
    density = _positive("density", density)
    kT = _positive("kT", kT, allow_zero=True)
    gamma = _positive("gamma", gamma, allow_zero=True)
    r_cut = _positive("r_cut", r_cut)
    delta = _positive("delta", delta)
    h_min = _positive("h_min", h_min)
    h_cut = _positive("h_cut", h_cut)
    if lubrication:
        if eta is None:
            raise ValueError("parameter 'eta' (the solvent viscosity) is required for lubrication")
        eta = _positive("eta", eta)
        if not h_min < h_cut:
            raise ValueError(f"parameter 'h_min' must be below h_cut = {h_cut}, got {h_min}")
    if log_term not in ("off", "on"):
        raise ValueError(f"parameter 'log_term' must be 'off' or 'on', got {log_term!r}")
    a_ss = 25.0 * kT / r_cut if a_ss is None else _positive("a_ss", a_ss, allow_zero=True)
    if cs_shell is not None:
        cs_shell = _positive("cs_shell", cs_shell)
    a_cs_given = a_cs is not None
    if a_cs is None:
        a_cs = colloid_solvent_repulsion(R, a_ss, r_cut, a_cs_rule, shell=cs_shell)
    a_cs = _positive("a_cs", a_cs, allow_zero=True)
    f_contact = 1e4 * kT / r_cut if f_contact is None else _positive("f_contact", f_contact)
    if seed is None or int(seed) != seed or seed < 0:
        raise ValueError(f"parameter 'seed' must be an integer >= 0, got {seed!r}")
    if solvent_type == colloid_type:
        raise ValueError("parameters 'solvent_type' and 'colloid_type' must differ")
    if len(system.part.all()):
        raise ValueError("setup_suspension needs an empty system (it places all particles)")
    L = np.asarray(system.box_l, float)
    V = float(np.prod(L))
    if np.min(L) <= 2 * R + max(h_cut, r_cut, delta):
        # a colloid would interact with its own periodic image (boxes smaller than
        # twice the colloid pair range are fine: several images of a pair interact,
        # which the pair list handles; doc/architecture.md, "Two cell grids")
        raise ValueError(f"the box (smallest edge {np.min(L)}) must exceed the colloid pair "
                         f"range 2R + cutoff = {2 * R + max(h_cut, r_cut, delta)}")
    rng = np.random.default_rng(int(seed))
    v_col = 4.0 / 3.0 * math.pi * R ** 3  # the core's volume
    v_user = 4.0 / 3.0 * math.pi * R_user ** 3  # the volume of a sphere of the given radius
    if positions is not None:
        cpos = np.asarray(positions, float)
        if cpos.ndim != 2 or cpos.shape[1] != 3 or not np.all(np.isfinite(cpos)):
            raise ValueError("parameter 'positions' must be an (N, 3) array of finite numbers")
        for i in range(len(cpos)):
            d = np.linalg.norm(_min_image(cpos[i + 1:] - cpos[i], L), axis=1)
            if np.any(d < 2 * R):
                j = i + 1 + int(np.argmin(d))
                raise ValueError(f"parameter 'positions': colloids {i} and {j} overlap "
                                 f"(distance {d.min():.4g} < 2R = {2 * R})")
        n_col = len(cpos)
    else:
        n_col = int(round(phi * V / v_user))
        if n_col < 1:
            raise ValueError(f"parameter 'phi': {phi} gives no colloid of radius {R_user} in volume {V:.4g}")
        cpos = place_colloids(L, n_col, R_user, rng, min_gap=delta)
    m_col = density * v_col if colloid_mass is None else _positive("colloid_mass", colloid_mass)
    if boundary == "stick":
        rinertia = 0.4 * m_col * R * R if rinertia is None else _positive("rinertia", rinertia)
    # solvent outside the cores
    if solvent_count not in ("poisson", "exact", "bulk"):
        raise ValueError(f"parameter 'solvent_count' must be 'poisson', 'exact' or 'bulk', got {solvent_count!r}")
    n_adsorbed = 0
    if solvent_count == "bulk":
        if adsorbed is None:
            if (density != 3.0 or a_ss != 25.0 * kT / r_cut or r_cut != 1.0 or a_cs_given
                    or a_cs_rule != "mean_field" or cs_shell is not None):
                raise ValueError("parameter 'adsorbed' (beads adsorbed per colloid) is required for "
                                 "solvent_count='bulk' unless the solvent is seed 004's (density 3, "
                                 "a_ss = 25 kT/r_c, r_c = 1, the mean-field colloid-solvent hat on the "
                                 "equal-volume shell, no cs_shell): measure it "
                                 "with marble.suspensions.solvent_structure, or pass solvent_count='exact'")
            adsorbed = ADSORBED_PER_AREA * 4.0 * math.pi * R * R
        adsorbed = _positive("adsorbed", adsorbed, allow_zero=True)
        n_adsorbed = int(round(adsorbed * n_col))
    elif adsorbed is not None:
        raise ValueError("parameter 'adsorbed' applies to solvent_count='bulk' only")

    def outside_cores(n_try):
        x = rng.uniform(0, 1, size=(n_try, 3)) * L
        keep = np.ones(n_try, bool)
        for c in cpos:
            keep &= np.linalg.norm(_min_image(x - c, L), axis=1) >= R
        return x[keep]

    if solvent_count == "poisson":
        spos = outside_cores(int(rng.poisson(density * V)))
    else:
        v_free = V - n_col * v_col  # the cores do not overlap
        n_want = int(round(density * v_free)) + n_adsorbed
        spos = np.empty((0, 3))
        while len(spos) < n_want:
            spos = np.vstack([spos, outside_cores(int(1.1 * (n_want - len(spos)) * V / v_free) + 16)])
        spos = spos[:n_want]

    # everything checked: now change the system
    sigma_v = math.sqrt(kT) if kT > 0 else 0.0
    col = system.part.add(pos=cpos, type=[colloid_type] * n_col, mass=[m_col] * n_col,
                          v=rng.normal(size=(n_col, 3)) * sigma_v / math.sqrt(m_col))
    if boundary == "stick":
        # spins at kT from their own stream: positions and velocities stay those of "slip"
        w_rng = np.random.default_rng([int(seed), 4])
        col.rotation = np.ones((n_col, 3), bool)
        col.rinertia = np.full((n_col, 3), rinertia)
        col.omega_lab = w_rng.normal(size=(n_col, 3)) * sigma_v / math.sqrt(rinertia)
    sol = system.part.add(pos=spos, type=[solvent_type] * len(spos),
                          v=rng.normal(size=(len(spos), 3)) * sigma_v)
    s, c = solvent_type, colloid_type
    rp = surface_cutoff(R, r_cut) if cs_shell is None else cs_shell
    ia = system.non_bonded_inter
    if a_ss > 0:
        ia[s, s].hat.set_params(F_max=a_ss, cutoff=r_cut)
    if a_cs > 0:
        ia[c, s].hat.set_params(F_max=a_cs, cutoff=rp, offset=R)
    if gamma > 0:
        ia[s, s].dpd.set_params(weight_function=1, gamma=gamma, r_cut=r_cut)
        ia[c, s].dpd.set_params(weight_function=1, gamma=gamma, r_cut=rp, offset=R)
        if colloid_dpd:
            ia[c, c].dpd.set_params(weight_function=1, gamma=gamma, r_cut=r_cut, offset=2 * R)
    if boundary == "stick" and trans_gamma > 0:
        ia[c, s].surface_friction.set_params(gamma=trans_gamma, r_cut=rp if stick_shell is None else stick_shell,
                                             a1=R, a2=0.0, shared=shared)
    ia[c, c].contact.set_params(f_contact=f_contact, delta=delta, offset=2 * R)
    if lubrication:
        lub = dict(eta=eta, a1=R, a2=R, h_cut=h_cut, h_min=h_min, log_term=log_term)
        if lubrication_form != "plain":  # "plain" is the kernel's default: seed 004's calls unchanged
            lub["form"] = lubrication_form
        ia[c, c].lubrication.set_params(**lub)
    if morse:
        ia[c, c].morse.set_params(**dict(morse, offset=2 * R))
    system.thermostat.set_dpd(kT=kT, seed=int(seed))
    hydro = rot = strain = None
    if boundary == "stick":
        hydro = R * (STICK_RADIUS_RATIO if isinstance(radius_calibration, str) else ratio)
        rot = R * STICK_ROTATIONAL_RADIUS_RATIO
        strain = R * STICK_STRESSLET_RADIUS_RATIO
    return dict(n_colloids=n_col, n_solvent=len(spos), phi=n_col * v_user / V, radius=R_user,
                core_radius=R, radius_ratio=ratio, radius_calibration=radius_calibration,
                phi_core=n_col * v_col / V, hydrodynamic_radius=hydro, solvent_count=solvent_count,
                adsorbed=adsorbed if solvent_count == "bulk" else None,
                phi_hydrodynamic=None if hydro is None else n_col * 4.0 / 3.0 * math.pi * hydro ** 3 / V,
                rotational_radius=rot,
                phi_rotational=None if rot is None else n_col * 4.0 / 3.0 * math.pi * rot ** 3 / V,
                stresslet_radius=strain,
                phi_stresslet=None if strain is None else n_col * 4.0 / 3.0 * math.pi * strain ** 3 / V,
                colloid_mass=m_col, colloid_ids=np.asarray(col.id), solvent_ids=np.asarray(sol.id),
                cutoff_centre=equal_volume_cutoff(R, r_cut) if cs_shell is None else R + rp,
                cutoff_surface=rp, a_ss=a_ss, a_cs=a_cs,
                f_contact=f_contact, delta=delta, eta=eta, h_cut=h_cut, h_min=h_min,
                lubrication=bool(lubrication), lubrication_form=lubrication_form if lubrication else None,
                log_term=log_term, colloid_dpd=bool(colloid_dpd),
                diffusion_time=diffusion_time(R_user, eta, kT) if (eta and kT > 0) else math.inf,
                boundary=boundary, trans_gamma=trans_gamma, rinertia=rinertia, shared=shared,
                stick_shell=(rp if stick_shell is None else stick_shell) if boundary == "stick" else None)


def solvent_structure(system, info, frames=100, every=1.0, far=1.0, dr=0.05, n_mc=100000, seed=1):
    """Measure the solvent around the colloids of a ``setup_suspension`` scene.

    Runs the system's integrator ``frames`` times for ``every`` time units and
    after each run takes one frame: the bead density against the distance
    h = r - a from the nearest core centre (a = ``info["core_radius"]``; shell
    volumes by Monte Carlo with ``n_mc`` random points per frame, stream
    ``seed``), the density of the "bulk" (farther than ``far`` from every core
    surface) and the excess number of beads per colloid within ``far`` of a
    surface relative to that bulk (the adsorbed beads: the ``adsorbed`` of
    ``setup_suspension(solvent_count="bulk")``). Needs a cubic or orthorhombic
    periodic box. Returns a dict: ``bulk_density`` and its error
    ``bulk_density_err`` (10 blocks of frames), ``excess_per_colloid``,
    ``nominal_density`` (beads / free volume), ``h`` and ``density`` (the
    profile, bins of ``dr`` from -0.1 to far + 1)."""
    frames = int(frames)
    if frames < 10:
        raise ValueError(f"parameter 'frames' must be >= 10 (the error uses 10 blocks), got {frames}")
    every = _positive("every", every)
    far = _positive("far", far)
    dr = _positive("dr", dr)
    if int(n_mc) < 1000:
        raise ValueError(f"parameter 'n_mc' must be >= 1000, got {n_mc}")
    box = np.asarray(system.box_l, float)
    V = float(np.prod(box))
    a = float(info["core_radius"])
    col = system.part.by_ids(info["colloid_ids"])
    sol = system.part.by_ids(info["solvent_ids"])
    n_col = int(info["n_colloids"])
    rng = np.random.default_rng(int(seed))
    edges = np.arange(-0.1, far + 1.0 + 1e-9, dr)
    cnt = np.zeros(len(edges) - 1)
    vol = np.zeros(len(edges) - 1)
    n_far, v_far = np.zeros(frames), np.zeros(frames)
    near_n = near_v = 0.0

    def gap(x, cp):
        dm = np.full(len(x), np.inf)
        for c in cp:
            dm = np.minimum(dm, np.linalg.norm(_min_image(x - c, box), axis=1))
        return dm - a

    steps = max(1, int(round(every / system.time_step)))
    for k in range(frames):
        system.integrator.run(steps)
        cp = np.mod(np.asarray(col.pos, float), box)
        hb = gap(np.mod(np.asarray(sol.pos, float), box), cp)
        hx = gap(rng.uniform(0, 1, (int(n_mc), 3)) * box, cp)
        cnt += np.histogram(hb, bins=edges)[0]
        vol += np.histogram(hx, bins=edges)[0] / len(hx) * V
        n_far[k] = np.count_nonzero(hb > far)
        v_far[k] = np.count_nonzero(hx > far) / len(hx) * V
        near_n += np.count_nonzero(hb <= far)
        near_v += np.count_nonzero((hx <= far) & (hx > 0)) / len(hx) * V
    if v_far.sum() <= 0:
        raise ValueError(f"no volume farther than far = {far} from every colloid: choose a smaller 'far'")
    bulk = float(n_far.sum() / v_far.sum())
    blocks = [n_far[b].sum() / max(v_far[b].sum(), 1e-300) for b in np.array_split(np.arange(frames), 10)]
    bulk_err = float(np.std(blocks, ddof=1) / math.sqrt(10))
    excess = (near_n - bulk * near_v) / frames / max(n_col, 1)
    return dict(bulk_density=bulk, bulk_density_err=bulk_err, excess_per_colloid=float(excess), far=far,
                nominal_density=len(info["solvent_ids"]) / (V - n_col * 4.0 / 3.0 * math.pi * a ** 3),
                n_colloids=n_col, n_solvent=len(info["solvent_ids"]), core_radius=a, frames=frames,
                h=(0.5 * (edges[1:] + edges[:-1])).tolist(), density=(cnt / np.maximum(vol, 1e-12)).tolist())
