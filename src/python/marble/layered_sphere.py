"""Stokes flow past a sphere with a graded, anisotropic Brinkman layer: its
translational, rotational and stresslet radii (doc/suspensions.md section 7o).

The model: an impermeable, free-slip core of radius r0 surrounded by a fluid of
viscosity eta(r) (r0 <= r <= r1; eta_out outside) in which the sphere's rigid-body
motion U(x) acts on the fluid through a friction density

    f = -K_t(r) P (u - U) - K_n(r) e e . (u - U),   P = I - e e,   e = x/r,

tangential (K_t) and radial (K_n) separately; K_t = K_n = 0 beyond r1. Each of
the three flows is one vector spherical harmonic, so each reduces to a linear
radial ODE:

- rotation (Omega e_z): u_phi = r omega(r) sin(theta); with tau = r^4 eta omega'
  (the transmitted torque over 8 pi/3): omega' = tau/(r^4 eta),
  tau' = r^4 K_t (omega - Omega); tau(r0) = 0 (free-slip core); outside
  omega = C/r^3, zeta_r = 8 pi eta_out C/Omega, R_r = (C/Omega)^(1/3).
- translation (V e_z, l = 1) and axisymmetric strain (E = eps diag(-1/2, -1/2, 1),
  the sphere at rest, l = 2), both in the sphere's frame (v = u - U, the stream
  -V far away for translation): v_r = A(r) P_l(cos theta), v_theta = B(r)
  (-2/(l(l+1))) sin(theta) P_l'(cos theta), p = P(r) P_l, sigma_rr = S(r) P_l and
  sigma_rtheta = T(r) times v_theta's angular function. With lam = l(l+1)/2:

      A' = 2 (B - A)/r  [- A d ln n/dr with mass continuity div(n v) = 0]
      B' = T/eta - (lam A - B)/r
      S' = K_n A - 4 eta A'/r + 2 eta B'/r + c1 eta A/r^2 - 6 eta B/r^2
      T' = K_t B - 3 eta B'/r + lam P/r - eta (lam A - B)/r^2 - c2 eta (A - B)/r^2

  with P = 2 eta A' - S, (c1, c2) = (6, 4) for l = 1 and (10, 12) for l = 2.
  (Derived from the divergence of the stress in spherical coordinates with a
  radially varying eta, whose derivative drops out in these variables; the
  isotropic part of the stress from div v != 0 is absorbed in p;
  testsuite/python/test_layered_sphere.py checks the Stokes solutions below
  against them.) Core: A(r0) = 0 (no penetration), T(r0) = 0 (free slip).
  Outside, the flow is the imposed one (A = -V for translation, A = eps r for
  strain) plus the two decaying Stokes solutions A ~ r^k: k = -1 (the Stokeslet
  A = c/r of the force 4 pi eta_out c on the fluid: R_t = 2c/(3V)) and -3 for
  l = 1; k = -2 (stresslet) and -4 for l = 2, where a no-slip sphere of radius R
  has A = -(5/2) eps R^3/r^2, so R_s = (-2c/(5 eps))^(1/3).

Limits (tested): no friction gives the free-slip sphere r0 (R_t = 2/3 r0, R_r = 0,
R_s = (2/5)^(1/3) r0); an impermeable layer (K -> inf) the no-slip sphere r1; a
uniform K on a sphere with a vanishing core Brinkman's porous sphere (Neale et
al. 1973 for translation; 8 pi eta b^3 (1 + 3/beta^2 - 3 coth(beta)/beta) for rotation).
"""
import math

import numpy as np

_C = {1: (6.0, 4.0), 2: (10.0, 12.0)}


def _check_layer(r0, r1, eta_out):
    if not (math.isfinite(r0) and r0 > 0):
        raise ValueError(f"parameter 'r0' (core radius) must be > 0, got {r0}")
    if not (math.isfinite(r1) and r1 > r0):
        raise ValueError(f"parameter 'r1' (outer edge of the layer) must be > r0 = {r0}, got {r1}")
    if not (math.isfinite(eta_out) and eta_out > 0):
        raise ValueError(f"parameter 'eta_out' must be > 0, got {eta_out}")


