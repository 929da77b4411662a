"""``espressomd.accumulators``: the same objects as :mod:`marble.accumulators`."""
from marble.accumulators import *  # noqa: F401,F403
