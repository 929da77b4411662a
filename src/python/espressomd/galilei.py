"""``espressomd.galilei``: the same objects as :mod:`marble.galilei`."""
from marble.galilei import *  # noqa: F401,F403
