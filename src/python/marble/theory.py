"""Hydrodynamic theory for a sphere in a periodic box (reference.md section 5,
doc/analysis.md): finite-size diffusion coefficients (Hasimoto), partial slip
(Basset), long-time-tail amplitudes, and the inverse problems (slip length or
hydrodynamic radius from a measured D). Reduced units; kT defaults to 1.

Conventions: ``L = numpy.inf`` (the default) is the unbounded fluid; ``b`` is the
Navier slip length (0: stick, inf: perfect slip).
"""
import math

import numpy as np

#: Hasimoto's constant for a simple cubic lattice of point forces.
HASIMOTO_XI = 2.837297


def _pos(name, x, allow_inf=False):
    x = np.asarray(x, dtype=float)
    ok = (x > 0) & (np.isfinite(x) | (allow_inf & np.isinf(x)))
    if not np.all(ok):
        raise ValueError(f"parameter '{name}' must be > 0{' (inf allowed)' if allow_inf else ''}, "
                         f"got {x}")
    return x


def _slip(b, R):
    b = np.asarray(b, dtype=float)
    if np.any(np.isnan(b)) or np.any(b <= -R / 3.0):
        raise ValueError(f"parameter 'b' (slip length) must be > -R/3 = {-R / 3.0}, got {b}")
    return b


def _scalar(x):
    return float(x) if np.ndim(x) == 0 else x


def _inv_L(L):
    L = _pos("L", L, allow_inf=True)
    return np.where(np.isinf(L), 0.0, 1.0 / np.where(np.isinf(L), 1.0, L))


def basset_friction(eta, R, b=0.0):
    """Translational and rotational friction of a sphere with slip length b:
    zeta_T = 6 pi eta R (1 + 2b/R)/(1 + 3b/R), zeta_R = 8 pi eta R^3/(1 + 3b/R).
    b = inf gives (4 pi eta R, 0). Returns (zeta_T, zeta_R)."""
    eta = _pos("eta", eta)
    R = _pos("R", R)
    b = _slip(b, R)
    with np.errstate(invalid="ignore", divide="ignore"):
        lam = b / R
        fT = np.where(np.isinf(lam), 2.0 / 3.0, (1 + 2 * lam) / (1 + 3 * lam))
        fR = np.where(np.isinf(lam), 0.0, 1.0 / (1 + 3 * lam))
    return _scalar(6 * np.pi * eta * R * fT), _scalar(8 * np.pi * eta * R ** 3 * fR)


def diffusion_coefficient(eta, R, L=np.inf, b=0.0, kT=1.0):
    """Translational D of a sphere (slip length b) in a periodic cubic box of side L:

        D(L) = kT/zeta_T(b) - 2.837297 kT/(6 pi eta L) + kT/(6 pi eta) (4 pi/3) R^2/L^3 * R/(R + 2b)

    The 1/L term is the same for any surface (Hasimoto). The L^-3 term comes from
    the source-dipole part of the flow around the sphere, whose strength per unit
    force is R^2/3 (1 + 2b/R)^-1 for the Basset solution: b = 0 gives Hasimoto's
    stick formula and b = inf the perfect-slip formula of reference.md section 5."""
    eta = _pos("eta", eta)
    R = _pos("R", R)
    b = _slip(b, R)
    kT = _pos("kT", kT)
    zT, _ = basset_friction(eta, R, b)
    iL = _inv_L(L)
    with np.errstate(invalid="ignore", divide="ignore"):
        dip = np.where(np.isinf(b), 0.0, R / (R + 2 * np.where(np.isinf(b), 0.0, b)))
    D = kT / zT - HASIMOTO_XI * kT * iL / (6 * np.pi * eta) \
        + kT / (6 * np.pi * eta) * (4 * np.pi / 3) * R ** 2 * iL ** 3 * dip
    return _scalar(D)


