"""``espressomd.io``: the same objects as :mod:`marble.io`."""
from marble.io import *  # noqa: F401,F403
