"""Integrators: ``system.integrator``."""
import sys
import time


class IntegratorParameterError(ValueError, RuntimeError):
    """Bad or missing integrator parameter. A ``ValueError`` (Marble's
    convention for bad input) that is also a ``RuntimeError`` (what ESPResSo
    4.2 raises for these), so scripts written for either catch it."""


def _progress_line(done, total, elapsed):
    rate = done / elapsed if elapsed > 0 else float("inf")
    eta = (total - done) / rate if rate > 0 and rate != float("inf") else 0.0
    return (f"\rstep {done}/{total} ({100.0 * done / total:5.1f}%), "
            f"{rate:.4g} steps/s, ETA {eta:.1f} s")


class Integrator:
    """``system.integrator``: velocity Verlet, steepest descent, Shardlow, DPD-VV,
    Brownian dynamics, and ``run``."""
    def __init__(self, system):
        self._core = system._core

    def run(self, steps=1, recalc_forces=False, reuse_forces=False, progress=False):
        """Integrate ``steps`` steps (int >= 0); ``run(0)`` only computes forces
        (with every integrator, steepest descent included).

        With steepest descent, stops early when the largest force is below
        ``f_max`` and returns the number of steps done.
        ``reuse_forces`` is accepted for ESPResSo scripts: Marble always reuses
        the forces of the last step while they are valid, and recomputes them
        when a parameter or particle changed; ``recalc_forces=True`` together
        with ``reuse_forces=True`` raises ValueError.
        ``progress=True`` runs in chunks of about 1% and prints the steps done,
        the rate and the estimated time left to stderr (rank 0 only); the
        trajectory is the same as one run (the noise is keyed by the step).
        Raises RuntimeError naming the step and particle if the run blows up;
        the system stays usable (fix the cause and run again).
        """
        if recalc_forces and reuse_forces:
            raise ValueError("cannot reuse old forces and recalculate forces: "
                             "set at most one of 'recalc_forces' and 'reuse_forces'")
        if not progress:
            return self._core.run(steps, recalc_forces)
        if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
            return self._core.run(steps, recalc_forces)  # validates / run(0)
        from ._marble import mpi_rank
        show = mpi_rank() == 0
        chunk = max(1, steps // 100)
        done, t0, last = 0, time.perf_counter(), 0.0
        sd = self._core.integrator_name() == "SteepestDescent"
        while done < steps:
            n = min(chunk, steps - done)
            did = self._core.run(n, recalc_forces and done == 0)
            done += did
            now = time.perf_counter()
            if show and (now - last > 0.5 or done >= steps or (sd and did < n)):
                sys.stderr.write(_progress_line(done, steps, now - t0))
                sys.stderr.flush()
                last = now
            if sd and did < n:  # converged
                break
        if show:
            sys.stderr.write("\n")
        return done

    def set_vv(self, substeps=1):
        """Velocity Verlet (the default).

        ``substeps`` (int in [1, 100], default 1 = plain velocity Verlet):
        RESPA multiple time stepping (Tuckerman, Berne & Martyna 1992) for the
        stiff colloid pairs: the conservative pair forces of the colloid pair
        list (e.g. a marble's LJ wall) are integrated with ``substeps`` inner
        steps of ``time_step / substeps``; all other forces (solvent pairs,
        walls, external, Langevin, the colloid pairs' friction and noise) keep
        the outer step. Runs on any number of MPI ranks (the same trajectory
        to round-off); not with Lees-Edwards or SRD (RuntimeError at run
        time). A step refused in a substep (a particle moving more than the
        skin) stops the run with the outer half kick and the substeps before
        the refused one done. See doc/speed-accuracy.md."""
        self._core.set_vv(substeps)

    def set_steepest_descent(self, f_max=None, gamma=None, max_displacement=None):
        """Steepest descent: x += clip(gamma F, +-max_displacement) until max ``|F|`` < f_max.

        ``f_max`` in [0, inf), ``gamma`` in [0, inf), ``max_displacement`` in
        (0, inf), all required. A missing or out-of-range parameter raises
        :class:`IntegratorParameterError` (both ValueError and RuntimeError).
        Thermostat forces are not applied during the descent."""
        for name, val in (("f_max", f_max), ("gamma", gamma), ("max_displacement", max_displacement)):
            if val is None:
                raise IntegratorParameterError(
                    f"Parameter '{name}' is missing: set_steepest_descent needs f_max, gamma "
                    f"and max_displacement")
        try:
            self._core.set_steepest_descent(f_max, gamma, max_displacement)
        except ValueError as err:
            raise IntegratorParameterError(str(err)) from None

    def set_shardlow(self, substeps=1):
        """Shardlow S1 splitting for DPD (doc/stability.md): each step first
        updates the velocities of every DPD pair of the solvent, one pair after
        the other, with the exact solution of the pair's friction + noise over
        dt (momentum-conserving, stable for any gamma*dt), then does velocity
        Verlet with the conservative forces. Removes most of the kT(dt) drift of
        plain VV. Colloid (marble) pairs and tunable-slip walls keep their explicit
        friction inside the VV part. ``particle.f`` then excludes the solvent's DPD
        pair forces. Raises FeaturesError without DPD.

        Several MPI ranks: supported for DPD fluids (any types and kernels,
        lubrication and the stick ``surface_friction`` included), marble
        colloids and RESPA substeps; the sweep's pairs that touch another
        rank's particles go in rounds by domain (the marble coupling's pairs
        rank by rank), so the trajectory depends on the decomposition, the
        statistics do not (doc/parallel.md). Domains narrower than twice the
        pair range stop ``run`` with a RuntimeError before any step.

        ``substeps`` (int in [1, 100], default 1): RESPA substeps for the stiff
        colloid pair forces, as in :meth:`set_vv`; the pair sweep stays at the
        outer step. ``set_shardlow(substeps=2)``
        lets the R = 3 marble scene run at a larger time_step
        (doc/speed-accuracy.md)."""
        self._core.set_shardlow(substeps)

    def set_dpd_vv(self):
        """DPD-VV (Besold et al. 2000): velocity Verlet whose DPD friction is
        recomputed with the full-step velocities after each step (doc/stability.md).
        Raises FeaturesError without DPD."""
        self._core.set_dpd_vv()

    def set_brownian_dynamics(self):
        """Brownian (overdamped Langevin) dynamics, as ESPResSo's
        ``set_brownian_dynamics()``: each step moves every particle by
        ``F dt / gamma + sqrt(2 kT dt / gamma) N(0, 1)`` per component and sets
        its velocity to ``F / gamma + sqrt(kT / m) N'(0, 1)`` (the drift plus a
        Maxwell velocity; rotating particles get ``omega = tau / gamma_rot +
        sqrt(kT / I) N''``, no orientation is tracked). kT, gamma and
        gamma_rotation come from ``thermostat.set_brownian(...)`` (required at
        run time, RuntimeError otherwise) or the particle's own ``gamma`` /
        ``gamma_rot``. Cannot be combined with the DPD or Langevin thermostat
        (RuntimeError at run time). See doc/thermostats.md."""
        self._core.set_brownian_dynamics()

    def get_state(self):
        """The active integrator: ``{"name": ...}`` plus steepest descent's
        parameters, or velocity Verlet's and Shardlow's ``substeps``."""
        name = self._core.integrator_name()
        if name in ("DPDVV", "BrownianDynamics"):
            return {"name": name}
        return dict(self._core.integrator_state())