def hasimoto_D(eta, R, L=np.inf, kT=1.0, boundary="stick"):
    """D(L) for a stick or a perfectly slipping sphere (reference.md section 5):
    stick: kT/(6 pi eta) [1/R - 2.837297/L + (4 pi/3) R^2/L^3];
    slip:  kT/(4 pi eta R) - 2.837297 kT/(6 pi eta L)."""
    if boundary not in ("stick", "slip"):
        raise ValueError(f"parameter 'boundary' must be 'stick' or 'slip', got {boundary!r}")
    return diffusion_coefficient(eta, R, L, 0.0 if boundary == "stick" else np.inf, kT)


def rotational_diffusion_coefficient(eta, R, L=np.inf, b=0.0, kT=1.0):
    """D_r = kT/zeta_R(b) - kT/(6 eta L^3). For stick this is
    kT/(8 pi eta R^3) [1 - (4 pi/3) R^3/L^3] (reference.md section 5); the L^-3
    correction (periodic rotlets) does not depend on the surface. inf for b = inf."""
    eta = _pos("eta", eta)
    R = _pos("R", R)
    b = _slip(b, R)
    kT = _pos("kT", kT)
    _, zR = basset_friction(eta, R, b)
    iL = _inv_L(L)
    with np.errstate(divide="ignore"):
        D = kT / np.asarray(zR, dtype=float) - kT * iL ** 3 / (6 * eta)
    return _scalar(D)


def vacf_tail_amplitude(eta, rho_m, kT=1.0, D=0.0):
    """A_T with C_v,x(t) -> A_T t^(-3/2) per Cartesian component:
    A_T = kT / (12 rho_m [pi (nu + D)]^(3/2)), nu = eta / rho_m."""
    eta, rho_m, kT = _pos("eta", eta), _pos("rho_m", rho_m), _pos("kT", kT)
    nu = eta / rho_m
    return _scalar(kT / (12 * rho_m * (np.pi * (nu + D)) ** 1.5))


def rotational_vacf_tail_amplitude(eta, rho_m, kT=1.0, D=0.0):
    """A_R with C_omega,x(t) -> A_R t^(-5/2) per Cartesian component:
    A_R = pi kT / (rho_m [4 pi (nu + D)]^(5/2)), nu = eta / rho_m."""
    eta, rho_m, kT = _pos("eta", eta), _pos("rho_m", rho_m), _pos("kT", kT)
    nu = eta / rho_m
    return _scalar(np.pi * kT / (rho_m * (4 * np.pi * (nu + D)) ** 2.5))


def vacf_tail(t, eta, rho_m, kT=1.0, D=0.0):
    """Translational tail A_T t^(-3/2) per component."""
    return vacf_tail_amplitude(eta, rho_m, kT, D) * np.asarray(t, dtype=float) ** -1.5


def rotational_vacf_tail(t, eta, rho_m, kT=1.0, D=0.0):
    """Rotational tail A_R t^(-5/2) per component."""
    return rotational_vacf_tail_amplitude(eta, rho_m, kT, D) * np.asarray(t, dtype=float) ** -2.5


def _bisect(f, lo, hi, tol=1e-13, maxiter=300):
    flo, fhi = f(lo), f(hi)
    if flo * fhi > 0:
        return None
    for _ in range(maxiter):
        mid = 0.5 * (lo + hi)
        fm = f(mid)
        if (fm > 0) == (flo > 0):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi - lo <= tol * max(1.0, abs(hi)):
            break
    return 0.5 * (lo + hi)


