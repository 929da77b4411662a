"""Compile-time features of this build (see doc/features.md).

``has_features`` follows ESPResSo: a name Marble does not know answers False
(the feature is not compiled in), so a script written for ESPResSo can ask for
``ELECTROSTATICS`` and skip what needs it. ESPResSo's spellings of Marble's
features are accepted as aliases (``EXTERNAL_FORCES`` for ``EXTERNAL_FORCE``).
"""
from . import _marble
from ._marble import FeaturesError

#: ESPResSo 4.2 feature names that Marble spells differently (ESPResSo -> Marble).
ESPRESSO_ALIASES = {"EXTERNAL_FORCES": "EXTERNAL_FORCE"}


def features():
    """Names of the features compiled into this build."""
    return list(_marble.features())


def all_features():
    """Names of every feature Marble knows (compiled in or not)."""
    return list(_marble.all_features())


def _flatten(names):
    """Names or lists of names -> one list of strings (ValueError for anything else)."""
    flat = []
    for n in names:
        if isinstance(n, (list, tuple, set, frozenset)):
            flat.extend(n)
        else:
            flat.append(n)
    for n in flat:
        if not isinstance(n, str):
            raise ValueError(f"feature names must be strings, got {n!r} ({type(n).__name__})")
    return flat


def _canonical(name):
    return ESPRESSO_ALIASES.get(name, name)


def has_features(*names):
    """True if every named feature is compiled in.

    Accepts names or lists of names. A name Marble does not know answers False
    (as in ESPResSo); ESPResSo's spellings (``EXTERNAL_FORCES``) are accepted.
    A name that is not a string raises ValueError.
    """
    active = set(features())
    return all(_canonical(n) in active for n in _flatten(names))


def missing_features(*names):
    """The named features that are not compiled in (a list, in the order given;
    unknown names are missing)."""
    active = set(features())
    return [n for n in _flatten(names) if _canonical(n) not in active]


def assert_features(*names):
    """Raise FeaturesError naming the missing features."""
    missing = missing_features(*names)
    if missing:
        raise FeaturesError(f"missing feature(s) {', '.join(missing)}")
