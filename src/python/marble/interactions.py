"""Non-bonded interactions: ``system.non_bonded_inter[i, j].<kind>``.

Each kind offers ``set_params(**kw)``, ``get_params()`` and ``deactivate()``,
as in espressomd. Parameters are validated in the core's script interface.
"""
import numbers


class _Interaction:
    _kind = None

    def __init__(self, system, i, j):
        self._core = system._core
        self._i, self._j = i, j

    def set_params(self, **params):
        """Set (replace) this interaction's parameters."""
        self._core.set_nonbonded(self._i, self._j, self._kind, params)

    def get_params(self):
        """The active parameters ({} if the interaction is off)."""
        return dict(self._core.get_nonbonded(self._i, self._j, self._kind))

    def deactivate(self):
        """Switch this interaction off for the type pair."""
        self._core.deactivate_nonbonded(self._i, self._j, self._kind)

    def is_active(self):
        return bool(self.get_params())

    def __repr__(self):
        try:
            params = self.get_params()
        except Exception as err:  # noqa: BLE001  (e.g. FeaturesError: repr must not raise)
            params = f"unavailable: {err}"
        return f"<{type(self).__name__} types=({self._i}, {self._j}) {params}>"


class LennardJonesInteraction(_Interaction):
    """V = 4 eps [(s/(r-offset))^12 - (s/(r-offset))^6 + shift] for min < r-offset < cutoff.

    Parameters: epsilon >= 0, sigma > 0, cutoff > 0 (measured from the offset),
    shift (number or "auto"), offset >= 0, min >= 0.
    """
    _kind = "lennard_jones"


class HatInteraction(_Interaction):
    """Groot-Warren soft repulsion F = F_max (1 - r/cutoff). Parameters: F_max >= 0, cutoff > 0."""
    _kind = "hat"


class DPDInteraction(_Interaction):
    """DPD pair friction and noise (needs ``system.thermostat.set_dpd``).

    Parameters: weight_function (0: w=1, 1: w=1-(r/r_cut)^k), gamma >= 0, k > 0,
    r_cut >= 0 and, with TRANS_DPD, trans_weight_function, trans_gamma, trans_r_cut.
    """
    _kind = "dpd"


class MarbleInteraction(_Interaction):
    """Marble colloid surface coupling (Zhou & Schmid) of colloid type i with solvent type j.

    Parameters: radius > 0 (required), gamma >= 0 (required), r_cut > 0 (1.0),
    weight_function 0 or 1 (1: w = 1 - (h/r_cut)^k), k > 0 (1.0),
    coupling 'tunable_slip' (default), 'transverse' or 'dpd' (central).
    Thermalised by the DPD thermostat (``system.thermostat.set_dpd``). The order
    of the types matters: ``non_bonded_inter[colloid_type, solvent_type]``.
    """
    _kind = "marble"

    def set_params(self, **params):
        self._core.set_marble(self._i, self._j, params)

    def get_params(self):
        return dict(self._core.get_marble(self._i, self._j))

    def deactivate(self):
        self._core.deactivate_marble(self._i, self._j)


class TunableSlipInteraction(_Interaction):
    """Tunable-slip wall friction (Smiatek et al.) between a wall's particle type i
    and fluid type j: F = -gamma w(z) (v - v_wall) + noise, w = 1 - (z - offset)/r_cut
    (w = 1 for z < offset). Parameters: gamma >= 0, r_cut > 0, offset >= 0 (0).
    Thermalised by the DPD thermostat."""
    _kind = "tunable_slip"

    def set_params(self, **params):
        self._core.set_tunable_slip(self._i, self._j, params)

    def get_params(self):
        return dict(self._core.get_tunable_slip(self._i, self._j))

    def deactivate(self):
        self._core.deactivate_tunable_slip(self._i, self._j)


class NonBondedInteractionHandle:
    """The interactions of one type pair."""

    def __init__(self, system, i, j):
        self.lennard_jones = LennardJonesInteraction(system, i, j)
        self.hat = HatInteraction(system, i, j)
        self.dpd = DPDInteraction(system, i, j)
        self.marble = MarbleInteraction(system, i, j)
        self.tunable_slip = TunableSlipInteraction(system, i, j)


def _check_type(t):
    if isinstance(t, bool) or not isinstance(t, numbers.Integral) or not 0 <= t < 256:
        raise ValueError(f"particle type must be an integer in [0, 256), got {t!r}")
    return int(t)


class NonBondedInteractions:
    """``system.non_bonded_inter``; index with a pair of particle types."""

    def __init__(self, system):
        self._system = system

    def __getitem__(self, key):
        if not isinstance(key, tuple) or len(key) != 2:
            raise ValueError("non_bonded_inter is indexed by two particle types: [i, j]")
        i, j = (_check_type(t) for t in key)
        return NonBondedInteractionHandle(self._system, i, j)

    def reset(self):
        """Deactivate every interaction."""
        core = self._system._core
        types = {int(t) for t in core.get_property("type", core.particle_ids())}
        n = max(types, default=0) + 1
        for i in range(n):
            for j in range(i, n):
                for kind in ("lennard_jones", "hat", "dpd"):
                    try:
                        core.deactivate_nonbonded(i, j, kind)
                    except Exception:  # kind not compiled in
                        pass
