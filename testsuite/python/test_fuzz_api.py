# labels: python
"""Property-based test of the public API (doc/reliability.md): hypothesis drives
a System with random sequences of calls and values (particles added, removed and
modified; Lennard-Jones, hat and DPD interactions set, deactivated and reset;
the DPD thermostat; integrator switches; runs of 0-20 steps; checkpoint save and
load) and checks after every call:

- no crash (the process survives; a sanitizer build also checks memory and UB);
- every rejection is a ValueError, marble.FeaturesError or RuntimeError with a
  non-empty message (IndexError only for a lookup of a missing particle id, as
  in espressomd);
- a rejected call changes nothing: every particle property, every interaction's
  get_params(), the thermostat and integrator state, step and time are bit for
  bit what they were (a failed *run* is exempt: it stops mid-run by design);
- momentum is conserved by a run with velocity Verlet, DPD-VV or Shardlow when
  no particle has an external force or a fixed coordinate (no walls here):
  |P_after - P_before| <= 1e-10 (sum_i |m_i v_i| + F_scale dt n) per component;
- a checkpoint load (pickle round trip or marble.checkpointing in a temp
  directory) gives the same state.

The sequences are derandomized (fixed seed): CI runs MARBLE_FUZZ_EXAMPLES
(default 500) sequences of up to MARBLE_FUZZ_STEPS (default 20) calls. By hand:

    MARBLE_FUZZ_EXAMPLES=20000 MARBLE_FUZZ_SEED=7 build/pymarble -m pytest -q \\
        testsuite/python/test_fuzz_api.py

(MARBLE_FUZZ_SEED != 0 switches derandomization off and seeds the search.)
"""
import math
import os
import pickle
import tempfile

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, settings, strategies as st  # noqa: E402
from hypothesis.stateful import (RuleBasedStateMachine, invariant, precondition,  # noqa: E402
                                 rule)

import marble  # noqa: E402
import marble.checkpointing  # noqa: E402
from marble import FeaturesError  # noqa: E402

N_EXAMPLES = int(os.environ.get("MARBLE_FUZZ_EXAMPLES", "500"))
N_STEPS = int(os.environ.get("MARBLE_FUZZ_STEPS", "20"))
SEED = int(os.environ.get("MARBLE_FUZZ_SEED", "0"))

L = 5.0
TYPES = (0, 1, 2)
KINDS = ("lennard_jones", "hat", "dpd")
MAX_PARTICLES = 40
PROPS = ("type", "pos", "v", "mass", "rotation", "rinertia", "omega_lab", "ext_force",
         "ext_torque", "fix")
ACCEPTED = (ValueError, FeaturesError, RuntimeError)

STATS = {"calls": 0, "rejected": 0, "runs": 0, "runs_failed": 0, "momentum_checks": 0,
         "checkpoints": 0}

# --- value strategies: mostly sensible, sometimes wrong -----------------------------------

weird_float = st.sampled_from([math.nan, math.inf, -math.inf, -1.0, 0.0, 1e300, -1e-300])


def num(lo, hi):
    return st.one_of(st.floats(lo, hi, allow_nan=False), st.floats(lo, hi, allow_nan=False),
                     st.floats(lo, hi, allow_nan=False), weird_float)


def vec(lo, hi):
    good = st.lists(st.floats(lo, hi, allow_nan=False), min_size=3, max_size=3)
    bad = st.one_of(st.lists(st.floats(lo, hi, allow_nan=False), min_size=0, max_size=4),
                    st.lists(weird_float, min_size=3, max_size=3),
                    st.just("abc"), st.just(None))
    return st.one_of(good, good, good, bad)


type_value = st.one_of(st.sampled_from(TYPES), st.sampled_from(TYPES),
                       st.sampled_from([-1, 255, 256, 1000, 1.5, True, "0", None]))
bool3 = st.one_of(st.lists(st.booleans(), min_size=3, max_size=3),
                  st.sampled_from([[1, 0], "x", None, [2, 0, 0]]))

