# labels: python long
"""A dense suspension (doc/suspensions.md, issue 13): phi = 0.40 with seed 004's
settings (R = 1, rho = 3, kT = 0.1, gamma = 4.5, contact f_c = 1e4 kT,
Delta = 1e-3, lubrication eta0 = 0.3 with h_cut = 1 and h_min = 1e-3,
colloid-colloid DPD), Shardlow at dt = 1e-3: 1e5 steps without a blow-up (a
RuntimeError would stop the run) and without an overlap deeper than 0.01 (the
contact force, stiffness 3 f_c/Delta = 3e6, keeps the gap above about -1e-3
at kT = 0.1). 32 colloids start on an fcc lattice (random sequential addition
jams near phi = 0.38), nearest gap 0.46. The colloids' kinetic temperature is
checked to stay near kT (a loose 25 % bound: 32 colloids, a few decorrelated
samples; the exact test of the thermostat is test_lubrication_fdt.py)."""
import numpy as np
import pytest

import marble

if not marble.has_features("DPD", "HAT", "CONTACT", "LUBRICATION", "MASS"):
    pytest.skip("needs DPD, HAT, CONTACT, LUBRICATION, MASS", allow_module_level=True)

sus = marble.suspensions


def fcc(n_cells, L):
    a = L / n_cells
    base = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    g = np.array([[i, j, k] for i in range(n_cells) for j in range(n_cells) for k in range(n_cells)])
    return ((g[:, None, :] + base[None, :, :]).reshape(-1, 3) + 0.25) * a


def min_gap(pos, L, R):
    d = pos[:, None, :] - pos[None, :, :]
    d -= L * np.round(d / L)
    r = np.linalg.norm(d, axis=2)
    r[np.diag_indices(len(pos))] = np.inf
    return r.min() - 2 * R


def test_phi_040_runs_without_overlap():
    R, n = 1.0, 32
    L = (n * 4 / 3 * np.pi * R ** 3 / 0.40) ** (1 / 3)  # 6.95
    s = marble.System(box_l=[L] * 3)
    s.time_step = 1e-3
    s.cell_system.skin = 0.3
    info = sus.setup_suspension(s, phi=0.40, radius=R, kT=0.1, gamma=4.5, eta=0.3, seed=9,
                                positions=fcc(2, L))
    assert info["phi"] == pytest.approx(0.40, abs=1e-9)
    s.integrator.set_shardlow()
    col = s.part.by_ids(info["colloid_ids"])
    assert s.cell_system.get_state()["large_range_types"] in ([], [1])
    gaps, kin = [], []
    for chunk in range(20):
        s.integrator.run(5000)
        pos = np.asarray(col.pos)
        gaps.append(min_gap(pos, L, R))
        v = np.asarray(col.v)
        kin.append(info["colloid_mass"] * np.mean(np.sum(v * v, axis=1)) / 3)
        assert np.all(np.isfinite(pos))
    assert s.cell_system.get_state()["large_range_types"] == [1]
    print("min gaps", np.round(gaps, 4), "colloid kT", np.round(kin, 4))
    assert min(gaps) > -0.01, f"overlap deeper than 0.01: min gap {min(gaps)}"
    # after the solvent's hat energy has been thermostatted away (a few time units)
    assert abs(np.mean(kin[5:]) / 0.1 - 1) < 0.25, np.mean(kin[5:])
