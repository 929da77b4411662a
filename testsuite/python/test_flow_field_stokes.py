# labels: python long
"""The flow around a dragged no-slip marble (Zhou & Schmid; gamma = 5) against the
periodic Stokes solution (issue 17's criterion, reduced size).

A marble of radius R = 2 in the paper's DPD solvent (L = 10, rho = 3, kT = 1,
eta = 1.24) is dragged along x by a constant force F (-F/N on each solvent
bead, total momentum zero) at V ~ 0.3 for 1200 tau. marble.flow.FlowField
averages the solvent velocity in the co-moving frame; adding the colloid's
velocity (block by block) gives the lab-frame velocity u_x near the drag axis
(cells with |y|, |z| <= 1.5, both sides pooled, bins in |x|). It is compared
with the Stokes (1851) solution made periodic (marble.flow.periodic_stokes_velocity:
Hasimoto's frame, counter force on the fluid), evaluated on the same cells with
the same weights. Nothing is fitted: F, R and the engine's eta = 1.24 only.

Criterion (the issue's): |u/u_Stokes - 1| < 10 % in the bins from r = R + 1 to
R + 2.5. For that to mean something the measured statistical error of each ratio
(40 blocks of 30 tau) must be below 5 % (10 % is then >= 2 sigma; the errors come
mostly from the colloid's Brownian motion and the solvent's hydrodynamic
fluctuations, and shrink only as 1/sqrt(time)). At 600 tau they were ~5 %
themselves, so the guard failed or passed with the realization (session 30:
0.047 in one, 0.058 in another); at 1200 tau they are ~3.7 %, and 40 blocks
estimate them to ~11 %, so the guard fails only if the errors really are
larger. The bin beyond R + 2.5, where
the images cancel much of the Stokeslet, is printed only. The colloid's own
velocity is checked against Hasimoto's D(L) F within max(10 %, 3 sigma).

Measured: doc/flow-fields.md (~2 min of CPU, deterministic for the fixed seed)."""
import time

import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(
    not marble.has_features("MARBLE", "EXTERNAL_FORCE"),
    reason="missing feature MARBLE or EXTERNAL_FORCE")

from marble import flow, theory  # noqa: E402
from marble.colloid_runs import DT, make_system  # noqa: E402

ETA = 1.24
R, L, GAMMA = 2.0, 10.0, 5.0
SPEED = 0.3          # Re = rho V R / eta ~ 1.5; the periodic box keeps inertia small
T_EQUIL, T_PROD, EVERY, N_BLOCKS = 20.0, 1200.0, 10, 40
CELL = 0.5
HALF_WIDTH = 1.5     # cells with |y|, |z| <= 1.5 around the axis (the theory on the same cells)


def test_drag_axis_velocity_against_stokes():
    t0 = time.time()
    D = theory.hasimoto_D(ETA, R, L)
    F = SPEED / D
    system, colloid, solvent = make_system(L, R, GAMMA, seed=7, warmup=0.0)
    colloid.ext_force = [F, 0.0, 0.0]
    solvent.ext_force = [-F / len(solvent), 0.0, 0.0]
    system.integrator.run(int(T_EQUIL / DT))
    ng = int(round(L / CELL))
    ng += 1 - ng % 2
    n_samples = int(T_PROD / (DT * EVERY))
    ff = flow.FlowField(system, grid=(ng, ng, ng), types=[0], co_moving=colloid,
                        block_size=n_samples // N_BLOCKS)
    ff.sample_run(n_samples, EVERY)
    assert ff.n_blocks == N_BLOCKS
    V = ff.frame_velocity[0]
    u_th = flow.periodic_stokes_velocity(ff.cell_centres, [F, 0, 0], ETA, R, L)
    edges = np.array([R + 1.0, R + 1.75, R + 2.5, L / 2])   # the last bin: reported only
    prof = flow.axis_profile(ff, edges, half_width=HALF_WIDTH, theory=u_th, lab=True)
    ratio = prof["u"] / prof["theory"]
    sig = prof["err"] / np.abs(prof["theory"])
    # the colloid's own speed: Hasimoto D(L) F
    v_blocks = np.array([b[2][0] for b in ff._blocks])
    dV = np.std(v_blocks, ddof=1) / np.sqrt(len(v_blocks))
    print(f"\nV = {V:.4f} +- {dV:.4f}, Hasimoto {SPEED:.4f} (ratio {V / SPEED:.3f} +- "
          f"{dV / SPEED:.3f}); {time.time() - t0:.0f} s")
    for r, u, e, t in zip(prof["r"], prof["u"], prof["err"], prof["theory"]):
        print(f"  r = {r:.2f}: u_x = {u:.4f} +- {e:.4f}, periodic Stokes {t:.4f}, "
              f"ratio {u / t:.3f} +- {e / abs(t):.3f}")
    assert abs(V / SPEED - 1) < max(0.10, 3 * dV / SPEED)
    assert np.all(sig[:2] < 0.05), f"statistical errors too large for a 10 % test: {sig}"
    assert np.all(np.abs(ratio[:2] - 1) < 0.10), f"u/u_Stokes = {ratio} +- {sig}"