def _fit_1d(model, D, D_err, L, lo, hi, name, hint=""):
    """Root of sum_i w_i (model(p, L_i) - D_i) dmodel/dp = 0 over p in (lo, hi):
    the exact solution of model(p, L) = D for one measurement, weighted least
    squares for several. Error from the linearised model."""
    D = np.atleast_1d(np.asarray(D, dtype=float))
    L = np.broadcast_to(np.atleast_1d(np.asarray(L, dtype=float)), D.shape)
    if D_err is None:
        w = np.ones_like(D)
    else:
        err = np.broadcast_to(np.atleast_1d(np.asarray(D_err, dtype=float)), D.shape)
        if np.any(err <= 0):
            raise ValueError("parameter 'D_err' must be > 0")
        w = 1.0 / err ** 2
    if np.any(~np.isfinite(D)) or np.any(D <= 0):
        raise ValueError(f"parameter 'D' must be finite and > 0, got {D}")

    def deriv(p):
        h = 1e-6 * max(1.0, abs(p))
        return (model(p + h, L) - model(p - h, L)) / (2 * h)

    def grad(p):
        return float(np.sum(w * (model(p, L) - D) * deriv(p)))

    # scan for a sign change (the model is monotonic in p for one L)
    grid = np.concatenate([np.linspace(lo, min(hi, lo + 1e-3 * (1 + abs(lo))), 3)[1:],
                           np.geomspace(1e-6, 1, 40) * (hi - lo) + lo])
    grid = np.unique(grid[(grid > lo) & (grid < hi)])
    vals = [grad(p) for p in grid]
    p = None
    for a, bb, fa, fb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:]):
        if fa * fb <= 0:
            p = _bisect(grad, a, bb)
            break
    if p is None:
        raise ValueError(f"no {name} in ({lo}, {hi}) reproduces D = {D}: D is outside the "
                         "range the model can give" + hint)
    J = deriv(p)
    if D_err is None:
        err = np.nan if D.size == 1 else np.sqrt(np.sum((model(p, L) - D) ** 2) / (D.size - 1)
                                                 / np.sum(J ** 2))
    else:
        err = 1.0 / np.sqrt(np.sum(w * J ** 2))
    return float(p), float(err)


def slip_length_from_D(D, eta, R, L=np.inf, D_err=None, kT=1.0, b_max=1e6):
    """Effective slip length b with diffusion_coefficient(eta, R, L, b) = D.

    D, L (and D_err) may be arrays of measurements at several box sizes: b is then
    the weighted least-squares fit. Returns (b, b_err); b_err from D_err by
    linearisation (NaN for one measurement without D_err). b may come out
    negative (down to -R/3): the hydrodynamic radius is then larger than R."""
    eta, R = float(_pos("eta", eta)), float(_pos("R", R))

    def model(b, L_):
        return diffusion_coefficient(eta, R, L_, b, kT)

    return _fit_1d(model, D, D_err, L, -R / 3.0, b_max, "slip length",
                   f" (the model used eta = {eta}, R = {R}, kT = {kT}: pass the run's kT)")


def hydrodynamic_radius_from_D(D, eta, L=np.inf, D_err=None, kT=1.0):
    """Stick-sphere radius R_h with hasimoto_D(eta, R_h, L) = D (arrays: least
    squares over several box sizes). Returns (R_h, R_h_err)."""
    eta = float(_pos("eta", eta))
    L_arr = np.atleast_1d(np.asarray(L, dtype=float))
    hi = 0.45 * float(np.min(L_arr)) if np.all(np.isfinite(L_arr)) else 1e6

    def model(R_, L_):
        return diffusion_coefficient(eta, R_, L_, 0.0, kT)

    return _fit_1d(model, D, D_err, L, 0.0, hi, "hydrodynamic radius",
                   f" (the model used eta = {eta}, kT = {kT}: pass the run's kT)")


# --- suspensions (doc/suspensions.md, reference.md section 7) ---------------

def batchelor_viscosity(phi):
    """Relative viscosity 1 + 2.5 phi + 6.2 phi^2 (Batchelor 1977, Brownian hard
    spheres, dilute): 1.141, 1.312, 1.748 at phi = 0.05, 0.1, 0.2."""
    phi = np.asarray(phi, dtype=float)
    if np.any(phi < 0) or np.any(~np.isfinite(phi)):
        raise ValueError(f"parameter 'phi' must be >= 0, got {phi}")
    return _scalar(1.0 + 2.5 * phi + 6.2 * phi ** 2)


