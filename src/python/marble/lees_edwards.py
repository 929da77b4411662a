"""Lees-Edwards boundary conditions (simple shear): ``system.lees_edwards``,
shaped like ESPResSo 4.2's ``espressomd.lees_edwards`` (doc/lees-edwards.md).

    import marble
    import marble.lees_edwards
    system.lees_edwards.set_boundary_conditions(
        shear_direction="x", shear_plane_normal="y",
        protocol=marble.lees_edwards.LinearShear(shear_velocity=0.1))

The periodic images one box length up along the shear-plane normal are
displaced by ``pos_offset`` along the shear direction and move with
``shear_velocity`` relative to the box: a particle leaving the box through the
upper face re-enters at the lower one with its position along the shear
direction shifted by -pos_offset and its velocity by -shear_velocity (the
opposite going down), pair distances use those images and so do the velocity
differences of DPD and every velocity-dependent kernel. The mean flow is
v_s(n) = shear_velocity * n / L_n + const, shear rate shear_velocity / L_n.
"""
import numbers

import numpy as np

__all__ = ["LeesEdwards", "LinearShear", "OscillatoryShear", "Off"]

_AXES = {"x": 0, "y": 1, "z": 2}
_NAMES = "xyz"


def _finite(name, value):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not np.isfinite(value):
        raise ValueError(f"parameter '{name}' must be a finite number, got {value!r}")
    return float(value)


class Off:
    """No shear: plain periodic boundaries (``system.lees_edwards.protocol = Off()``
    or ``None`` switches Lees-Edwards off)."""

    _kind = 0

    def __init__(self):
        pass

    def _params(self):
        return (0.0, 0.0, 0.0, 0.0, 0.0)

    def __repr__(self):
        return "Off()"

    def __eq__(self, other):
        return type(other) is type(self) and other._params() == self._params()


class LinearShear(Off):
    """offset(t) = initial_pos_offset + shear_velocity * (t - time_0);
    constant shear velocity."""

    _kind = 1

    def __init__(self, initial_pos_offset=0.0, shear_velocity=0.0, time_0=0.0):
        self.initial_pos_offset = _finite("initial_pos_offset", initial_pos_offset)
        self.shear_velocity = _finite("shear_velocity", shear_velocity)
        self.time_0 = _finite("time_0", time_0)

    def _params(self):
        return (self.initial_pos_offset, self.shear_velocity, 0.0, 0.0, self.time_0)

    def __repr__(self):
        return (f"LinearShear(initial_pos_offset={self.initial_pos_offset}, "
                f"shear_velocity={self.shear_velocity}, time_0={self.time_0})")


class OscillatoryShear(Off):
    """offset(t) = initial_pos_offset + amplitude * sin(omega * (t - time_0));
    shear velocity = amplitude * omega * cos(omega * (t - time_0))."""

    _kind = 2

    def __init__(self, initial_pos_offset=0.0, amplitude=0.0, omega=0.0, time_0=0.0):
        self.initial_pos_offset = _finite("initial_pos_offset", initial_pos_offset)
        self.amplitude = _finite("amplitude", amplitude)
        self.omega = _finite("omega", omega)
        self.time_0 = _finite("time_0", time_0)

    def _params(self):
        return (self.initial_pos_offset, 0.0, self.amplitude, self.omega, self.time_0)

    def __repr__(self):
        return (f"OscillatoryShear(initial_pos_offset={self.initial_pos_offset}, "
                f"amplitude={self.amplitude}, omega={self.omega}, time_0={self.time_0})")


def _axis(name, value):
    if isinstance(value, str) and value in _AXES:
        return _AXES[value]
    if isinstance(value, numbers.Integral) and not isinstance(value, bool) and 0 <= value <= 2:
        return int(value)
    raise ValueError(f"parameter '{name}' must be 'x', 'y' or 'z' (or 0, 1, 2), got {value!r}")


