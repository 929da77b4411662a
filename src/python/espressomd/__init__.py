"""ESPResSo compatibility package: ``import espressomd`` runs on Marble.

A script written for ESPResSo 4.2 ports by keeping its imports: this package
maps the ``espressomd`` module names onto Marble's (``espressomd.interactions``
is ``marble.interactions``, ...) and answers feature questions with ESPResSo's
feature names (``EXTERNAL_FORCES``; a feature Marble does not have answers
False). The physics lives in :mod:`marble`; what differs is listed in
doc/porting-from-espresso.md.

    import espressomd
    system = espressomd.System(box_l=[10, 10, 10])
"""
from marble import System, FeaturesError  # noqa: F401
from marble import __version__  # noqa: F401

from .code_features import features, all_features, has_features, missing_features, \
    assert_features  # noqa: F401
from . import code_features  # noqa: F401

__all__ = ["System", "FeaturesError", "features", "all_features", "has_features",
           "missing_features", "assert_features", "code_features"]
