"""Skip tests whose features are not compiled into this build.

One module for Marble's tests (``from unittest_decorators import
skipIfMissingFeatures``) and the ESPResSo-style compatibility tests
(``import unittest_decorators as utx``; testsuite/espresso_compat gets it on
its PYTHONPATH), so one pytest call may collect both directories. Feature
names may be Marble's or ESPResSo 4.2's spellings."""
import unittest

from espressomd import code_features as _espresso_features


def skipIfMissingFeatures(*args):
    """Decorator: skip unless every named feature is compiled in. A name neither
    Marble nor ESPResSo knows raises ValueError (a typo must not silently skip
    a test; ``has_features`` itself answers False for it, as ESPResSo does)."""
    names = list(args[0]) if len(args) == 1 and isinstance(args[0], (list, tuple)) else list(args)
    import marble
    known = (set(marble.all_features()) | set(_espresso_features.all_features())
             | set(_espresso_features.ESPRESSO_TO_MARBLE))
    unknown = [n for n in names if n not in known]
    if unknown:
        raise ValueError(f"unknown feature(s) {', '.join(map(str, unknown))} "
                         f"(known: {', '.join(sorted(known))})")
    missing = _espresso_features.missing_features(names)
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
