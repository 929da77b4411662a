"""``espressomd.thermostat``: the same objects as :mod:`marble.thermostat`."""
from marble.thermostat import *  # noqa: F401,F403
