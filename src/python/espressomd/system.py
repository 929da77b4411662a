"""``espressomd.system``: the same objects as :mod:`marble.system`."""
from marble.system import *  # noqa: F401,F403
