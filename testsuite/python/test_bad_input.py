# labels: python
"""Bad input: every case must raise the natural error (ValueError, or
IndexError / AttributeError / FeaturesError) and leave the system exactly as
it was (parameters, particles, interactions, integrator, thermostat)."""
import numpy as np
import pytest

import marble

NAN, INF = float("nan"), float("inf")
KINDS = ("lennard_jones", "hat", "dpd")


def make_system():
    s = marble.System(box_l=[6.0, 6.0, 6.0], time_step=0.01)
    s.cell_system.skin = 0.3
    rng = np.random.default_rng(11)
    props = dict(pos=rng.uniform(0, 6, (5, 3)), v=rng.normal(size=(5, 3)), type=[0, 1, 0, 1, 2])
    if marble.has_features("MASS"):
        props["mass"] = [1.0, 2.0, 1.5, 1.0, 3.0]
    s.part.add(**props)
    if marble.has_features("LENNARD_JONES"):
        s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1, sigma=0.5, cutoff=1.2)
    if marble.has_features("HAT"):
        s.non_bonded_inter[0, 1].hat.set_params(F_max=2.0, cutoff=1.0)
    if marble.has_features("DPD"):
        s.non_bonded_inter[1, 1].dpd.set_params(gamma=1.0, r_cut=1.0, weight_function=1)
    return s


def snapshot(s):
    core = s._core
    ids = core.particle_ids()
    snap = dict(box_l=s.box_l.tolist(), periodicity=s.periodicity.tolist(),
                time_step=s.time_step, skin=s.cell_system.skin, time=s.time, step=s.step,
                ids=list(ids), integrator=s.integrator.get_state(),
                thermostat=dict(core.dpd_state()))
    for name in core.property_names():
        if name not in ("f", "torque_lab"):
            snap["p_" + name] = core.get_property(name, ids).tolist()
    for i in range(3):
        for j in range(i, 3):
            for kind in KINDS:
                try:
                    snap[(i, j, kind)] = core.get_nonbonded(i, j, kind)
                except marble.FeaturesError:
                    pass
    return snap


def needs(*features):
    return pytest.mark.skipif(not marble.has_features(*features),
                              reason=f"missing feature(s) {features}")


def p(sys_, pid=1):
    return sys_.part.by_id(pid)


def lj(sys_, **kw):
    sys_.non_bonded_inter[0, 0].lennard_jones.set_params(**kw)


LJ_OK = dict(epsilon=1.0, sigma=1.0, cutoff=2.5)
LJ_F = (needs("LENNARD_JONES"),)
MASS_F = (needs("MASS"),)
ROT_F = (needs("ROTATION"),)

