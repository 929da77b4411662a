# labels: python
"""Compile-time features: marble.features() / has_features(), FeaturesError
for anything of a feature not compiled in, and the feature resolver."""
import pathlib
import re
import subprocess
import sys

import numpy as np
import pytest

import marble
from unittest_decorators import skipIfMissingFeatures

SRC = pathlib.Path(__file__).resolve().parents[2]
FEATURES_DEF = SRC / "src" / "config" / "features.def"


def parse_def():
    rel = {}
    for raw in FEATURES_DEF.read_text().splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        m = re.fullmatch(r"(\w+)(?:\s+implies\s+([\w,\s]+?))?(?:\s+requires\s+not\s+([\w,\s]+))?",
                         line)
        split = lambda s: [x.strip() for x in s.split(",")] if s else []
        rel[m.group(1)] = (split(m.group(2)), split(m.group(3)))
    return rel


def test_features_lists():
    active, known = marble.features(), marble.all_features()
    assert set(active) <= set(known)
    assert set(known) == set(parse_def())
    for f in known:
        assert marble.has_features(f) == (f in active)
    assert marble.has_features(*active)
    assert marble.has_features(list(active))
    assert marble.has_features()  # nothing asked: True
    missing = [f for f in known if f not in active]
    if missing:
        assert not marble.has_features(active + missing[:1])


def test_active_features_respect_relations():
    active = set(marble.features())
    for name, (implies, excludes) in parse_def().items():
        if name in active:
            assert set(implies) <= active, name
            assert not (set(excludes) & active), name


@pytest.mark.parametrize("bad", ["FOO", "lennard_jones", "", "DPD_MASS"])
def test_unknown_feature_name_is_missing(bad):
    """ESPResSo behaviour: a name Marble does not know is not compiled in."""
    assert marble.has_features(bad) is False
    assert marble.has_features(["DPD", bad]) is False
    assert marble.missing_features("DPD", bad)[-1] == bad
    with pytest.raises(marble.FeaturesError, match=bad or "missing"):
        marble.assert_features(bad)


@pytest.mark.parametrize("bad", [1, None, 2.5, b"DPD"])
def test_non_string_feature_name_raises(bad):
    with pytest.raises(ValueError, match="feature names must be strings"):
        marble.has_features(bad)
    with pytest.raises(ValueError, match="feature names must be strings"):
        marble.missing_features(["DPD", bad])


def test_espresso_alias():
    assert marble.has_features("EXTERNAL_FORCES") == marble.has_features("EXTERNAL_FORCE")
    assert marble.missing_features(list(marble.features())) == []


def test_assert_features():
    marble.assert_features(*marble.features())
    missing = [f for f in marble.all_features() if f not in marble.features()]
    if missing:
        with pytest.raises(marble.FeaturesError, match=missing[0]):
            marble.assert_features(missing[0])
    with pytest.raises(marble.FeaturesError, match="NOT_A_FEATURE"):
        marble.assert_features("NOT_A_FEATURE")


# (feature, particle property, a valid value)
PROPERTY_FEATURES = [
    ("MASS", "mass", 2.0),
    ("ROTATION", "rotation", [True, True, True]),
    ("ROTATION", "rinertia", [1.0, 1.0, 1.0]),
    ("ROTATION", "omega_lab", [0.0, 0.0, 1.0]),
    ("EXTERNAL_FORCE", "ext_force", [1.0, 0.0, 0.0]),
    ("EXTERNAL_FORCE", "fix", [True, False, False]),
    (("EXTERNAL_FORCE", "ROTATION"), "ext_torque", [0.0, 1.0, 0.0]),
]


@pytest.mark.parametrize("feature,prop,value", PROPERTY_FEATURES)
def test_property_of_missing_feature(feature, prop, value):
    s = marble.System(box_l=[5.0] * 3)
    p = s.part.add(pos=[1.0, 1.0, 1.0])
    if marble.has_features(feature):
        # compiled in: the property works
        setattr(p, prop, value)
        np.testing.assert_array_equal(getattr(p, prop), value)
        s.part.add(pos=[2.0, 2.0, 2.0], **{prop: value})
        return
    if prop == "mass":
        assert p.mass == 1.0  # without MASS every particle has mass 1 (readable)
    else:
        with pytest.raises(marble.FeaturesError):
            getattr(p, prop)
    with pytest.raises(marble.FeaturesError):
        setattr(p, prop, value)
    with pytest.raises(marble.FeaturesError):
        s.part.add(pos=[2.0, 2.0, 2.0], **{prop: value})
    assert len(s.part) == 1  # nothing was added


