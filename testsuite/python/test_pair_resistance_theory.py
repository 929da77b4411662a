# labels: python
"""marble.theory's two-sphere resistances (doc/suspensions.md section 7g): the exact
bispherical series against their far-field reflection expansions, the near-field
(lubrication) form, Stimson & Jeffery's tabulated values and bad input."""
import math

import numpy as np
import pytest

from marble import theory


def reflections(s, sign):
    """Resistance of the mode from the two-sphere mobility functions of equal spheres to
    O(s^-4) (Jeffrey & Onishi 1984: x11a = 1 - 15/(4 s^4), x12a = 3/(2s) - 1/s^3):
    lambda = 1/(x11a - sign x12a); sign +1: squeeze, -1: same velocity."""
    x11 = 1 - 15.0 / (4 * s ** 4)
    x12 = 1.5 / s - 1.0 / s ** 3
    return 1.0 / (x11 - sign * x12)


@pytest.mark.parametrize("s", [6.0, 10.0, 30.0])
def test_far_field(s):
    xi = s - 2.0
    # the O(s^-6) remainder: 2e-4 at s = 6 (measured 1e-4), 1e-5 at 10
    tol = 10.0 / s ** 6 + 1e-10
    assert theory.two_sphere_squeeze_resistance(xi) == pytest.approx(reflections(s, +1), abs=tol)
    assert theory.two_sphere_translation_resistance(xi) == pytest.approx(reflections(s, -1), abs=tol)


def test_far_limit():
    assert theory.two_sphere_squeeze_resistance(1e4) == pytest.approx(1.0, abs=2e-4)
    assert theory.two_sphere_translation_resistance(1e4) == pytest.approx(1.0, abs=2e-4)


@pytest.mark.parametrize("xi", [1e-4, 1e-3, 1e-2])
def test_near_field(xi):
    lam = theory.two_sphere_squeeze_resistance(xi)
    # Jeffrey & Onishi's form to O(1): the remainder is O(xi) (0.19 xi from the series)
    assert lam == pytest.approx(theory.two_sphere_squeeze_lubrication(xi), abs=0.3 * xi + 1e-5)
    # the leading Reynolds term 1/(2 xi) alone misses (9/20) ln(1/xi) + 1.35
    lead = theory.two_sphere_squeeze_lubrication(xi, terms="reynolds")
    assert lead == pytest.approx(0.5 / xi)
    assert lam - lead == pytest.approx(0.45 * math.log(1 / xi) + theory.SQUEEZE_NEAR_FIELD_CONSTANT,
                                       abs=0.3 * xi + 0.06 * xi * math.log(1 / xi) + 1e-5)
    log = theory.two_sphere_squeeze_lubrication(xi, terms="log")
    assert log - lead == pytest.approx(0.45 * math.log(1 / xi))


def test_stimson_jeffery_table():
    # Stimson & Jeffery (1926), their table at alpha = 0.5 and 1 (s = 2 cosh alpha):
    # 0.6596 and 0.7024; the touching doublet 0.645
    for al, ref in [(0.5, 0.6596), (1.0, 0.7024)]:
        xi = 2 * (math.cosh(al) - 1)
        assert theory.two_sphere_translation_resistance(xi) == pytest.approx(ref, abs=1e-4)
    assert theory.two_sphere_translation_resistance(1e-5) == pytest.approx(0.645, abs=1e-3)


def test_vector_and_values():
    lam = theory.two_sphere_squeeze_resistance(np.array([0.1, 1.0, 2.0]))
    assert lam.shape == (3,)
    np.testing.assert_allclose(lam, [7.4133, 2.0387, 1.5967], atol=1e-4)
    assert np.all(np.diff(theory.two_sphere_squeeze_resistance(np.geomspace(1e-3, 100, 30))) < 0)


@pytest.mark.parametrize("bad", [0.0, -0.1, float("nan"), float("inf")])
def test_bad_input(bad):
    for fn in (theory.two_sphere_squeeze_resistance, theory.two_sphere_translation_resistance,
               theory.two_sphere_squeeze_lubrication):
        with pytest.raises(ValueError, match="xi"):
            fn(bad)
    with pytest.raises(ValueError, match="terms"):
        theory.two_sphere_squeeze_lubrication(0.1, terms="cubic")
