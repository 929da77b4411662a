"""Compile-time features of this build (see doc/features.md)."""
from . import _marble
from ._marble import FeaturesError


def features():
    """Names of the features compiled into this build."""
    return list(_marble.features())


def all_features():
    """Names of every feature Marble knows (compiled in or not)."""
    return list(_marble.all_features())


def has_features(*names):
    """True if every named feature is compiled in.

    Accepts names or lists of names; an unknown name raises ValueError.
    """
    flat = []
    for n in names:
        if isinstance(n, (list, tuple, set)):
            flat.extend(n)
        else:
            flat.append(n)
    known = set(all_features())
    for n in flat:
        if n not in known:
            raise ValueError(f"unknown feature '{n}' (known: {', '.join(sorted(known))})")
    active = set(features())
    return all(n in active for n in flat)


def assert_features(*names):
    """Raise FeaturesError naming the first missing feature."""
    has_features(*names)  # validates the names
    active = set(features())
    for n in names if not (len(names) == 1 and isinstance(names[0], (list, tuple))) else names[0]:
        if n not in active:
            raise FeaturesError(f"missing feature {n}")
