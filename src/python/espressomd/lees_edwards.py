"""``espressomd.lees_edwards``: the same objects as :mod:`marble.lees_edwards`."""
from marble.lees_edwards import *  # noqa: F401,F403
