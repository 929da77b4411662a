"""Flow field around a dragged stick and slip marble colloid, compared with Stokes.

A marble colloid (Zhou & Schmid, doc/marble.md) of radius R in the paper's DPD
solvent (rho = 3, gamma = 5, kT = 1, eta = 1.24) in a periodic box of side L is
dragged along x by a constant force F; every solvent bead gets -F/N so the net
force is zero and the total momentum stays zero (the lab frame is the frame in
which the box's mean velocity vanishes). ``marble.flow.FlowField`` averages the
solvent velocity on a grid in the colloid's co-moving frame. Two surfaces:

- stick:  gamma = 5 (no slip, doc/marble.md), Stokes (1851);
- slip:   gamma = 0.5 (a slippery surface), Basset's (1888) partial-slip sphere with
  the Navier slip length b fitted to the colloid's own measured drag
  (marble.theory.slip_length_from_D; finite-box Hasimoto correction included).

The theory is the *periodic* Stokes solution (marble.flow.periodic_stokes_velocity:
Fourier sum of the Oseen tensor over the reciprocal lattice with a sphere form
factor reproducing the Stokes/Basset Stokeslet + source doublet), not the unbounded
one: in a box of side L the images shift the flow by O(R/L) (here ~30 %).

Figure (PNG): the streamlines of the co-moving flow in the plane z = 0 through the
centre (drag axis x), the measured field in the upper half (y > 0), the periodic
Stokes solution mirrored in the lower half, colour = speed / V; and the lab-frame
velocity u_x on the drag axis against r. The fields are also written as VTK
(ParaView).

    build/pymarble samples/flow_field.py                 # R=2.5, L=16: doc/figures/flow_field.png
                                                         # (2 x 55000 steps of 12300 beads, ~15 min)
    build/pymarble samples/flow_field.py --time 2000     # smoother streamlines
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/flow_field.py   # quick check (seconds)
"""
import argparse
import os
import time
import warnings

import numpy as np

import marble
from marble import flow, theory

quick = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--radius", type=float, default=1.5 if quick else 2.5)
parser.add_argument("--box", type=float, default=8.0 if quick else 16.0)
parser.add_argument("--time", type=float, default=10.0 if quick else 500.0,
                    help="production time per colloid (tau)")
parser.add_argument("--equil", type=float, default=5.0 if quick else 50.0,
                    help="time to reach the steady state (tau)")
parser.add_argument("--speed", type=float, default=0.2,
                    help="target colloid speed (sets F through the theory)")
parser.add_argument("--gammas", type=float, nargs=2, default=[5.0, 0.5],
                    metavar=("STICK", "SLIP"), help="surface friction of the two marbles")
parser.add_argument("--cell", type=float, default=0.8, help="grid cell size (about)")
parser.add_argument("--eta", type=float, default=1.24, help="solvent viscosity (measured)")
parser.add_argument("--seed", type=int, default=11)
parser.add_argument("--png", default="flow_field.png")
parser.add_argument("--vtk", default="flow_field", help="VTK file prefix ('' : none)")
args = parser.parse_args()
marble.assert_features("MARBLE", "EXTERNAL_FORCE")
from marble.colloids import add_marble  # noqa: E402

R, L, eta, kT, rho, dt = args.radius, args.box, args.eta, 1.0, 3.0, 0.01
every = 10


