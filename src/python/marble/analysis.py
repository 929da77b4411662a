"""Analysis of the current state: ``system.analysis``."""
import numpy as np

from .code_features import has_features


def _masses(parts):
    """Masses of a ParticleSlice: 1 for every particle in a build without MASS."""
    return parts.mass if has_features("MASS") else np.ones(len(parts))


def _type_list(types, name):
    """Particle types as a list of ints (ValueError for anything else, e.g. 0.5)."""
    try:
        arr = np.asarray(types)
    except Exception:  # noqa: BLE001
        arr = np.asarray([None])
    if arr.ndim == 1 and arr.size == 0:
        return []
    if arr.ndim != 1 or arr.dtype.kind not in "iu" or np.any(arr < 0):
        raise ValueError(f"parameter '{name}' must be a list of particle types "
                         f"(integers >= 0), got {types!r}")
    return [int(t) for t in arr]


class Analysis:
    """``system.analysis``: energies, pressure, DPD stress, temperature, momentum, distances."""
    def __init__(self, system):
        self._system = system
        self._core = system._core

    def energy(self):
        """Energies: 'total', 'kinetic' (incl. rotation), 'kinetic_rotational',
        'non_bonded' and ('non_bonded', i, j) per type pair."""
        return dict(self._core.energy())

    def pressure_tensor(self):
        """Pressure tensors (3x3), (1/V) sum of m v (x) v and d_ij (x) F_ij:
        'kinetic', 'non_bonded' (conservative forces, including the colloid
        pairs), 'total' = kinetic + non_bonded (as ESPResSo's total), and the
        dissipative contributions of the current velocities and noise, kept
        out of 'total': 'dpd' (DPD pair friction + noise, main list and colloid
        pairs; the main-list part is :meth:`dpd_stress_split`'s 'total') and
        'marble' (the marble surface coupling, d = r_bead - r_colloid, F on the
        bead). The full mechanical stress is total + dpd + marble (doc/dpd.md)."""
        return dict(self._core.pressure_tensor())

    def pressure(self):
        """Scalar pressures (trace / 3 of the tensors)."""
        return {k: float(np.trace(v)) / 3.0 for k, v in self.pressure_tensor().items()}

    def dpd_stress(self):
        """Viscous DPD stress (3x3 numpy array), as ESPResSo returns it:
        (1/V) sum_pairs d_ij (x) F_ij with d_ij = r_i - r_j and F_ij the DPD
        friction force on i (radial and transverse) of the current velocities,
        without the noise (doc/dpd.md). Same sign as ``pressure_tensor()``.
        Zero when the DPD thermostat is off. :meth:`dpd_stress_split` gives the
        friction and noise parts separately. Feature DPD."""
        return np.array(self._core.dpd_stress()["friction"])

    def dpd_stress_split(self):
        """DPD part of the pressure tensor (3x3 arrays): 'friction' (what
        :meth:`dpd_stress` returns), 'noise' (the random forces of the current
        step) and 'total' = their sum, each (1/V) sum_pairs d_ij (x) F_ij,
        F_ij summed over the pair-dissipative kernels (DPD, lubrication) and
        the stick friction (surface_friction).
        The full pressure tensor of a DPD fluid is
        ``pressure_tensor()["total"] + dpd_stress_split()["total"]``."""
        return dict(self._core.dpd_stress())

    def check_scene(self, target=None):
        """Warnings for parameter choices known to be inaccurate (doc/stability.md):
        a list of dicts with 'code', 'message' (quoting the measured number behind
        the rule), 'value' (the scene's) and 'limit'. Empty when nothing is flagged.
        Codes: dt_kT_error, solvent_density, box_too_small, marble_slip,
        friction_near_limit, skin_small.

        ``target``: optionally the observable ("D", "D_rot", "viscosity") or a
        dict ``{"observable": ..., "accuracy": ..., "R": ..., "boundary": ...}``.
        Then the scene advisor (:mod:`marble.advisor`) adds the features the
        observable does not need (codes unneeded_rotation, unneeded_conservative,
        unneeded_colloid_pairs) and, as the last entry, code 'recommendation'
        with the cheapest model for that accuracy (printed, and its
        :class:`marble.advisor.Recommendation` under 'value';
        doc/choosing-a-model.md)."""
        out = [dict(w) for w in self._core.check_scene()]
        if target is None:
            return out
        from . import advisor
        t = {"observable": target} if isinstance(target, str) else dict(target)
        obs = t.pop("observable", "D")
        out += advisor.check_scene(self._system, obs, verbose=True)
        rec = advisor.recommend(obs, **t)
        out.append(dict(code="recommendation", message=str(rec), value=rec))
        return out

    def linear_momentum(self, include_particles=True, include_lbfluid=True):
        """Total linear momentum sum m v."""
        if not include_particles:
            return np.zeros(3)
        return self._core.linear_momentum()

    def kinetic_temperature(self, types=None):
        """Translational kinetic temperature 2 E_kin / (3 N) (optionally of some types)."""
        parts = self._system.part.all()
        if types is not None:
            types = np.atleast_1d(types)
            sel = np.isin(parts.type, types)
            ids = parts.id[sel]
            parts = self._system.part.by_ids(ids)
        n = len(parts)
        if n == 0:
            raise ValueError("no particles to compute a temperature from")
        v = parts.v
        m = _masses(parts)
        return float(np.sum(m[:, None] * v * v) / (3.0 * n))

    def center_of_mass(self, p_type=None):
        """Centre of mass of all particles, or of those of type ``p_type``."""
        if p_type is None:
            return self._core.center_of_mass()
        parts = self._system.part.select(type=p_type)
        if len(parts) == 0:
            raise ValueError(f"no particles of type {p_type}")
        m = _masses(parts)
        return np.sum(m[:, None] * parts.pos, axis=0) / np.sum(m)

    def min_dist(self, p1="default", p2="default"):
        """Smallest minimum-image distance between a particle of a type in p1 and
        one of a type in p2 ('default': any type)."""
        t1 = [] if isinstance(p1, str) and p1 == "default" else _type_list(p1, "p1")
        t2 = [] if isinstance(p2, str) and p2 == "default" else _type_list(p2, "p2")
        return float(self._core.min_dist(t1, t2))
