"""Skip tests whose features are not compiled into this build."""
import unittest

import marble
from marble.code_features import ESPRESSO_ALIASES


def skipIfMissingFeatures(*args):
    """Decorator: skip unless every named feature is compiled in. A name Marble
    does not know raises ValueError (a typo must not silently skip a test;
    ``marble.has_features`` itself answers False for it, as ESPResSo does)."""
    names = list(args[0]) if len(args) == 1 and isinstance(args[0], (list, tuple)) else list(args)
    known = set(marble.all_features()) | set(ESPRESSO_ALIASES)
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ValueError(f"unknown feature(s) {', '.join(map(str, unknown))} "
                         f"(known: {', '.join(sorted(known))})")
    missing = marble.missing_features(names)
    if missing:
        return unittest.skip(f"Skipping test: missing feature(s) {', '.join(missing)}")
    return lambda x: x
