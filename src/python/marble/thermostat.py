"""Thermostats: ``system.thermostat``: the DPD pair thermostat, the Langevin
thermostat and the Brownian dynamics thermostat (doc/thermostats.md)."""
from . import _marble  # noqa: F401


class DPDThermostatState:
    """``system.thermostat.dpd``: kT, seed and the Philox counter of the DPD noise."""

    def __init__(self, system):
        self._core = system._core

    @property
    def kT(self):
        """Temperature of the DPD thermostat (0 when off)."""
        return self._core.dpd_state().get("kT", 0.0)

    @property
    def seed(self):
        """Seed of the DPD noise (None before the first ``set_dpd``)."""
        return self._core.dpd_state().get("seed")

    @property
    def active(self):
        """True while the DPD thermostat is on."""
        return bool(self._core.dpd_state().get("active", False))

    @property
    def philox_counter(self):
        """Counter of the noise: advances by one per integration step."""
        return self._core.dpd_state().get("philox_counter", 0)

    @philox_counter.setter
    def philox_counter(self, value):
        self._core.set_dpd_philox_counter(value)


class SingleParticleThermostatState:
    """``system.thermostat.langevin`` / ``system.thermostat.brownian``: kT,
    gamma, gamma_rotation, seed and the Philox counter of that thermostat."""

    def __init__(self, system, which):
        self._core = system._core
        self._which = which

    def _state(self):
        return self._core.single_particle_thermostat_state(self._which)

    @property
    def kT(self):
        """Temperature (0 when off)."""
        return self._state()["kT"]

    @property
    def gamma(self):
        """Global translational friction (a particle's own ``gamma`` >= 0 replaces it)."""
        return self._state()["gamma"]

    @property
    def gamma_rotation(self):
        """Global rotational friction (a particle's own ``gamma_rot`` >= 0 replaces it)."""
        return self._state()["gamma_rotation"]

    @property
    def seed(self):
        """Seed of the noise (None before the first activation)."""
        return self._state()["seed"]

    @property
    def active(self):
        """True while this thermostat is on."""
        return bool(self._state()["active"])

    @property
    def philox_counter(self):
        """Counter of the noise: advances by one per integration step."""
        return self._state()["philox_counter"]

    @philox_counter.setter
    def philox_counter(self, value):
        self._core.set_single_particle_philox_counter(self._which, value)


class Thermostat:
    """``system.thermostat``: the DPD pair thermostat (doc/dpd.md), the
    Langevin thermostat and Brownian dynamics (doc/thermostats.md)."""
    def __init__(self, system):
        self._core = system._core
        self.dpd = DPDThermostatState(system)
        self.langevin = SingleParticleThermostatState(system, "langevin")
        self.brownian = SingleParticleThermostatState(system, "brownian")

    def set_dpd(self, kT=None, seed=None):
        """Activate the DPD thermostat at temperature ``kT`` (>= 0).

        ``seed`` (int >= 0) is required the first time; later calls may omit it
        (the noise stream then continues). Re-seeding keeps the Philox counter.
        The per-pair friction is set with ``non_bonded_inter[i, j].dpd``.
        """
        if kT is None:
            raise ValueError("parameter 'kT' is required")
        self._core.set_dpd(kT, seed)

    def set_langevin(self, kT=None, gamma=None, gamma_rotation=None, seed=None, **kwargs):
        """Activate the Langevin thermostat (ESPResSo 4.2 call shape).

        Every particle feels ``-gamma v + sqrt(24 kT gamma / dt) xi`` (``xi``
        uniform, variance 1/12 per component) and, if it rotates (ROTATION),
        the torque ``-gamma_rotation omega + ...``. ``kT`` >= 0 and ``gamma``
        >= 0 are required; ``gamma_rotation`` >= 0 defaults to ``gamma``;
        ``seed`` (int >= 0) is required the first time (later calls may omit it
        to continue the noise stream). A particle's own ``gamma`` / ``gamma_rot``
        (>= 0; -1 = use these) replaces the global value. Combines with the DPD
        thermostat. ``act_on_virtual`` is accepted and ignored (no virtual sites).
        Bad values raise ValueError naming the parameter and its range.
        """
        _check_kwargs("set_langevin", kwargs)
        for name, val in (("kT", kT), ("gamma", gamma)):
            if val is None:
                raise ValueError(f"parameter '{name}' is required")
        self._core.set_single_particle_thermostat("langevin", kT, gamma, gamma_rotation, seed)

    def set_brownian(self, kT=None, gamma=None, gamma_rotation=None, seed=None, **kwargs):
        """Activate the Brownian dynamics thermostat (ESPResSo 4.2 call shape);
        it acts only with ``integrator.set_brownian_dynamics()`` (RuntimeError
        at run time with another integrator). ``kT`` >= 0, ``gamma`` > 0 are
        required; ``gamma_rotation`` > 0 defaults to ``gamma``; ``seed`` (int
        >= 0) is required the first time. A particle's own ``gamma`` /
        ``gamma_rot`` replaces the global value. ``act_on_virtual`` is accepted
        and ignored."""
        _check_kwargs("set_brownian", kwargs)
        for name, val in (("kT", kT), ("gamma", gamma)):
            if val is None:
                raise ValueError(f"parameter '{name}' is required")
        self._core.set_single_particle_thermostat("brownian", kT, gamma, gamma_rotation, seed)

    def turn_off(self):
        """Switch every thermostat off (DPD, Langevin, Brownian). Seeds and
        counters are kept, so a later ``set_*`` may omit the seed."""
        self._core.thermostat_turn_off()

    def get_state(self):
        """One dict per active thermostat: ``{"type": "DPD", "kT", "seed",
        "active", "philox_counter"}``, ``{"type": "LANGEVIN", "kT", "gamma",
        "gamma_rotation", "seed", "active", "philox_counter"}``, ``{"type":
        "BROWNIAN", ...}``; ``[]`` when every thermostat is off."""
        out = []
        st = self._core.dpd_state()
        if st.get("active"):
            out.append(dict(type="DPD", **st))
        for which in ("langevin", "brownian"):
            st = self._core.single_particle_thermostat_state(which)
            if st["active"]:
                out.append(dict(type=which.upper(), **st))
        return out


def _check_kwargs(call, kwargs):
    """ESPResSo's act_on_virtual is accepted (no virtual sites here); anything else is an error."""
    extra = set(kwargs) - {"act_on_virtual"}
    if extra:
        raise ValueError(f"{call}: unknown parameter(s) {', '.join(sorted(extra))} "
                         f"(known: kT, gamma, gamma_rotation, seed)")
