# labels: python
"""Every kernel of the core's kernel list (marble.interactions.KERNELS), generic
over the list, so a new kernel is tested without writing a test (issue A):
set -> get -> checkpoint (pickle of the System: the core blob) -> restore
gives back exactly what was set; deactivate and non_bonded_inter.reset()
switch every kind off; bad values generated from the field list (below the
range, a string, an unknown key, a missing required key) raise ValueError
naming the parameter and change nothing; a kernel that is not compiled in
raises FeaturesError naming its feature."""
import math
import pickle

import pytest

import marble
from marble.interactions import KERNELS

COMPILED = [k for k in KERNELS if k["compiled"]]
MISSING = [k for k in KERNELS if not k["compiled"]]


def ids(kernels):
    return [k["name"] for k in kernels]


def types_of(k):
    """(i, j) for the kernel: ordered kernels take the colloid/wall type first."""
    return (1, 0) if k["ordered"] else (0, 1)


def value_for(field, index):
    """A value inside the field's range that differs from its default:
    required fields get 0.25, 0.5, ... in list order, optional ones small
    offsets above their lower bound (so cross-field rules such as LJ's
    min < cutoff hold)."""
    if field["type"] == "choice":
        return next(c for c in field["choices"] if c != field["default"])
    if field["type"] == "integer":
        return 0 if field["default"] != 0 else 1
    lo = float(field["range"].split(",")[0][1:])
    step = 0.25 if field["required"] else 0.05
    v = (lo if math.isfinite(lo) else 0.0) + step * (index + 1)
    return v


def params_for(k):
    return {f["key"]: value_for(f, n) for n, f in enumerate(k["fields"]) if not f["feature"]}


#: symmetric kernels whose per-type fields read swapped from non_bonded_inter[j, i]
MIRRORED = {"surface_friction": (("a1", "a2"),)}


def make_system():
    s = marble.System(box_l=[6.0, 6.0, 6.0])
    s.time_step = 0.01
    return s


def test_kernel_list_is_complete():
    names = ids(KERNELS)
    assert len(names) == len(set(names))
    for expected in ("lennard_jones", "hat", "dpd", "marble", "tunable_slip"):
        assert expected in names
    for k in KERNELS:
        assert k["fields"], k["name"]
        assert hasattr(marble.interactions, k["py_class"])
        assert k["feature"] in marble.all_features()


@pytest.mark.parametrize("k", COMPILED, ids=ids(COMPILED))
def test_set_get_checkpoint_restore(k):
    s = make_system()
    i, j = types_of(k)
    params = params_for(k)
    handle = getattr(s.non_bonded_inter[i, j], k["name"])
    handle.set_params(**params)
    got = handle.get_params()
    for key, value in params.items():
        assert got[key] == value and type(got[key]) is type(value), (key, got[key], value)
    if not k["ordered"]:  # pair kernels are symmetric, ordered ones are not
        want = dict(got)
        for a, b in MIRRORED.get(k["name"], ()):  # per-type values: swapped for [j, i]
            want[a], want[b] = got[b], got[a]
        assert getattr(s.non_bonded_inter[j, i], k["name"]).get_params() == want
    else:
        assert getattr(s.non_bonded_inter[j, i], k["name"]).get_params() == {}
    restored = pickle.loads(pickle.dumps(s))
    assert getattr(restored.non_bonded_inter[i, j], k["name"]).get_params() == got
    handle.deactivate()
    assert handle.get_params() == {}
    assert getattr(restored.non_bonded_inter[i, j], k["name"]).get_params() == got


def test_reset_switches_every_kind_off():
    """Regression: reset() used to leave marble and tunable-slip couplings on."""
    s = make_system()
    for k in COMPILED:
        i, j = types_of(k)
        getattr(s.non_bonded_inter[i, j], k["name"]).set_params(**params_for(k))
    for k in COMPILED:
        i, j = types_of(k)
        assert getattr(s.non_bonded_inter[i, j], k["name"]).get_params(), k["name"]
    s.non_bonded_inter.reset()
    for k in COMPILED:
        for a, b in ((0, 0), (0, 1), (1, 0), (1, 1)):
            assert getattr(s.non_bonded_inter[a, b], k["name"]).get_params() == {}, k["name"]
    assert s.cell_system.get_state()["max_cut"] == 0.0


def bad_values(k):
    """(description, params, key named in the message) generated from the fields."""
    good = params_for(k)
    out = [("unknown key", {**good, "no_such_parameter": 1.0}, "no_such_parameter")]
    for f in k["fields"]:
        key = f["key"]
        if f["feature"]:
            continue
        if f["required"]:
            out.append((f"missing {key}", {a: v for a, v in good.items() if a != key}, key))
        if f["type"] == "real":
            lo = float(f["range"].split(",")[0][1:])
            if math.isfinite(lo):
                out.append((f"{key} below range", {**good, key: lo - 1.0}, key))
            if not f["keyword"]:
                out.append((f"{key} string", {**good, key: "1.0"}, key))
            out.append((f"{key} nan", {**good, key: float("nan")}, key))
        elif f["type"] == "integer":
            out.append((f"{key} float", {**good, key: 0.5}, key))
            out.append((f"{key} out of set", {**good, key: 7}, key))
        else:
            out.append((f"{key} unknown choice", {**good, key: "no_such_choice"}, key))
            out.append((f"{key} number", {**good, key: 1.0}, key))
    return out


CASES = [(k, *case) for k in COMPILED for case in bad_values(k)]


@pytest.mark.parametrize("k,what,params,key", CASES,
                         ids=[f"{c[0]['name']}-{c[1]}" for c in CASES])
def test_bad_values_raise_and_change_nothing(k, what, params, key):
    s = make_system()
    i, j = types_of(k)
    handle = getattr(s.non_bonded_inter[i, j], k["name"])
    handle.set_params(**params_for(k))
    before = handle.get_params()
    with pytest.raises(ValueError, match=key):
        handle.set_params(**params)
    assert handle.get_params() == before


@pytest.mark.parametrize("k", MISSING, ids=ids(MISSING))
def test_missing_feature(k):
    s = make_system()
    handle = getattr(s.non_bonded_inter[1, 0], k["name"])
    for call in (lambda: handle.set_params(), handle.get_params, handle.deactivate):
        with pytest.raises(marble.FeaturesError, match=k["feature"]):
            call()
