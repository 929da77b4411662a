"""Observables (espressomd-shaped): functions of the current state, evaluated in C++
so that accumulators can sample them during ``integrator.run`` (doc/analysis.md).

    import marble.observables
    pos = marble.observables.ParticlePositions(ids=[0, 1])
    pos.calculate()          # (2, 3) unfolded positions

An observable belongs to one System: ``system=`` names it; without it, the most
recently created System that is still alive (the usual one-system script).
"""
import weakref

import numpy as np

from . import _marble

_live_systems = []  # weak references, in creation order


def _register_system(system):
    """Called by System.__init__ (through AutoUpdateAccumulators)."""
    _live_systems[:] = [r for r in _live_systems if r() is not None] + [weakref.ref(system)]


def _resolve_system(system):
    if system is not None:
        if not hasattr(system, "_core") or not isinstance(system._core, _marble.System):
            raise ValueError("parameter 'system' must be a marble.System")
        return system
    alive = [r() for r in _live_systems if r() is not None]
    if not alive:
        raise ValueError("no marble.System exists: create the System before its observables")
    return alive[-1]


class Observable:
    """Base of all observables: ``calculate()`` returns a numpy array of ``shape()``."""

    _core_class = None
    _allowed = ("system",)

    def __init__(self, **kwargs):
        unknown = set(kwargs) - set(self._allowed)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)} for {type(self).__name__} "
                             f"(allowed: {', '.join(self._allowed)})")
        self._system = _resolve_system(kwargs.get("system"))
        self._obs = self._make(kwargs)
        self._kwargs = {k: v for k, v in kwargs.items() if k != "system"}

    def __reduce__(self):
        # built completely on unpickling (accumulators need the core object)
        return (_restore_observable, (type(self), self._system, self._kwargs))

    def _make(self, kwargs):
        raise NotImplementedError

    def calculate(self):
        """The observable's current value (numpy array of shape ``shape()``)."""
        return self._obs.calculate(self._system._core)

    def shape(self):
        """Shape of the array ``calculate()`` returns (a tuple)."""
        return tuple(self._obs.shape())

    @property
    def system(self):
        """The System this observable reads."""
        return self._system

    def __repr__(self):
        return f"{type(self).__name__}(shape={self.shape()})"


def _ids_list(ids):
    if ids is None:
        raise ValueError("parameter 'ids' is required")
    if isinstance(ids, (int, np.integer)) and not isinstance(ids, bool):
        raise ValueError("parameter 'ids' must be a list of particle ids, e.g. ids=[0]")
    arr = np.asarray(ids)
    if arr.ndim != 1:
        raise ValueError(f"parameter 'ids' must be a 1D list of particle ids, "
                         f"got shape {arr.shape}")
    return list(ids)


class _PidObservable(Observable):
    _allowed = ("ids", "system")

    def _make(self, kwargs):
        return self._core_class(self._system._core, _ids_list(kwargs.get("ids")))

    @property
    def ids(self):
        return list(self._obs.ids)


class ParticlePositions(_PidObservable):
    """Unfolded positions (pos + image_box * box_l), shape (n, 3)."""
    _core_class = _marble.ParticlePositions


class ParticleVelocities(_PidObservable):
    """Velocities, shape (n, 3)."""
    _core_class = _marble.ParticleVelocities


class ParticleAngularVelocities(_PidObservable):
    """Angular velocities in the lab frame, shape (n, 3). Needs ROTATION
    (marble.FeaturesError otherwise)."""
    _core_class = _marble.ParticleAngularVelocities


class ComVelocity(_PidObservable):
    """Mass-weighted centre-of-mass velocity of the ids, shape (3,)."""
    _core_class = _marble.ComVelocity


class DPDStress(Observable):
    """Viscous DPD stress tensor, shape (3, 3): ``system.analysis.dpd_stress()``
    (friction of the current velocities, no noise; the ESPResSo observable).
    Feature DPD. Evaluated in Python: ``calculate()`` works anywhere, but the
    C++ accumulators cannot sample it (ValueError); sample it in a Python
    loop around ``integrator.run``."""

    def _make(self, kwargs):
        return None

    def calculate(self):
        return self._system.analysis.dpd_stress()

    def shape(self):
        """(3, 3)"""
        return (3, 3)


def _restore_observable(cls, system, kwargs):
    return cls(system=system, **kwargs)