def krieger_dougherty_viscosity(phi, phi_m=0.63, intrinsic=2.5):
    """Relative viscosity (1 - phi/phi_m)^(-[eta] phi_m) (Krieger & Dougherty 1959):
    1.139, 1.313, 1.825, 2.77, 4.89 at phi = 0.05, 0.1, 0.2, 0.3, 0.4 (phi_m = 0.63)."""
    phi, phi_m = _below_phi_m(phi, phi_m)
    return _scalar((1.0 - phi / phi_m) ** (-intrinsic * phi_m))


def _below_phi_m(phi, phi_m):
    """(phi as an array, phi_m as a float); ValueError unless phi_m > 0 and
    0 <= phi < phi_m."""
    phi = np.asarray(phi, dtype=float)
    phi_m = float(_pos("phi_m", phi_m))
    if np.any(phi < 0) or np.any(phi >= phi_m) or np.any(~np.isfinite(phi)):
        raise ValueError(f"parameter 'phi' must be in [0, phi_m = {phi_m}), got {phi}")
    return phi, phi_m


def quemada_viscosity(phi, phi_m=0.63, exponent=2.0):
    """Relative viscosity (1 - phi/phi_m)^(-exponent) (Quemada 1977, Rheol. Acta 16,
    82; exponent 2). De Kruif, van Iersel, Vrij & Russel (1985, J. Chem. Phys. 83,
    4717) fitted this form to sterically stabilised silica hard spheres: phi_m = 0.63
    for the low-shear (zero-shear) viscosity, phi_m = 0.71 for the high-shear limit
    (3.71 and 3.04 at phi = 0.303). It is Krieger-Dougherty with [eta] = exponent/phi_m
    (3.17 at phi_m = 0.63, not Einstein's 2.5), so it is meant for concentrated
    suspensions, not for the dilute limit (Batchelor there)."""
    exponent = float(_pos("exponent", exponent))
    phi, phi_m = _below_phi_m(phi, phi_m)
    return _scalar((1.0 - phi / phi_m) ** (-exponent))


def carnahan_starling_contact(phi):
    """Hard-sphere contact value g(2R+) = (1 - phi/2)/(1 - phi)^3 (1.758 at phi = 0.2)."""
    phi = np.asarray(phi, dtype=float)
    if np.any(phi < 0) or np.any(phi >= 1):
        raise ValueError(f"parameter 'phi' must be in [0, 1), got {phi}")
    return _scalar((1.0 - phi / 2.0) / (1.0 - phi) ** 3)


# --- two equal rigid spheres in Stokes flow (doc/suspensions.md section 7g) ---
#
# xi = h/a: the surface gap over the radius. Bispherical coordinates: the spheres
# are the surfaces +/-alpha with cosh(alpha) = (centre distance/2)/a = 1 + xi/2.
# The resistances are F/(6 pi eta a U) per sphere (Jeffrey & Onishi's normalisation
# for equal spheres, 3 pi (a1 + a2) = 6 pi a).

def _two_sphere_alpha(xi):
    return np.arccosh(1.0 + 0.5 * _pos("xi", xi))


def _bispherical_sum(alpha, term):
    # terms fall as n^2 exp(-(2n + 1) alpha): n up to 40/alpha + 10 leaves < 1e-30
    n = np.arange(1, int(40.0 / alpha) + 11, dtype=float)
    k = n * (n + 1) / ((2 * n - 1) * (2 * n + 3))
    return 4.0 / 3.0 * np.sinh(alpha) * np.sum(k * term(n, alpha))


def _squeeze_term(n, al):
    # Brenner (1961): a sphere moving towards a plane free surface (no normal velocity,
    # no shear stress), the symmetry plane of two equal spheres approaching each other
    m = 2 * n + 1
    return (4 * np.cosh((n + 0.5) * al) ** 2 + m * m * np.sinh(al) ** 2) \
        / (2 * np.sinh(m * al) - m * np.sinh(2 * al)) - 1.0


