"""``espressomd.shapes``: the same objects as :mod:`marble.shapes`."""
from marble.shapes import *  # noqa: F401,F403
