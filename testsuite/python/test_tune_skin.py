# labels: python
"""cell_system.tune_skin (ESPResSo's signature): it picks a skin inside
[min_skin, max_skin] by timing trial runs on a pickled copy of the system, so
the system's own state is untouched: after tuning, a run gives bit for bit the
trajectory of an identical system whose skin was set to the same value by hand.
Bad input is refused with a ValueError naming the parameter."""
import numpy as np
import pytest

import marble

if not marble.has_features("DPD"):
    pytest.skip("needs DPD", allow_module_level=True)


def fluid(L=6.0, seed=3):
    rng = np.random.default_rng(seed)
    s = marble.System(box_l=[L] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    n = int(3 * L**3)
    s.part.add(pos=rng.uniform(0, L, (n, 3)), v=rng.normal(size=(n, 3)))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=4.5, k=1.0, r_cut=1.0)
    s.thermostat.set_dpd(kT=1.0, seed=7)
    s.integrator.run(10)
    return s


def state(s):
    p = s.part.all()
    o = np.argsort(p.id)
    return [np.asarray(x)[o] for x in (p.pos, p.v, p.f)]


def test_picks_a_skin_in_range_and_leaves_the_state():
    s = fluid()
    before = state(s)
    t0 = s.time
    skin = s.cell_system.tune_skin(min_skin=0.1, max_skin=1.2, tol=0.15, int_steps=15)
    assert 0.1 <= skin <= 1.2
    assert s.cell_system.skin == skin
    assert s.time == t0
    for a, b in zip(before, state(s)):
        np.testing.assert_array_equal(a, b)
    # the same trajectory as a twin whose skin is set by hand
    twin = fluid()
    twin.cell_system.skin = skin
    s.integrator.run(30)
    twin.integrator.run(30)
    for a, b in zip(state(s), state(twin)):
        np.testing.assert_array_equal(a, b)


def test_adjust_max_skin():
    s = fluid(L=4.0)
    skin = s.cell_system.tune_skin(0.2, 5.0, 0.5, 5, adjust_max_skin=True)
    assert 0.2 <= skin <= 2.0


@pytest.mark.parametrize("kw, name", [
    (dict(min_skin=0.0), "min_skin"),
    (dict(min_skin=-1.0), "min_skin"),
    (dict(max_skin=0.05), "max_skin"),
    (dict(max_skin=10.0), "max_skin"),
    (dict(tol=0.0), "tol"),
    (dict(tol=float("nan")), "tol"),
    (dict(int_steps=0), "int_steps"),
    (dict(int_steps=2.5), "int_steps"),
    (dict(min_skin="a"), "min_skin"),
])
def test_bad_input(kw, name):
    s = fluid(L=4.0)
    args = dict(min_skin=0.1, max_skin=1.0, tol=0.1, int_steps=5)
    args.update(kw)
    with pytest.raises(ValueError, match=name):
        s.cell_system.tune_skin(**args)
