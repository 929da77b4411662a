"""``espressomd.cell_system``: the same objects as :mod:`marble.cell_system`."""
from marble.cell_system import *  # noqa: F401,F403
