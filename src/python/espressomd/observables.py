"""``espressomd.observables``: the same objects as :mod:`marble.observables`."""
from marble.observables import *  # noqa: F401,F403
