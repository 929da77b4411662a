"""A single marble colloid (Zhou & Schmid) in the paper's DPD solvent.

Measures the colloid's translational diffusion coefficient D = kT / zeta by the
drag method (reference.md section 5: a constant force F on the colloid and
-F/N_s on every solvent bead, so the net force is zero; the steady velocity of
the colloid relative to the solvent gives zeta = F / v) and compares it with
Hasimoto's finite-box law for a stick and a perfectly slipping sphere.
It also checks equipartition of the colloid's translation and rotation.

    build/pymarble samples/marble_colloid.py            # R=2, L=12, a few minutes
    build/pymarble samples/marble_colloid.py --paper    # R=3, L=20 (the paper's box)
    build/pymarble samples/marble_colloid.py --gamma 0.5   # a slippery surface
    MARBLE_SAMPLE_TEST=1 build/pymarble samples/marble_colloid.py   # quick check
"""
import argparse
import os
import time

import numpy as np

import marble
from marble.colloids import add_marble

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--paper", action="store_true", help="paper size: R=3, L=20")
parser.add_argument("--gamma", type=float, default=5.0, help="surface friction (5: no slip)")
parser.add_argument("--coupling", default="tunable_slip",
                    choices=["tunable_slip", "transverse", "dpd"])
parser.add_argument("--force", type=float, default=None,
                    help="drag force on the colloid (default: colloid speed ~0.1)")
parser.add_argument("--time", type=float, default=None, help="production time (tau)")
parser.add_argument("--eta", type=float, default=1.24,
                    help="solvent viscosity for the theory (the engine's measured value)")
parser.add_argument("--seed", type=int, default=3)
args = parser.parse_args()

quick = os.environ.get("MARBLE_SAMPLE_TEST") == "1"
R, L = (3.0, 20.0) if args.paper else (2.0, 12.0)
if quick:
    R, L = 1.5, 8.0
t_prod = args.time or (20.0 if quick else 200.0)
dt, kT, rho, eta = 0.01, 1.0, 3.0, args.eta
xi = 2.837297
D_stick = kT / (6 * np.pi * eta) * (1 / R - xi / L + 4 * np.pi / 3 * R ** 2 / L ** 3)
D_slip = kT / (4 * np.pi * eta * R) - xi * kT / (6 * np.pi * eta * L)
F = args.force if args.force is not None else 0.1 / D_stick * kT  # v ~ 0.1

system = marble.System(box_l=[L] * 3)
system.time_step = dt
system.cell_system.skin = 0.4
rng = np.random.default_rng(args.seed)
n = int(rho * L ** 3)
system.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)) * np.sqrt(kT), type=0)
system.thermostat.set_dpd(kT=kT, seed=args.seed)
system.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
colloid = add_marble(system, pos=[L / 2] * 3, radius=R, gamma=args.gamma,
                     coupling=args.coupling)
solvent = system.part.select(type=0)
print(f"marble R={R} in L={L}: {len(solvent)} solvent beads, M={colloid.mass:.1f}, "
      f"gamma={args.gamma}, coupling={args.coupling}, drag force F={F:.2f}")
colloid.ext_force = [F, 0.0, 0.0]
solvent.ext_force = [-F / len(solvent), 0.0, 0.0]   # zero net force
system.integrator.run(int(20.0 / dt))                # reach the steady state

every = 10
n_samples = int(t_prod / (dt * every))
v_rel = np.empty(n_samples)
ekin_t, ekin_r = np.empty(n_samples), np.empty(n_samples)
M, I = colloid.mass, colloid.rinertia[0]
t0 = time.time()
for k in range(n_samples):
    system.integrator.run(every)
    v = colloid.v
    v_rel[k] = v[0] - np.mean(solvent.v[:, 0])
    ekin_t[k] = M * np.mean(v[1:] ** 2)           # transverse components: no drift
    ekin_r[k] = I * np.mean(colloid.omega_lab ** 2)
    if (k + 1) % max(1, n_samples // 10) == 0:
        el = time.time() - t0
        print(f"  {100 * (k + 1) // n_samples:3d} %  t={(k + 1) * every * dt:7.1f}  "
              f"v={np.mean(v_rel[:k + 1]):.4f}  ETA {el / (k + 1) * (n_samples - k - 1):5.0f} s",
              flush=True)


def blocked(x, n_blocks=20):
    b = x[: len(x) // n_blocks * n_blocks].reshape(n_blocks, -1).mean(axis=1)
    return b.mean(), b.std(ddof=1) / np.sqrt(n_blocks)


v, dv = blocked(v_rel)
D, dD = v / F * kT, dv / F * kT
mt, dmt = blocked(ekin_t)
mr, dmr = blocked(ekin_r)
print(f"equipartition: <M v_perp^2> = {mt:.3f} +- {dmt:.3f}, <I omega^2> = {mr:.3f} +- {dmr:.3f}"
      f" (kT = {kT})")
print(f"drag: v = {v:.5f} +- {dv:.5f}  ->  zeta = {F / v:.2f},  D = {D:.5f} +- {dD:.5f}")
print(f"Hasimoto (eta = {eta}): stick D = {D_stick:.5f}, perfect slip D = {D_slip:.5f}")
print(f"D / D_stick = {D / D_stick:.3f} +- {dD / D_stick:.3f}")
