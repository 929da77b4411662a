"""``espressomd.integrate``: the same objects as :mod:`marble.integrate`."""
from marble.integrate import *  # noqa: F401,F403
