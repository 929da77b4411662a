"""Particles: ``system.part`` (a ParticleList), ParticleHandle, ParticleSlice.

Reads and writes go to the core in bulk: ``system.part.all().pos`` is one call
that returns an (N, 3) numpy array.
"""
import numbers

import numpy as np

# Properties with an espressomd per-axis form that Marble stores isotropically.
_AXIS3 = ("rotation", "rinertia")

_PROPERTIES = ("id", "type", "pos", "pos_folded", "image_box", "v", "f", "mass",
               "rotation", "rinertia", "omega_lab", "omega_body", "torque_lab",
               "ext_force", "ext_torque", "fix", "gamma", "gamma_rot")
_READ_ONLY = ("id", "pos_folded", "image_box", "f", "torque_lab")


def _ids_array(ids):
    return [int(i) for i in ids]


def _expand_axis3(name, arr):
    if name == "rotation":
        return np.repeat(np.asarray(arr, dtype=bool)[..., None], 3, axis=-1)
    if name == "rinertia":
        return np.repeat(np.asarray(arr, dtype=float)[..., None], 3, axis=-1)
    return arr


def _make_handle_property(name):
    doc = f"Particle property '{name}'."

    def getter(self):
        val = self._core.get_property(name, [self._id])[0]
        if name in _AXIS3:
            return _expand_axis3(name, val)
        if isinstance(val, np.ndarray):
            return val
        if isinstance(val, (np.integer,)):
            return int(val)
        if isinstance(val, (np.bool_,)):
            return bool(val)
        return float(val)

    if name in _READ_ONLY:
        def setter(self, value):
            raise AttributeError(f"particle property '{name}' is read-only")
    else:
        def setter(self, value):
            self._core.set_property(name, [self._id], value)
    return property(getter, setter, doc=doc)


def _make_slice_property(name):
    doc = f"Particle property '{name}' of every particle in the slice (numpy array)."

    def getter(self):
        val = self._core.get_property(name, self._ids)
        return _expand_axis3(name, val) if name in _AXIS3 else val

    if name in _READ_ONLY:
        def setter(self, value):
            raise AttributeError(f"particle property '{name}' is read-only")
    else:
        def setter(self, value):
            self._core.set_property(name, self._ids, value)
    return property(getter, setter, doc=doc)


def _no_virtual_sites(value):
    """ESPResSo's ``virtual`` flag: Marble has no virtual sites, so every
    particle reads False and setting True raises FeaturesError."""
    if np.any(np.asarray(value, dtype=bool)):
        from ._marble import FeaturesError
        raise FeaturesError("missing feature VIRTUAL_SITES: Marble has no virtual sites "
                            "(particle property 'virtual' can only be False)")


class ParticleHandle:
    """One particle, addressed by its id. Attributes read and write the core."""

    __slots__ = ("_system", "_core", "_id")

    def __init__(self, system, pid):
        self._system = system
        self._core = system._core
        self._id = int(pid)

    @property
    def id(self):
        """The particle's id (int, read-only)."""
        return self._id

    def remove(self):
        """Delete the particle from the system."""
        self._core.remove_particles([self._id])

    def to_dict(self):
        """Every compiled-in property of the particle, as a dict."""
        out = {}
        for name in self._core.property_names():
            out[name] = getattr(self, name)
        return out

    def __reduce__(self):
        return (ParticleHandle, (self._system, self._id))

    def __repr__(self):
        return f"<ParticleHandle id={self._id}>"

    def __eq__(self, other):
        return isinstance(other, ParticleHandle) and other._id == self._id and \
            other._core is self._core

    def __hash__(self):
        return hash(self._id)


class ParticleSlice:
    """Several particles; attributes are numpy arrays with one row per particle."""

    __slots__ = ("_system", "_core", "_ids")

    def __init__(self, system, ids):
        self._system = system
        self._core = system._core
        self._ids = _ids_array(ids)

    @property
    def id(self):
        """Ids of the particles in the slice (numpy int array)."""
        return np.array(self._ids, dtype=int)

    def __len__(self):
        return len(self._ids)

    def __iter__(self):
        for pid in self._ids:
            yield ParticleHandle(self._system, pid)

    def __getitem__(self, k):
        if isinstance(k, slice):
            return ParticleSlice(self._system, self._ids[k])
        return ParticleHandle(self._system, self._ids[k])

    def remove(self):
        """Delete these particles."""
        self._core.remove_particles(self._ids)

    def __reduce__(self):
        return (ParticleSlice, (self._system, list(self._ids)))

    def __repr__(self):
        return f"<ParticleSlice of {len(self._ids)} particles>"


for _name in _PROPERTIES:
    if _name != "id":
        setattr(ParticleHandle, _name, _make_handle_property(_name))
        setattr(ParticleSlice, _name, _make_slice_property(_name))


def _handle_virtual_set(self, value):
    _no_virtual_sites(value)


