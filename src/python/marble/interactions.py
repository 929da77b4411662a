"""Non-bonded interactions: ``system.non_bonded_inter[i, j].<kind>``.

Each kind offers ``set_params(**kw)``, ``get_params()`` and ``deactivate()``,
as in espressomd. The kinds and their classes are generated from the core's
kernel list (``nonbonded/kernel_list.hpp``): a kernel added there appears here
with its parameters documented, nothing else to write. Parameters are
validated in the core (``ValueError`` naming the parameter and its allowed
range; ``marble.FeaturesError`` for a kernel that is not compiled in).
"""
import numbers

from . import _marble


_SCRATCH = []


def _scratch_core():
    """A private one-type core that validates the parameters of interaction
    objects constructed on their own (the same checks and messages as
    set_params on a system)."""
    if not _SCRATCH:
        _SCRATCH.append(_marble.System([10.0, 10.0, 10.0]))
    return _SCRATCH[0]


class _Interaction:
    """One kernel of one type pair. Subclasses are generated per kernel.

    Two ways to get one, as in ESPResSo: ``system.non_bonded_inter[i, j].<kind>``
    (bound to the type pair), or constructed on its own with its parameters,
    e.g. ``LennardJonesInteraction(epsilon=1, sigma=1, cutoff=2.5, shift="auto")``
    (validated at once), then assigned: ``system.non_bonded_inter[i, j].lennard_jones = lj``.
    """
    _kind = None

    def __init__(self, *args, **params):
        if len(args) == 3 and not params and hasattr(args[0], "_core"):
            system, i, j = args
            self._core = system._core
            self._i, self._j = i, j
            return
        if args:
            raise ValueError(f"{type(self).__name__}() takes keyword parameters only "
                             f"(e.g. {type(self).__name__}(**params)), got positional {args!r}")
        # Unbound: validate on a scratch core, keep the normalised parameters.
        core = _scratch_core()
        core.set_nonbonded(0, 1, self._kind, params)
        self._params = dict(core.get_nonbonded(0, 1, self._kind))
        core.deactivate_nonbonded(0, 1, self._kind)
        self._core = None
        self._i = self._j = None

    def _bound(self):
        return self._core is not None

    def set_params(self, **params):
        """Set (replace) this interaction's parameters."""
        if not self._bound():
            core = _scratch_core()
            core.set_nonbonded(0, 1, self._kind, params)
            self._params = dict(core.get_nonbonded(0, 1, self._kind))
            core.deactivate_nonbonded(0, 1, self._kind)
            return
        self._core.set_nonbonded(self._i, self._j, self._kind, params)

    def get_params(self):
        """The active parameters ({} if the interaction is off)."""
        if not self._bound():
            return dict(self._params)
        return dict(self._core.get_nonbonded(self._i, self._j, self._kind))

    def deactivate(self):
        """Switch this interaction off for the type pair."""
        if not self._bound():
            self._params = {}
            return
        self._core.deactivate_nonbonded(self._i, self._j, self._kind)

    def is_active(self):
        return bool(self.get_params())

    def __repr__(self):
        try:
            params = self.get_params()
        except Exception as err:  # noqa: BLE001  (e.g. FeaturesError: repr must not raise)
            params = f"unavailable: {err}"
        where = f"types=({self._i}, {self._j})" if self._bound() else "unbound"
        return f"<{type(self).__name__} {where} {params}>"


def _field_doc(f):
    what = f["key"]
    if f["feature"]:
        return f"{what} (needs {f['feature']})"
    if f["type"] == "choice":
        rng = "one of " + ", ".join(repr(c) for c in f["choices"])
    else:
        rng = f["range"]
        if f["keyword"]:
            rng += f' or "{f["keyword"]}"'
    tail = "required" if f["required"] else f"default {f['default']!r}"
    return f"{what}: {rng}, {tail}"


def _make_class(k):
    doc = k["doc"] + "\n\nParameters: " + "; ".join(_field_doc(f) for f in k["fields"]) + "."
    doc += f"\n\nKernel '{k['name']}', feature {k['feature']}" + \
        ("" if k["compiled"] else " (not compiled into this build)") + "."
    if k["ordered"]:
        doc += " Ordered: non_bonded_inter[i, j] with i the colloid or wall type."
    return type(k["py_class"], (_Interaction,), {"_kind": k["name"], "__doc__": doc,
                                                  "__module__": __name__})


#: The core's kernel list: name, feature, role, fields (key, type, range, default).
KERNELS = tuple(_marble.System.nonbonded_kernels())
_CLASSES = {k["name"]: _make_class(k) for k in KERNELS}
globals().update({cls.__name__: cls for cls in _CLASSES.values()})
__all__ = ["NonBondedInteractions", "NonBondedInteractionHandle", "KERNELS"] + \
    [cls.__name__ for cls in _CLASSES.values()]


class NonBondedInteractionHandle:
    """The interactions of one type pair: one attribute per kernel (``lennard_jones``, ``dpd``, ...)."""

    def __init__(self, system, i, j):
        for name, cls in _CLASSES.items():
            object.__setattr__(self, name, cls(system, i, j))

    def __setattr__(self, name, value):
        """``handle.<kind> = <Kind>Interaction(...)``: set this type pair's
        parameters from an interaction object (ESPResSo 4.3 style)."""
        cls = _CLASSES.get(name)
        if cls is None:
            raise AttributeError(f"non_bonded_inter[i, j] has no interaction '{name}' "
                                 f"(known: {', '.join(_CLASSES)})")
        if not isinstance(value, cls):
            raise ValueError(f"non_bonded_inter[i, j].{name} takes a {cls.__name__}, "
                             f"got {type(value).__name__}")
        bound = getattr(self, name)
        params = value.get_params()
        if params:
            bound.set_params(**params)
        else:
            bound.deactivate()


def _check_type(t):
    if isinstance(t, bool) or not isinstance(t, numbers.Integral) or not 0 <= t < 256:
        raise ValueError(f"particle type must be an integer in [0, 256), got {t!r}")
    return int(t)


class NonBondedInteractions:
    """``system.non_bonded_inter``; index with a pair of particle types."""

    def __init__(self, system):
        self._system = system

    def __getitem__(self, key):
        if not isinstance(key, tuple) or len(key) != 2:
            raise ValueError("non_bonded_inter is indexed by two particle types: [i, j]")
        i, j = (_check_type(t) for t in key)
        return NonBondedInteractionHandle(self._system, i, j)

    def reset(self):
        """Deactivate every interaction of every kind (pair potentials, DPD,
        marble couplings, tunable-slip walls) for every type pair."""
        self._system._core.reset_nonbonded()
