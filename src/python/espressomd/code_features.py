"""Feature names as ESPResSo 4.2 spells them, answered by Marble's build.

``EXTERNAL_FORCES`` is Marble's ``EXTERNAL_FORCE``; every other name is the
same in both codes. ``THERMOSTAT_PER_PARTICLE`` (per-particle Langevin /
Brownian ``gamma``, ``gamma_rot``) is always compiled into Marble: it is
listed and answers True. A name Marble does not know (``ELECTROSTATICS``,
``VIRTUAL_SITES``, ...) is not compiled in: ``has_features`` answers False and
``missing_features`` lists it.
"""
from marble import code_features as _cf
from marble import FeaturesError

#: ESPResSo name -> Marble name, for the names that differ.
ESPRESSO_TO_MARBLE = dict(_cf.ESPRESSO_ALIASES)
_MARBLE_TO_ESPRESSO = {v: k for k, v in ESPRESSO_TO_MARBLE.items()}
#: ESPResSo feature names whose functionality Marble always has (no Marble feature).
ALWAYS_COMPILED = frozenset({"THERMOSTAT_PER_PARTICLE"})


def _flat(names):
    out = []
    for n in names:
        out.extend(n if isinstance(n, (list, tuple, set, frozenset)) else [n])
    return out


def _espresso_name(name):
    return _MARBLE_TO_ESPRESSO.get(name, name)


def features():
    """Features compiled into this build, with ESPResSo's names (sorted)."""
    return sorted([_espresso_name(n) for n in _cf.features()] + list(ALWAYS_COMPILED))


def all_features():
    """Every feature Marble knows, with ESPResSo's names (sorted)."""
    return sorted([_espresso_name(n) for n in _cf.all_features()] + list(ALWAYS_COMPILED))


def has_features(*names):
    """True if every named feature is compiled in (names or lists of names).
    Unknown names answer False; a name that is not a string raises ValueError.
    Marble's own spellings (``EXTERNAL_FORCE``) are accepted too."""
    return not missing_features(*names)


def missing_features(*names):
    """The named features (ESPResSo or Marble names) that are not compiled in."""
    missing = _cf.missing_features(*names)
    if not missing:
        return missing
    known = set(_flat(names)) & ALWAYS_COMPILED
    return [n for n in missing if n not in known]


def assert_features(*names):
    """Raise :class:`marble.FeaturesError` naming the missing features."""
    missing = missing_features(*names)
    if missing:
        raise FeaturesError(f"missing feature(s) {', '.join(missing)}")
