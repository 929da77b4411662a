"""``espressomd.particle_data``: the same objects as :mod:`marble.particle_data`."""
from marble.particle_data import *  # noqa: F401,F403