def _same_term(n, al):
    # Stimson & Jeffery (1926): two equal spheres moving with the same velocity
    m = 2 * n + 1
    return 1.0 - (4 * np.sinh((n + 0.5) * al) ** 2 - m * m * np.sinh(al) ** 2) \
        / (2 * np.sinh(m * al) + m * np.sinh(2 * al))


def two_sphere_squeeze_resistance(xi):
    """Exact squeeze resistance of two equal rigid (no-slip) spheres of radius a
    approaching each other along their line of centres with velocities +U and -U,
    gap h = xi a, in an unbounded fluid at rest: F = 6 pi eta a U lambda(xi) on each,
    lambda = X^A_11 - X^A_12 (Jeffrey & Onishi 1984, J. Fluid Mech. 139, 261).

    Bispherical series (Brenner 1961, Chem. Eng. Sci. 16, 242, the sphere approaching
    a free surface; Maude 1961, Br. J. Appl. Phys. 12, 293), cosh(alpha) = 1 + xi/2:

        lambda = (4/3) sinh(alpha) sum_{n>=1} n(n+1)/((2n-1)(2n+3))
                 [ (4 cosh^2((n+1/2) alpha) + (2n+1)^2 sinh^2(alpha))
                   / (2 sinh((2n+1) alpha) - (2n+1) sinh(2 alpha)) - 1 ].

    Limits: 1 + 3/(2s) + 9/(4 s^2) + ... for s = 2 + xi -> inf (reflections);
    1/(2 xi) + (9/20) ln(1/xi) + ... as xi -> 0 (two_sphere_squeeze_lubrication).
    Values: 7.413 at xi = 0.1, 2.039 at 1, 1.597 at 2."""
    al = _two_sphere_alpha(xi)
    out = np.vectorize(lambda x: _bispherical_sum(x, _squeeze_term))(al)
    return _scalar(out)


def two_sphere_translation_resistance(xi):
    """Exact resistance of two equal rigid spheres moving with the same velocity U
    along their line of centres: F = 6 pi eta a U lambda on each, lambda = X^A_11 +
    X^A_12 (Stimson & Jeffery 1926, Proc. R. Soc. A 111, 110; the same bispherical
    series with [1 - (4 sinh^2((n+1/2) alpha) - (2n+1)^2 sinh^2 alpha) /
    (2 sinh((2n+1) alpha) + (2n+1) sinh 2 alpha)]). Limits: 1 - 3/(2s) + ... far
    apart, 0.645 at contact (the doublet)."""
    al = _two_sphere_alpha(xi)
    out = np.vectorize(lambda x: _bispherical_sum(x, _same_term))(al)
    return _scalar(out)


#: O(1) constant of the equal-sphere squeeze resistance's near-field form
#: (two_sphere_squeeze_lubrication), from the exact series: lambda - 1/(2 xi)
#: - (9/20) ln(1/xi) - (3/56) xi ln(1/xi) extrapolated to xi -> 0.
SQUEEZE_NEAR_FIELD_CONSTANT = 1.3456


def two_sphere_squeeze_lubrication(xi, terms="all"):
    """Near-field (lubrication) form of two_sphere_squeeze_resistance (Jeffrey &
    Onishi 1984, their near-field form at beta = 1: g1 = 1/4, g2 = 9/40, g3 = 3/112, and
    X^A_12 = -X^A_11 in the singular terms):

        lambda ~ 1/(2 xi) + (9/20) ln(1/xi) + (3/56) xi ln(1/xi) + C,

    C = SQUEEZE_NEAR_FIELD_CONSTANT (from the exact series). terms="reynolds": the
    leading term 1/(2 xi) alone (Reynolds' squeeze film, the lubrication kernel's
    (3 pi/2) eta a^2/h for the relative velocity 2U); "log": plus (9/20) ln(1/xi)
    (Ball & Melrose's, the kernel's log_term="on" for equal spheres)."""
    xi = _pos("xi", xi)
    if terms not in ("reynolds", "log", "all"):
        raise ValueError(f"parameter 'terms' must be 'reynolds', 'log' or 'all', got {terms!r}")
    lam = 0.5 / xi
    if terms != "reynolds":
        lam = lam + 0.45 * np.log(1.0 / xi)
    if terms == "all":
        lam = lam + (3.0 / 56.0) * xi * np.log(1.0 / xi) + SQUEEZE_NEAR_FIELD_CONSTANT
    return _scalar(lam)


