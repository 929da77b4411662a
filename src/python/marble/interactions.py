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


class _Interaction:
    """One kernel of one type pair. Subclasses are generated per kernel."""
    _kind = None

    def __init__(self, system, i, j):
        self._core = system._core
        self._i, self._j = i, j

    def set_params(self, **params):
        """Set (replace) this interaction's parameters."""
        self._core.set_nonbonded(self._i, self._j, self._kind, params)

    def get_params(self):
        """The active parameters ({} if the interaction is off)."""
        return dict(self._core.get_nonbonded(self._i, self._j, self._kind))

    def deactivate(self):
        """Switch this interaction off for the type pair."""
        self._core.deactivate_nonbonded(self._i, self._j, self._kind)

    def is_active(self):
        return bool(self.get_params())

    def __repr__(self):
        try:
            params = self.get_params()
        except Exception as err:  # noqa: BLE001  (e.g. FeaturesError: repr must not raise)
            params = f"unavailable: {err}"
        return f"<{type(self).__name__} types=({self._i}, {self._j}) {params}>"


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
            setattr(self, name, cls(system, i, j))


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
