"""Two equal rigid spheres in Stokes flow: squeeze and transverse resistances by a
regularized-Stokeslet boundary solve (issue 13, doc/suspensions.md section 7g).

Why: `bench/suspension_pair_resistance.py --mode frozen` measures, for two stick
colloids held at a gap h, the squeeze friction (relative motion along the line of
centres) and the transverse one (relative motion perpendicular to it, no rotation).
The squeeze has an exact bispherical series (`marble.theory.two_sphere_squeeze_resistance`);
the transverse mode (Jeffrey & Onishi's Y^A_11 - Y^A_12) has none in closed form. This
script computes both numerically, checks the squeeze against the exact series at the
same gap, and so gives the transverse value with a checked error.

Method (Cortez, Fauci & Medovikov, Phys. Fluids 17, 031504 (2005)): n point forces on
each sphere, regularized Stokeslets of blob size eps_j = ce x the local point spacing,
the rigid-body velocity imposed at every point. The points are graded towards the gap
(density ~ 1/(theta^2 + theta0^2) + const, theta from the point facing the other
sphere). The two spheres are mirror images in the mid-plane, and each mode is even or
odd under the mirror, so only sphere 1's forces are unknowns (3n). Every resistance is
normalized by the single sphere's drag computed with the same points (so the leading
discretization error of the blob cancels), and the results at n, 2n, 4n points are
extrapolated in the spacing (error ~ n^-1/2; Richardson with the observed ratio).

Modes, per sphere, in units of 6 pi eta a U (sphere 1 at -x, sphere 2 at +x):
    squeeze     U1 = +U e_x, U2 = -U e_x  ->  X^A_11 - X^A_12 (exact series to compare)
    transverse  U1 = +U e_y, U2 = -U e_y, no rotation  ->  Y^A_11 - Y^A_12

Reference forms printed with the transverse value:
    near field  (1/3) ln(1/xi) + C_Y  (Jeffrey & Onishi 1984, J. Fluid Mech. 139, 261,
                their g2 = 4 l (2 + l + 2 l^2)/(15 (1 + l)^3) = 1/6 at l = 1 for Y11 and -Y12;
                C_Y = 1.2720 from their tabulated O(1) constants A^Y_11(1) = 0.9983 and
                A^Y_12(1) = -0.2737, quoted without a copy of the paper: the same table's
                X constants, 0.9954 and -0.3502, give 1.3456, which is what the exact squeeze
                series gives, marble.theory.SQUEEZE_NEAR_FIELD_CONSTANT; and this solve gives
                1.276 +/- 0.01 for it, from xi = 0.1, 0.25 and 0.6: doc/suspensions.md 7t)
    far field   1/m with m = 1 - 3/(4s) - 1/(2 s^3), s = 2 + xi (the Rotne-Prager
                mobility of the relative transverse motion, inverted)

    build/pymarble bench/two_sphere_stokes.py --xi 0.25 0.6 1.0 [--n 300 600 1200] \
        [--json bench/results/two_sphere_stokes.json]

Cost: dense solves of 3n unknowns (three per level) with the reference BLAS; the default
n = 300, 600, 1200 takes ~25 CPU-s per gap, n = 2400 about 8 times the n = 1200 level.
"""
import argparse
import json
import math
import time

import numpy as np

from marble import theory

#: Jeffrey & Onishi's O(1) constant of Y^A_11 - Y^A_12 for equal spheres (see the module doc)
TRANSVERSE_NEAR_FIELD_CONSTANT = 0.9983 + 0.2737


