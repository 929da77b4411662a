"""Skip tests whose features are not compiled into this build."""
import unittest

import marble


def skipIfMissingFeatures(*args):
    """Decorator: skip unless every named feature is compiled in."""
    if not marble.has_features(*args):
        missing = [f for f in (args[0] if len(args) == 1 and isinstance(args[0], (list, tuple))
                               else args) if not marble.has_features(f)]
        return unittest.skip(f"Skipping test: missing feature(s) {', '.join(missing)}")
    return lambda x: x