# --- one sphere's radii by mode: translation, rotation, stresslet (doc/suspensions.md 7m) ---

def rotational_friction_unbounded(zeta_L, eta, L, zeta_err=None):
    """Rotational friction of a sphere in unbounded fluid from the one measured in a
    periodic cube of edge L (torque / spin, one sphere per box):

        1/zeta_0 = 1/zeta_L + 1/(6 eta L^3),

    i.e. zeta_0 = zeta_L / (1 + zeta_L/(6 eta L^3)). The periodic velocity field has
    zero mean vorticity, while a rotlet T (sphere included) carries the net
    vorticity T/(3 eta); the lattice therefore counter-rotates the fluid at the
    sphere by T/(6 eta L^3) (the image rotlets' own dipolar vorticity sums to zero
    on a cubic lattice), and Faxen's law Omega = (1/2) curl u + T/zeta_0 gives the
    above: the mobility is lowered by phi_r = (4 pi/3) R_r^3/L^3 of itself
    (theory.rotational_diffusion_coefficient's L^-3 term; reference.md section 5),
    whatever the surface. The next images' terms are higher order in R/L. With
    ``zeta_err`` returns (zeta_0, its error), else zeta_0."""
    zeta_L = _pos("zeta_L", zeta_L)
    eta = _pos("eta", eta)
    iL = _inv_L(L)
    z0 = 1.0 / (1.0 / zeta_L + iL ** 3 / (6.0 * eta))
    if zeta_err is None:
        return _scalar(z0)
    ze = np.asarray(zeta_err, dtype=float)
    if np.any(ze < 0) or np.any(~np.isfinite(ze)):
        raise ValueError(f"parameter 'zeta_err' must be >= 0 and finite, got {zeta_err}")
    return _scalar(z0), _scalar(ze * (z0 / zeta_L) ** 2)


def rotational_radius(zeta_r, eta, zeta_err=0.0, eta_err=0.0):
    """Rotational (no-slip) radius R_r = (zeta_r / (8 pi eta))^(1/3) of an unbounded
    rotational friction zeta_r (rotational_friction_unbounded for a periodic box);
    returns (R_r, its error) with the relative errors of zeta_r and eta added in
    quadrature and divided by 3."""
    zeta_r = _pos("zeta_r", zeta_r)
    eta = _pos("eta", eta)
    for name, v in (("zeta_err", zeta_err), ("eta_err", eta_err)):
        v = np.asarray(v, dtype=float)
        if np.any(v < 0) or np.any(~np.isfinite(v)):
            raise ValueError(f"parameter '{name}' must be >= 0 and finite, got {v}")
    Rr = (zeta_r / (8.0 * np.pi * eta)) ** (1.0 / 3.0)
    err = Rr / 3.0 * np.hypot(np.asarray(zeta_err, float) / zeta_r, np.asarray(eta_err, float) / eta)
    return _scalar(Rr), _scalar(err)


def _slip_beta(beta, lo):
    beta = np.asarray(beta, dtype=float)
    if np.any(np.isnan(beta)) or np.any(beta <= lo):
        raise ValueError(f"parameter 'beta' (slip length / radius) must be > {lo}, got {beta}")
    return beta