def graded_points(n, theta0):
    """n points on the unit sphere, denser around +x: density ~ 1/(theta^2 + theta0^2) +
    4/pi^2 per unit area (theta the angle from +x). Returns (points (n, 3), local spacing (n,))."""
    if n < 10:
        raise ValueError(f"parameter 'n' must be >= 10, got {n}")
    if not theta0 > 0:
        raise ValueError(f"parameter 'theta0' must be > 0, got {theta0}")
    th = np.linspace(0.0, np.pi, 20001)
    rho = 1.0 / (th ** 2 + theta0 ** 2) + 4.0 / np.pi ** 2
    ds = 0.5 * (rho[1:] * np.sin(th[1:]) + rho[:-1] * np.sin(th[:-1])) * np.diff(th)
    cum = 2.0 * np.pi * np.concatenate([[0.0], np.cumsum(ds)])
    u = (np.arange(n) + 0.5) / n
    t = np.interp(u * cum[-1], cum, th)
    ph = np.pi * (1.0 + math.sqrt(5.0)) * np.arange(n)
    P = np.stack([np.cos(t), np.sin(t) * np.cos(ph), np.sin(t) * np.sin(ph)], axis=1)
    density = n * np.interp(t, th, rho) / cum[-1]
    return P, 1.0 / np.sqrt(density)


def stokeslet_matrix(Xt, Xs, eps):
    """(nt, 3, ns, 3) regularized Stokeslet velocities at Xt from unit forces at Xs,
    blob size eps[j] per source (viscosity 1): (8 pi)^-1 [delta (r^2 + 2 e^2) + x x]/(r^2 + e^2)^1.5."""
    d = Xt[:, None, :] - Xs[None, :, :]
    e2 = (np.asarray(eps) ** 2)[None, :]
    r2 = np.einsum("ijk,ijk->ij", d, d) + e2
    den = r2 ** -1.5
    M = np.empty((len(Xt), 3, len(Xs), 3))
    for a in range(3):
        for b in range(3):
            M[:, a, :, b] = d[:, :, a] * d[:, :, b] * den
        M[:, a, :, a] += (r2 + e2) * den
    return M / (8.0 * np.pi)


def pair_resistances(n, xi, ce=0.5, theta0=0.3, full=False):
    """Single-sphere drag / (6 pi) and the squeeze and transverse resistances (per sphere,
    over the single sphere's drag with the same points) of two unit spheres at gap xi.
    full=True solves the 6n x 6n system of both spheres instead of using the mirror
    symmetry (a check)."""
    if not xi > 0:
        raise ValueError(f"parameter 'xi' must be > 0, got {xi}")
    if not ce > 0:
        raise ValueError(f"parameter 'ce' must be > 0, got {ce}")
    P, h = graded_points(n, theta0)
    eps = ce * h
    X1 = P - [0.5 * (2.0 + xi), 0.0, 0.0]
    X2 = X1 * [-1.0, 1.0, 1.0]
    A = stokeslet_matrix(X1, X1, eps)
    f = np.linalg.solve(A.reshape(3 * n, 3 * n), np.tile([1.0, 0.0, 0.0], n))
    F0 = f.reshape(n, 3).sum(axis=0)[0]
    B = stokeslet_matrix(X1, X2, eps)
    out = {}
    modes = (("squeeze", 1.0, [1.0, 0.0, 0.0], 0), ("transverse", -1.0, [0.0, 1.0, 0.0], 1))
    if full:
        M = np.block([[A.reshape(3 * n, 3 * n), B.reshape(3 * n, 3 * n)],
                      [stokeslet_matrix(X2, X1, eps).reshape(3 * n, 3 * n),
                       stokeslet_matrix(X2, X2, eps).reshape(3 * n, 3 * n)]])
    for name, sign, v, c in modes:
        if full:
            f = np.linalg.solve(M, np.concatenate([np.tile(v, n), np.tile(np.negative(v), n)])).reshape(2 * n, 3)[:n]
        else:
            # sphere 2's force at the mirror point: +R f1 (squeeze, even) or -R f1 (transverse, odd)
            Mm = (A + sign * B * np.array([-1.0, 1.0, 1.0])[None, None, None, :]).reshape(3 * n, 3 * n)
            f = np.linalg.solve(Mm, np.tile(v, n)).reshape(n, 3)
        out[name] = f.sum(axis=0)[c] / F0
    return F0 / (6.0 * np.pi), out