def _linear_bvp(rhs, n, mesh, inner, outer, n_par):
    """Solve the linear system y' = rhs(r, y) on mesh (trapezoidal rule on every
    interval, one sparse solve: stable for the stiff, exponentially growing and
    decaying modes of a Brinkman layer, where shooting overflows, and exact at
    kinks of the coefficients to the mesh's order) with the boundary rows
    inner = (Bi, bi): Bi y(r0) = bi and outer = (Bo, Po, bo): Bo y(r1) + Po p = bo
    for n_par unknown parameters p. Returns (y on the mesh, p)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.linalg import spsolve
    r = np.asarray(mesh, dtype=float)
    N = len(r)
    g = np.asarray(rhs(r, np.zeros((n, N))), dtype=float)
    M = np.empty((N, n, n))
    for j in range(n):
        e = np.zeros((n, N))
        e[j] = 1.0
        M[:, :, j] = (np.asarray(rhs(r, e), dtype=float) - g).T
    dr = np.diff(r)
    rows, cols, vals = [], [], []
    rhs_vec = np.zeros(N * n + n_par)
    eye = np.eye(n)
    for i in range(N - 1):
        blk_i = -eye - 0.5 * dr[i] * M[i]
        blk_j = eye - 0.5 * dr[i] * M[i + 1]
        rr = i * n + np.repeat(np.arange(n), n)
        cc = np.tile(np.arange(n), n)
        rows += [rr, rr]
        cols += [i * n + cc, (i + 1) * n + cc]
        vals += [blk_i.ravel(), blk_j.ravel()]
        rhs_vec[i * n:(i + 1) * n] = 0.5 * dr[i] * (g[:, i] + g[:, i + 1])
    row = (N - 1) * n
    Bi, bi = inner
    for k in range(len(bi)):
        rows.append(np.full(n, row))
        cols.append(np.arange(n))
        vals.append(np.asarray(Bi[k], dtype=float))
        rhs_vec[row] = bi[k]
        row += 1
    Bo, Po, bo = outer
    for k in range(len(bo)):
        rows.append(np.full(n + n_par, row))
        cols.append(np.r_[(N - 1) * n + np.arange(n), N * n + np.arange(n_par)])
        vals.append(np.r_[np.asarray(Bo[k], dtype=float), np.asarray(Po[k], dtype=float)])
        rhs_vec[row] = bo[k]
        row += 1
    if row != N * n + n_par:
        raise RuntimeError("layered_sphere: boundary rows do not close the system")
    A = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                   shape=(row, row)).tocsc()
    x = spsolve(A, rhs_vec)
    if not np.all(np.isfinite(x)):
        raise RuntimeError("layered_sphere: the radial boundary-value problem has no finite solution")
    return x[:N * n].reshape(N, n).T, x[N * n:]


def _extrapolated(solve, r0, r1, max_step):
    """Richardson extrapolation of a trapezoidal solution (error h^2) from the
    mesh and its halving: returns the parameters."""
    m = _mesh(r0, r1, max_step)
    p1 = solve(m)
    m2 = np.sort(np.r_[m, 0.5 * (m[1:] + m[:-1])])
    p2 = solve(m2)
    return (4.0 * p2 - p1) / 3.0


def _mesh(r0, r1, max_step):
    ms = max_step or (r1 - r0) / 200.0
    return np.linspace(r0, r1, max(int(math.ceil((r1 - r0) / ms)) + 1, 50))


def rotation(r0, r1, K_t, eta, eta_out, max_step=None):
    """Rotational friction of the layered sphere: returns (zeta_r, R_r) with
    zeta_r = 8 pi eta_out R_r^3. K_t, eta: vectorised callables of r."""
    _check_layer(r0, r1, eta_out)

    def rhs(r, y):
        w, tau = y
        return np.vstack([tau / (r ** 4 * eta(r)), r ** 4 * K_t(r) * (w - 1.0)])

    def solve(m):
        return _linear_bvp(rhs, 2, m, ([[0.0, 1.0]], [0.0]),
                           (np.eye(2), [[-1.0 / r1 ** 3], [3.0 * eta_out]], [0.0, 0.0]), 1)[1]
    C = float(_extrapolated(solve, r0, r1, max_step)[0])
    return 8.0 * math.pi * eta_out * C, math.copysign(abs(C) ** (1.0 / 3.0), C)


def free_solution(l, k, r, eta=1.0):
    """(A, B, S, T) of the Stokes solution A = r^k of the l-th harmonic (uniform eta)."""
    lam = l * (l + 1) / 2.0
    c1, c2 = _C[l]
    A, dA = r ** k, k * r ** (k - 1)
    B = A + r * dA / 2.0
    dB = (1.0 + k / 2.0) * k * r ** (k - 1)
    T = eta * (dB + (lam * A - B) / r)
    dT = eta * (1.0 + k / 2.0) * k * (k - 1) * r ** (k - 2) + eta * (lam * dA - dB) / r - eta * (lam * A - B) / r ** 2
    # the theta equation solved for P
    P = (r / lam) * (dT + 3.0 * eta * dB / r + eta * (lam * A - B) / r ** 2 + c2 * eta * (A - B) / r ** 2)
    S = 2.0 * eta * dA - P
    return np.array([A, B, S, T])


def _poloidal_rhs(l, K_n, K_t, eta, dlnn=None):
    lam = l * (l + 1) / 2.0
    c1, c2 = _C[l]

    def rhs(r, y):
        A, B, S, T = y
        e = eta(r)
        dA = 2.0 * (B - A) / r
        if dlnn is not None:
            dA = dA - A * dlnn(r)
        dB = T / e - (lam * A - B) / r
        P = 2.0 * e * dA - S
        dS = K_n(r) * A - 4 * e * dA / r + 2 * e * dB / r + c1 * e * A / r ** 2 - 6 * e * B / r ** 2
        dT = K_t(r) * B - 3 * e * dB / r + lam * P / r - e * (lam * A - B) / r ** 2 \
            - c2 * e * (A - B) / r ** 2
        return np.array([dA, dB, dS, dT])
    return rhs


def _poloidal(l, r0, r1, K_n, K_t, eta, eta_out, max_step, dlnn=None):
    """Coefficients (c, d) of the decaying solutions A = c r^k1 + d r^k2 outside, in
    the sphere's frame (the friction acts on the velocity relative to the sphere):
    translation at V = 1 (l = 1: the stream -V far away, k = -1, -3), strain at
    eps = 1 (l = 2: k = -2, -4). dlnn: d ln n/dr for the mass continuity
    div(n v) = 0 (None: div v = 0)."""
    rhs = _poloidal_rhs(l, K_n, K_t, eta, dlnn)
    ks = (-1, -3) if l == 1 else (-2, -4)
    f1, f2 = free_solution(l, ks[0], r1, eta_out), free_solution(l, ks[1], r1, eta_out)
    bg = -free_solution(1, 0, r1, eta_out) if l == 1 else free_solution(2, 1, r1, eta_out)

    def solve(m):
        return _linear_bvp(rhs, 4, m, ([[1.0, 0, 0, 0], [0, 0, 0, 1.0]], [0.0, 0.0]),
                           (np.eye(4), -np.column_stack([f1, f2]), bg), 2)[1]
    p = _extrapolated(solve, r0, r1, max_step)
    return float(p[0]), float(p[1])


def translation(r0, r1, K_n, K_t, eta, eta_out, max_step=None, dlnn=None):
    """Translational friction: returns (zeta_t, R_t), zeta_t = 6 pi eta_out R_t.
    Outside, A = -1 + c/r + ...: the Stokeslet of the force 4 pi eta_out c on the fluid."""
    _check_layer(r0, r1, eta_out)
    c, _ = _poloidal(1, r0, r1, K_n, K_t, eta, eta_out, max_step, dlnn)
    return 4.0 * math.pi * eta_out * c, 2.0 * c / 3.0


def stresslet(r0, r1, K_n, K_t, eta, eta_out, max_step=None, dlnn=None):
    """Stresslet in a pure strain: returns (the intrinsic viscosity 2.5 R_s^3 per
    unit volume of a sphere of radius 1, R_s); a no-slip sphere of radius R has
    A = -(5/2) R^3/r^2 + ... outside."""
    _check_layer(r0, r1, eta_out)
    c, _ = _poloidal(2, r0, r1, K_n, K_t, eta, eta_out, max_step, dlnn)
    Rs3 = -2.0 * c / 5.0
    return 2.5 * Rs3, math.copysign(abs(Rs3) ** (1.0 / 3.0), Rs3)


def _dpd_shear_weight(s, r_cut=1.0, m=400):
    """G(s): the shear-stress weight of DPD pairs (w = 1 - r/r_cut) whose separation
    has the component s normal to a plane: int d^2 r_perp w(r)^2 (r_x^2 s^2/r^2)."""
    rho = np.linspace(0.0, math.sqrt(max(r_cut * r_cut - s * s, 0.0)), m)
    rr = np.sqrt(s * s + rho ** 2)
    if s <= 0.0 or len(rho) < 2:
        return 0.0
    f = 2.0 * math.pi * rho * (1.0 - rr / r_cut) ** 2 * (rho ** 2 / 2.0) * s * s / rr ** 2
    return float(np.trapz(f, rho))


def dpd_pair_viscosity_fraction(z, h, n, n_bulk, r_cut=1.0, ns=201, nz=60):
    """The fraction of the bulk pair (dissipative) shear stress carried across a plane
    at height z above a flat wall, for a bead density n(h) (h: distance from the
    wall; n = 0 below the profile): pairs straddle the plane when their lower end
    lies within s (their normal separation) below it, weighted by
    n(z1) n(z1 + s)/n_bulk^2 and by the DPD shear weight G(s):

        f(z) = int_0^rc ds G(s) int_{z-s}^{z} dz1 n(z1) n(z1+s)/n_bulk^2 / int_0^rc ds G(s) s.

    A uniform fluid (n = n_bulk for h > 0) gives f(0) = 0 and f(z >= r_cut) = 1.
    Near a wall the DPD fluid loses the partners behind the wall, so a local
    continuum sees a lower viscosity there (the wall slip of DPD)."""
    h = np.asarray(h, dtype=float)
    n = np.asarray(n, dtype=float)
    S = np.linspace(0.0, r_cut, ns)
    G = np.array([_dpd_shear_weight(x, r_cut) for x in S])
    norm = float(np.trapz(G * S, S))

    def nf(x):
        return np.interp(x, h, n, left=0.0) / n_bulk
    out = []
    for zz in np.atleast_1d(z):
        inner = []
        for sv in S:
            z1 = np.linspace(zz - sv, zz, nz)
            inner.append(np.trapz(nf(z1) * nf(z1 + sv), z1))
        out.append(float(np.trapz(G * np.asarray(inner), S)) / norm)
    return np.asarray(out) if np.ndim(z) else out[0]


ETA_MODELS = ("uniform", "density", "pairs")


def layer_from_profile(h, n, a, trans_gamma, shell, gamma, dpd_shell, eta, eta_model="uniform", n_bulk=None,
                       h0=None, eta_kinetic=0.0, r_cut=1.0, eta_floor=1e-3, continuity="volume", smooth=0.02,
                       h_bulk=1.5):
    """The stick colloid's layer from a bead density profile n(h) on the gap h = r - a:
    K_t = n trans_gamma w^2 with w = 1 - max(h, 0)/shell (surface_friction), K_n = n
    gamma w_c^2 with w_c = 1 - max(h, 0)/dpd_shell (the colloid-solvent DPD), the
    core at r0 = a + h0 (default: where n first exceeds 1 % of n_bulk). The viscosity
    in the layer (eta outside):

    - ``"uniform"``: eta; the layer ends at a + max(shell, dpd_shell);
    - ``"density"``: eta n(h)/n_bulk (not below eta_floor eta);
    - ``"pairs"``: eta_kinetic n(h)/n_bulk + (eta - eta_kinetic) f(h) with f of
      dpd_pair_viscosity_fraction (flat-wall approximation on the gap); the layer
      ends at a + max(shells) + r_cut + 0.5, where f is 1 within 1 %.

    ``continuity``: ``"volume"`` (div v = 0) or ``"mass"``: the steady flow relative
    to the sphere conserves the beads, div(n v) = 0 with the equilibrium n(h)
    (smoothed with a Gaussian of width ``smooth``, and n = n_bulk beyond
    ``h_bulk``, where the layer then ends): the DPD fluid is compressible, and its
    density near the core is far from uniform. Rotation is the same either way.

    Returns a dict for radii()."""
    h = np.asarray(h, dtype=float)
    n = np.asarray(n, dtype=float)
    for name, v in (("a", a), ("trans_gamma", trans_gamma), ("shell", shell), ("gamma", gamma),
                    ("dpd_shell", dpd_shell), ("eta", eta), ("eta_kinetic", eta_kinetic), ("r_cut", r_cut)):
        strict = name in ("a", "shell", "dpd_shell", "eta", "r_cut")
        if not (math.isfinite(v) and v >= 0) or (strict and v == 0):
            raise ValueError(f"parameter '{name}' must be {'> 0' if strict else '>= 0'}, got {v}")
    if eta_kinetic > eta:
        raise ValueError(f"parameter 'eta_kinetic' must be <= eta = {eta}, got {eta_kinetic}")
    if continuity not in ("volume", "mass"):
        raise ValueError(f"parameter 'continuity' must be 'volume' or 'mass', got {continuity!r}")
    if eta_model not in ETA_MODELS:
        raise ValueError(f"parameter 'eta_model' must be one of {ETA_MODELS}, got {eta_model!r}")
    if h.shape != n.shape or h.ndim != 1 or len(h) < 2 or np.any(np.diff(h) <= 0) or np.any(n < 0):
        raise ValueError("parameters 'h', 'n': equal-length 1-d arrays, h increasing, n >= 0")
    nb = float(n_bulk) if n_bulk is not None else float(n[-1])
    if not (math.isfinite(nb) and nb > 0):
        raise ValueError(f"parameter 'n_bulk' must be > 0, got {nb}")
    if h0 is None:
        above = np.nonzero(n > 0.01 * nb)[0]
        h0 = float(h[above[0]]) if len(above) else 0.0
    r0 = a + h0
    r1 = a + max(shell, dpd_shell) + (r_cut + 0.5 if eta_model == "pairs" else 0.0)
    dlnn = None
    if continuity == "mass":
        if not (math.isfinite(smooth) and smooth >= 0):
            raise ValueError(f"parameter 'smooth' must be >= 0, got {smooth}")
        if not (math.isfinite(h_bulk) and h_bulk > max(shell, dpd_shell) and h_bulk <= h[-1]):
            raise ValueError(f"parameter 'h_bulk' must lie between the shells and the profile's end {h[-1]}, got {h_bulk}")
        r1 = max(r1, a + h_bulk)
        hg = np.arange(h[0], h[-1], 0.0025)
        ng = np.interp(hg, h, n)
        if smooth > 0:
            k = np.arange(-4 * smooth, 4 * smooth + 1e-12, 0.0025)
            wk = np.exp(-0.5 * (k / smooth) ** 2)
            ng = np.convolve(np.pad(ng, len(k) // 2, mode="edge"), wk / wk.sum(), mode="valid")[:len(hg)]
        ng = np.where(hg >= h_bulk, nb, ng)
        lg = np.gradient(np.log(np.maximum(ng, eta_floor * nb)), hg)

        def dlnn(r):
            return np.interp(r - a, hg, lg)

    def n_of(r):
        return np.interp(r - a, h, n)

    def K_t(r):
        w = np.clip(1.0 - np.maximum(r - a, 0.0) / shell, 0.0, None)
        return n_of(r) * trans_gamma * w * w

    def K_n(r):
        w = np.clip(1.0 - np.maximum(r - a, 0.0) / dpd_shell, 0.0, None)
        return n_of(r) * gamma * w * w

    if eta_model == "density":
        def eta_of(r):
            return eta * np.maximum(n_of(r) / nb, eta_floor)
    elif eta_model == "pairs":
        zg = np.arange(h0 - 0.05, r1 - a + 0.02, 0.02)
        fg = dpd_pair_viscosity_fraction(zg, h, n, nb, r_cut=r_cut)

        def eta_of(r):
            return np.maximum(eta_kinetic * n_of(r) / nb + (eta - eta_kinetic) * np.interp(r - a, zg, fg),
                              eta_floor * eta)
    else:
        def eta_of(r):
            return eta + 0.0 * r
    step = min(float(np.min(np.diff(h))), (max(shell, dpd_shell) - h0) / 200.0)
    return dict(r0=r0, r1=r1, K_t=K_t, K_n=K_n, eta=eta_of, eta_out=eta, max_step=step, h0=h0,
                eta_model=eta_model, dlnn=dlnn, continuity=continuity)


def radii(layer):
    """R_t, R_r, R_s (and the frictions) of a layer dict from layer_from_profile()."""
    kw = dict(max_step=layer["max_step"])
    d = dict(dlnn=layer.get("dlnn"))
    zt, Rt = translation(layer["r0"], layer["r1"], layer["K_n"], layer["K_t"], layer["eta"], layer["eta_out"], **kw, **d)
    zr, Rr = rotation(layer["r0"], layer["r1"], layer["K_t"], layer["eta"], layer["eta_out"], **kw)
    iv, Rs = stresslet(layer["r0"], layer["r1"], layer["K_n"], layer["K_t"], layer["eta"], layer["eta_out"], **kw, **d)
    return dict(R_t=Rt, R_r=Rr, R_s=Rs, zeta_t=zt, zeta_r=zr, intrinsic_viscosity=iv)