# (id, action(system), expected exception, marks)
CASES = [
    # --- System construction and parameters ---
    ("box_negative", lambda s: marble.System(box_l=[-1.0, 1.0, 1.0]), ValueError, ()),
    ("box_zero", lambda s: marble.System(box_l=[0.0, 1.0, 1.0]), ValueError, ()),
    ("box_nan", lambda s: marble.System(box_l=[NAN, 1.0, 1.0]), ValueError, ()),
    ("box_inf", lambda s: marble.System(box_l=[1.0, INF, 1.0]), ValueError, ()),
    ("box_shape", lambda s: marble.System(box_l=[1.0, 1.0]), ValueError, ()),
    ("box_string", lambda s: marble.System(box_l="10"), ValueError, ()),
    ("box_missing", lambda s: marble.System(), ValueError, ()),
    ("system_unknown_key", lambda s: marble.System(box_l=[1.0] * 3, box=[1.0] * 3), ValueError, ()),
    ("system_bad_time_step", lambda s: marble.System(box_l=[1.0] * 3, time_step=-1), ValueError, ()),
    ("box_change_with_particles", lambda s: setattr(s, "box_l", [7.0] * 3), ValueError, ()),
    ("box_set_nan", lambda s: setattr(s, "box_l", [NAN] * 3), ValueError, ()),
    ("time_step_negative", lambda s: setattr(s, "time_step", -0.01), ValueError, ()),
    ("time_step_zero", lambda s: setattr(s, "time_step", 0), ValueError, ()),
    ("time_step_nan", lambda s: setattr(s, "time_step", NAN), ValueError, ()),
    ("time_step_inf", lambda s: setattr(s, "time_step", INF), ValueError, ()),
    ("time_step_string", lambda s: setattr(s, "time_step", "0.01"), ValueError, ()),
    ("time_step_none", lambda s: setattr(s, "time_step", None), ValueError, ()),
    ("time_negative", lambda s: setattr(s, "time", -1.0), ValueError, ()),
    ("step_read_only", lambda s: setattr(s, "step", 5), AttributeError, ()),
    ("skin_negative", lambda s: setattr(s.cell_system, "skin", -0.1), ValueError, ()),
    ("skin_nan", lambda s: setattr(s.cell_system, "skin", NAN), ValueError, ()),
    ("skin_inf", lambda s: setattr(s.cell_system, "skin", INF), ValueError, ()),
    ("skin_above_half_box", lambda s: setattr(s.cell_system, "skin", 3.5), ValueError, ()),
    ("skin_string", lambda s: setattr(s.cell_system, "skin", "0.4"), ValueError, ()),
    ("periodicity_not_bool", lambda s: setattr(s, "periodicity", [True, True, 1.5]), ValueError, ()),
    ("periodicity_shape", lambda s: setattr(s, "periodicity", [True, True]), ValueError, ()),
    # --- adding particles ---
    ("add_pos_missing", lambda s: s.part.add(v=[0.0, 0.0, 0.0]), ValueError, ()),
    ("add_pos_nan", lambda s: s.part.add(pos=[NAN, 1.0, 1.0]), ValueError, ()),
    ("add_pos_inf", lambda s: s.part.add(pos=[1.0, -INF, 1.0]), ValueError, ()),
    ("add_pos_huge", lambda s: s.part.add(pos=[1e300, 1.0, 1.0]), ValueError, ()),
    ("add_pos_shape_2", lambda s: s.part.add(pos=[1.0, 1.0]), ValueError, ()),
    ("add_pos_shape_n4", lambda s: s.part.add(pos=np.ones((3, 4))), ValueError, ()),
    ("add_pos_shape_3d", lambda s: s.part.add(pos=np.ones((2, 3, 3))), ValueError, ()),
    ("add_pos_empty", lambda s: s.part.add(pos=np.ones((0, 3))), ValueError, ()),
    ("add_pos_strings", lambda s: s.part.add(pos=["a", "b", "c"]), ValueError, ()),
    ("add_v_inf", lambda s: s.part.add(pos=[1.0] * 3, v=[INF, 0.0, 0.0]), ValueError, ()),
    ("add_v_nan_last_row", lambda s: s.part.add(pos=np.ones((3, 3)),
                                                v=[[0, 0, 0], [0, 0, 0], [0, NAN, 0]]), ValueError, ()),
    ("add_v_shape", lambda s: s.part.add(pos=[1.0] * 3, v=[1.0, 2.0]), ValueError, ()),
    ("add_v_rows_mismatch", lambda s: s.part.add(pos=np.ones((2, 3)), v=np.ones((3, 3))), ValueError, ()),
    ("add_v_string", lambda s: s.part.add(pos=[1.0] * 3, v="fast"), ValueError, ()),
    ("add_unknown_property", lambda s: s.part.add(pos=[1.0] * 3, charge=1.0), ValueError, ()),
    ("add_duplicate_id", lambda s: s.part.add(pos=[1.0] * 3, id=3), ValueError, ()),
    ("add_duplicate_id_in_batch", lambda s: s.part.add(pos=np.ones((2, 3)), id=[7, 7]), ValueError, ()),
    ("add_negative_id", lambda s: s.part.add(pos=[1.0] * 3, id=-1), ValueError, ()),
    ("add_float_id", lambda s: s.part.add(pos=[1.0] * 3, id=7.5), ValueError, ()),
    ("add_type_negative", lambda s: s.part.add(pos=[1.0] * 3, type=-1), ValueError, ()),
    ("add_type_float", lambda s: s.part.add(pos=[1.0] * 3, type=1.5), ValueError, ()),
    ("add_type_string", lambda s: s.part.add(pos=[1.0] * 3, type="solvent"), ValueError, ()),
    ("add_type_too_large", lambda s: s.part.add(pos=[1.0] * 3, type=10 ** 6), ValueError, ()),
    ("add_type_nan", lambda s: s.part.add(pos=[1.0] * 3, type=NAN), ValueError, ()),
    ("add_read_only_f", lambda s: s.part.add(pos=[1.0] * 3, f=[1.0, 0.0, 0.0]), ValueError, ()),
    ("add_read_only_image_box", lambda s: s.part.add(pos=[1.0] * 3, image_box=[1, 0, 0]), ValueError, ()),
    ("add_positional_args", lambda s: s.part.add([1.0, 1.0, 1.0]), ValueError, ()),
    ("add_mass_negative", lambda s: s.part.add(pos=[1.0] * 3, mass=-1.0), ValueError, MASS_F),
    ("add_mass_zero", lambda s: s.part.add(pos=[1.0] * 3, mass=0.0), ValueError, MASS_F),
    ("add_mass_nan", lambda s: s.part.add(pos=[1.0] * 3, mass=NAN), ValueError, MASS_F),
    ("add_mass_inf_in_batch", lambda s: s.part.add(pos=np.ones((3, 3)), mass=[1.0, INF, 1.0]),
     ValueError, MASS_F),
    ("add_rinertia_negative", lambda s: s.part.add(pos=[1.0] * 3, rinertia=[-1.0] * 3),
     ValueError, ROT_F),
    ("add_rinertia_inf", lambda s: s.part.add(pos=[1.0] * 3, rinertia=[INF] * 3),
     ValueError, ROT_F),
    ("add_rinertia_anisotropic", lambda s: s.part.add(pos=[1.0] * 3, rinertia=[1.0, 2.0, 3.0]),
     ValueError, ROT_F),
    ("add_rotation_not_bool", lambda s: s.part.add(pos=[1.0] * 3, rotation=[2, 2, 2]),
     ValueError, ROT_F),
    ("add_omega_nan", lambda s: s.part.add(pos=[1.0] * 3, omega_lab=[NAN, 0.0, 0.0]),
     ValueError, ROT_F),
    ("add_ext_force_nan", lambda s: s.part.add(pos=[1.0] * 3, ext_force=[0.0, NAN, 0.0]),
     ValueError, (needs("EXTERNAL_FORCE"),)),
    ("add_fix_not_bool", lambda s: s.part.add(pos=[1.0] * 3, fix=[2, 0, 0]),
     ValueError, (needs("EXTERNAL_FORCE"),)),
    ("add_fix_shape", lambda s: s.part.add(pos=[1.0] * 3, fix=[True, False]),
     ValueError, (needs("EXTERNAL_FORCE"),)),
    ("add_mass_missing_feature", lambda s: s.part.add(pos=[1.0] * 3, mass=2.0),
     marble.FeaturesError, (pytest.mark.skipif(marble.has_features("MASS"), reason="MASS exists"),)),
    ("add_rotation_missing_feature", lambda s: s.part.add(pos=[1.0] * 3, rotation=[True] * 3),
     marble.FeaturesError,
     (pytest.mark.skipif(marble.has_features("ROTATION"), reason="ROTATION exists"),)),
    # --- changing particles ---
    ("set_v_nan", lambda s: setattr(p(s), "v", [NAN, 0.0, 0.0]), ValueError, ()),
    ("set_pos_inf", lambda s: setattr(p(s), "pos", [INF, 0.0, 0.0]), ValueError, ()),
    ("set_pos_shape", lambda s: setattr(p(s), "pos", [1.0, 2.0, 3.0, 4.0]), ValueError, ()),
    ("set_slice_v_one_bad_row", lambda s: setattr(s.part.all(), "v",
                                                  [[0, 0, 0]] * 4 + [[0, 0, NAN]]), ValueError, ()),
    ("set_slice_pos_wrong_rows", lambda s: setattr(s.part.all(), "pos", np.ones((4, 3))), ValueError, ()),
    ("set_type_negative", lambda s: setattr(p(s), "type", -2), ValueError, ()),
    ("set_type_string", lambda s: setattr(p(s), "type", "a"), ValueError, ()),
    ("set_f_read_only", lambda s: setattr(p(s), "f", [1.0, 0.0, 0.0]), AttributeError, ()),
    ("set_id_read_only", lambda s: setattr(p(s), "id", 9), AttributeError, ()),
    ("set_pos_folded_read_only", lambda s: setattr(p(s), "pos_folded", [1.0] * 3), AttributeError, ()),
    ("set_image_box_read_only", lambda s: setattr(p(s), "image_box", [1, 0, 0]), AttributeError, ()),
    ("set_unknown_attribute", lambda s: setattr(p(s), "charge", 1.0), AttributeError, ()),
    ("get_unknown_attribute", lambda s: p(s).charge, AttributeError, ()),
    ("set_mass_negative_in_slice", lambda s: setattr(s.part.all(), "mass", [1, 1, 1, 1, -1]),
     ValueError, MASS_F),
    ("set_mass_string", lambda s: setattr(p(s), "mass", "heavy"), ValueError, MASS_F),
    ("set_rinertia_zero", lambda s: setattr(p(s), "rinertia", [0.0] * 3), ValueError, ROT_F),
    ("by_id_missing", lambda s: s.part.by_id(99), IndexError, ()),
    ("by_id_string", lambda s: s.part.by_id("1"), ValueError, ()),
    ("by_id_float", lambda s: s.part.by_id(1.0), ValueError, ()),
    ("by_ids_missing", lambda s: s.part.by_ids([1, 99]), IndexError, ()),
    ("remove_some_missing", lambda s: s._core.remove_particles([1, 99]), IndexError, ()),
    ("select_unknown_property", lambda s: s.part.select(charge=1), ValueError, ()),
    # --- interactions ---
    ("ia_index_negative", lambda s: s.non_bonded_inter[-1, 0], ValueError, ()),
    ("ia_index_float", lambda s: s.non_bonded_inter[0.5, 0], ValueError, ()),
    ("ia_index_single", lambda s: s.non_bonded_inter[0], ValueError, ()),
    ("ia_index_too_large", lambda s: s.non_bonded_inter[0, 5000], ValueError, ()),
    ("lj_epsilon_negative", lambda s: lj(s, **{**LJ_OK, "epsilon": -1.0}), ValueError, LJ_F),
    ("lj_epsilon_nan", lambda s: lj(s, **{**LJ_OK, "epsilon": NAN}), ValueError, LJ_F),
    ("lj_sigma_zero", lambda s: lj(s, **{**LJ_OK, "sigma": 0.0}), ValueError, LJ_F),
    ("lj_sigma_inf", lambda s: lj(s, **{**LJ_OK, "sigma": INF}), ValueError, LJ_F),
    ("lj_cutoff_negative", lambda s: lj(s, **{**LJ_OK, "cutoff": -2.5}), ValueError, LJ_F),
    ("lj_cutoff_nan", lambda s: lj(s, **{**LJ_OK, "cutoff": NAN}), ValueError, LJ_F),
    ("lj_offset_negative", lambda s: lj(s, **LJ_OK, offset=-0.5), ValueError, LJ_F),
    ("lj_min_above_cutoff", lambda s: lj(s, **LJ_OK, min=3.0), ValueError, LJ_F),
    ("lj_shift_bad_string", lambda s: lj(s, **LJ_OK, shift="automatic"), ValueError, LJ_F),
    ("lj_shift_inf", lambda s: lj(s, **LJ_OK, shift=INF), ValueError, LJ_F),
    ("lj_epsilon_string", lambda s: lj(s, **{**LJ_OK, "epsilon": "1"}), ValueError, LJ_F),
    ("lj_unknown_key", lambda s: lj(s, **LJ_OK, eps=1.0), ValueError, LJ_F),
    ("lj_missing_key", lambda s: lj(s, epsilon=1.0, sigma=1.0), ValueError, LJ_F),
    ("lj_missing_feature", lambda s: lj(s, **LJ_OK), marble.FeaturesError,
     (pytest.mark.skipif(marble.has_features("LENNARD_JONES"), reason="LENNARD_JONES exists"),)),
    ("hat_fmax_negative", lambda s: s.non_bonded_inter[0, 1].hat.set_params(F_max=-1.0, cutoff=1.0),
     ValueError, (needs("HAT"),)),
    ("hat_cutoff_zero", lambda s: s.non_bonded_inter[0, 1].hat.set_params(F_max=1.0, cutoff=0.0),
     ValueError, (needs("HAT"),)),
    ("hat_unknown_key", lambda s: s.non_bonded_inter[0, 1].hat.set_params(F_max=1.0, cutoff=1.0, k=2),
     ValueError, (needs("HAT"),)),
    ("hat_missing_feature", lambda s: s.non_bonded_inter[0, 1].hat.set_params(F_max=1.0, cutoff=1.0),
     marble.FeaturesError, (pytest.mark.skipif(marble.has_features("HAT"), reason="HAT exists"),)),
    ("dpd_gamma_negative", lambda s: s.non_bonded_inter[1, 1].dpd.set_params(gamma=-1.0, r_cut=1.0),
     ValueError, (needs("DPD"),)),
    ("dpd_weight_function_bad", lambda s: s.non_bonded_inter[1, 1].dpd.set_params(
        gamma=1.0, r_cut=1.0, weight_function=2), ValueError, (needs("DPD"),)),
    ("dpd_unknown_key", lambda s: s.non_bonded_inter[1, 1].dpd.set_params(gamma=1.0, rcut=1.0),
     ValueError, (needs("DPD"),)),
    ("dpd_kT_negative", lambda s: s.thermostat.set_dpd(kT=-1.0, seed=1), ValueError, (needs("DPD"),)),
    ("dpd_seed_negative", lambda s: s.thermostat.set_dpd(kT=1.0, seed=-1), ValueError, (needs("DPD"),)),
    ("dpd_seed_missing", lambda s: s.thermostat.set_dpd(kT=1.0), ValueError, (needs("DPD"),)),
    ("dpd_seed_float", lambda s: s.thermostat.set_dpd(kT=1.0, seed=1.5), ValueError, (needs("DPD"),)),
    # --- integrator ---
    ("sd_f_max_negative", lambda s: s.integrator.set_steepest_descent(
        f_max=-1.0, gamma=0.1, max_displacement=0.1), ValueError, ()),
    ("sd_gamma_nan", lambda s: s.integrator.set_steepest_descent(
        f_max=1.0, gamma=NAN, max_displacement=0.1), ValueError, ()),
    ("sd_max_displacement_zero", lambda s: s.integrator.set_steepest_descent(
        f_max=1.0, gamma=0.1, max_displacement=0.0), ValueError, ()),
    ("sd_missing_parameter", lambda s: s.integrator.set_steepest_descent(f_max=1.0, gamma=0.1),
     ValueError, ()),
    ("run_negative", lambda s: s.integrator.run(-1), ValueError, ()),
    ("run_float", lambda s: s.integrator.run(2.5), ValueError, ()),
    ("run_nan", lambda s: s.integrator.run(NAN), ValueError, ()),
    ("run_string", lambda s: s.integrator.run("10"), ValueError, ()),
    ("run_none", lambda s: s.integrator.run(None), ValueError, ()),
    ("run_bool", lambda s: s.integrator.run(True), ValueError, ()),
    ("run_huge", lambda s: s.integrator.run(10 ** 12), ValueError, ()),
    # --- analysis and helpers ---
    ("min_dist_float_type", lambda s: s.analysis.min_dist([0.5], [1]), ValueError, ()),
    ("min_dist_negative_type", lambda s: s.analysis.min_dist([-1], [1]), ValueError, ()),
    ("distance_bad_shape", lambda s: s.distance([1.0, 2.0], [1.0, 2.0, 3.0]), ValueError, ()),
    ("distance_vec_nan", lambda s: s.distance_vec([NAN, 0.0, 0.0], p(s)), ValueError, ()),
    ("has_features_not_a_string", lambda s: marble.has_features(3), ValueError, ()),
]


@pytest.mark.parametrize(
    "action,error", [pytest.param(a, e, id=n, marks=m) for n, a, e, m in CASES])
def test_bad_input_raises_and_changes_nothing(action, error):
    s = make_system()
    s.integrator.run(3)  # a state with forces, steps and time
    before = snapshot(s)
    with pytest.raises(error):
        action(s)
    after = snapshot(s)
    assert after.keys() == before.keys()
    for key in before:
        np.testing.assert_equal(after[key], before[key], err_msg=str(key))
    # still usable
    s.integrator.run(2)
    assert s.step == before["step"] + 2


def test_enough_cases():
    assert len({c[0] for c in CASES}) == len(CASES)  # unique ids
    runnable = [c for c in CASES if not any(m.args and m.args[0] for m in c[3]
                                            if m.name == "skipif")]
    assert len(runnable) >= 30
