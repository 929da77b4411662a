"""``espressomd.checkpointing``: the same objects as :mod:`marble.checkpointing`."""
from marble.checkpointing import *  # noqa: F401,F403
