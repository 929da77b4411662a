"""Trajectory output in H5MD (doc/io.md), shaped like ``espressomd.io.writer.h5md``::

    import marble.io
    h5 = marble.io.H5md(file_path="traj.h5", system=system, fields="all")
    for i in range(10):
        system.integrator.run(100)
        h5.write()
    h5.close()

The file follows the H5MD 1.1 layout (``/h5md``, ``/particles/atoms/...``,
positions folded into the box with their image counts) and is readable by
h5py and by MDAnalysis (``u = MDAnalysis.Universe.empty(n_atoms, trajectory=True);
u.load_new("traj.h5", format="H5MD", convert_units=False)``). Every call is
collective in an MPI run (every rank runs the script).
"""
import atexit
import getpass
import os
import weakref

from . import _marble
from ._marble import FeaturesError
from .observables import _resolve_system

FIELDS = ("position", "image", "velocity", "force", "species", "mass", "id", "box", "time", "step")

_open_files = weakref.WeakSet()


def have_hdf5():
    """True if this build writes H5MD (built with MARBLE_WITH_HDF5)."""
    return bool(_marble.have_hdf5())


def _close_all():
    # at interpreter exit, before MPI is finalised (atexit runs this first:
    # it was registered after marble._marble's MPI finalisation)
    for f in list(_open_files):
        try:
            f.close()
        except Exception:  # noqa: BLE001
            pass


atexit.register(_close_all)


class H5md:
    """H5MD trajectory writer bound to one System.

    Parameters
    ----------
    file_path : str or os.PathLike
        File to create; an existing file is replaced.
    system : marble.System, optional
        The System whose frames ``write()`` stores (default: the most recently
        created System, as for observables).
    fields : "all" or list of str
        Subset of position, image, velocity, force, species, mass, id, box,
        time, step, srd. ``step`` is always written (H5MD requires it).
        ``srd``: the particles of an SRD solvent (``system.srd``, feature SRD)
        in their own group ``/particles/srd`` (position, velocity, species,
        id: those of them listed; rows by increasing SRD id; box, step and
        time shared with ``/particles/atoms``), if the fluid has particles
        when the first frame is written.
    author : str, optional
        ``h5md/author`` name (default: the user name).
    mode : "w" or "append"
        ``"w"`` (default) creates the file, replacing an existing one;
        ``"append"`` continues the time series of an existing file written by
        Marble with the same ``fields`` (``n_frames`` starts at the file's
        frame count; the number of particles stays the file's), or creates a
        missing file.

    Raises ``marble.FeaturesError`` in a build without HDF5, ``ValueError``
    for bad parameters, ``RuntimeError`` if the file cannot be created.
    """

    _allowed = ("file_path", "system", "fields", "author", "mode")

    def __init__(self, **kwargs):
        unknown = set(kwargs) - set(self._allowed)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)} for H5md "
                             f"(allowed: {', '.join(self._allowed)})")
        if not have_hdf5():
            raise FeaturesError("missing feature H5MD (build with MARBLE_WITH_HDF5=ON and "
                                "libhdf5-openmpi-dev installed)")
        path = kwargs.get("file_path")
        if path is None:
            raise ValueError("parameter 'file_path' is required")
        if not isinstance(path, (str, os.PathLike)) or not os.fspath(path):
            raise ValueError("parameter 'file_path' must be a non-empty str or path")
        path = os.fspath(path)
        if isinstance(path, bytes):
            raise ValueError("parameter 'file_path' must be a str path")
        self._system = _resolve_system(kwargs.get("system"))
        fields = kwargs.get("fields", "all")
        author = kwargs.get("author")
        if author is None:
            try:
                author = getpass.getuser()
            except Exception:  # noqa: BLE001
                author = "unknown"
        if not isinstance(author, str):
            raise ValueError("parameter 'author' must be a str")
        mode = kwargs.get("mode", "w")
        if mode not in ("w", "append"):
            raise ValueError(f"parameter 'mode' must be 'w' (create or replace) or 'append', "
                             f"got {mode!r}")
        self._fields = fields
        self._mode = mode
        self._file = _marble.H5mdFile(self._system._core, path, fields, author, mode)
        _open_files.add(self)

    @property
    def file_path(self):
        """Path of the H5MD file."""
        return self._file.file_path

    @property
    def fields(self):
        """The fields as given ("all" or a list)."""
        return self._fields

    @property
    def mode(self):
        return self._mode

    @property
    def system(self):
        """The System written."""
        return self._system

    @property
    def n_frames(self):
        """Frames written so far."""
        return self._file.n_frames

    @property
    def is_open(self):
        """True until ``close()``."""
        return self._file.is_open

    def write(self):
        """Append the System's current state as one frame. The number of
        particles is fixed by the first frame (RuntimeError if it changed)."""
        self._file.write(self._system._core)

    def flush(self):
        """Write buffered data to disk (the file stays open)."""
        self._file.flush()

    def close(self):
        """Close the file (idempotent); later ``write()`` raises RuntimeError."""
        self._file.close()
        _open_files.discard(self)

    def __reduce__(self):
        raise TypeError("an H5md file cannot be pickled or checkpointed: open a new file "
                        "(a new file_path) after loading a checkpoint")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        state = "open" if self.is_open else "closed"
        return f"H5md(file_path={self.file_path!r}, {state}, n_frames={self.n_frames})"
