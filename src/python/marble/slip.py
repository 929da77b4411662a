"""Slip length and hydrodynamic boundary of tunable-slip walls (doc/walls.md).

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
