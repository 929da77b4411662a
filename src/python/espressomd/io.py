"""``espressomd.io``: the same objects as :mod:`marble.io`, plus ESPResSo's
module path ``espressomd.io.writer.h5md`` for :class:`marble.io.H5md`
(``from espressomd.io.writer import h5md; h5md.H5md(file_path=...)``)."""
import sys
import types

from marble.io import *  # noqa: F401,F403
from marble.io import H5md as _H5md

writer = types.ModuleType("espressomd.io.writer", "ESPResSo's writer package: h5md")
h5md = types.ModuleType("espressomd.io.writer.h5md", "H5MD writer (marble.io.H5md)")
h5md.H5md = _H5md
writer.h5md = h5md
sys.modules.setdefault("espressomd.io.writer", writer)
sys.modules.setdefault("espressomd.io.writer.h5md", h5md)