PROP_VALUES = {
    "type": type_value,
    "pos": vec(-3 * L, 4 * L),
    "v": vec(-3.0, 3.0),
    "mass": num(0.2, 5.0),
    "rotation": st.one_of(st.booleans(), st.sampled_from([1, 0, "yes", None, [True, False]])),
    "rinertia": num(0.1, 5.0),
    "omega_lab": vec(-2.0, 2.0),
    "ext_force": vec(-2.0, 2.0),
    "ext_torque": vec(-2.0, 2.0),
    "fix": bool3,
}

INTERACTION_PARAMS = {
    "lennard_jones": st.fixed_dictionaries(
        {"epsilon": num(0.0, 2.0), "sigma": num(0.3, 1.2), "cutoff": num(0.5, 2.0)},
        optional={"shift": st.one_of(num(-1.0, 1.0), st.just("auto"), st.just("bad")),
                  "offset": num(0.0, 0.5), "min": num(0.0, 0.5),
                  "bogus": st.just(1.0)}),
    "hat": st.fixed_dictionaries(
        {"F_max": num(0.0, 30.0), "cutoff": num(0.5, 1.5)},
        optional={"bogus": st.just(1.0)}),
    "dpd": st.fixed_dictionaries(
        {"weight_function": st.sampled_from([0, 1, 1, 2, -1]), "gamma": num(0.0, 10.0),
         "k": num(0.2, 2.0), "r_cut": num(0.0, 1.5)},
        optional={"trans_weight_function": st.sampled_from([0, 1, 3]),
                  "trans_gamma": num(0.0, 5.0), "trans_r_cut": num(0.0, 1.5),
                  "bogus": st.just(1.0)}),
}

# --- state snapshots ------------------------------------------------------------------------


def _arr(x):
    a = np.asarray(x)
    return (a.dtype.str, a.shape, a.tobytes())


def snapshot(system):
    """Everything observable through the public API, as comparable bytes."""
    parts = system.part.all()
    snap = {"ids": _arr(parts.id), "step": system.step, "time": _arr(system.time),
            "time_step": _arr(system.time_step), "box": _arr(system.box_l)}
    for name in PROPS + ("image_box", "f"):
        try:
            snap[name] = _arr(getattr(parts, name)) if len(parts) else None
        except FeaturesError:
            snap[name] = "n/a"
    for i in TYPES:
        for j in TYPES:
            if j < i:
                continue
            for kind in KINDS:
                try:
                    p = getattr(system.non_bonded_inter[i, j], kind).get_params()
                    snap[(i, j, kind)] = repr(sorted(p.items()))
                except FeaturesError:
                    snap[(i, j, kind)] = "n/a"
    snap["thermostat"] = repr(system.thermostat.get_state())
    snap["integrator"] = repr(system.integrator.get_state())
    return snap


def diff(a, b):
    return [k for k in a if a[k] != b.get(k)] + [k for k in b if k not in a]


def momentum(system):
    parts = system.part.all()
    if not len(parts):
        return np.zeros(3), 0.0
    v = parts.v
    try:
        m = np.asarray(parts.mass, dtype=float)
    except FeaturesError:
        m = np.ones(len(parts))
    p = m[:, None] * v
    return p.sum(axis=0), float(np.abs(p).sum())


