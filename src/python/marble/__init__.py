"""Marble: mesoscale colloids in a DPD solvent, with an espressomd-shaped API.

    import marble
    system = marble.System(box_l=[10, 10, 10])
"""
from ._marble import FeaturesError, mpi_rank, mpi_size, build_options  # noqa: F401  (SPMD: rank of this process, number of ranks)
from .code_features import features, has_features, missing_features, all_features, assert_features
from .system import System
from . import shapes, colloids, suspensions  # noqa: F401  (marble.shapes.Wall, marble.colloids.add_marble, marble.suspensions)
from . import lees_edwards  # noqa: F401  (marble.lees_edwards.LinearShear, ...)
from . import io, checkpointing  # noqa: F401  (marble.io.H5md, marble.checkpointing.Checkpoint)
from . import srd  # noqa: F401,E402  (marble.srd.SRDFluid)  # SRD

__version__ = "0.1.0"
__all__ = ["System", "FeaturesError", "features", "has_features", "missing_features",
           "all_features", "assert_features"]


def _abort_all_ranks_on_uncaught_exception():
    """Under MPI (more than one rank) an uncaught exception on one rank would
    leave the others waiting in a collective call forever (and MPI_Finalize at
    exit would wait for them): print the traceback, then MPI_Abort every rank.
    Errors raised by marble itself are collective (every rank raises them), so
    scripts that catch them keep running on all ranks."""
    import sys
    previous = sys.excepthook

    def hook(exc_type, exc, tb):
        previous(exc_type, exc, tb)
        sys.stderr.flush()
        sys.stdout.flush()
        _marble.mpi_abort(1)

    sys.excepthook = hook


from . import _marble  # noqa: E402
if mpi_size() > 1:
    _abort_all_ranks_on_uncaught_exception()
