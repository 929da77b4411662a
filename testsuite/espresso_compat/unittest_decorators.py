"""ESPResSo-style test decorators (``import unittest_decorators as utx``),
written for Marble's compatibility tests."""
import unittest

import espressomd


def _names(args):
    if len(args) == 1 and isinstance(args[0], (list, tuple)):
        return list(args[0])
    return list(args)


def skipIfMissingFeatures(*args):
    """Skip the test (class or method) unless every named feature is compiled in."""
    missing = espressomd.missing_features(_names(args))
    if missing:
        return unittest.skip(f"Skipping test: missing feature(s) {', '.join(missing)}")
    return lambda x: x


def skipIfUnmetModuleVersionRequirement(module_name, version_requirement):
    """Skip unless ``module_name`` imports (the version is not checked)."""
    try:
        __import__(module_name)
    except ImportError:
        return unittest.skip(f"Skipping test: module {module_name} not available")
    return lambda x: x