class ApiMachine(RuleBasedStateMachine):
    def __init__(self):
        super().__init__()
        self.system = marble.System(box_l=[L, L, L])
        self.system.time_step = 0.01
        self.system.cell_system.skin = 0.3
        self.tmp = tempfile.TemporaryDirectory(prefix="marble_fuzz_")
        self.n_saves = 0

    def teardown(self):
        self.tmp.cleanup()

    # -- the checked call: accepted, or rejected cleanly without a change --
    def attempt(self, fn, what, lookup=False, mutate_on_error=False):
        STATS["calls"] += 1
        before = snapshot(self.system)
        try:
            result = fn()
        except ACCEPTED + ((IndexError,) if lookup else ()) as err:
            STATS["rejected"] += 1
            assert str(err).strip(), f"{what}: {type(err).__name__} without a message"
            if not mutate_on_error:
                after = snapshot(self.system)
                changed = diff(before, after)
                assert not changed, f"{what} was rejected ({type(err).__name__}: {err}) " \
                    f"but changed {changed}"
            return False, err
        # anything else (TypeError, KeyError, SystemError, ...) propagates: a failure
        return True, result

    def ids(self):
        return [int(i) for i in self.system.part.all().id]

    # -- particles --
    @precondition(lambda self: len(self.system.part) < MAX_PARTICLES)
    @rule(n=st.integers(1, 6), data=st.data())
    def add_particles(self, n, data):
        kw = {}
        if n == 1:
            kw["pos"] = data.draw(vec(-L, 2 * L), label="pos")
        else:
            kw["pos"] = data.draw(st.one_of(
                st.lists(st.lists(st.floats(-L, 2 * L, allow_nan=False), min_size=3, max_size=3),
                         min_size=n, max_size=n),
                st.just(np.full((n, 3), np.nan)), st.just([])), label="pos")
        for name in data.draw(st.lists(st.sampled_from(PROPS[:1] + PROPS[2:]), max_size=3,
                                       unique=True), label="props"):
            val = data.draw(PROP_VALUES[name], label=name)
            kw[name] = val if n == 1 else [val] * n
        if data.draw(st.booleans(), label="with id"):
            ids = self.ids()
            kw["id"] = data.draw(st.one_of(st.integers(-2, 60), st.sampled_from(ids or [0])),
                                 label="id") if n == 1 else None
            if n > 1:
                del kw["id"]
        count = len(self.system.part)
        ok, _ = self.attempt(lambda: self.system.part.add(**kw), f"part.add({kw})")
        if ok:
            assert len(self.system.part) == count + n
            if "id" in kw:
                assert self.system.part.exists(kw["id"])

    @rule(data=st.data())
    def remove_particle(self, data):
        ids = self.ids()
        pid = data.draw(st.one_of(st.sampled_from(ids or [0]), st.integers(-1, 80)), label="pid")
        exists = pid in ids
        ok, _ = self.attempt(lambda: self.system.part.by_id(pid).remove(), f"remove {pid}",
                             lookup=True)
        assert ok == exists, f"remove({pid}): exists={exists} but ok={ok}"
        assert not self.system.part.exists(pid) if pid >= 0 else True

    @precondition(lambda self: len(self.system.part) > 0)
    @rule(data=st.data(), name=st.sampled_from(PROPS), whole=st.booleans())
    def set_property(self, data, name, whole):
        ids = self.ids()
        value = data.draw(PROP_VALUES[name], label="value")
        if whole:
            sl = self.system.part.all()
            ok, _ = self.attempt(lambda: setattr(sl, name, value), f"all().{name} = {value!r}")
        else:
            pid = data.draw(st.sampled_from(ids), label="pid")
            p = self.system.part.by_id(pid)
            ok, _ = self.attempt(lambda: setattr(p, name, value), f"p[{pid}].{name} = {value!r}")
        if ok and name in ("v", "ext_force") and not whole:
            np.testing.assert_array_equal(getattr(self.system.part.by_id(pid), name),
                                          np.asarray(value, dtype=float))

    @precondition(lambda self: len(self.system.part) > 0)
    @rule()
    def read_properties(self):
        # reading never fails and never changes anything
        self.attempt(lambda: [getattr(p, n) for p in self.system.part for n in ("pos", "v", "f")],
                     "read")

    # -- interactions --
    @rule(kind=st.sampled_from(KINDS), i=type_value, j=type_value, data=st.data())
    def set_interaction(self, kind, i, j, data):
        params = data.draw(INTERACTION_PARAMS[kind], label="params")

        def call():
            getattr(self.system.non_bonded_inter[i, j], kind).set_params(**params)
        ok, _ = self.attempt(call, f"non_bonded_inter[{i}, {j}].{kind}.set_params({params})")
        if ok:
            got = getattr(self.system.non_bonded_inter[i, j], kind).get_params()
            if not got:  # zero strength switches an interaction off (by design)
                if kind == "lennard_jones":
                    zero = params["epsilon"] == 0
                elif kind == "hat":
                    zero = params["F_max"] == 0
                else:
                    zero = (params["gamma"] == 0 or params["r_cut"] == 0) and \
                        (params.get("trans_gamma", 0) == 0 or params.get("trans_r_cut", 0) == 0)
                assert zero, f"{kind} {params} accepted but inactive"
            for k, v in params.items():
                if isinstance(v, float) and k in got and not (k == "shift"):
                    assert got[k] == pytest.approx(v), (kind, k, v, got[k])
            # symmetric (compared as text: NaN == NaN)
            other = getattr(self.system.non_bonded_inter[j, i], kind).get_params()
            assert repr(sorted(other.items())) == repr(sorted(got.items()))
            # accepted parameters are finite (regression: test_lj_auto_shift_overflow)
            for k, v in got.items():
                if isinstance(v, float):
                    assert math.isfinite(v), f"{kind} {params} accepted with {k} = {v}"

    @rule(kind=st.sampled_from(KINDS), i=type_value, j=type_value)
    def deactivate_interaction(self, kind, i, j):
        ok, _ = self.attempt(lambda: getattr(self.system.non_bonded_inter[i, j], kind).deactivate(),
                             f"{kind}[{i}, {j}].deactivate()")
        if ok:
            assert getattr(self.system.non_bonded_inter[i, j], kind).get_params() == {}

    @rule()
    def reset_interactions(self):
        ok, _ = self.attempt(lambda: self.system.non_bonded_inter.reset(), "non_bonded_inter.reset()")
        assert ok
        # every type pair, with or without particles (regression:
        # test_reset_clears_types_without_particles)
        checked = sorted(set(TYPES) | {255})
        for i in checked:
            for j in checked:
                for kind in KINDS:
                    try:
                        p = getattr(self.system.non_bonded_inter[i, j], kind).get_params()
                    except FeaturesError:
                        continue
                    assert p == {}, f"after reset(): {kind}[{i}, {j}] still {p}"

    # -- thermostat and integrator --
    @rule(kT=num(0.0, 2.0), seed=st.one_of(st.integers(0, 2 ** 31), st.sampled_from(
        [None, -1, 2 ** 64, 1.5, "s"])))
    def set_dpd_thermostat(self, kT, seed):
        self.attempt(lambda: self.system.thermostat.set_dpd(kT=kT, seed=seed),
                     f"set_dpd(kT={kT}, seed={seed})")

    @rule()
    def thermostat_off(self):
        ok, _ = self.attempt(self.system.thermostat.turn_off, "turn_off")
        assert ok

    @rule(which=st.sampled_from(["vv", "shardlow", "dpd_vv", "sd"]),
          f_max=num(0.0, 10.0), gamma=num(0.0, 1.0), maxd=num(0.0, 0.1))
    def set_integrator(self, which, f_max, gamma, maxd):
        integ = self.system.integrator
        call = {"vv": integ.set_vv, "shardlow": integ.set_shardlow, "dpd_vv": integ.set_dpd_vv,
                "sd": lambda: integ.set_steepest_descent(f_max=f_max, gamma=gamma,
                                                         max_displacement=maxd)}[which]
        self.attempt(call, f"set integrator {which} ({f_max}, {gamma}, {maxd})")

    @rule(steps=st.one_of(st.integers(0, 20), st.integers(0, 20),
                          st.sampled_from([-1, 1.5, None, "3"])))
    def run(self, steps):
        STATS["runs"] += 1
        name = self.system.integrator.get_state().get("name", "")
        parts = self.system.part.all()
        free = True
        if len(parts):
            try:
                free = not np.any(parts.ext_force) and not np.any(parts.fix)
            except FeaturesError:
                free = True
        conserving = free and name in ("VelocityVerlet", "DPDVV", "Shardlow")
        p0, s0 = momentum(self.system)
        step0 = self.system.step
        valid_steps = isinstance(steps, int) and steps >= 0
        ok, err = self.attempt(lambda: self.system.integrator.run(steps), f"run({steps!r})",
                               mutate_on_error=valid_steps)
        if not ok:
            if valid_steps:
                STATS["runs_failed"] += 1
            return
        assert valid_steps, f"run({steps!r}) was accepted"
        if name != "SteepestDescent":
            assert self.system.step == step0 + steps
        if conserving and steps > 0:
            p1, s1 = momentum(self.system)
            STATS["momentum_checks"] += 1
            tol = 1e-10 * (s0 + s1) + 1e-12
            assert np.all(np.abs(p1 - p0) <= tol), \
                f"momentum not conserved by {name}: {p0} -> {p1} (tol {tol:.3g})"

    # -- checkpoints --
    @rule(how=st.sampled_from(["pickle", "checkpoint"]))
    def checkpoint_round_trip(self, how):
        STATS["checkpoints"] += 1
        before = snapshot(self.system)
        if how == "pickle":
            new = pickle.loads(pickle.dumps(self.system))
        else:
            ns = {"system": self.system}
            cp = marble.checkpointing.Checkpoint(checkpoint_id="fuzz",
                                                 checkpoint_path=self.tmp.name, namespace=ns)
            cp.register("system")
            idx = cp.save()
            assert idx == self.n_saves
            self.n_saves += 1
            ns2 = {}
            marble.checkpointing.Checkpoint(checkpoint_id="fuzz", checkpoint_path=self.tmp.name,
                                            namespace=ns2).load()
            new = ns2["system"]
        after = snapshot(new)
        changed = diff(before, after)
        assert not changed, f"{how} round trip changed {changed}"
        self.system = new

    @invariant()
    def particle_count_consistent(self):
        assert len(self.system.part) == len(self.ids()) <= MAX_PARTICLES + 6


