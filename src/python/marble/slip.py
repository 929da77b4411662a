"""Slip length and hydrodynamic boundary of tunable-slip walls (doc/walls.md), and
slip length on request for walls and marble colloids (doc/walls.md, doc/marble.md)::

  g, g_err = gamma_for_slip_length(0.5, surface="wall")    # or surface="marble"
  b, b_err = slip_length_for_gamma(g, "wall")
  calibrate(surface="wall", gammas=[...], out="curve.json", rho=4.0)  # own conditions

from measured calibration curves b(gamma) shipped in marble/data/slip_*.json.

A channel of DPD fluid between two walls at z = 0 and z = L (normals +z / -z,
periodic in x and y). A Poiseuille run (body force g along x on every bead) and
a Couette run (walls moving at -v_w / +v_w along x) give two profiles v_x(z).
With the partial-slip boundary condition v(z_B) - v_wall = delta_B v'(z_B) at
z_B and L - z_B (Smiatek, Allen, Schmid 2008; reference.md section 4)::

  Poiseuille: v(z) = A [(z - z_B)(L - z_B - z) + delta_B (L - 2 z_B)],  A = rho g / (2 eta)
  Couette:    v(z) = v_w (2 z - L) / (L - 2 z_0),   z_0 = z_B - delta_B.

So the Couette line's zero (relative to the wall) is z_0 = z_B - delta_B, the
parabola's curvature gives eta, and its zero z_P obeys::

  z_P (L - z_P) = z_0 (L - z_0) + delta_B^2,

i.e. delta_B^2 = (z_P - z_0)(L - z_P - z_0): the slip length is fixed by how far
the Poiseuille zero lies inside the Couette zero (z_P - z_0 ~ delta_B^2 / L). The
difference is small, so both zeros must be measured precisely: the profiles are
(anti)symmetrised about the mid-plane, fitted in the bulk only (beyond the
friction layer, where the Stokes solution is exact), and every error is a
jackknife over blocks much longer than the slowest hydrodynamic mode (bins of
a profile are strongly correlated, so least-squares covariances of independent
bins would underestimate them).

When z_P < z_0 (d2 = (z_P - z_0)(L - z_P - z_0) < 0) no real (z_B, delta_B)
fits both flows; that happens in the continuum model for gamma_L >~ 1, where
the boundary is effectively no-slip inside the layer. ``delta_B`` is then
reported as -sqrt(-d2) (flagged by ``d2 < 0``) and z_B as (z_P + z_0)/2.

The approximate theory (small gamma_L, uniform fluid across the layer, layer
starting where the fluid starts) gives z_B ~ layer start and
delta_B / z_c ~ 2 eta / (z_c^2 rho gamma_L) - 7/15 (``smiatek_slip_length``).
"""
import numpy as np

from .shapes import Wall


def smiatek_slip_length(gamma_L, eta=1.23, rho=3.0, z_c=1.0):
    """delta_B ~ z_c [2 eta / (z_c^2 rho gamma_L) - 7/15] (small-gamma_L approximation,
    measured from the start of the friction layer; reference.md section 4)."""
    return z_c * (2.0 * eta / (z_c ** 2 * rho * gamma_L) - 7.0 / 15.0)


def continuum_slip(gamma_L, eta=1.23, rho=3.0, z_c=1.0, height=10.0, n=2001):
    """The model behind the formula, solved exactly: a uniform Stokes fluid on
    [0, height] (0 = layer start, stress-free edges) with friction
    rho gamma_L w(z) (v - v_wall), w = 1 - z/z_c in both layers. Returns z_P, z_0
    (measured from the layer start), d2, delta_B and z_B as ``analyse`` defines
    them (finite differences on n points)."""
    z = np.linspace(0.0, height, n)
    h = z[1] - z[0]
    w = np.clip(1.0 - z / z_c, 0.0, None) + np.clip(1.0 - (height - z) / z_c, 0.0, None)

    def solve(g, vw):
        vwall = np.where(z < height / 2, -vw, vw)
        A = np.zeros((n, n))
        b = -rho * g * np.ones(n) - rho * gamma_L * w * vwall
        i = np.arange(1, n - 1)
        A[i, i - 1] = A[i, i + 1] = eta / h ** 2
        A[i, i] = -2.0 * eta / h ** 2 - rho * gamma_L * w[i]
        # stress-free edges (second-order one-sided): v'(0) = v'(L) = 0
        A[0, :3] = [-3.0, 4.0, -1.0]
        A[-1, -3:] = [1.0, -4.0, 3.0]
        b[0] = b[-1] = 0.0
        return np.linalg.solve(A, b)

    sel = (z > z_c + 0.5) & (z < height - z_c - 0.5)
    x = z[sel] - height / 2
    vp = solve(1e-2, 0.0)
    vc = solve(0.0, 0.1)
    c0, c2 = np.linalg.lstsq(np.column_stack([np.ones_like(x), x * x]), vp[sel], rcond=None)[0]
    S = np.sum(x * vc[sel]) / np.sum(x * x)
    z_p = height / 2 - np.sqrt(-c0 / c2)
    z_0 = height / 2 - 0.1 / S
    d2 = (z_p - z_0) * (height - z_p - z_0)
    delta = np.sign(d2) * np.sqrt(abs(d2))
    z_b = z_0 + delta if d2 >= 0 else 0.5 * (z_p + z_0)
    return {"z_P": z_p, "z_0": z_0, "d2": d2, "delta_B": delta, "z_B": z_b}


#: Gibbs dividing surface of an ideal-gas (pure DPD) fluid at a WCA wall
#: (eps = sigma = 1, cut 2^(1/6)): int_0^inf (1 - exp(-V(z)/kT)) dz at kT = 1.
WCA_FLUID_EDGE = 1.016