class LeesEdwards:
    """``system.lees_edwards``: Lees-Edwards boundary conditions of the box.

    Supported: any number of MPI ranks (the node grid then splits only the
    vorticity axis, neither the shear direction nor the normal), velocity
    Verlet, DPD-VV and Shardlow (its sweep adds the shear velocity jump to
    pairs across the plane) with the DPD (and Langevin) thermostat and every
    pair kernel of the main pair list, large-range types as long as their range
    is at most the box along the normal; the pressure tensor and energies use
    the same images. Refused at run time (RuntimeError naming the reason): an
    SRD solvent, marble colloids, Brownian dynamics, RESPA substeps, a
    non-periodic shear direction or normal."""

    def __init__(self, system):
        self._system = system

    def _state(self):
        return self._system._core.le_state()

    def set_boundary_conditions(self, shear_direction=None, shear_plane_normal=None, protocol=None):
        """Switch Lees-Edwards on with ``protocol`` (LinearShear,
        OscillatoryShear; Off or None switches it off). ``shear_direction``
        and ``shear_plane_normal``: 'x', 'y' or 'z', different."""
        if protocol is None or type(protocol) is Off:
            self._system._core.le_set(-1, -1, 0, 0.0, 0.0, 0.0, 0.0, 0.0)
            return
        if not isinstance(protocol, Off):
            raise ValueError("parameter 'protocol' must be marble.lees_edwards.LinearShear, "
                             f"OscillatoryShear or Off, got {protocol!r}")
        d = _axis("shear_direction", shear_direction)
        n = _axis("shear_plane_normal", shear_plane_normal)
        if d == n:
            raise ValueError("parameters 'shear_direction' and 'shear_plane_normal' must be "
                             f"different axes, got {shear_direction!r} for both")
        self._system._core.le_set(d, n, protocol._kind, *protocol._params())

    @property
    def protocol(self):
        """The protocol (LinearShear, OscillatoryShear) or None when off.
        Setting None or Off() switches Lees-Edwards off; setting another
        protocol keeps the axes (they must have been set before)."""
        st = self._state()
        if st["kind"] == 1:
            return LinearShear(st["initial_pos_offset"], st["shear_velocity_param"], st["time_0"])
        if st["kind"] == 2:
            return OscillatoryShear(st["initial_pos_offset"], st["amplitude"], st["omega"],
                                    st["time_0"])
        return None

    @protocol.setter
    def protocol(self, value):
        if value is None or type(value) is Off:
            self.set_boundary_conditions(protocol=None)
            return
        st = self._state()
        if st["shear_direction"] < 0:
            raise ValueError("set the axes first: system.lees_edwards.set_boundary_conditions("
                             "shear_direction=..., shear_plane_normal=..., protocol=...)")
        self.set_boundary_conditions(_NAMES[st["shear_direction"]],
                                     _NAMES[st["shear_plane_normal"]], value)

    @property
    def pos_offset(self):
        """Current offset along the shear direction (0 when off; read-only)."""
        return float(self._state()["pos_offset"])

    @property
    def shear_velocity(self):
        """Current shear velocity (d offset / dt; 0 when off; read-only)."""
        return float(self._state()["shear_velocity"])

    @property
    def shear_direction(self):
        """'x', 'y' or 'z' (None when off; read-only)."""
        d = self._state()["shear_direction"]
        return _NAMES[d] if d >= 0 else None

    @property
    def shear_plane_normal(self):
        """'x', 'y' or 'z' (None when off; read-only)."""
        n = self._state()["shear_plane_normal"]
        return _NAMES[n] if n >= 0 else None

    def distance_vec(self, a, b):
        """Lees-Edwards minimum-image vector b - a of two positions (the image
        of b nearest to a); plain minimum image when off."""
        a = np.asarray(a, dtype=float)
        b = np.asarray(b, dtype=float)
        d = b - a
        L = np.asarray(self._system.box_l, dtype=float)
        st = self._state()
        if st["shear_direction"] < 0:
            return d - L * np.round(d / L)
        n, s = st["shear_plane_normal"], st["shear_direction"]
        k = np.round(d[n] / L[n])
        d[n] -= k * L[n]
        d[s] -= k * st["pos_offset"]
        per = np.asarray(self._system.periodicity, dtype=bool)
        for i in range(3):
            if i != n and per[i]:
                d[i] -= L[i] * np.round(d[i] / L[i])
        return d