ApiMachine.TestCase.settings = settings(
    max_examples=N_EXAMPLES, stateful_step_count=N_STEPS, deadline=None, database=None,
    derandomize=SEED == 0, print_blob=True,
    suppress_health_check=list(HealthCheck))
if SEED:
    ApiMachine.TestCase = hypothesis.seed(SEED)(ApiMachine.TestCase)
TestApiFuzz = ApiMachine.TestCase


@pytest.mark.skipif(not marble.has_features("HAT", "DPD"), reason="needs HAT and DPD")
def test_reset_clears_types_without_particles():
    """Found by the fuzzer: reset() used to clear only the types of existing
    particles; the kernel registry's reset clears the whole table."""
    s = marble.System(box_l=[L, L, L])
    s.part.add(pos=[1.0, 1.0, 1.0], type=0)
    s.non_bonded_inter[0, 1].hat.set_params(F_max=1.0, cutoff=1.0)
    s.non_bonded_inter[2, 2].dpd.set_params(weight_function=0, gamma=1.0, r_cut=1.0)
    s.non_bonded_inter.reset()
    assert s.non_bonded_inter[0, 1].hat.get_params() == {}
    assert s.non_bonded_inter[2, 2].dpd.get_params() == {}


@pytest.mark.skipif(not marble.has_features("LENNARD_JONES"), reason="needs LENNARD_JONES")
def test_lj_auto_shift_overflow():
    """Found by the fuzzer (seed 7): shift="auto" with (sigma/cutoff)^12
    overflowing gave a NaN shift; a keyword value that is not finite is now a
    ValueError naming what it is computed from."""
    s = marble.System(box_l=[L, L, L])
    with pytest.raises(ValueError, match="sigma"):
        s.non_bonded_inter[0, 0].lennard_jones.set_params(epsilon=1.0, sigma=1e300, cutoff=1.0,
                                                          shift="auto")


def test_huge_cutoff_is_refused_at_run():
    """Found by the fuzzer under UBSan: a cutoff of 1e300 made the periodic
    image count overflow an int (CellSystem::make_ghosts); now the run stops
    with a RuntimeError naming the range, and the System stays usable."""
    if not marble.has_features("DPD"):
        pytest.skip("needs DPD")
    s = marble.System(box_l=[L, L, L])
    s.time_step = 0.01
    s.part.add(pos=[[1.0, 1.0, 1.0], [1.5, 1.0, 1.0]])
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=0, gamma=1.0, r_cut=1e300)
    before = snapshot(s)
    with pytest.raises(RuntimeError, match="interaction range .* box lengths"):
        s.integrator.run(1)
    assert not diff(before, snapshot(s))
    s.non_bonded_inter[0, 0].dpd.set_params(weight_function=0, gamma=1.0, r_cut=1.0)
    s.integrator.run(2)
    assert s.step == 2


def teardown_module(module):
    print(f"\nfuzz: {N_EXAMPLES} sequences of <= {N_STEPS} calls; {STATS}")
