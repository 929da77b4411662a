"""The System: the one object a script creates; it owns everything else."""
import numbers

import numpy as np

from . import _marble
from .accumulators import AutoUpdateAccumulators
from .analysis import Analysis
from .cell_system import CellSystem
from .constraints import Constraints
from .galilei import GalileiTransform
from .integrate import Integrator
from .lees_edwards import LeesEdwards
from .interactions import NonBondedInteractions
from .particle_data import ParticleList, ParticleHandle
from .thermostat import Thermostat


class System:
    """A simulation box with its particles, interactions, thermostat and integrator.

    Parameters
    ----------
    box_l : (3,) array_like of float > 0
        Box lengths. The box is periodic in all three directions.
    time_step : float > 0, optional
    """

    _allowed = ("box_l", "time_step", "periodicity")

    def __init__(self, **kwargs):
        unknown = set(kwargs) - set(self._allowed)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)} for System "
                             f"(allowed: {', '.join(self._allowed)})")
        if "box_l" not in kwargs:
            raise ValueError("parameter 'box_l' is required")
        self._core = _marble.System(kwargs["box_l"])
        self._init_wrappers()
        if "periodicity" in kwargs:
            self.periodicity = kwargs["periodicity"]
        if "time_step" in kwargs:
            self.time_step = kwargs["time_step"]

    _wrappers = ("_core", "part", "non_bonded_inter", "thermostat", "integrator", "cell_system",
                 "analysis", "galilei", "constraints", "auto_update_accumulators",
                 "lees_edwards")

    def _init_wrappers(self):
        self.part = ParticleList(self)
        self.non_bonded_inter = NonBondedInteractions(self)
        self.thermostat = Thermostat(self)
        self.integrator = Integrator(self)
        self.cell_system = CellSystem(self)
        self.analysis = Analysis(self)
        self.galilei = GalileiTransform(self)
        self.constraints = Constraints(self)
        self.auto_update_accumulators = AutoUpdateAccumulators(self)
        self.lees_edwards = LeesEdwards(self)

    # --- pickling (marble.checkpointing, doc/io.md) -------------------------
    def __reduce__(self):
        """Pickled as the core's checkpoint blob (the whole state, bit for bit:
        particles in their stored order with forces and pos_at_rebuild,
        parameters, thermostat counter, integrator) plus the Python-side state:
        the walls' shapes, the accumulators in ``auto_update_accumulators``
        (with their full state) and any attribute a script added. Collective
        in an MPI run: every rank's particles are gathered."""
        extra = {k: v for k, v in self.__dict__.items() if k not in self._wrappers + ("_srd",)}  # SRD
        state = {"constraints": [(c._id, c.shape) for c in self.constraints],
                 "accumulators": list(self.auto_update_accumulators),
                 "extra": extra}
        if self._core.srd_active():  # SRD: the fluid's parameters and state
            state["srd"] = (self._srd._kw, self._core.srd_get_state())
        return (_restore_system, (self._core.get_checkpoint_state(),), state)

    def __setstate__(self, state):
        from .constraints import ShapeBasedConstraint
        for cid, shape in state["constraints"]:
            self.constraints._list.append(ShapeBasedConstraint(self, cid, shape))
        for acc in state["accumulators"]:
            self.auto_update_accumulators._restore(acc)
        self.__dict__.update(state["extra"])
        if "_large_range_types" in state["extra"]:  # pickles of before checkpoint format 4
            self.__dict__.pop("_large_range_types")
            if state["extra"]["_large_range_types"] != "auto":
                self.cell_system.large_range_types = state["extra"]["_large_range_types"]
        if "srd" in state:  # SRD
            from .srd import SRDFluid
            self.srd = SRDFluid(**state["srd"][0])
            self._srd._restore(state["srd"][1])

    # --- SRD solvent (marble.srd.SRDFluid; None if none) -------------------  # SRD
    @property
    def srd(self):
        return self.__dict__.get("_srd")

    @srd.setter
    def srd(self, fluid):
        from .srd import _attach
        _attach(self, fluid)

    # --- parameters -------------------------------------------------------
    @property
    def box_l(self):
        """Box lengths (3,)."""
        return self._core.box_l

    @box_l.setter
    def box_l(self, value):
        self._core.box_l = value

    @property
    def periodicity(self):
        """Periodicity per axis (3 bools). Switch it off along the normal of
        walls that bound the box."""
        return np.array(self._core.get_periodicity())

    @periodicity.setter
    def periodicity(self, value):
        v = np.asarray(value)
        if v.shape != (3,) or v.dtype.kind not in "bi" or not np.all((v == 0) | (v == 1)):
            raise ValueError("parameter 'periodicity' must be 3 bools")
        self._core.set_periodicity([bool(x) for x in v])

    @property
    def time_step(self):
        """Integration time step (> 0). Unset: -1."""
        return self._core.time_step

    @time_step.setter
    def time_step(self, value):
        self._core.time_step = value

    @property
    def time(self):
        """Simulation time."""
        return self._core.time

    @time.setter
    def time(self, value):
        self._core.time = value

    @property
    def step(self):
        """Number of integration steps done (keys the counter-based noise)."""
        return self._core.step

    # --- geometry helpers ---------------------------------------------------
    def volume(self):
        """Box volume box_l[0] * box_l[1] * box_l[2] (a float)."""
        L = self.box_l
        return float(L[0] * L[1] * L[2])

    def _position_of(self, x, name):
        if isinstance(x, ParticleHandle):
            return x.pos_folded
        a = np.asarray(x, dtype=float)
        if a.shape != (3,) or not np.all(np.isfinite(a)):
            raise ValueError(f"parameter '{name}' must be a particle or a finite 3-vector")
        return a

    def rotate_system(self, phi=None, theta=None, alpha=None):
        """Rotate every particle position by the angle ``alpha`` about the axis
        (sin(theta) cos(phi), sin(theta) sin(phi), cos(theta)) through the
        centre of mass (unfolded positions, mass-weighted), right-handed; as
        ESPResSo's ``rotate_system(phi=, theta=, alpha=)``. Velocities are not
        changed (as in ESPResSo); Marble's particles are isotropic spheres
        without an orientation, so there is no orientation to rotate.
        All three angles are required finite numbers (ValueError otherwise)."""
        angles = {}
        for name, val in (("phi", phi), ("theta", theta), ("alpha", alpha)):
            if val is None:
                raise ValueError(f"parameter '{name}' is required")
            if isinstance(val, bool) or not isinstance(val, numbers.Real) or \
                    not np.isfinite(val):
                raise ValueError(f"parameter '{name}' must be a finite number, got {val!r}")
            angles[name] = float(val)
        parts = self.part.all()
        if len(parts) == 0:
            return
        from .code_features import has_features
        m = np.asarray(parts.mass, dtype=float) if has_features("MASS") else np.ones(len(parts))
        pos = np.asarray(parts.pos, dtype=float)
        com = (m[:, None] * pos).sum(axis=0) / m.sum()
        ph, th, a = angles["phi"], angles["theta"], angles["alpha"]
        k = np.array([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
        r = pos - com
        rot = (np.cos(a) * r + np.sin(a) * np.cross(k, r)
               + (1.0 - np.cos(a)) * np.outer(r @ k, k))
        parts.pos = com + rot

    def distance_vec(self, p1, p2):
        """Minimum-image vector from p1 to p2 (particles or positions)."""
        a = self._position_of(p1, "p1")
        b = self._position_of(p2, "p2")
        if self.lees_edwards.shear_direction is not None:  # the Lees-Edwards images
            return self.lees_edwards.distance_vec(a, b)
        d = b - a
        L = self.box_l
        return d - L * np.round(d / L)

    def distance(self, p1, p2):
        """Minimum-image distance between p1 and p2 (particles or positions)."""
        return float(np.linalg.norm(self.distance_vec(p1, p2)))


def _restore_system(blob):
    """Unpickling: a System whose core state is ``blob`` (validated completely
    before use: RuntimeError for a corrupt or foreign blob)."""
    core = _marble.System([1.0, 1.0, 1.0])
    core.set_checkpoint_state(blob)
    system = System.__new__(System)
    system._core = core
    system._init_wrappers()
    return system
