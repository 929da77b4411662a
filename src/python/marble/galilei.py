"""Galilei transforms: ``system.galilei``."""
import numpy as np

from .code_features import has_features


class GalileiTransform:
    """Momentum and force removal: ``system.galilei``, or on its own as in
    ESPResSo, ``marble.galilei.GalileiTransform()``, which acts on the most
    recently created System that is still alive (or on ``system=``)."""

    def __init__(self, system=None):
        self._given = system

    @property
    def _system(self):
        if self._given is not None:
            return self._given
        from .observables import _resolve_system
        return _resolve_system(None)

    def kill_particle_motion(self, rotation=False):
        """Set all velocities (and with rotation=True the angular velocities) to zero."""
        parts = self._system.part.all()
        if len(parts) == 0:
            return
        parts.v = np.zeros(3)
        if rotation and has_features("ROTATION"):
            parts.omega_lab = np.zeros(3)

    def kill_particle_forces(self, torque=False):
        """Set all external forces (and torques) to zero."""
        parts = self._system.part.all()
        if len(parts) == 0 or not has_features("EXTERNAL_FORCE"):
            return
        parts.ext_force = np.zeros(3)
        if torque and has_features("ROTATION"):
            parts.ext_torque = np.zeros(3)

    def system_CMS(self):
        """Centre of mass of all particles (unfolded positions)."""
        return self._system._core.center_of_mass()

    def system_CMS_velocity(self):
        """Centre-of-mass velocity of all particles."""
        core = self._system._core
        m = core.total_mass()
        return core.linear_momentum() / m if m > 0 else np.zeros(3)

    def galilei_transform(self):
        """Subtract the centre-of-mass velocity from every particle."""
        parts = self._system.part.all()
        if len(parts) == 0:
            return
        parts.v = parts.v - self.system_CMS_velocity()
