# labels: paper
"""Zhou & Schmid, Figs. 4 and 5, at the paper's size (R = 3, L = 20; hours of
CPU time, not run in CI). Theory: Hasimoto's D(L) with the engine's viscosity
eta = 1.24 (reference.md section 2; MARBLE_PAPER_ETA overrides it).

Fig. 4 (gamma = 0.5 and 5, three seeds each, R = 3, L = 20):
- no slip (gamma = 5): the drag D is within max(5 %, 3 sigma) of Hasimoto stick;
- VACF (Green-Kubo) and MSD (fit t > 25 tau) agree with the drag value within
  3 combined sigma (errors: standard error over the seeds, as in the paper);
- the slippery marble (gamma = 0.5) diffuses faster than the no-slip one by
  more than 3 combined sigma and stays below the perfect-slip value.
Fig. 5 (gamma = 5, L = 12, 16, 20, 24, 30, drag):
- every point within max(5 %, 3 sigma) of Hasimoto stick; the weighted fit of
  the hydrodynamic radius gives R_h within 5 % of R.

Run lengths (tau) can be scaled with MARBLE_PAPER_SCALE (default 1):
equilibrium 2000, drag 500 per seed. Expected CPU time on one core: about
4 hours (Fig. 4) + 1 hour (Fig. 5)."""
import os

import numpy as np
import pytest

import marble

pytestmark = pytest.mark.skipif(
    not marble.has_features("MARBLE", "EXTERNAL_FORCE"),
    reason="missing feature MARBLE or EXTERNAL_FORCE")

from marble.colloid_runs import (analyse_equilibrium, drag_run, equilibrium_run,  # noqa: E402
                         make_system)
from marble import theory as th  # noqa: E402

ETA = float(os.environ.get("MARBLE_PAPER_ETA", 1.24))
SCALE = float(os.environ.get("MARBLE_PAPER_SCALE", 1.0))
R, L = 3.0, 20.0
T_EQ, T_DRAG = 2000.0 * SCALE, 500.0 * SCALE
SEEDS = (1, 2, 3)
SPEED = 0.1


def force(L_):
    return SPEED / th.hasimoto_D(ETA, R, L_)


def seeds_run(gamma):
    vacf, msd, drag = [], [], []
    for s in SEEDS:
        system, col, _ = make_system(L, R, gamma, s)
        eq = equilibrium_run(system, col, T_EQ, 1, 100.0, T_EQ / 4)
        gk, _, ms, _ = analyse_equilibrium(eq, L, ETA, paper=True)
        del system
        system, col, _ = make_system(L, R, gamma, s + 50)
        res = drag_run(system, col, force(L), T_DRAG)
        del system
        vacf.append(gk.value)
        msd.append(ms.value)
        drag.append(res.D)
        print(f"\ngamma={gamma} seed={s}: D_vacf={gk.value:.5f} D_msd={ms.value:.5f} "
              f"D_drag={res.D:.5f}+-{res.D_err:.5f}", flush=True)

    def me(x):
        return float(np.mean(x)), float(np.std(x, ddof=1) / np.sqrt(len(x)))
    return me(vacf), me(msd), me(drag)


def test_fig4_diffusion_vs_gamma():
    (v5, ev5), (m5, em5), (d5, ed5) = seeds_run(5.0)
    D_stick = th.hasimoto_D(ETA, R, L)
    D_slip = th.hasimoto_D(ETA, R, L, boundary="slip")
    print(f"\ngamma=5: vacf {v5:.5f}+-{ev5:.5f} msd {m5:.5f}+-{em5:.5f} drag {d5:.5f}+-{ed5:.5f};"
          f" Hasimoto stick {D_stick:.5f} (eta {ETA})")
    assert abs(d5 - D_stick) < max(0.05 * D_stick, 3 * ed5)
    assert abs(v5 - d5) < 3 * np.hypot(ev5, ed5)
    assert abs(m5 - d5) < 3 * np.hypot(em5, ed5)
    (v05, ev05), (m05, em05), (d05, ed05) = seeds_run(0.5)
    print(f"\ngamma=0.5: vacf {v05:.5f}+-{ev05:.5f} msd {m05:.5f}+-{em05:.5f} "
          f"drag {d05:.5f}+-{ed05:.5f}; Hasimoto slip {D_slip:.5f}")
    assert d05 - d5 > 3 * np.hypot(ed05, ed5)
    assert d05 < D_slip + 3 * ed05
    assert abs(v05 - d05) < 3 * np.hypot(ev05, ed05)
    assert abs(m05 - d05) < 3 * np.hypot(em05, ed05)


def test_fig5_hasimoto():
    Ls = np.array([12.0, 16.0, 20.0, 24.0, 30.0])
    D, E = [], []
    for i, L_ in enumerate(Ls):
        system, col, _ = make_system(L_, R, 5.0, 200 + i)
        res = drag_run(system, col, force(L_), T_DRAG)
        del system
        D_h = th.hasimoto_D(ETA, R, L_)
        print(f"\nL={L_}: D = {res.D:.5f} +- {res.D_err:.5f}, Hasimoto {D_h:.5f}, "
              f"ratio {res.D / D_h:.3f}", flush=True)
        D.append(res.D)
        E.append(res.D_err)
        assert abs(res.D - D_h) < max(0.05 * D_h, 3 * res.D_err)
    Rh, Rh_err = th.hydrodynamic_radius_from_D(np.array(D), ETA, Ls, D_err=np.array(E))
    print(f"\nR_h = {Rh:.3f} +- {Rh_err:.3f}")
    assert abs(Rh - R) < 0.05 * R
