"""Integrators: ``system.integrator``."""


class Integrator:
    def __init__(self, system):
        self._core = system._core

    def run(self, steps=1, recalc_forces=False):
        """Integrate ``steps`` steps (int >= 0); ``run(0)`` only recomputes forces.

        With steepest descent, stops early when the largest force is below
        ``f_max`` and returns the number of steps done.
        Raises RuntimeError naming the step and particle if the run blows up;
        the system stays usable (fix the cause and run again).
        """
        return self._core.run(steps, recalc_forces)

    def set_vv(self):
        """Velocity Verlet (the default)."""
        self._core.set_vv()

    def set_steepest_descent(self, f_max=None, gamma=None, max_displacement=None):
        """Steepest descent: x += clip(gamma F, +-max_displacement) until max |F| < f_max.
        Thermostat forces are not applied during the descent."""
        for name, val in (("f_max", f_max), ("gamma", gamma), ("max_displacement", max_displacement)):
            if val is None:
                raise ValueError(f"parameter '{name}' is required")
        self._core.set_steepest_descent(f_max, gamma, max_displacement)

    def get_state(self):
        return dict(self._core.integrator_state())