def make_channel(marble, box_xy=6.0, height=10.0, rho=3.0, gamma_dpd=5.0, gamma_L=1.0,
                 z_c=1.0, layer_offset=WCA_FLUID_EDGE, kT=1.0, dt=0.01, seed=1, wall_velocity=0.0,
                 body_force=0.0):
    """A DPD fluid (the marble paper's solvent, reference.md section 2) between two
    WCA walls with tunable-slip friction layers [layer_offset, layer_offset + z_c].

    The fluid is an ideal gas (no bead-bead conservative force), so its density
    near a wall is rho exp(-V_WCA(z)/kT): it rises from 0 at z ~ 0.9 to rho at
    z ~ 1.1, with its Gibbs dividing surface at z = 1.016 (kT = 1). The default
    layer_offset = 1.016 starts the friction layer there, so the friction on the
    real (depleted) density profile, int rho(z) w(z) dz with w = 1 below the
    offset, equals that on a uniform fluid filling the layer, as the slip formula
    assumes (offset 1.0 gives 3 % less, 0.9 gives 22 % less). Beads fill
    [layer_offset, height - layer_offset] at density rho."""
    system = marble.System(box_l=[box_xy, box_xy, height])
    system.periodicity = [True, True, False]
    system.time_step = dt
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    z_lo, z_hi = layer_offset, height - layer_offset
    n = int(round(rho * box_xy * box_xy * (z_hi - z_lo)))
    pos = np.column_stack([rng.random(n) * box_xy, rng.random(n) * box_xy,
                           z_lo + rng.random(n) * (z_hi - z_lo)])
    system.part.add(pos=pos, v=rng.normal(size=(n, 3)) * np.sqrt(kT), type=0,
                    ext_force=[body_force, 0.0, 0.0])
    system.thermostat.set_dpd(kT=kT, seed=seed)
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=gamma_dpd, k=1,
                                                 r_cut=1.0)
    for wtype, normal, dist, v in ((1, [0, 0, 1], 0.0, -wall_velocity),
                                   (2, [0, 0, -1], -height, wall_velocity)):
        system.constraints.add(shape=Wall(normal=normal, dist=dist), particle_type=wtype,
                               velocity=[v, 0.0, 0.0])
        system.non_bonded_inter[wtype, 0].lennard_jones.set_params(
            epsilon=1.0, sigma=1.0, cutoff=2.0 ** (1.0 / 6.0), shift="auto")
        system.non_bonded_inter[wtype, 0].tunable_slip.set_params(
            gamma=gamma_L, r_cut=z_c, offset=layer_offset)
    return system


