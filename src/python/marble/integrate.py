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

    def set_shardlow(self):
        """Shardlow S1 splitting for DPD (doc/stability.md): each step first
        updates the velocities of every DPD pair of the solvent, one pair after
        the other, with the exact solution of the pair's friction + noise over
        dt (momentum-conserving, stable for any gamma*dt), then does velocity
        Verlet with the conservative forces. Removes most of the kT(dt) drift of
        plain VV. Colloid (marble) pairs and tunable-slip walls keep their explicit
        friction inside the VV part. ``particle.f`` then excludes the solvent's DPD
        pair forces. Raises FeaturesError without DPD."""
        self._core.set_shardlow()

    def set_dpd_vv(self):
        """DPD-VV (Besold et al. 2000): velocity Verlet whose DPD friction is
        recomputed with the full-step velocities after each step (doc/stability.md).
        Raises FeaturesError without DPD."""
        self._core.set_dpd_vv()

    def get_state(self):
        name = self._core.integrator_name()
        if name in ("Shardlow", "DPDVV"):
            return {"name": name}
        return dict(self._core.integrator_state())
