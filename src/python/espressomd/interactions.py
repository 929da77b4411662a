"""``espressomd.interactions``: the same objects as :mod:`marble.interactions`."""
from marble.interactions import *  # noqa: F401,F403
