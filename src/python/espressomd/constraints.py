"""``espressomd.constraints``: the same objects as :mod:`marble.constraints`."""
from marble.constraints import *  # noqa: F401,F403
