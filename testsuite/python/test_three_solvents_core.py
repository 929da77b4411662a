# labels: python long
"""The core-modified colloid of test_three_solvents.py, run long enough for its D
(R = 2, L = 11, 20 time units to the steady state, then 150 of drag,
~90 CPU-s): D(inf) against the
slip Stokes value kT/(4 pi eta R) within the systematic error stated in the
measured table (marble/data/three_solvents.json, doc/choosing-a-model.md),
3 sigma of this run's error combined with the table's uncertainty."""
import math

import pytest

import marble

FEATURES = ("DPD", "HAT", "CONTACT", "MASS", "EXTERNAL_FORCE")
pytestmark = pytest.mark.skipif(not marble.has_features(*FEATURES),
                                reason="missing one of the features " + ", ".join(FEATURES))

if marble.has_features(*FEATURES):
    import marble.advisor as adv
    from marble import theory as th
    from marble.viscosity import block_average


def test_core_colloid_D_within_stated_systematic_error():
    R, L, T = 2.0, 11.0, 150.0
    m = adv.load_table()["models"]["core"]
    eta = m["eta"][0]
    stokes = th.diffusion_coefficient(eta, R, math.inf, math.inf)
    shift = stokes - th.diffusion_coefficient(eta, R, L, math.inf)
    sc = adv.Scene("core", R, L, 207, "slip", warmup=5.0)
    F = 0.12 / (stokes * (1 + m["drag"]["sys"]) - shift)
    v, _, _ = sc.drag_series(F, T, 15.0)
    vm, ve = block_average(v, min_blocks=8)
    D = vm / F
    err = max(ve, math.sqrt(2 * D / T)) / F
    dev = (D + shift) / stokes - 1 - m["drag"]["sys"]
    sigma = math.hypot(err / stokes, m["drag"]["sys_err"])
    print(f"core: D(inf) = {D + shift:.5f} +/- {err:.5f}, slip Stokes {stokes:.5f}, "
          f"deviation from the stated systematic error {100 * dev:+.1f} % (sigma {100 * sigma:.1f} %)")
    assert abs(dev) < 3 * sigma
