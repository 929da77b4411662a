"""``espressomd.analysis``: the same objects as :mod:`marble.analysis`."""
from marble.analysis import *  # noqa: F401,F403
