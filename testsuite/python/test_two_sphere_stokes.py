# labels: python
"""bench/two_sphere_stokes.py (doc/suspensions.md section 7g): the regularized-Stokeslet
solve of two equal spheres that gives the transverse pair resistance Y^A_11 - Y^A_12.
Checked against what is known exactly: the mirror-symmetric solve equals the full
two-sphere solve; the squeeze resistance, extrapolated in the point spacing, equals the
exact bispherical series (marble.theory) at several gaps; far apart the transverse value
equals the inverted Rotne-Prager mobility, and the Stimson-Jeffery-like symmetry holds
(the transverse resistance falls towards 1 as the gap opens); the extrapolation helper
on a synthetic O(h) sequence; bad input."""
import math

import numpy as np
import pytest

from bench_module import load_bench
from marble import theory


B = load_bench("two_sphere_stokes")


def test_mirror_solve_equals_full_solve():
    single, half = B.pair_resistances(100, 0.4)
    single_f, full = B.pair_resistances(100, 0.4, full=True)
    assert single == single_f
    for k in ("squeeze", "transverse"):
        assert half[k] == pytest.approx(full[k], rel=1e-10, abs=0)


def test_points_and_spacing():
    P, h = B.graded_points(400, 0.3)
    assert np.allclose(np.linalg.norm(P, axis=1), 1.0, atol=1e-12)
    # the spacing is smallest towards +x (the gap) and the areas h^2 add up to the sphere's
    assert h[np.argmax(P[:, 0])] < 0.5 * h[np.argmin(P[:, 0])]
    assert np.sum(h ** 2) == pytest.approx(4 * math.pi, rel=0.02)


@pytest.mark.parametrize("xi", [1.0, 4.0])
def test_squeeze_against_exact_series(xi):
    sq = [B.pair_resistances(n, xi)[1]["squeeze"] for n in (150, 300, 600)]
    exact = theory.two_sphere_squeeze_resistance(xi)
    # the raw values are off by ~1-3 %; the extrapolation must get within 0.3 %
    assert abs(sq[0] / exact - 1) > 0.005
    val, err = B.extrapolate(sq)
    assert val == pytest.approx(exact, rel=3e-3)
    assert err < 0.01 * exact


def test_transverse_far_apart_and_monotonic():
    far = [B.pair_resistances(n, 6.0)[1]["transverse"] for n in (150, 300, 600)]
    val, _ = B.extrapolate(far)
    assert val == pytest.approx(B.transverse_far_field(6.0), rel=3e-3)
    near = B.pair_resistances(300, 0.5)[1]["transverse"]
    mid = B.pair_resistances(300, 2.0)[1]["transverse"]
    assert near > mid > far[1] > 1.0


def test_extrapolate_synthetic():
    h = np.array([1.0, 1 / math.sqrt(2), 0.5])
    v = 2.0 + 0.3 * h + 0.05 * h ** 2
    # an O(h) error with an O(h^2) part: the estimate must cover the true limit and be
    # far smaller than the raw error (0.17)
    val, err = B.extrapolate(v)
    assert abs(val - 2.0) <= err < 0.05
    v2, e2 = B.extrapolate(v[:2])
    assert abs(v2 - 2.0) <= e2
    # a pure O(h) sequence is extrapolated exactly
    val, err = B.extrapolate(2.0 + 0.3 * h)
    assert val == pytest.approx(2.0, abs=1e-12)


def test_bad_input():
    with pytest.raises(ValueError, match="xi"):
        B.pair_resistances(100, 0.0)
    with pytest.raises(ValueError, match="ce"):
        B.pair_resistances(100, 0.5, ce=0.0)
    with pytest.raises(ValueError, match="'n'"):
        B.graded_points(5, 0.3)
    with pytest.raises(ValueError, match="theta0"):
        B.graded_points(100, -1.0)