INTERACTION_FEATURES = [
    ("LENNARD_JONES", "lennard_jones", dict(epsilon=1.0, sigma=1.0, cutoff=1.5)),
    ("HAT", "hat", dict(F_max=1.0, cutoff=1.0)),
    ("DPD", "dpd", dict(gamma=1.0, r_cut=1.0, weight_function=0)),
]


@pytest.mark.parametrize("feature,kind,params", INTERACTION_FEATURES)
def test_interaction_of_missing_feature(feature, kind, params):
    s = marble.System(box_l=[5.0] * 3)
    ia = getattr(s.non_bonded_inter[0, 0], kind)
    if marble.has_features(feature):
        ia.set_params(**params)
        assert ia.get_params()  # active
        ia.deactivate()
        assert ia.get_params() == {}
        return
    for call in (lambda: ia.set_params(**params), ia.get_params, ia.deactivate):
        with pytest.raises(marble.FeaturesError, match=feature):
            call()


def test_dpd_thermostat_of_missing_feature():
    s = marble.System(box_l=[5.0] * 3)
    if marble.has_features("DPD"):
        s.thermostat.set_dpd(kT=1.0, seed=3)
        assert s.thermostat.dpd.active and s.thermostat.dpd.kT == 1.0
        return
    with pytest.raises(marble.FeaturesError, match="DPD"):
        s.thermostat.set_dpd(kT=1.0, seed=3)


@skipIfMissingFeatures("DPD")
def test_trans_dpd_parameter_needs_feature():
    s = marble.System(box_l=[5.0] * 3)
    dpd = s.non_bonded_inter[0, 0].dpd
    if marble.has_features("TRANS_DPD"):
        dpd.set_params(gamma=1.0, r_cut=1.0, trans_gamma=2.0, trans_r_cut=1.0)
        assert dpd.get_params()["trans_gamma"] == 2.0
    else:
        with pytest.raises(marble.FeaturesError, match="TRANS_DPD"):
            dpd.set_params(gamma=1.0, r_cut=1.0, trans_gamma=2.0, trans_r_cut=1.0)


# --- the resolver (cmake/gen_features.py) ------------------------------------

def run_resolver(tmp_path, defines):
    cfg = tmp_path / "myconfig.hpp"
    cfg.write_text("".join(f"#define {d}\n" for d in defines))
    out = tmp_path / "out"
    res = subprocess.run([sys.executable, str(SRC / "cmake" / "gen_features.py"),
                          str(FEATURES_DEF), str(cfg), str(out)],
                         capture_output=True, text=True)
    active = None
    hdr = out / "config" / "features.hpp"
    if res.returncode == 0 and hdr.exists():
        active = set(re.findall(r"#define (\w+)", hdr.read_text())) & set(parse_def())
    return res, active


def test_resolver_closes_implications(tmp_path):
    res, active = run_resolver(tmp_path, ["TRANS_DPD", "DPD_MASS_LIN"])
    assert res.returncode == 0, res.stderr
    assert {"TRANS_DPD", "DPD", "DPD_MASS_LIN", "MASS"} <= active
    assert "DPD_MASS_RED" not in active and "LENNARD_JONES" not in active


def test_resolver_rejects_conflicts_and_unknown_names(tmp_path):
    res, _ = run_resolver(tmp_path, ["DPD_MASS_RED", "DPD_MASS_LIN"])
    assert res.returncode != 0
    assert "DPD_MASS" in (res.stderr + res.stdout)
    res, _ = run_resolver(tmp_path, ["DPD", "NOT_A_FEATURE"])
    assert res.returncode != 0
    assert "NOT_A_FEATURE" in (res.stderr + res.stdout)


@pytest.mark.parametrize("kind", ["lennard_jones", "hat", "dpd"])
def test_interaction_repr_never_raises(kind):
    s = marble.System(box_l=[5.0] * 3)
    text = repr(getattr(s.non_bonded_inter[0, 1], kind))
    assert "types=(0, 1)" in text