def _slice_virtual_set(self, value):
    _no_virtual_sites(value)


ParticleHandle.virtual = property(
    lambda self: False, _handle_virtual_set,
    doc="Always False: Marble has no virtual sites (setting True raises FeaturesError "
        "naming VIRTUAL_SITES).")
ParticleSlice.virtual = property(
    lambda self: np.zeros(len(self._ids), dtype=bool), _slice_virtual_set,
    doc="All False: Marble has no virtual sites (setting True raises FeaturesError).")


class ParticleList:
    """``system.part``: add, look up, select and remove particles."""

    def __init__(self, system):
        self._system = system
        self._core = system._core

    def add(self, *args, **kwargs):
        """Add one particle (``pos`` of shape (3,)) or N particles (``pos`` (N, 3)).

        Returns a ParticleHandle for one particle, a ParticleSlice for several.
        Accepts the properties of ParticleHandle plus ``id``; positions outside
        the box are folded into it (``pos`` keeps the unfolded value).
        """
        if args:
            if len(args) != 1 or not isinstance(args[0], dict) or kwargs:
                raise ValueError("part.add() takes keyword arguments or one dict")
            kwargs = dict(args[0])
        if "pos" not in kwargs:
            raise ValueError("particle property 'pos' is required")
        if "virtual" in kwargs:
            kwargs = dict(kwargs)
            _no_virtual_sites(kwargs.pop("virtual"))
        try:
            pos = np.asarray(kwargs["pos"], dtype=float)
        except (TypeError, ValueError):
            raise ValueError("particle property 'pos' must be numeric") from None
        if pos.ndim == 1 and pos.shape[0] == 3:
            n, single = 1, True
        elif pos.ndim == 2 and pos.shape[1] == 3 and pos.shape[0] > 0:
            n, single = pos.shape[0], False
        else:
            raise ValueError(f"particle property 'pos' must have shape (3,) or (N, 3), "
                             f"got {pos.shape}")
        # One particle: each value becomes a single row (scalar -> (1,), vector -> (1, 3)).
        props = {k: [v] for k, v in kwargs.items()} if single else dict(kwargs)
        ids = self._core.add_particles(n, props)
        if single:
            return ParticleHandle(self._system, ids[0])
        return ParticleSlice(self._system, ids)

    def by_id(self, pid):
        """The particle with id ``pid`` (IndexError if there is none)."""
        if isinstance(pid, bool) or not isinstance(pid, numbers.Integral):
            raise ValueError(f"particle id must be an integer, got {pid!r}")
        if not self._core.particle_exists(int(pid)):
            raise IndexError(f"particle {pid} does not exist")
        return ParticleHandle(self._system, pid)

    def by_ids(self, ids):
        """A ParticleSlice of the given ids."""
        ids = _ids_array(ids)
        for pid in ids:
            if not self._core.particle_exists(pid):
                raise IndexError(f"particle {pid} does not exist")
        return ParticleSlice(self._system, ids)

    def all(self):
        """Every particle, in ascending id order."""
        return ParticleSlice(self._system, self._core.particle_ids())

    def select(self, *args, **kwargs):
        """Particles whose properties equal the given values (``select(type=0)``),
        or for which a function of the handle returns True."""
        ids = self._core.particle_ids()
        if args:
            if len(args) != 1 or not callable(args[0]) or kwargs:
                raise ValueError("select() takes one function or keyword arguments")
            fn = args[0]
            return ParticleSlice(self._system,
                                 [i for i in ids if fn(ParticleHandle(self._system, i))])
        mask = np.ones(len(ids), dtype=bool)
        for key, value in kwargs.items():
            if key not in _PROPERTIES:
                raise ValueError(f"unknown particle property '{key}'")
            vals = self._core.get_property(key, ids)
            target = np.asarray(value)
            if vals.ndim == 2:
                mask &= np.all(np.isclose(vals, target), axis=1)
            else:
                mask &= np.isclose(vals, target) if vals.dtype.kind == "f" else vals == target
        return ParticleSlice(self._system, np.asarray(ids)[mask])

    def pairs(self):
        """Every unordered pair of particles (ParticleHandle, ParticleHandle),
        ids ascending (i < j): a generator of N (N - 1) / 2 pairs."""
        ids = self._core.particle_ids()
        handles = [ParticleHandle(self._system, i) for i in ids]
        for a in range(len(handles)):
            for b in range(a + 1, len(handles)):
                yield handles[a], handles[b]

    def exists(self, pid):
        """True if a particle with id ``pid`` exists."""
        return self._core.particle_exists(int(pid))

    def clear(self):
        """Delete all particles."""
        self._core.clear_particles()

    @property
    def highest_particle_id(self):
        """Highest particle id in use, -1 if there are no particles."""
        return self._core.highest_particle_id()

    def __len__(self):
        return self._core.n_part()

    def __iter__(self):
        return iter(self.all())
