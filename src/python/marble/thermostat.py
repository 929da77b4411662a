"""Thermostats: ``system.thermostat``. Marble's is the DPD pair thermostat."""
from . import _marble


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


class Thermostat:
    """``system.thermostat``: the DPD pair thermostat (doc/dpd.md)."""
    def __init__(self, system):
        self._core = system._core
        self.dpd = DPDThermostatState(system)

    def set_dpd(self, kT=None, seed=None):
        """Activate the DPD thermostat at temperature ``kT`` (>= 0).

        ``seed`` (int >= 0) is required the first time; later calls may omit it
        (the noise stream then continues). Re-seeding keeps the Philox counter.
        The per-pair friction is set with ``non_bonded_inter[i, j].dpd``.
        """
        if kT is None:
            raise ValueError("parameter 'kT' is required")
        self._core.set_dpd(kT, seed)

    def turn_off(self):
        """Switch every thermostat off (removes DPD friction and noise)."""
        self._core.thermostat_turn_off()

    def get_state(self):
        """``[{"type": "DPD", "kT", "seed", "active", "philox_counter"}]`` while on, else ``[]``."""
        st = self._core.dpd_state()
        return [dict(type="DPD", **st)] if st.get("active") else []