def extrapolate(values):
    """Richardson extrapolation of a sequence at n, 2n, 4n, ... points (error ~ spacing):
    returns (value, error estimate). Two levels: the ratio 1/sqrt(2) assumed, error =
    the correction; three or more: the observed ratio of the last two differences, error
    = the difference from the two-level value."""
    v = np.asarray(values, dtype=float)
    if len(v) < 2:
        return float(v[-1]), float("nan")
    r0 = 1.0 / math.sqrt(2.0)
    two = v[-1] + (v[-1] - v[-2]) * r0 / (1.0 - r0)
    if len(v) < 3 or (v[-1] - v[-2]) * (v[-2] - v[-3]) <= 0:
        return float(two), float(abs(two - v[-1]))
    r = (v[-1] - v[-2]) / (v[-2] - v[-3])
    if not 0 < r < 0.95:
        return float(two), float(abs(two - v[-1]))
    three = v[-1] + (v[-1] - v[-2]) * r / (1.0 - r)
    return float(three), float(max(abs(three - two), 1e-4 * abs(three)))


def transverse_near_field(xi):
    """(1/3) ln(1/xi) + C_Y: Jeffrey & Onishi's near-field form of Y^A_11 - Y^A_12 for equal spheres."""
    return math.log(1.0 / xi) / 3.0 + TRANSVERSE_NEAR_FIELD_CONSTANT


def transverse_far_field(xi):
    """1/m, m = 1 - 3/(4s) - 1/(2 s^3), s = 2 + xi: the inverted Rotne-Prager relative mobility."""
    s = 2.0 + xi
    return 1.0 / (1.0 - 0.75 / s - 0.5 / s ** 3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--xi", type=float, nargs="+", default=[0.25, 0.6, 1.0], help="gaps h/a")
    ap.add_argument("--n", type=int, nargs="+", default=[300, 600, 1200],
                    help="points per sphere, each twice the one before")
    ap.add_argument("--ce", type=float, default=0.5, help="blob size over the local spacing")
    ap.add_argument("--theta0", type=float, default=0.3, help="width of the grading towards the gap")
    ap.add_argument("--json", help="write the results (JSON) here")
    args = ap.parse_args()
    rows = []
    for xi in args.xi:
        t0 = time.process_time()
        levels = [pair_resistances(n, xi, args.ce, args.theta0) for n in args.n]
        sq = [lv[1]["squeeze"] for lv in levels]
        tr = [lv[1]["transverse"] for lv in levels]
        sq_x, sq_e = extrapolate(sq)
        tr_x, tr_e = extrapolate(tr)
        exact = theory.two_sphere_squeeze_resistance(xi)
        row = dict(xi=xi, n=args.n, ce=args.ce, theta0=args.theta0, single=[lv[0] for lv in levels],
                   squeeze=sq, squeeze_extrapolated=sq_x, squeeze_err=sq_e, squeeze_exact=exact,
                   transverse=tr, transverse_extrapolated=tr_x, transverse_err=tr_e,
                   transverse_near_field=transverse_near_field(xi), transverse_far_field=transverse_far_field(xi),
                   cpu_s=time.process_time() - t0)
        rows.append(row)
        print(f"xi {xi}: squeeze {' '.join(f'{x:.4f}' for x in sq)} -> {sq_x:.4f} +/- {sq_e:.4f} "
              f"(exact {exact:.4f}, {100 * (sq_x / exact - 1):+.2f} %); transverse {' '.join(f'{x:.4f}' for x in tr)} "
              f"-> {tr_x:.4f} +/- {tr_e:.4f} (near field {row['transverse_near_field']:.4f}, far field "
              f"{row['transverse_far_field']:.4f}); {row['cpu_s']:.0f} CPU-s", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(dict(bench="two_sphere_stokes", rows=rows), fh, indent=1)


if __name__ == "__main__":
    main()
