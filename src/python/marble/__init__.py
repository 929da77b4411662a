"""Marble: mesoscale colloids in a DPD solvent, with an espressomd-shaped API.

    import marble
    system = marble.System(box_l=[10, 10, 10])
"""
from ._marble import FeaturesError, mpi_rank, mpi_size, build_options  # noqa: F401  (SPMD: rank of this process, number of ranks)
from .code_features import features, has_features, all_features, assert_features
from .system import System
from . import shapes, colloids  # noqa: F401  (marble.shapes.Wall, marble.colloids.add_marble)
from . import io, checkpointing  # noqa: F401  (marble.io.H5md, marble.checkpointing.Checkpoint)

__version__ = "0.1.0"
__all__ = ["System", "FeaturesError", "features", "has_features", "all_features",
           "assert_features"]