def slip_sphere_intrinsic_viscosity(beta):
    """Intrinsic viscosity (Einstein coefficient per volume fraction of the sphere
    of radius a) of a sphere with Navier slip length b = beta a:

        [eta] = 5/2 (1 + 2 beta)/(1 + 5 beta),

    the stresslet S = (20/3) pi eta a^3 E (1 + 2 beta)/(1 + 5 beta) in a pure strain E.
    Derivation (doc/suspensions.md 7m): u = E.x + A a^5 [E.x/r^5 - (5/2)(x.E.x) x/r^7]
    + B a^3 (x.E.x) x/r^5; no penetration gives B = (3/2) A - 1, the Navier condition
    u_t = (b/eta) sigma_rt gives A = -1/(1 + 5 beta), and S = -(8 pi eta/3) B a^3 E.
    beta = 0: 5/2 (Einstein), beta = inf: 1 (Taylor's bubble). Valid for
    beta > -1/5 (a negative slip length: the no-slip plane beyond a)."""
    beta = _slip_beta(beta, -0.2)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(np.isinf(beta), 1.0, 2.5 * (1 + 2 * beta) / (1 + 5 * beta))
    return _scalar(out)


def slip_sphere_radii(a, beta):
    """The no-slip radii by mode of a sphere of radius a with Navier slip length
    beta a: translation R_t = a (1 + 2 beta)/(1 + 3 beta) (Basset), rotation
    R_r = a (1 + 3 beta)^(-1/3), stresslet R_s = a [(1 + 2 beta)/(1 + 5 beta)]^(1/3)
    (zeta_t = 6 pi eta R_t, zeta_r = 8 pi eta R_r^3, S = (20/3) pi eta R_s^3 E).
    All three are a (1 - beta) + O(beta^2): a thin slip layer shifts every mode's
    radius alike to first order. Returns (R_t, R_r, R_s)."""
    a = _pos("a", a)
    beta = _slip_beta(beta, -0.2)
    with np.errstate(invalid="ignore", divide="ignore"):
        Rt = np.where(np.isinf(beta), 2.0 / 3.0, (1 + 2 * beta) / (1 + 3 * beta)) * a
        Rr = np.where(np.isinf(beta), 0.0, (1 + 3 * beta) ** (-1.0 / 3.0)) * a
        Rs = (slip_sphere_intrinsic_viscosity(beta) / 2.5) ** (1.0 / 3.0) * a
    return _scalar(Rt), _scalar(Rr), _scalar(Rs)


def slip_sphere_from_radii(R_t, R_r, branch="positive"):
    """The Navier-slip sphere (a, beta) with translational radius R_t and rotational
    radius R_r (slip_sphere_radii). q = R_r/R_t = (1 + 3 beta)^(2/3)/(1 + 2 beta) has
    its maximum 1 at beta = 0 (q = 1 - beta^2 + O(beta^3)): a slip sphere of either
    sign of slip has R_r <= R_t, so ValueError for R_r > R_t (no slip sphere fits),
    and every q < 1 has two solutions: ``branch="positive"`` (beta > 0, q falls to 0
    as beta -> inf) or ``"negative"`` (-1/5 < beta < 0, the no-slip plane beyond a;
    q > 0.9048 there). Returns (a, beta)."""
    R_t = float(_pos("R_t", R_t))
    R_r = float(_pos("R_r", R_r))
    if branch not in ("positive", "negative"):
        raise ValueError(f"parameter 'branch' must be 'positive' or 'negative', got {branch!r}")
    q = R_r / R_t

    def ratio(b):
        return (1 + 3 * b) ** (2.0 / 3.0) / (1 + 2 * b)

    if q > 1.0:
        raise ValueError(f"R_r/R_t = {q:.5g} > 1: no Navier-slip sphere has R_r > R_t "
                         f"(R_r/R_t = 1 - beta^2 + ...)")
    if q == 1.0:
        return R_t, 0.0
    if branch == "positive":
        hi = 1.0
        while ratio(hi) > q:
            hi *= 2.0
            if hi > 1e12:
                raise ValueError(f"R_r/R_t = {q:.5g} too small for a slip sphere")
        beta = _bisect(lambda b: ratio(b) - q, 0.0, hi)
    else:
        qmin = ratio(-0.2)
        if not q > qmin:
            raise ValueError(f"R_r/R_t = {q:.5g} must be > {qmin:.5g} on the negative branch "
                             f"(slip length > -a/5)")
        beta = _bisect(lambda b: ratio(b) - q, -0.2, 0.0)
    a = R_t * (1 + 3 * beta) / (1 + 2 * beta)
    return a, beta


