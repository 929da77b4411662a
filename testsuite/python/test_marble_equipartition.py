# labels: python long
"""Equipartition of a marble colloid in the paper's DPD solvent (reference.md
sections 2-3): <M v_x^2> and <I omega_x^2> equal kT within 3 sigma of their
own (blocked) error, for gamma = 1 and 10 and each coupling that transmits
torque; the solvent temperature stays at kT within its error."""
import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(not marble.has_features("MARBLE"),
                                reason="missing feature MARBLE")

KT = 1.0
L = 8.0
RADIUS = 1.5
STEPS = 30000
EVERY = 10
N_BLOCKS = 20


def blocked(x, n_blocks=N_BLOCKS):
    """Mean and its error from block averages (blocks much longer than the
    velocity correlation time)."""
    x = np.asarray(x)
    n = len(x) // n_blocks * n_blocks
    blocks = x[:n].reshape(n_blocks, -1).mean(axis=1)
    return blocks.mean(), blocks.std(ddof=1) / np.sqrt(n_blocks)


def run_case(coupling, gamma, seed):
    from marble.colloids import add_marble
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(seed)
    n = int(3 * L ** 3)
    s.part.add(pos=rng.random((n, 3)) * L, v=rng.normal(size=(n, 3)) * np.sqrt(KT), type=0)
    s.thermostat.set_dpd(kT=KT, seed=seed)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    col = add_marble(s, pos=[L / 2] * 3, radius=RADIUS, gamma=gamma, coupling=coupling)
    s.integrator.run(2000)
    M, I = col.mass, col.rinertia[0]
    solvent = s.part.select(type=0)
    ekin_v, ekin_w, t_solv = [], [], []
    for k in range(STEPS // EVERY):
        s.integrator.run(EVERY)
        ekin_v.append(np.mean(M * col.v ** 2))        # mean over the 3 components
        ekin_w.append(np.mean(I * col.omega_lab ** 2))
        if k % 10 == 0:
            t_solv.append(np.mean(solvent.v ** 2))
    return blocked(ekin_v), blocked(ekin_w), blocked(t_solv, 10)


@pytest.mark.parametrize("coupling", ["tunable_slip", "transverse"])
@pytest.mark.parametrize("gamma", [1.0, 10.0])
def test_equipartition(coupling, gamma):
    (mv, emv), (iw, eiw), (ts, ets) = run_case(coupling, gamma, seed=int(gamma) + 7)
    print(f"{coupling} gamma={gamma}: <M v^2>={mv:.4f}+-{emv:.4f} "
          f"<I w^2>={iw:.4f}+-{eiw:.4f} solvent kT={ts:.5f}+-{ets:.5f}")
    assert abs(mv - KT) < 3 * emv
    assert abs(iw - KT) < 3 * eiw
    # plain velocity Verlet at dt = 0.01 heats the a=0, gamma=5 solvent by ~0.7 %
    # (reference.md section 2): allow that bias on top of 3 sigma
    assert abs(ts - KT) < 3 * ets + 0.01
    # the errors must be small enough for the test to mean something
    assert emv < 0.15 and eiw < 0.15
