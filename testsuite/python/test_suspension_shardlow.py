# labels: python long
"""Shardlow beyond velocity Verlet's limit in a dense suspension (issue 13,
doc/suspensions.md section 5): phi = 0.40, 108 colloids (R = 1, fcc start,
L = 10.44, about 2070 solvent beads), seed 004's solvent and colloid settings
(rho = 3, kT = 0.1, gamma = 4.5, mean-field colloid-solvent hat, colloid mass
12.57, lubrication eta0 = 0.3 with h_cut = 1, h_min = 1e-3, colloid-colloid
DPD) but a softer contact force (f_c = 100 kT, Delta = 0.01 instead of seed
004's 1e4 kT, 1e-3: that one's stiffness 3e6 limits both integrators to
dt ~ 5e-3, doc section 5).

Velocity Verlet with the lubrication explicit (measured, doc section 5):
colloid kT/kT = 1.0028(27) at dt = 0.005, 1.0126(25) at 0.01, 1.042(3) at
0.015, 1.150(25) at 0.02, blow-up at 0.04 and 0.05: its 1 % limit is
dt ~ 0.009. Shardlow (lubrication and colloid-solvent DPD in the exact pair
update) at dt = 0.05, 5.5x that limit: the colloids' kinetic temperature
M <v^2>/3 (all 108 colloids, 4000 samples over 800 time units, blocking
error over 20 blocks) is within 1 % of kT (+ 3 sigma; sigma is required to be
below 0.4 % so the test can fail). The same scene with velocity Verlet at that
dt stops with a RuntimeError."""
import numpy as np
import pytest

import marble

if not marble.has_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS"):
    pytest.skip("needs DPD, HAT, CONTACT, LUBRICATION, MASS", allow_module_level=True)

sus = marble.suspensions
KT, DT = 0.1, 0.05


def fcc(n_cells, L):
    a = L / n_cells
    base = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.array([[i, j, k] for i in range(n_cells) for j in range(n_cells) for k in range(n_cells)])
    return ((g[:, None, :] + base[None, :, :]).reshape(-1, 3) + 0.25) * a


def scene(integrator):
    R, n = 1.0, 108
    L = (n * 4 / 3 * np.pi * R ** 3 / 0.40) ** (1 / 3)
    s = marble.System(box_l=[L] * 3)
    s.time_step = DT
    s.cell_system.skin = 0.4
    info = sus.setup_suspension(s, phi=0.40, radius=R, kT=KT, gamma=4.5, eta=0.3, seed=9,
                                positions=fcc(3, L), f_contact=100 * KT, delta=0.01, h_min=1e-3)
    getattr(s.integrator, "set_" + integrator)()
    return s, info


def blocking(x, n_blocks=20):
    x = np.asarray(x)
    n = len(x) // n_blocks
    b = x[:n * n_blocks].reshape(n_blocks, n).mean(axis=1)
    return b.mean(), b.std(ddof=1) / np.sqrt(n_blocks)


def test_shardlow_colloid_kT_at_5x_the_vv_limit():
    s, info = scene("shardlow")
    col = s.part.by_ids(info["colloid_ids"])
    s.integrator.run(int(round(10 / DT)))  # the random solvent's hat energy thermostatted away
    every = int(round(0.2 / DT))
    kin = []
    for _ in range(4000):
        s.integrator.run(every)
        v = np.asarray(col.v)
        kin.append(info["colloid_mass"] * np.mean(v * v))
    m, err = blocking(np.asarray(kin) / KT)
    print(f"Shardlow dt = {DT}: colloid kT/kT = {m:.4f} +- {err:.4f}")
    assert err < 0.004, f"statistics too poor to test 1 %: sigma = {err}"
    assert abs(m - 1) < 0.01 + 3 * err, f"colloid kT/kT = {m} +- {err}"


def test_velocity_verlet_fails_at_that_dt():
    s, _ = scene("vv")
    with pytest.raises(RuntimeError, match="integration stopped at step"):
        s.integrator.run(int(round(50 / DT)))