#: Lattice sums of a simple cubic array (lattice constant 1) for the stresslet
#: factor below, with the image disturbance u' of a sphere of radius R in the strain
#: E (E_xy = E_yx = 1): u' = -(5/2) R^3 A(x) - (R^5/2) B(x), A = x (x.E.x)/r^5,
#: B = 2 E.x/r^5 - 5 x (x.E.x)/r^7. STRESSLET_LATTICE_K3 is the sum of the xy strain
#: of A over the sites n != 0 within a ball of radius N, N -> inf (3.1120, 3.1129,
#: 3.1128, 3.1130, 3.1131 at N = 40, 60, 80, 100, 120); K5 that of B (absolutely
#: convergent); the Laplacian of A's strain sums to 2 K5.
STRESSLET_LATTICE_K3 = 3.1130
STRESSLET_LATTICE_K5 = -24.8658


def stresslet_lattice_factor(R, L):
    """Stresslet of a no-slip sphere of radius R in a periodic cube of edge L (one
    sphere per box: a simple cubic array) in Lees-Edwards shear along a cube axis
    (E_xy), relative to the unbounded (20/3) pi eta R^3 E (Einstein):

        s = 1 / (1 - phi - c3 - c5),  phi = (4 pi/3) R^3/L^3,
        c3 = -(5/2) K3 (R/L)^3 = -1.858 phi,  c5 = -K5 (R/L)^5 = +24.87 (R/L)^5,

    so that the box's viscosity is eta_0 (1 + 2.5 phi s). Derivation
    (doc/suspensions.md section 7p): the sphere's stresslet is Faxen's
    (20/3) pi eta R^3 (1 + R^2 nabla^2/10) of the strain its images make at it
    (first reflection). The images' far field (-(5/2) R^3 A) is conditionally
    convergent: summed over a ball of sites in unbounded fluid under an applied
    strain, each shell's own average vanishes (the strain of one stresslet
    averaged over a sphere around it is zero outside it), leaving the cubic
    (l = 4) part K3, while the ball of stresslet density P = n S has the uniform
    inner strain -P/(5 eta) (Eshelby; the same integral as 7m's rotlet
    vorticity T/(3 eta)). The periodic box fixes the mean strain instead, which
    adds +phi s. The R^5 term and Faxen's Laplacian (each -K5/2 (R/L)^5) are
    absolutely convergent. Left out: O(phi^2) (second reflections). At
    L = 4.3756: s = 0.973 for R = 1 (-4.3 % from c3, +1.6 % from c5), 0.970 for
    R = 1.05. The shear along a cube axis is the weaker of the cubic array's two
    shear modes (a strain along the axes, E = diag(1, -1, 0), has -1.5 K3)."""
    R = float(_pos("R", R))
    L = float(_pos("L", L))
    if not R < 0.5 * L:
        raise ValueError(f"parameter 'R' must be < L/2 (spheres that do not overlap their images), got "
                         f"R = {R}, L = {L}")
    x = R / L
    phi = 4.0 * math.pi * x ** 3 / 3.0
    c3 = -2.5 * STRESSLET_LATTICE_K3 * x ** 3
    c5 = -STRESSLET_LATTICE_K5 * x ** 5
    return 1.0 / (1.0 - phi - c3 - c5)
