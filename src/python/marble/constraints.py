"""Constraints: ``system.constraints`` (walls acting on particle types)."""
import numpy as np

from .shapes import Wall


class ShapeBasedConstraint:
    """A wall constraint. Interactions with particle type t are those of
    ``system.non_bonded_inter[particle_type, t]`` (e.g. lennard_jones for the
    WCA repulsion at distance z from the wall, tunable_slip for friction)."""

    def __init__(self, system, cid, shape):
        self._core = system._core
        self._id = cid
        self.shape = shape

    @property
    def particle_type(self):
        """Particle type of the wall (its interactions are ``non_bonded_inter[particle_type, t]``)."""
        return self._core.constraint_state(self._id)["particle_type"]

    @property
    def velocity(self):
        """Velocity of the wall (3,)."""
        return np.array(self._core.constraint_state(self._id)["velocity"])

    def total_force(self):
        """Force the particles exerted on the wall in the last force evaluation."""
        return np.array(self._core.constraint_state(self._id)["total_force"])

    def __repr__(self):
        return f"<ShapeBasedConstraint {self.shape} type={self.particle_type}>"


class Constraints:
    """``system.constraints``: the walls of the system."""
    def __init__(self, system):
        self._system = system
        self._list = []

    def add(self, shape=None, particle_type=None, velocity=(0.0, 0.0, 0.0), **kwargs):
        """Add a wall: ``add(shape=Wall(normal=, dist=), particle_type=, velocity=)``."""
        if kwargs:
            raise ValueError(f"unknown parameter(s) {sorted(kwargs)} for constraints.add "
                             "(allowed: shape, particle_type, velocity)")
        if not isinstance(shape, Wall):
            raise ValueError("parameter 'shape' must be a marble.shapes.Wall")
        if particle_type is None:
            raise ValueError("parameter 'particle_type' is required")
        cid = self._system._core.add_wall(shape.normal, shape.dist, particle_type, velocity)
        c = ShapeBasedConstraint(self._system, cid, shape)
        self._list.append(c)
        return c

    def remove(self, constraint):
        """Remove ``constraint`` from the system."""
        self._system._core.remove_constraint(constraint._id)
        self._list.remove(constraint)

    def clear(self):
        """Remove every constraint."""
        self._system._core.clear_constraints()
        self._list.clear()

    def __len__(self):
        return len(self._list)

    def __iter__(self):
        return iter(list(self._list))

    def __getitem__(self, k):
        return self._list[k]
