# labels: python long
"""The scene advisor's cost estimate (marble.advisor.estimate_cost: the
measured table of bench/three_solvents.py, rescaled to this machine by a
probe run, to the scene's particle count and time step) against the measured
CPU time (time.process_time of integrator.run) of three scenes that are not
the table's own: the marble in a smaller box, the SRD colloid in a larger
one, the core-modified colloid at R = 2.5 (another dt and cutoff, between the
measured R = 2 and 3).
Within a factor 1.5 each (a ratio of CPU times on the same machine, not an
absolute timing)."""
import time

import pytest

import marble

FEATURES = ("DPD", "MARBLE", "TUNABLE_SLIP", "SRD", "HAT", "CONTACT", "ROTATION", "MASS",
            "EXTERNAL_FORCE")
pytestmark = pytest.mark.skipif(not marble.has_features(*FEATURES),
                                reason="missing one of the features " + ", ".join(FEATURES))

if marble.has_features(*FEATURES):
    import marble.advisor as adv

SCENES = [("marble", 2.0, 8.0, 40.0), ("srd", 2.0, 12.0, 150.0), ("core", 2.5, 13.0, 2.0)]


@pytest.mark.parametrize("model,R,L,T", SCENES)
def test_cost_estimate_within_factor_1_5(model, R, L, T):
    speed = adv.probe_speed()
    sc = adv.Scene(model, R, L, seed=5, warmup=0.5)
    est = adv.estimate_cost(model, R, L, T, speed=speed)
    c = time.process_time()
    sc.system.integrator.run(int(round(T / sc.dt)))
    cpu = time.process_time() - c
    print(f"{model} R = {R} L = {L} T = {T}: estimated {est:.2f} CPU-s, measured {cpu:.2f} "
          f"(ratio {est / cpu:.2f}; probe {speed:.3g} particle-steps/CPU-s)")
    assert 1 / 1.5 < est / cpu < 1.5
