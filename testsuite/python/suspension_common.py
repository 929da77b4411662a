"""Shared setting of the single-colloid tests (test_suspension_hasimoto.py,
test_suspension_stick.py; doc/suspensions.md sections 7b and 7c): seed 004's
solvent and colloid (R = 1, rho = 3, kT = 0.1, gamma = 4.5, mean-field
colloid-solvent hat and DPD on the gap, colloid mass 12.57), one colloid in a
periodic cube of edge L = (4 pi R^3/(3 phi))^(1/3) = 4.376 (phi = 0.05),
Shardlow dt = 0.01, and D by drag. A helper module, not a test: ctest
registers test_*.py only (CMakeLists.txt) and pytest collects test_*.py only."""
import math

import numpy as np

import marble

R, KT, PHI, DT, F = 1.0, 0.1, 0.05, 0.01, 0.5
# the solvent's viscosity at these settings and dt (reverse Poiseuille,
# bench/suspension_hasimoto.py --part eta, 1500 time units)
ETA, ETA_ERR = 0.3227, 0.0069
# the solvent at exactly density 3 (solvent_count="exact", box 7 x 7 x 10, g = 0.02,
# 3000 time units per seed; doc/suspensions.md section 7d): the eta_0 of the stick
# radius calibration. ETA above was measured at a Poisson density 2.97 (section 7b).
ETA0, ETA0_ERR = 0.3290, 0.0030
L = (4.0 * math.pi * R ** 3 / (3.0 * PHI)) ** (1.0 / 3.0)


def single_colloid(seed, equil=20.0, **kw):
    """One colloid at the box centre with seed 004's solvent, Shardlow, zero
    total momentum, equilibrated for ``equil`` time units. ``kw`` go to
    setup_suspension (e.g. boundary="stick"). Returns (system, info)."""
    s = marble.System(box_l=[L] * 3)
    s.time_step = DT
    s.cell_system.skin = 0.4
    info = marble.suspensions.setup_suspension(s, phi=PHI, radius=R, kT=KT, gamma=4.5, eta=0.3, seed=seed,
                                               positions=[[L / 2] * 3], **kw)
    s.integrator.set_shardlow()
    p = s.part.all()
    v, m = np.asarray(p.v), np.asarray(p.mass)
    p.v = v - np.sum(m[:, None] * v, axis=0) / np.sum(m)
    s.integrator.run(int(round(equil / DT)))
    return s, info


def drag_D(s, info, time, force=F):
    """D by drag (marble.diffusion.measure_drag: ``force`` along x on the
    colloid, the opposite force spread over the solvent) over ``time``; the
    error is the larger of the blocking error and sqrt(2 D/T) (the thermal
    displacement's). Returns (D, D_err)."""
    from marble.diffusion import measure_drag
    res = measure_drag(s, info["colloid_ids"], force=[force, 0, 0], steps=int(round(time / DT)),
                       equilibration_steps=int(round(20 / DT)), delta_N=10, kT=KT)
    D = res.D
    return D, max(res.D_err, KT * math.sqrt(2 * max(D, 0.0) / time) / force)
