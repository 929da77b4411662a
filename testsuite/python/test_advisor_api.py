# labels: python
"""marble.advisor without long runs: recommendations from the measured table
(bad input -> ValueError naming the parameter), the warnings for features an
observable does not need, and system.analysis.check_scene(target=...) (without
target it returns the core's warnings only, as before)."""
import numpy as np
import pytest

import marble

FEATURES = ("DPD", "MARBLE", "TUNABLE_SLIP", "HAT", "CONTACT", "ROTATION", "MASS")
pytestmark = pytest.mark.skipif(not marble.has_features(*FEATURES),
                                reason="missing one of the features " + ", ".join(FEATURES))

if marble.has_features(*FEATURES):
    import marble.advisor as adv
    from marble.colloids import add_marble

SPEED = 3.0e6   # a fixed machine speed: no probe run here


def test_recommend_D_and_tighter_costs_more():
    r5 = adv.recommend("D", 0.05, R=2.0, speed=SPEED, verbose=False)
    r1 = adv.recommend("D", 0.01, R=2.0, speed=SPEED, verbose=False)
    assert r5.model in ("marble", "srd", "core")
    assert r5.L > 0 and r5.dt > 0 and r5.run_time > 0 and r5.cpu_s > 0
    assert r1.cpu_s > r5.cpu_s
    assert "CPU-s" in str(r5)
    # a slower machine costs more, in proportion
    r5s = adv.recommend("D", 0.05, R=2.0, speed=SPEED / 2, verbose=False)
    assert r5s.cpu_s == pytest.approx(2 * r5.cpu_s)


def test_recommend_other_observables():
    for obs in ("D_rot", "viscosity"):
        r = adv.recommend(obs, 0.05, R=2.0, speed=SPEED, verbose=False)
        assert r.cpu_s > 0


@pytest.mark.parametrize("kw,name", [(dict(observable="pressure"), "observable"),
                                     (dict(accuracy=0.0), "accuracy"),
                                     (dict(accuracy=2.0), "accuracy"),
                                     (dict(R=-1.0), "R"),
                                     (dict(boundary="rough"), "boundary")])
def test_bad_input(kw, name):
    with pytest.raises(ValueError, match=name):
        adv.recommend(**dict(dict(speed=SPEED, verbose=False), **kw))


def test_bad_model():
    with pytest.raises(ValueError, match="model"):
        adv.estimate_cost("lb", 2.0, 10.0, 1.0, speed=SPEED)
    with pytest.raises(ValueError, match="'T'"):
        adv.estimate_cost("marble", 2.0, 10.0, -1.0, speed=SPEED)


def _scene(hat=False, rotation=True):
    s = marble.System(box_l=[8.0] * 3)
    s.time_step = 0.01
    s.cell_system.skin = 0.4
    rng = np.random.default_rng(1)
    s.part.add(pos=rng.random((300, 3)) * 8.0, type=0)
    s.thermostat.set_dpd(kT=1.0, seed=1)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    if hat:
        s.non_bonded_inter[0, 0].hat.set_params(F_max=25.0, cutoff=1.0)
    col = add_marble(s, pos=[4.0] * 3, radius=2.0, gamma=5.0)
    if not rotation:
        col.rotation = [False] * 3
    return s


def test_check_scene_flags_unneeded_features():
    codes = {w["code"] for w in adv.check_scene(_scene(hat=True), "D")}
    assert {"unneeded_rotation", "unneeded_conservative"} <= codes
    codes = {w["code"] for w in adv.check_scene(_scene(hat=False, rotation=False), "D")}
    assert not codes & {"unneeded_rotation", "unneeded_conservative"}
    # rotation is what D_rot measures
    codes = {w["code"] for w in adv.check_scene(_scene(hat=False), "D_rot")}
    assert "unneeded_rotation" not in codes
    s = _scene()
    s.non_bonded_inter[1, 1].contact.set_params(f_contact=100.0, delta=0.01, offset=4.0)
    s.cell_system.large_range_types = None      # one cell grid: the kernel's range sets it
    assert "unneeded_colloid_pairs" in {w["code"] for w in adv.check_scene(s, "D")}

    # a core-modified colloid (DPD on the gap) goes on the second cell grid by default:
    # its colloid-pair kernels then cost nothing and are not flagged
    s = marble.System(box_l=[8.0] * 3)
    s.time_step = 0.01
    rng = np.random.default_rng(2)
    s.part.add(pos=rng.random((300, 3)) * 8.0, type=0)
    s.part.add(pos=[4.0] * 3, type=1)
    s.thermostat.set_dpd(kT=1.0, seed=1)
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0)
    s.non_bonded_inter[1, 0].dpd.set_params(weight_function=1, gamma=5.0, k=1, r_cut=1.0, offset=2.0)
    s.non_bonded_inter[1, 1].contact.set_params(f_contact=100.0, delta=0.01, offset=4.0)
    s.integrator.run(0)
    assert 1 in s.cell_system.get_state()["large_range_types"]
    assert "unneeded_colloid_pairs" not in {w["code"] for w in adv.check_scene(s, "D")}
    s.cell_system.large_range_types = None
    assert "unneeded_colloid_pairs" in {w["code"] for w in adv.check_scene(s, "D")}


def test_analysis_check_scene_target():
    s = _scene(hat=True)
    plain = s.analysis.check_scene()
    assert all(w["code"] not in ("recommendation", "unneeded_conservative") for w in plain)
    adv._speed_cache[300] = SPEED
    out = s.analysis.check_scene(target={"observable": "D", "accuracy": 0.05, "R": 2.0})
    assert out[-1]["code"] == "recommendation"
    assert isinstance(out[-1]["value"], adv.Recommendation)
    assert "unneeded_conservative" in {w["code"] for w in out}
    assert len(out) >= len(plain) + 2