def sample_profile(system, n_steps, every=10, bin_width=0.25, n_blocks=20, progress=None):
    """Sample v_x(z) and the density over n_steps in n_blocks blocks.

    Returns a dict: z (bin centres), v (mean v_x), err (block error), dens,
    and the per-block sums ``sum_v`` and ``count`` (n_blocks x n_bins) that
    ``analyse`` jackknifes."""
    height = system.box_l[2]
    n_bins = max(2, int(round(height / bin_width)))
    edges = np.linspace(0.0, height, n_bins + 1)
    parts = system.part.all()
    per_block = max(1, n_steps // every // n_blocks)
    sums = np.zeros((n_blocks, n_bins))
    counts = np.zeros((n_blocks, n_bins))
    for k in range(per_block * n_blocks):
        system.integrator.run(every)
        z = parts.pos_folded[:, 2]
        vx = parts.v[:, 0]
        idx = np.clip(np.digitize(z, edges) - 1, 0, n_bins - 1)
        b = k // per_block
        sums[b] += np.bincount(idx, weights=vx, minlength=n_bins)
        counts[b] += np.bincount(idx, minlength=n_bins)
        if progress:
            progress(k + 1, per_block * n_blocks)
    with np.errstate(invalid="ignore", divide="ignore"):
        block_means = sums / counts
        v = sums.sum(0) / counts.sum(0)
    err = np.full(n_bins, np.nan)
    ok = np.all(counts > 0, axis=0)  # bins inside the wall repulsion stay NaN
    if n_blocks > 1:
        err[ok] = np.std(block_means[:, ok], axis=0, ddof=1) / np.sqrt(n_blocks)
    area = system.box_l[0] * system.box_l[1]
    dens = counts.sum(0) / (per_block * n_blocks) / (area * np.diff(edges))
    return {"z": 0.5 * (edges[1:] + edges[:-1]), "v": v, "err": err, "dens": dens,
            "sum_v": sums, "count": counts, "height": height, "area": area,
            "bin_width": height / n_bins, "samples_per_block": per_block,
            "time": per_block * n_blocks * every * system.time_step}


def _jackknife(fn, n_blocks):
    """Estimate with all blocks, and the jackknife standard error."""
    full = np.asarray(fn(np.ones(n_blocks, dtype=bool)), dtype=float)
    reps = []
    for j in range(n_blocks):
        keep = np.ones(n_blocks, dtype=bool)
        keep[j] = False
        reps.append(fn(keep))
    reps = np.asarray(reps, dtype=float)
    err = np.sqrt((n_blocks - 1) / n_blocks * np.sum((reps - reps.mean(0)) ** 2, axis=0))
    return full, err


def _half_profile(prof, keep, parity):
    """Pooled v_x over the kept blocks, folded onto the lower half:
    (v(z) + parity v(L - z)) / 2 for the bins below the mid-plane."""
    s = prof["sum_v"][keep].sum(0)
    c = prof["count"][keep].sum(0)
    v = s / np.maximum(c, 1)
    n = len(v) // 2
    return 0.5 * (v[:n] + parity * v[::-1][:n]), 0.5 * (c[:n] + c[::-1][:n])


def analyse(poiseuille, couette, body_force, wall_velocity, fit_min=2.25, fit_max=None):
    """Fit both profiles in the bulk window [fit_min, L - fit_min] (by default
    from 0.25 beyond the friction layer of ``make_channel`` to the mid-plane) and
    solve for eta, z_P, z_0, z_B, delta_B. Each quantity comes with a jackknife
    error (key + '_err'). Also returns the Couette velocity relative to the
    wall at z_B and at z_P ('v_couette_at_zB', 'v_couette_at_zP') and the bulk
    density 'rho'."""
    L = poiseuille["height"]
    zbin = poiseuille["z"][: len(poiseuille["z"]) // 2]
    hi = L / 2 if fit_max is None else fit_max
    sel = (zbin > fit_min) & (zbin < hi)
    nb = poiseuille["sum_v"].shape[0]
    if couette["sum_v"].shape[0] != nb:
        raise ValueError("both profiles need the same number of blocks")
    norm = 1.0 / (poiseuille["samples_per_block"] * poiseuille["area"] * poiseuille["bin_width"])

    def derived(keep):
        vp, cp = _half_profile(poiseuille, keep, +1)
        vc, cc = _half_profile(couette, keep, -1)
        x = zbin[sel] - L / 2
        # Poiseuille: v = c0 + c2 x^2 (symmetric); weights ~ counts (thermal noise per bin).
        w = cp[sel]
        M = np.column_stack([np.ones_like(x), x * x])
        c0, c2 = np.linalg.lstsq(M * np.sqrt(w)[:, None], vp[sel] * np.sqrt(w), rcond=None)[0]
        # Couette: v = S x (antisymmetric), relative to the lower wall v + v_w.
        wc = cc[sel]
        S = np.sum(wc * x * vc[sel]) / np.sum(wc * x * x)
        rho = np.sum(cp[sel]) / np.sum(keep) / np.sum(sel) * norm
        eta = -rho * body_force / (2.0 * c2)
        z_p = L / 2 - np.sqrt(c0 / -c2) if c0 / -c2 > 0 else np.nan
        z_0 = L / 2 - wall_velocity / S
        d2 = (z_p - z_0) * (L - z_p - z_0)
        delta = np.sign(d2) * np.sqrt(abs(d2))
        z_b = z_0 + delta if d2 >= 0 else 0.5 * (z_p + z_0)
        vc_zb = S * (z_b - L / 2) + wall_velocity  # relative to the lower wall (-v_w)
        vc_zp = S * (z_p - L / 2) + wall_velocity
        return [eta, z_p, z_0, d2, delta, z_b, vc_zb, vc_zp, rho, c2, S]

    full, err = _jackknife(derived, nb)
    keys = ["eta", "z_P", "z_0", "d2", "delta_B", "z_B", "v_couette_at_zB", "v_couette_at_zP",
            "rho", "curvature", "shear_rate"]
    out = {}
    for k, f, e in zip(keys, full, err):
        out[k] = float(f)
        out[k + "_err"] = float(e)
    out["fit_window"] = (fit_min, hi)
    return out


def slip_length_at_boundary(z_P, z_P_err, z_0, z_0_err, z_B, height):
    """delta_B of one two-flow run when the hydrodynamic boundary z_B is known.

    With z_B fixed, both zeros give delta_B linearly (analyse's relations)::

      Couette:     z_0 = z_B - delta_B
                   delta_C = z_B - z_0
      Poiseuille:  z_P (L - z_P) = z_B (L - z_B) + delta_B (2 z_B - L)
                   delta_P = [z_B (L - z_B) - z_P (L - z_P)] / (L - 2 z_B)

    with errors sigma(z_0) and abs(L - 2 z_P) / (L - 2 z_B) sigma(z_P). Returns
    (delta_B, its error, delta_C, delta_P): the weighted mean of the two, whose
    error is of the order of the zeros' (~0.01-0.02), against the
    ~(L/2b) sigma(z) of the unconstrained d2 route. The error of z_B itself is
    not included (it is common to every run analysed with the same z_B)."""
    L = float(height)
    d_c, s_c = z_B - z_0, z_0_err
    d_p = (z_B * (L - z_B) - z_P * (L - z_P)) / (L - 2.0 * z_B)
    s_p = abs(L - 2.0 * z_P) / (L - 2.0 * z_B) * z_P_err
    w_c, w_p = 1.0 / s_c ** 2, 1.0 / s_p ** 2
    return ((w_c * d_c + w_p * d_p) / (w_c + w_p), 1.0 / np.sqrt(w_c + w_p), d_c, d_p)


def common_boundary_fit(points, height):
    """Joint analysis of the wall calibration points with one hydrodynamic
    boundary z_B for all of them (doc/walls.md, "Resolution near b = 0.5").

    Each point's two-flow run fixes z_B and delta_B exactly (two zeros, two
    unknowns), but near b ~ 0.5 the pair is ill-conditioned: delta_B^2 ~
    (z_P - z_0) L, so delta_B's error is ~(L / 2 b) times the zeros'. The
    measured z_B does not depend on gamma_L within its errors (doc/walls.md), so
    one z_B is fitted to all points (chi^2 of delta_C - delta_P, see
    slip_length_at_boundary, minimised over z_B) and each delta_B follows from
    its own zeros at that z_B. ``points``: dicts with z_P, z_P_err, z_0,
    z_0_err (calibrate()'s wall points); ``height``: the channel height.

    Returns a dict: z_B, z_B_err (Delta chi^2 = 1), chi2, dof (= points - 1: the
    consistency test of a common z_B), and per point (lists) delta_B,
    delta_B_err_stat (z_B held fixed), delta_B_err (with z_B's error, which
    moves every point the same way: d delta_B / d z_B ~ 1)."""
    pts = [p for p in points if np.isfinite(p.get("z_P", np.nan)) and np.isfinite(p.get("z_0", np.nan))]
    if len(pts) < 2:
        raise ValueError("common_boundary_fit needs >= 2 points with finite z_P and z_0")
    L = float(height)

    def chi2(zb):
        c = 0.0
        for p in pts:
            _, _, dc, dp = slip_length_at_boundary(p["z_P"], p["z_P_err"], p["z_0"], p["z_0_err"],
                                                   zb, L)
            sp = abs(L - 2.0 * p["z_P"]) / (L - 2.0 * zb) * p["z_P_err"]
            c += (dc - dp) ** 2 / (p["z_0_err"] ** 2 + sp ** 2)
        return c

    grid = np.linspace(0.0, 0.4 * L, 801)
    vals = np.array([chi2(z) for z in grid])
    k = int(np.argmin(vals))
    lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    for _ in range(100):   # golden section on the bracket
        m1, m2 = lo + 0.382 * (hi - lo), lo + 0.618 * (hi - lo)
        if chi2(m1) < chi2(m2):
            hi = m2
        else:
            lo = m1
    zb = 0.5 * (lo + hi)
    c0 = chi2(zb)
    h = 1e-3
    curv = (chi2(zb + h) - 2.0 * c0 + chi2(zb - h)) / h ** 2
    zb_err = float(np.sqrt(2.0 / curv)) if curv > 0 else np.inf
    out = {"z_B": float(zb), "z_B_err": zb_err, "chi2": float(c0), "dof": len(pts) - 1,
           "delta_B": [], "delta_B_err_stat": [], "delta_B_err": []}
    for p in points:
        if p not in pts:
            for key in ("delta_B", "delta_B_err_stat", "delta_B_err"):
                out[key].append(float("nan"))
            continue
        args = (p["z_P"], p["z_P_err"], p["z_0"], p["z_0_err"])
        d, e = slip_length_at_boundary(*args, zb, L)[:2]
        slope = (slip_length_at_boundary(*args, zb + h, L)[0]
                 - slip_length_at_boundary(*args, zb - h, L)[0]) / (2 * h)
        out["delta_B"].append(float(d))
        out["delta_B_err_stat"].append(float(e))
        out["delta_B_err"].append(float(np.hypot(e, slope * zb_err)))
    return out


def refit_common_boundary(curve, out=None):
    """A wall calibration curve (dict or path, calibrate()'s format) re-analysed
    with common_boundary_fit: every point's b becomes the delta_B at the common
    z_B (b_err includes z_B's error); the two-flow values are kept as
    b_two_flow, b_two_flow_err, and measurement['estimator'] records the fit
    (z_B, z_B_err, chi2, dof). Points with delta_B <= 0 get use = False.
    Written to ``out`` if given; returns the new dict."""
    import copy
    data = copy.deepcopy(load_curve("wall", curve))
    height = data["measurement"]["height"]
    for p in data["points"]:   # a second refit starts from the two-flow values
        if "b_two_flow" in p:
            p["b"], p["b_err"] = p["b_two_flow"], p["b_two_flow_err"]
    fit = common_boundary_fit(data["points"], height)
    for p, d, e, es in zip(data["points"], fit["delta_B"], fit["delta_B_err"],
                           fit["delta_B_err_stat"]):
        p["b_two_flow"], p["b_two_flow_err"] = p["b"], p["b_err"]
        if np.isfinite(d):
            p.update(b=d, b_err=e, b_err_stat=es, use=bool(d > 0))
    data["measurement"]["estimator"] = {
        "name": "common_boundary", "z_B": fit["z_B"], "z_B_err": fit["z_B_err"],
        "chi2": fit["chi2"], "dof": fit["dof"],
        "note": "b = delta_B at one hydrodynamic boundary z_B for all points "
                "(marble.slip.common_boundary_fit); b_two_flow: each point's own z_B"}
    if out is not None:
        tmp = out + ".tmp"
        with open(tmp, "w") as f:
            json.dump(data, f, indent=1)
            f.write("\n")
        os.replace(tmp, out)
    return data


def measure_slip(marble, gamma_L, n_steps=200000, equil_steps=10000, body_force=0.1,
                 wall_velocity=3.0, height=10.0, box_xy=6.0, seed=1, rho=3.0, n_blocks=20,
                 fit_min=None, progress=None, **channel_kwargs):
    """Run a Poiseuille and a Couette channel; return analyse()'s dict plus the
    profiles ('poiseuille', 'couette') and the run parameters."""
    prof = {}
    for kind in ("poiseuille", "couette"):
        system = make_channel(marble, box_xy=box_xy, height=height, gamma_L=gamma_L, rho=rho,
                              seed=seed + (kind == "couette"),
                              body_force=body_force if kind == "poiseuille" else 0.0,
                              wall_velocity=wall_velocity if kind == "couette" else 0.0,
                              **channel_kwargs)
        system.integrator.run(equil_steps)
        prof[kind] = sample_profile(system, n_steps, n_blocks=n_blocks, progress=progress)
    if fit_min is None:
        fit_min = (channel_kwargs.get("layer_offset", WCA_FLUID_EDGE)
                   + channel_kwargs.get("z_c", 1.0) + 0.25)
    res = analyse(prof["poiseuille"], prof["couette"], body_force, wall_velocity, fit_min=fit_min)
    res.update(prof)
    res.update({"gamma_L": gamma_L, "n_steps": n_steps, "height": height, "box_xy": box_xy,
                "body_force": body_force, "wall_velocity": wall_velocity})
    return res


# --------------------------------------------------------------------------
# Slip calibration: b(gamma) measured once, inverted on request (issue 14)
# --------------------------------------------------------------------------
#
# A calibration curve is a JSON file (format "marble-slip-calibration/1"):
#   surface      "wall" or "marble"
#   parameter    the coupling it calibrates: "gamma_L" (tunable-slip wall) or
#                "gamma" (the marble's surface friction)
#   conditions   what the slip length depends on (solvent: rho, gamma_dpd, a,
#                kT, dt, r_cut, weight_function, k; wall: z_c, layer_offset,
#                wall potential; marble: radius, marble_r_cut, coupling, ...)
#   measurement  how it was measured (box, forcing, run lengths, seed, eta,
#                Marble git revision, date, CPU time)
#   points       one per gamma: b, b_err, "use" (False: no resolved slip
#                length, kept for the record) and the raw analysis numbers
# The shipped curves are marble/data/slip_wall.json and slip_marble.json.

import json
import os
import subprocess
import time
from collections import namedtuple

FORMAT = "marble-slip-calibration/1"
DATA_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
_SURFACES = {"wall": ("slip_wall.json", "gamma_L"), "marble": ("slip_marble.json", "gamma")}

#: The solvent both shipped curves were measured in (the marble paper's,
#: reference.md section 2): DPD with w_D = (1 - r/r_cut)^2, no conservative force.
SOLVENT_CONDITIONS = {"rho": 3.0, "gamma_dpd": 5.0, "a": 0.0, "kT": 1.0, "dt": 0.01,
                      "r_cut": 1.0, "weight_function": 1, "k": 1.0, "integrator": "velocity_verlet"}
#: Wall set-up of make_channel (WCA wall eps = sigma = 1, friction layer of width z_c).
WALL_CONDITIONS = dict(SOLVENT_CONDITIONS, z_c=1.0, layer_offset=WCA_FLUID_EDGE,
                       wall_potential="WCA epsilon=1 sigma=1")
#: Marble set-up of make_marble_box (add_marble defaults: WCA excluded volume,
#: neutrally buoyant, rotating, tunable-slip coupling with w = 1 - h/r_cut).
MARBLE_CONDITIONS = dict(SOLVENT_CONDITIONS, radius=2.0, marble_r_cut=1.0, marble_k=1.0,
                         marble_weight_function=1, coupling="tunable_slip",
                         excluded_volume="WCA epsilon=1 sigma=1 offset=R-1")
#: Viscosity of the solvent above (rho = 3, DPD gamma = 5, dt = 0.01, VV):
#: reverse Poiseuille in a periodic 12 x 12 x 16 box, 2000 tau (doc/dpd.md,
#: test_dpd_viscosity_paper.py). Used to turn marble drags into slip lengths.
ETA_SOLVENT, ETA_SOLVENT_ERR = 1.273, 0.007

#: gamma_for_slip_length's answer: the coupling and its standard error.
SlipCoupling = namedtuple("SlipCoupling", ["gamma", "gamma_err"])


def _git_revision():
    here = os.path.dirname(os.path.abspath(__file__))
    try:
        out = subprocess.run(["git", "-C", here, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def _check_surface(surface):
    if surface not in _SURFACES:
        raise ValueError(f"parameter 'surface' must be 'wall' or 'marble', got {surface!r}")
    return surface


def load_curve(surface="wall", curve=None):
    """The calibration curve as a dict: the shipped one for ``surface``
    ("wall" or "marble"), or ``curve`` (a path written by calibrate(), or a
    dict of the same form)."""
    _check_surface(surface)
    if curve is None:
        curve = os.path.join(DATA_DIR, _SURFACES[surface][0])
    if isinstance(curve, dict):
        data = curve
    else:
        with open(curve) as f:
            data = json.load(f)
    if data.get("format") != FORMAT:
        raise ValueError(f"parameter 'curve': not a slip calibration ({FORMAT}) file")
    if data.get("surface") != surface:
        raise ValueError(f"parameter 'curve' holds a {data.get('surface')!r} calibration, "
                         f"not {surface!r}")
    return data


def _check_conditions(data, conditions):
    """ValueError unless every requested condition equals the curve's."""
    known = data["conditions"]
    for key, want in conditions.items():
        if key not in known:
            raise ValueError(f"unknown condition {key!r} for the {data['surface']} slip curve; "
                             f"it records {sorted(known)}")
        have = known[key]
        if isinstance(have, str) or isinstance(want, str):
            same = str(have) == str(want)
        else:
            same = bool(np.isclose(float(want), float(have), rtol=1e-6, atol=1e-12))
        if not same:
            raise ValueError(
                f"condition {key}={want!r} differs from the {data['surface']} calibration, "
                f"which was measured at {key}={have!r} (conditions: {known}); the slip length "
                f"depends on it: measure a curve at your conditions with "
                f"marble.slip.calibrate(surface={data['surface']!r}, ..., out=path) and pass "
                f"curve=path")


def _pava_decreasing(y, w):
    """Weighted isotonic (non-increasing) regression; returns blocks as lists of indices."""
    blocks = [[i] for i in range(len(y))]
    vals = [float(y[i]) for i in range(len(y))]
    wts = [float(w[i]) for i in range(len(y))]
    i = 0
    while i < len(blocks) - 1:
        if vals[i] <= vals[i + 1]:  # violates strict decrease: pool
            wt = wts[i] + wts[i + 1]
            vals[i] = (wts[i] * vals[i] + wts[i + 1] * vals[i + 1]) / wt
            wts[i] = wt
            blocks[i] += blocks[i + 1]
            del blocks[i + 1], vals[i + 1], wts[i + 1]
            i = max(i - 1, 0)
        else:
            i += 1
    return blocks


def _nodes(data):
    """Interpolation nodes (log gamma, log b, sigma of log b), strictly
    decreasing in log b. Points without a resolved slip length are left out;
    points that break monotonicity (noise) are pooled (weighted means)."""
    pts = sorted((p for p in data["points"] if p.get("use", True) and p["b"] > 0),
                 key=lambda p: p["gamma"])
    if len(pts) < 2:
        raise ValueError("the slip calibration needs >= 2 resolved points")
    x = np.log([p["gamma"] for p in pts])
    y = np.log([p["b"] for p in pts])
    s = np.array([p["b_err"] / p["b"] for p in pts])
    w = 1.0 / s ** 2
    X, Y, S = [], [], []
    for blk in _pava_decreasing(y, w):
        wb = w[blk]
        X.append(float(np.sum(wb * x[blk]) / np.sum(wb)))
        Y.append(float(np.sum(wb * y[blk]) / np.sum(wb)))
        S.append(float(1.0 / np.sqrt(np.sum(wb))))
    if len(X) < 2:
        raise ValueError("the slip calibration is not monotone enough to interpolate")
    return np.array(X), np.array(Y), np.array(S)


def _pchip(x, y, xq):
    """Fritsch-Carlson monotone cubic Hermite interpolation (as scipy's PCHIP)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    h = np.diff(x)
    d = np.diff(y) / h
    n = len(x)
    m = np.zeros(n)
    if n == 2:
        m[:] = d[0]
    else:
        for k in range(1, n - 1):
            if d[k - 1] * d[k] > 0:
                w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
                m[k] = (w1 + w2) / (w1 / d[k - 1] + w2 / d[k])
        for k, (h0, h1, d0, d1) in ((0, (h[0], h[1], d[0], d[1])),
                                    (n - 1, (h[-1], h[-2], d[-1], d[-2]))):
            mk = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
            if np.sign(mk) != np.sign(d0):
                mk = 0.0
            elif np.sign(d0) != np.sign(d1) and abs(mk) > abs(3 * d0):
                mk = 3 * d0
            m[k] = mk
    xq = np.asarray(xq, float)
    i = np.clip(np.searchsorted(x, xq) - 1, 0, n - 2)
    t = (xq - x[i]) / h[i]
    h00, h10 = (1 + 2 * t) * (1 - t) ** 2, t * (1 - t) ** 2
    h01, h11 = t * t * (3 - 2 * t), t * t * (t - 1)
    val = h00 * y[i] + h10 * h[i] * m[i] + h01 * y[i + 1] + h11 * h[i] * m[i + 1]
    dval = ((6 * t * t - 6 * t) * y[i] + (3 * t * t - 4 * t + 1) * h[i] * m[i]
            + (-6 * t * t + 6 * t) * y[i + 1] + (3 * t * t - 2 * t) * h[i] * m[i + 1]) / h[i]
    return val, dval


def _curve_at(nodes, xq):
    """log b at log gamma = xq, its slope, and the standard error of log b:
    the nodes' errors propagated through the interpolation (quadrature, by
    linearisation) plus the interpolation error, estimated as the difference
    between the monotone cubic and straight lines in (log gamma, log b): zero
    at the nodes, largest between them."""
    X, Y, S = nodes
    yq, dy = _pchip(X, Y, xq)
    var = np.zeros_like(np.asarray(yq, float))
    for j in range(len(X)):
        h = 1e-4 * max(S[j], 1e-6)
        Yp = Y.copy()
        Yp[j] += h
        var = var + ((_pchip(X, Yp, xq)[0] - yq) / h * S[j]) ** 2
    lin = np.interp(xq, X, Y)
    return yq, dy, np.sqrt(var + (yq - lin) ** 2)


def calibrated_range(surface="wall", curve=None):
    """(b_min, b_max, gamma_min, gamma_max) covered by the calibration curve
    (between its extreme resolved points)."""
    X, Y, _ = _nodes(load_curve(surface, curve))
    return float(np.exp(Y[-1])), float(np.exp(Y[0])), float(np.exp(X[0])), float(np.exp(X[-1]))


def slip_length_for_gamma(gamma, surface="wall", curve=None, **conditions):
    """The calibration curve read forwards: slip length b and its standard
    error at coupling ``gamma`` (gamma_L of a tunable-slip wall, or the
    marble's surface friction gamma), interpolated monotonically in
    (log gamma, log b). ValueError outside the calibrated gamma range or when
    ``conditions`` differ from the curve's (see gamma_for_slip_length)."""
    data = load_curve(surface, curve)
    _check_conditions(data, conditions)
    nodes = _nodes(data)
    g = float(gamma)
    lo, hi = np.exp(nodes[0][0]), np.exp(nodes[0][-1])
    if not (np.isfinite(g) and lo * (1 - 1e-12) <= g <= hi * (1 + 1e-12)):
        raise ValueError(f"parameter 'gamma' = {gamma} is outside the calibrated range "
                         f"[{lo:.4g}, {hi:.4g}] of the {surface} slip curve")
    y, _, s = _curve_at(nodes, np.log(g))
    b = float(np.exp(y))
    return b, float(b * s)


def gamma_for_slip_length(b, surface="wall", curve=None, **conditions):
    """The coupling that gives slip length ``b``, from a measured calibration curve.

    surface: "wall" -- returns gamma_L of a tunable-slip wall
    (``non_bonded_inter[wall_type, solvent].tunable_slip``, with r_cut = z_c and
    offset = layer_offset as in the curve's conditions; b = delta_B of
    Smiatek's two-flow definition, doc/walls.md); "marble" -- returns the
    surface friction gamma of a marble colloid (``add_marble(..., gamma=)``;
    b = the Navier slip length of Basset's drag formula, doc/marble.md).

    curve: a file written by calibrate() (default: the shipped curve,
    marble/data/slip_<surface>.json).

    conditions: any of the curve's recorded conditions (rho, gamma_dpd, a, kT,
    dt, r_cut, z_c, layer_offset, radius, ...; see load_curve(surface)
    ["conditions"]). Each one given must equal the value the curve was
    measured at, otherwise ValueError: the slip length depends on them, and a
    new curve must be measured with calibrate().

    Returns SlipCoupling(gamma, gamma_err): gamma_err is the curve's error at b
    (the calibration points' error bars propagated through the monotone
    interpolation, plus the interpolation error between points) divided by
    the slope of the curve. ValueError when b is outside the calibrated range.
    """
    data = load_curve(surface, curve)
    _check_conditions(data, conditions)
    nodes = _nodes(data)
    X, Y, _ = nodes
    b_min, b_max = float(np.exp(Y[-1])), float(np.exp(Y[0]))
    try:
        bb = float(b)
    except (TypeError, ValueError):
        raise ValueError(f"parameter 'b' must be a number, got {b!r}") from None
    if not (np.isfinite(bb) and b_min * (1 - 1e-12) <= bb <= b_max * (1 + 1e-12)):
        raise ValueError(
            f"parameter 'b' = {b} is outside the calibrated range [{b_min:.3g}, {b_max:.3g}] "
            f"of the {surface} slip curve ({data['parameter']} in "
            f"[{np.exp(X[0]):.3g}, {np.exp(X[-1]):.3g}]); extend it with "
            f"marble.slip.calibrate(surface={surface!r}, gammas=[...], out=path)")
    target = np.log(min(max(bb, b_min), b_max))
    lo, hi = X[0], X[-1]
    for _ in range(200):  # bisection: log b decreases monotonically in log gamma
        mid = 0.5 * (lo + hi)
        if _pchip(X, Y, mid)[0] > target:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-13:
            break
    x = 0.5 * (lo + hi)
    _, dy, s = _curve_at(nodes, x)
    gamma = float(np.exp(x))
    # sigma(log gamma) = sigma(log b) / |d log b / d log gamma|
    slope = abs(float(dy))
    gerr = gamma * float(s) / slope if slope > 0 else np.inf
    return SlipCoupling(gamma, gerr)


def marble_slip_estimate(gamma, eta=ETA_SOLVENT, rho=3.0, r_cut=1.0):
    """Smiatek-type estimate of the marble's slip length (flat-surface limit, small gamma).

    The tunable-slip marble coupling acts on the beads within r_cut of the
    surface with friction gamma w^2, w = 1 - h/r_cut (doc/marble.md). Treating
    that shell as a flat friction layer of density rho gamma (1 - h/r_cut)^2 on a
    uniform Stokes fluid that starts at the surface (stress-free there) and
    expanding to the same order as Smiatek, Allen and Schmid did for the linear
    wall profile (reference.md section 4), the plane of zero velocity lies at

        b ~ 3 eta / (rho gamma r_cut) - (5/14) r_cut

    beyond the surface (the wall's 2 eta / (rho gamma z_c) - 7/15 z_c, with
    7/15 = 1/3 + 2/15, becomes 3 eta / (rho gamma r_cut) - (1/4 + 3/28) r_cut for the
    squared weight). Curvature (r_cut / R) and the DPD fluid's
    non-local stress within one cutoff of the surface are neglected."""
    return 3.0 * eta / (rho * gamma * r_cut) - 5.0 / 14.0 * r_cut


def make_marble_box(marble, L=10.0, radius=2.0, gamma=5.0, rho=3.0, gamma_dpd=5.0, kT=1.0,
                    dt=0.01, seed=1, marble_r_cut=1.0, coupling="tunable_slip"):
    """The marble paper's solvent (rho, DPD gamma_dpd, w = 1 - r, r_c = 1, no
    conservative force) in a periodic cube of side L with one neutrally buoyant
    marble (add_marble defaults) of surface friction ``gamma`` at the centre.
    Total momentum zero. Returns (system, colloid)."""
    from .colloid_runs import marble_box
    system, colloid, _ = marble_box(L, radius, gamma, seed, rho=rho, gamma_dpd=gamma_dpd, kT=kT,
                                    dt=dt, marble_r_cut=marble_r_cut, coupling=coupling)
    return system, colloid


def measure_marble_slip(marble, gamma, radius=2.0, L=10.0, t_prod=2000.0, t_equil=20.0,
                        velocity=0.2, seed=1, eta=ETA_SOLVENT, eta_err=ETA_SOLVENT_ERR,
                        rho=3.0, gamma_dpd=5.0, kT=1.0, dt=0.01, **box_kwargs):
    """Slip length of a marble colloid from its drag (reference.md section 5).

    A force F on the colloid and -F/N_s on every bead (marble.diffusion.measure_drag)
    gives the drift velocity U relative to the solvent and D = kT U / F in the
    periodic box. Basset's partial-slip friction zeta_T = 6 pi eta R (1 + 2b/R) /
    (1 + 3b/R) (Basset 1888) with Hasimoto's periodic-lattice correction (Hasimoto
    1959; the L^-3 term scaled for partial slip, marble.theory.diffusion_coefficient)
    is inverted for b (theory.slip_length_from_D), with the solvent's measured
    viscosity ``eta`` (default: ETA_SOLVENT). F = velocity / D_stick(L): the stick
    sphere would drift at ``velocity``.

    The error of U is the larger of the blocking error and the floor
    sqrt(2 D / t_prod) (colloid_runs.drag_run explains why). b_err is the
    statistical error; b_err_eta the shift of b when eta moves by eta_err (a
    systematic error shared by every point of a curve)."""
    from . import diffusion as dif
    from . import theory as th
    system, colloid = make_marble_box(marble, L=L, radius=radius, gamma=gamma, rho=rho,
                                      gamma_dpd=gamma_dpd, kT=kT, dt=dt, seed=seed, **box_kwargs)
    D_stick = th.diffusion_coefficient(eta, radius, L, 0.0, kT)
    F = velocity * kT / D_stick
    cpu0 = time.process_time()
    res = dif.measure_drag(system, [colloid], force=[F, 0.0, 0.0],
                           steps=int(round(t_prod / dt)),
                           equilibration_steps=int(round(t_equil / dt)), delta_N=10, kT=kT)
    cpu = time.process_time() - cpu0
    D = float(res.D)
    v_err = max(float(res.v_err), np.sqrt(2.0 * max(D, 0.0) / t_prod))
    D_err = kT * v_err / F
    out = {"gamma": float(gamma), "D": D, "D_err": D_err, "v": float(res.v), "v_err": v_err,
           "v_err_blocking": float(res.v_err), "force": float(F), "eta": eta, "eta_err": eta_err,
           "D_stick": float(D_stick), "D_slip": float(th.hasimoto_D(eta, radius, L, kT, "slip")),
           "t_prod": t_prod, "t_equil": t_equil, "L": L, "radius": radius, "seed": seed,
           "cpu_s": cpu, "n_solvent": int(len(system.part.select(type=0)))}
    try:
        b, b_err = th.slip_length_from_D(D, eta, radius, L, D_err, kT)
        b_eta = th.slip_length_from_D(D, eta + eta_err, radius, L, D_err, kT)[0]
        out.update(b=b, b_err=b_err, b_err_eta=abs(b_eta - b), use=bool(b > 0))
    except ValueError as e:  # D beyond perfect slip or below -R/3
        out.update(b=float("nan"), b_err=float("nan"), b_err_eta=float("nan"), use=False,
                   note=str(e))
    return out


_WALL_RUN = {"n_steps": 200000, "equil_steps": 10000, "body_force": 0.1, "wall_velocity": 3.0,
             "height": 10.0, "box_xy": 6.0, "n_blocks": 20}
_MARBLE_RUN = {"L": 10.0, "t_prod": 2000.0, "t_equil": 20.0, "velocity": 0.2,
               "eta": ETA_SOLVENT, "eta_err": ETA_SOLVENT_ERR}


def _wall_point(marble, gamma, seed, run, progress=None):
    cpu0 = time.process_time()
    res = measure_slip(marble, gamma, seed=seed, progress=progress, **run)
    cpu = time.process_time() - cpu0
    d2, d2e = res["d2"], res["d2_err"]
    use = bool(d2 > 0 and np.isfinite(res["delta_B"]))
    keys = ["eta", "z_P", "z_0", "d2", "delta_B", "z_B", "rho"]
    pt = {"gamma": float(gamma), "b": float(res["delta_B"]), "b_err": float(res["delta_B_err"]),
          "use": use, "seed": seed, "cpu_s": cpu}
    for k in keys:
        pt[k] = float(res[k])
        pt[k + "_err"] = float(res[k + "_err"])
    if not use:
        pt["note"] = (f"d2 = {d2:.3g} +- {d2e:.2g} <= 0: no real partial-slip solution "
                      "(effectively no slip inside the friction layer)")
    # profiles for the record (mean v_x per bin)
    for kind in ("poiseuille", "couette"):
        pt[kind] = {"z": np.round(res[kind]["z"], 4).tolist(),
                    "v": [None if not np.isfinite(v) else round(float(v), 6)
                          for v in res[kind]["v"]]}
    return pt


def calibrate(surface="wall", gammas=(0.3, 0.5, 0.7, 1.0), out=None, seed=1, resume=True,
              progress=None, marble_module=None, **run):
    """Measure the calibration curve b(gamma) and (optionally) write it as JSON.

    surface="wall": for each gamma_L a Poiseuille and a Couette run in a
    tunable-slip channel (measure_slip; b = delta_B, error by jackknife over
    blocks). run keys (defaults in brackets): n_steps [200000 per flow],
    equil_steps [10000], body_force [0.1], wall_velocity [3], height [10],
    box_xy [6], n_blocks [20], and the channel's rho [3], gamma_dpd [5],
    kT [1], dt [0.01], z_c [1], layer_offset [WCA_FLUID_EDGE].

    surface="marble": for each surface friction gamma a drag run of a marble
    colloid (measure_marble_slip: Basset + Hasimoto, eta = ETA_SOLVENT).
    run keys: radius [2], L [10], t_prod [2000 tau], t_equil [20],
    velocity [0.2], eta, eta_err, rho, gamma_dpd, kT, dt, marble_r_cut [1].

    n_steps (walls) and t_prod (marble) may be lists, one run length per gamma;
    each point records its own (a resumed calibration may use other lengths).
    Point k runs with seed + 2 k (the wall's Couette run with seed + 2 k + 1).
    out: JSON path, rewritten after every point; with resume=True points
    already in it (same gamma, same conditions and run parameters) are kept,
    so an interrupted calibration continues. Returns the curve dict (the
    format of load_curve); pass it, or out, as ``curve=`` to
    gamma_for_slip_length.
    """
    _check_surface(surface)
    if marble_module is None:
        import marble as marble_module
    gammas = [float(g) for g in gammas]
    if not gammas or any(not (np.isfinite(g) and g > 0) for g in gammas):
        raise ValueError(f"parameter 'gammas' must be a non-empty list of numbers > 0, got {gammas}")
    base = dict(_WALL_RUN if surface == "wall" else _MARBLE_RUN)
    cond_keys = {"rho": "rho", "gamma_dpd": "gamma_dpd", "kT": "kT", "dt": "dt"}
    allowed = set(base) | set(cond_keys) | ({"z_c", "layer_offset"} if surface == "wall"
                                            else {"radius", "marble_r_cut"})
    unknown = set(run) - allowed
    if unknown:
        raise ValueError(f"unknown run parameter(s) {sorted(unknown)} for surface={surface!r}; "
                         f"allowed: {sorted(allowed)}")
    base.update(run)
    conditions = dict(WALL_CONDITIONS if surface == "wall" else MARBLE_CONDITIONS)
    for k in ("rho", "gamma_dpd", "kT", "dt"):
        if k in base:
            conditions[k] = float(base[k])
    if surface == "wall":
        for k in ("z_c", "layer_offset"):
            if k in base:
                conditions[k] = float(base[k])
    else:
        if "radius" in base:
            conditions["radius"] = float(base["radius"])
        if "marble_r_cut" in base:
            conditions["marble_r_cut"] = float(base["marble_r_cut"])
    measurement = {k: (list(v) if isinstance(v, (list, tuple, np.ndarray)) else v)
                   for k, v in base.items() if k not in conditions}
    measurement.update(seed=int(seed), marble_git=_git_revision())
    data = {"format": FORMAT, "surface": surface, "parameter": _SURFACES[surface][1],
            "conditions": conditions, "measurement": measurement, "points": []}
    if out is not None and resume and os.path.exists(out):
        with open(out) as f:
            old = json.load(f)
        skip = ("marble_git", "date", "cpu_s", "n_steps", "t_prod")  # lengths: per point
        same_m = {k: v for k, v in old.get("measurement", {}).items() if k not in skip} == \
            {k: v for k, v in measurement.items() if k not in skip}
        if old.get("conditions") == conditions and same_m:
            data["points"] = [p for p in old["points"]]
    done = {round(p["gamma"], 12) for p in data["points"]}
    length_key = "n_steps" if surface == "wall" else "t_prod"

    def write():
        data["points"].sort(key=lambda p: p["gamma"])
        data["measurement"]["date"] = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
        data["measurement"]["cpu_s"] = float(sum(p.get("cpu_s", 0.0) for p in data["points"]))
        data["measurement"][length_key] = [p.get(length_key) for p in data["points"]]
        if out is not None:
            tmp = out + ".tmp"
            with open(tmp, "w") as f:
                json.dump(data, f, indent=1)
            os.replace(tmp, out)

    lengths = base[length_key]
    if np.ndim(lengths) == 0:
        lengths = [lengths] * len(gammas)
    elif len(lengths) != len(gammas):
        raise ValueError(f"parameter '{length_key}' must be a number or one per gamma "
                         f"({len(gammas)}), got {len(lengths)}")
    for k, g in enumerate(gammas):
        if round(g, 12) in done:
            continue
        s = int(seed) + 2 * k
        if surface == "wall":
            run_kw = {key: base[key] for key in base if key != "velocity"}
            run_kw["n_steps"] = int(lengths[k])
            pt = _wall_point(marble_module, g, s, run_kw, progress)
            pt["n_steps"] = int(lengths[k])
        else:
            mkw = {key: base[key] for key in base}
            mkw["marble_r_cut"] = conditions["marble_r_cut"]
            mkw["t_prod"] = float(lengths[k])
            pt = measure_marble_slip(marble_module, g, seed=s, **mkw)
        pt["marble_git"] = measurement["marble_git"]
        data["points"].append(pt)
        write()
    write()
    return data