def drag_run(gamma, boundary, seed):
    """One colloid dragged at ~args.speed; returns the FlowField and the force."""
    F = args.speed / theory.hasimoto_D(eta, R, L, kT, boundary) * kT
    system = marble.System(box_l=[L] * 3)
    system.time_step = dt
    system.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    n = int(rho * L ** 3)
    v = rng.normal(size=(n, 3)) * np.sqrt(kT)
    system.part.add(pos=rng.random((n, 3)) * L, v=v - v.mean(axis=0), type=0)  # momentum 0
    system.thermostat.set_dpd(kT=kT, seed=seed)
    system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    colloid = add_marble(system, pos=[L / 2] * 3, radius=R, gamma=gamma)
    solvent = system.part.select(type=0)
    solvent.v = solvent.v - solvent.v.mean(axis=0)   # overlap removal changed the momentum
    colloid.ext_force = [F, 0.0, 0.0]
    solvent.ext_force = [-F / len(solvent), 0.0, 0.0]
    system.integrator.run(int(args.equil / dt))
    ng = int(round(L / args.cell))
    ng += 1 - ng % 2                                  # odd: a cell row on the drag axis
    n_samples = int(args.time / (dt * every))
    ff = flow.FlowField(system, grid=(ng, ng, ng), types=[0], co_moving=colloid,
                        block_size=max(1, n_samples // 20))
    t0 = time.time()
    for k in range(10):
        ff.sample_run(n_samples // 10, every)
        print(f"  gamma={gamma}: {10 * (k + 1):3d} %  V={ff.frame_velocity[0]:.4f}  "
              f"{time.time() - t0:.0f} s", flush=True)
    return ff, F


results = {}
for label, gamma, boundary, seed in (("stick", args.gammas[0], "stick", args.seed),
                                     ("slip", args.gammas[1], "slip", args.seed + 1)):
    ff, F = drag_run(gamma, boundary, seed)
    V = ff.frame_velocity[0]
    D = kT * V / F
    if label == "stick":
        b = 0.0
    else:
        try:
            b = theory.slip_length_from_D(D, eta, R, L)[0]
        except (ValueError, RuntimeError):
            b = np.inf
        if not np.isfinite(b) or b > 1e3:
            b = np.inf
        b = max(b, 0.0)
    x = ff.cell_centres
    u_th = flow.periodic_stokes_velocity(x, [F, 0, 0], eta, R, L, b=b)   # lab frame
    V_th = F * theory.diffusion_coefficient(eta, R, L, b, kT) / kT
    results[label] = dict(ff=ff, F=F, V=V, b=b, u_th=u_th, V_th=V_th, gamma=gamma)
    print(f"{label}: gamma={gamma}, F={F:.3f}, V={V:.4f} (Stokes, b={b:.3g}: {V_th:.4f}), "
          f"{ff.n_samples} samples")
    edges = np.arange(R + 1.0, L / 2 + 1e-9, 0.75)
    prof = flow.axis_profile(ff, edges, half_width=1.0, theory=u_th, lab=True)
    print("   r      u_x/V (lab, |y|,|z| <= 1)   periodic Stokes   ratio")
    for r, u, e, t in zip(prof["r"], prof["u"], prof["err"], prof["theory"]):
        print(f"  {r:5.2f}   {u / V:7.3f} +- {e / V:.3f}        {t / V:7.3f}      "
              f"{u / t:6.3f} +- {e / abs(t):.3f}")
    results[label]["prof"] = prof
    if args.vtk and marble.mpi_rank() == 0:
        path = f"{args.vtk}_{label}.vtk"
        ff.write_vtk(path)
        print("wrote", path)

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("matplotlib not available: no plot")
    raise SystemExit(0)


def plane(field, ff):
    """In-plane (x, s) components on the plane z = 0 and, rotated, y = 0 (equivalent by
    the symmetry of the drag about x), averaged: (ns, nx, 2) arrays, s = y or z."""
    c = ff.grid[2] // 2
    a = field[:, :, c, :][..., [0, 1]]
    b = field[:, c, :, :][..., [0, 2]]
    with warnings.catch_warnings():      # cells inside the colloid are NaN in both
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.nanmean(np.stack([a, b]), axis=0).transpose(1, 0, 2)


fig, axes = plt.subplots(1, 3, figsize=(17, 6.2), gridspec_kw={"width_ratios": [1, 1, 1.1]})
for ax, label in zip(axes[:2], ("stick", "slip")):
    res = results[label]
    ff, V = res["ff"], res["V"]
    xs, ys = ff.axes[0], ff.axes[1]
    meas = plane(ff.velocity, ff)                          # co-moving, measured
    th = plane(res["u_th"] - [res["V_th"], 0, 0], ff)      # co-moving, Stokes
    upper = ys[:, None] > 0
    both = np.where(upper[..., None], meas, th) / V
    X, Y = np.meshgrid(xs, ys)
    inside = X ** 2 + Y ** 2 < R ** 2
    both[inside] = 0.0
    speed = np.ma.masked_where(inside, np.hypot(both[..., 0], both[..., 1]))
    u = np.ma.masked_where(inside, np.nan_to_num(both[..., 0]))
    w = np.ma.masked_where(inside, np.nan_to_num(both[..., 1]))
    sp = ax.streamplot(xs, ys, u, w, color=speed, cmap="viridis", density=1.4, linewidth=0.9,
                       norm=matplotlib.colors.Normalize(0, 1.2))
    ax.add_patch(plt.Circle((0, 0), R, color="0.3"))
    ax.axhline(0, color="w", lw=0.8)
    ax.set_aspect("equal")
    ax.set_xlim(xs[0], xs[-1])
    ax.set_ylim(ys[0], ys[-1])
    btxt = "b = 0" if res["b"] == 0 else (r"b = $\infty$" if np.isinf(res["b"])
                                          else f"b = {res['b']:.2f}")
    ax.set_title(f"{label}: gamma = {res['gamma']}, V = {V:.3f}\n"
                 f"y > 0: measured; y < 0: Stokes, {btxt}", fontsize=10)
    ax.set_xlabel("x (drag axis)")
    ax.set_ylabel("y")
fig.colorbar(sp.lines, ax=axes[:2], orientation="horizontal", shrink=0.5, pad=0.12,
             label="|u - V| / V (co-moving frame)")
ax = axes[2]
rr = np.linspace(R + 0.6, L / 2, 200)  # with sigma = 0.15 the sum is exact from a + 4 sigma <= R + 0.6
for k, label in enumerate(("stick", "slip")):
    res = results[label]
    V, prof = res["V"], res["prof"]
    pts = np.stack([rr, 0 * rr, 0 * rr], axis=1)
    line = flow.periodic_stokes_velocity(pts, [res["F"], 0, 0], eta, R, L, b=res["b"],
                                         sigma=0.15)[:, 0]   # finer: exact from ~R + 0.6
    ax.plot(rr, line / V, f"C{k}-", label=f"{label}: periodic Stokes/Basset")
    unb = flow.stokes_velocity(pts, [V, 0, 0], R, b=res["b"])[:, 0]
    ax.plot(rr, unb / V, f"C{k}:", label=f"{label}: unbounded (same V)")
    ax.errorbar(prof["r"], prof["u"] / V, prof["err"] / V, fmt=f"C{k}o", ms=4,
                label=f"{label}: measured")
ax.axvline(R, color="0.5", lw=0.8)
ax.axvspan(R, R + 1, color="0.9")
ax.axhline(0, color="0.5", lw=0.5)
ax.set_xlabel("distance from the centre along the drag axis, r")
ax.set_ylabel(r"lab-frame $u_x / V$")
ax.set_title(f"R = {R}, L = {L}: on the drag axis (both sides)", fontsize=10)
ax.legend(fontsize=8)
if marble.mpi_rank() == 0:
    fig.savefig(args.png, dpi=110, bbox_inches="tight")
    print("wrote", args.png)
