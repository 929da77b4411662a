# labels: python
"""Non-bonded interactions: set_params / get_params / deactivate, and the
energy and force they produce for a pair, against the formulas."""
import numpy as np
import pytest

import marble
from unittest_decorators import skipIfMissingFeatures


def lj_energy(r, eps, sig, cut, shift, offset=0.0, rmin=0.0):
    ro = r - offset
    if ro >= cut or ro <= rmin:
        return 0.0
    q6 = (sig / ro) ** 6
    return 4 * eps * (q6 * q6 - q6 + shift)


def lj_force(r, eps, sig, cut, offset=0.0):
    """Force magnitude along d = r_i - r_j (positive: repulsive)."""
    ro = r - offset
    if ro >= cut:
        return 0.0
    q6 = (sig / ro) ** 6
    return 24 * eps * (2 * q6 * q6 - q6) / ro


def pair_system(r, types=(0, 0)):
    s = marble.System(box_l=[10.0] * 3, time_step=0.001)
    s.part.add(pos=[[2.0, 3.0, 4.0], [2.0 + r, 3.0, 4.0]], type=list(types))
    return s


@skipIfMissingFeatures("LENNARD_JONES")
def test_lj_set_get_deactivate():
    s = marble.System(box_l=[10.0] * 3)
    lj = s.non_bonded_inter[0, 1].lennard_jones
    assert lj.get_params() == {} and not lj.is_active()
    lj.set_params(epsilon=1.5, sigma=0.9, cutoff=2.0, shift=0.1, offset=0.2, min=0.05)
    expected = dict(epsilon=1.5, sigma=0.9, cutoff=2.0, shift=0.1, offset=0.2, min=0.05)
    assert lj.get_params() == pytest.approx(expected)
    # the table is symmetric
    assert s.non_bonded_inter[1, 0].lennard_jones.get_params() == pytest.approx(expected)
    # set_params replaces: omitted optional keys take their defaults
    lj.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5)
    assert lj.get_params() == pytest.approx(
        dict(epsilon=1.0, sigma=1.0, cutoff=2.5, shift=0.0, offset=0.0, min=0.0))
    # shift="auto" makes V(cutoff) = 0
    lj.set_params(epsilon=1.0, sigma=1.0, cutoff=2.5, shift="auto")
    q6 = (1.0 / 2.5) ** 6
    assert lj.get_params()["shift"] == pytest.approx(-(q6 * q6 - q6), rel=1e-14)
    lj.set_params(epsilon=1.0, sigma=1.0, cutoff=2 ** (1 / 6), shift="auto")
    assert lj.get_params()["shift"] == pytest.approx(0.25, rel=1e-12)
    lj.deactivate()
    assert lj.get_params() == {}
    assert s.non_bonded_inter[1, 0].lennard_jones.get_params() == {}
    # other pairs are untouched
    assert s.non_bonded_inter[0, 0].lennard_jones.get_params() == {}


@skipIfMissingFeatures("LENNARD_JONES")
@pytest.mark.parametrize("r", [0.95, 1.1, 1.5, 2.3, 2.6, 3.3])
@pytest.mark.parametrize("params", [
    dict(epsilon=1.0, sigma=1.0, cutoff=2.5, shift="auto"),
    dict(epsilon=2.0, sigma=0.8, cutoff=2.0, shift=0.05, offset=0.5),
    dict(epsilon=1.0, sigma=1.0, cutoff=2 ** (1 / 6), shift=0.25, offset=1.0, min=0.1),
])
def test_lj_pair_energy_and_force(r, params):
    s = pair_system(r, types=(0, 1))
    s.non_bonded_inter[0, 1].lennard_jones.set_params(**params)
    p = s.non_bonded_inter[0, 1].lennard_jones.get_params()
    e_ref = lj_energy(r, p["epsilon"], p["sigma"], p["cutoff"], p["shift"], p["offset"], p["min"])
    e = s.analysis.energy()
    assert e["non_bonded"] == pytest.approx(e_ref, rel=1e-12, abs=1e-14)
    assert e[("non_bonded", 0, 1)] == pytest.approx(e_ref, rel=1e-12, abs=1e-14)
    assert e[("non_bonded", 0, 0)] == 0.0
    s.integrator.run(0)
    ro = r - p["offset"]
    f_ref = lj_force(r, p["epsilon"], p["sigma"], p["cutoff"], p["offset"]) \
        if p["min"] < ro < p["cutoff"] else 0.0
    f = s.part.all().f
    np.testing.assert_allclose(f[0], [-f_ref, 0, 0], rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(f[1], [f_ref, 0, 0], rtol=1e-12, atol=1e-14)


@skipIfMissingFeatures("LENNARD_JONES")
def test_lj_only_acts_on_its_type_pair():
    s = pair_system(1.2, types=(0, 0))
    s.non_bonded_inter[0, 1].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=2.5)
    assert s.analysis.energy()["non_bonded"] == 0.0
    s.part.by_id(1).type = 1
    assert s.analysis.energy()["non_bonded"] == pytest.approx(lj_energy(1.2, 1, 1, 2.5, 0))
    s.non_bonded_inter[0, 1].lennard_jones.deactivate()
    s.integrator.run(0)
    assert s.analysis.energy()["non_bonded"] == 0.0
    np.testing.assert_array_equal(s.part.all().f, np.zeros((2, 3)))


@skipIfMissingFeatures("LENNARD_JONES")
def test_cutoff_change_rebuilds_lists():
    # A pair outside the first cutoff (and skin) must be found after the cutoff grows.
    s = pair_system(3.0)
    s.cell_system.skin = 0.1
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=1.5)
    assert s.analysis.energy()["non_bonded"] == 0.0
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=1, cutoff=3.5)
    assert s.analysis.energy()["non_bonded"] == pytest.approx(lj_energy(3.0, 1, 1, 3.5, 0))


@skipIfMissingFeatures("HAT")
def test_hat_set_get_deactivate_and_pair():
    s = pair_system(0.4)
    hat = s.non_bonded_inter[0, 0].hat
    assert hat.get_params() == {}
    hat.set_params(F_max=25.0, cutoff=1.0)
    assert hat.get_params() == pytest.approx(dict(F_max=25.0, cutoff=1.0, offset=0.0))
    e = s.analysis.energy()["non_bonded"]
    assert e == pytest.approx(25.0 * 0.6 ** 2 / 2, rel=1e-12)
    s.integrator.run(0)
    f = s.part.all().f
    np.testing.assert_allclose(f[1], [25.0 * 0.6, 0, 0], rtol=1e-12)
    np.testing.assert_allclose(f[0], -f[1], rtol=1e-12)
    hat.set_params(F_max=3.0, cutoff=0.3)  # now out of range
    s.integrator.run(0)
    np.testing.assert_array_equal(s.part.all().f, np.zeros((2, 3)))
    hat.deactivate()
    assert hat.get_params() == {}


@skipIfMissingFeatures("LENNARD_JONES", "HAT")
def test_kernels_add_up():
    s = pair_system(0.9)
    s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=0.5, sigma=0.8, cutoff=2.0)
    s.non_bonded_inter[0, 0].hat.set_params(F_max=10.0, cutoff=1.5)
    e_ref = lj_energy(0.9, 0.5, 0.8, 2.0, 0.0) + 10.0 * 0.6 ** 2 / 3.0
    assert s.analysis.energy()["non_bonded"] == pytest.approx(e_ref, rel=1e-12)
    s.integrator.run(0)
    f_ref = lj_force(0.9, 0.5, 0.8, 2.0) + 10.0 * (1 - 0.9 / 1.5)
    np.testing.assert_allclose(s.part.by_id(1).f, [f_ref, 0, 0], rtol=1e-12)


@skipIfMissingFeatures("LENNARD_JONES")
def test_interaction_object_constructed_on_its_own():
    """ESPResSo 4.3 style: an interaction object built with its parameters
    (validated at once, like set_params), assigned to a type pair; the pair's
    forces are then those of set_params with the same parameters."""
    from marble.interactions import LennardJonesInteraction
    lj = LennardJonesInteraction(epsilon=1.2, sigma=1.0, cutoff=2.5, shift="auto")
    p = lj.get_params()
    assert p["epsilon"] == 1.2 and p["cutoff"] == 2.5
    assert p["shift"] == pytest.approx(-(1.0 / 2.5 ** 12 - 1.0 / 2.5 ** 6))
    assert "unbound" in repr(lj)
    s1, s2 = pair_system(1.1), pair_system(1.1)
    s1.non_bonded_inter[0, 0].lennard_jones = lj
    s2.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.2, sigma=1.0, cutoff=2.5, shift="auto")
    assert s1.non_bonded_inter[0, 0].lennard_jones.get_params() == p
    s1.integrator.run(0)
    s2.integrator.run(0)
    np.testing.assert_array_equal(s1.part.all().f, s2.part.all().f)
    assert np.abs(s1.part.all().f).max() > 0
    # the object is a value: changing it later leaves the system alone
    lj.set_params(epsilon=2.0, sigma=1.0, cutoff=2.5)
    assert s1.non_bonded_inter[0, 0].lennard_jones.get_params()["epsilon"] == 1.2
    # a deactivated object switches the pair off when assigned
    lj.deactivate()
    s1.non_bonded_inter[0, 0].lennard_jones = lj
    assert not s1.non_bonded_inter[0, 0].lennard_jones.is_active()


@skipIfMissingFeatures("LENNARD_JONES")
def test_interaction_object_bad_input():
    from marble.interactions import LennardJonesInteraction
    with pytest.raises(ValueError, match="epsilon"):
        LennardJonesInteraction(epsilon=-1.0, sigma=1.0, cutoff=2.5)
    with pytest.raises(ValueError, match="sigma"):
        LennardJonesInteraction(epsilon=1.0, cutoff=2.5)
    with pytest.raises(ValueError, match="keyword"):
        LennardJonesInteraction(1.0, 1.0, 2.5)
    s = marble.System(box_l=[10.0] * 3)
    with pytest.raises(ValueError, match="LennardJonesInteraction"):
        s.non_bonded_inter[0, 0].lennard_jones = 3
    with pytest.raises(AttributeError, match="no interaction"):
        s.non_bonded_inter[0, 0].no_such_kind = LennardJonesInteraction(epsilon=1.0, sigma=1.0, cutoff=2.5)
    assert not s.non_bonded_inter[0, 0].lennard_jones.is_active()


def test_interaction_object_of_missing_feature():
    """A kernel that is not compiled in: FeaturesError naming its feature."""
    from marble import interactions
    missing = [k for k in interactions.KERNELS if not k["compiled"]]
    if not missing:
        pytest.skip("every kernel is compiled into this build")
    k = missing[0]
    cls = getattr(interactions, k["py_class"])
    with pytest.raises(marble.FeaturesError, match=k["feature"]):
        cls()
