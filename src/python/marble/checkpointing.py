"""Checkpoint and restart (doc/io.md), shaped like ``espressomd.checkpointing``:

    import marble.checkpointing
    cp = marble.checkpointing.Checkpoint(checkpoint_id="run1", checkpoint_path=".")
    cp.register("system")        # names in the script's __main__ namespace
    cp.register("corr")
    ...
    cp.save()                    # run1/0.checkpoint, run1/1.checkpoint, ...

and in a new process:

    cp = marble.checkpointing.Checkpoint(checkpoint_id="run1", checkpoint_path=".")
    cp.load()                    # restores `system` and `corr` into __main__
    system.integrator.run(n)     # continues bit for bit

A checkpoint file is ``MARBLE-CHECKPOINT\\n`` | format version (u32) | payload
size (u64) | CRC-32 of the payload (u32) | payload (a pickle of the registered
objects; a marble.System pickles as its core's own validated blob). The file is
checked completely before anything is unpickled, and nothing in the namespace
changes unless the whole load succeeds. Writes are atomic: a temporary file in
the same directory, flushed and fsync'ed, then renamed over the final name.
In an MPI run every rank calls save/load (SPMD); rank 0 writes the file.
"""
import os
import pickle
import re
import struct
import sys
import tempfile

from . import _marble

_MAGIC = b"MARBLE-CHECKPOINT\n"
_VERSION = 1
_HEADER = struct.Struct("<IQI")  # format version, payload size, CRC-32 of the payload
_FILE_RE = re.compile(r"^(\d+)\.checkpoint$")
_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


class CheckpointError(RuntimeError):
    """A checkpoint file is missing, truncated, corrupt or from another build."""


def _write_all(f, data):
    """Write ``data`` to the open file ``f`` (a hook for tests of atomicity)."""
    f.write(data)


def _atomic_write(path, data):
    """Write ``data`` to ``path`` atomically: temp file in the same directory,
    flush + fsync, os.replace; on any error the temp file is removed and an
    existing ``path`` is left as it was."""
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                               dir=directory)
    try:
        umask = os.umask(0)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # mkstemp creates 0600; use the usual permissions
        with os.fdopen(fd, "wb") as f:
            _write_all(f, data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
    try:  # make the rename itself durable (best effort)
        dfd = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(dfd)
        finally:
            os.close(dfd)
    except OSError:
        pass


def _pack(payload):
    crc = _marble.crc32(payload, 0)
    return _MAGIC + _HEADER.pack(_VERSION, len(payload), crc) + payload


def _unpack(data, path):
    """The payload of a checkpoint file, after checking magic, version, size and CRC."""
    def bad(why):
        raise CheckpointError(f"'{path}' is not a valid Marble checkpoint: {why}")
    if not data.startswith(_MAGIC):
        bad("bad magic (not a Marble checkpoint file)" if len(data) >= len(_MAGIC)
            else f"only {len(data)} bytes (truncated)")
    head = data[len(_MAGIC):len(_MAGIC) + _HEADER.size]
    if len(head) < _HEADER.size:
        bad("the header is truncated")
    version, size, crc = _HEADER.unpack(head)
    if version != _VERSION:
        bad(f"format version {version}, this build reads version {_VERSION}")
    payload = data[len(_MAGIC) + _HEADER.size:]
    if len(payload) != size:
        bad(f"the header announces {size} bytes of data, the file has {len(payload)} "
            "(truncated or corrupt)")
    if _marble.crc32(payload, 0) != crc:
        bad("checksum mismatch (the file is corrupt)")
    return payload


def _systems_of(objects):
    """marble.System objects the registered objects belong to (pickled first,
    so that everything referring to a System finds it already built)."""
    from .system import System
    out = []

    def add(s):
        if isinstance(s, System) and all(s is not o for o in out):
            out.append(s)
    for obj in objects:
        add(obj)
        for attr in ("_system", "_obs_py"):
            sub = getattr(obj, attr, None)
            if callable(sub) and attr == "_system":
                sub = sub()
            add(sub)
            add(getattr(sub, "_system", None))
    return out


class Checkpoint:
    """Checkpoints of objects named in the script's namespace.

    Parameters
    ----------
    checkpoint_id : str
        Name of the run; the files go to ``checkpoint_path/checkpoint_id/<index>.checkpoint``.
    checkpoint_path : str or os.PathLike (default ".")
    namespace : dict, optional
        Where registered names are looked up and restored (default: the
        ``__main__`` module's namespace, i.e. the script's globals).
    """

    def __init__(self, checkpoint_id=None, checkpoint_path=".", namespace=None):
        if not isinstance(checkpoint_id, str) or not checkpoint_id or \
                checkpoint_id in (".", "..") or "/" in checkpoint_id or os.sep in checkpoint_id:
            raise ValueError("parameter 'checkpoint_id' must be a non-empty name without path "
                             f"separators, got {checkpoint_id!r}")
        if not isinstance(checkpoint_path, (str, os.PathLike)):
            raise ValueError("parameter 'checkpoint_path' must be a str or path")
        if namespace is not None and not isinstance(namespace, dict):
            raise ValueError("parameter 'namespace' must be a dict (e.g. globals())")
        self.checkpoint_id = checkpoint_id
        self.checkpoint_dir = os.path.join(os.fspath(checkpoint_path), checkpoint_id)
        self._namespace = namespace
        self._registered = []
        err = ""
        if _marble.mpi_rank() == 0:
            try:
                os.makedirs(self.checkpoint_dir, exist_ok=True)
            except OSError as e:
                err = f"cannot create the checkpoint directory '{self.checkpoint_dir}': {e}"
        _marble.comm_throw_if_any(err)

    def _ns(self):
        return self._namespace if self._namespace is not None else sys.modules["__main__"].__dict__

    # --- registration -----------------------------------------------------
    def register(self, *names):
        """Register objects by their names in the namespace (e.g. "system")."""
        for name in names:
            if not isinstance(name, str) or not _NAME_RE.match(name):
                raise ValueError(f"register() takes variable names (identifiers), got {name!r}")
            if name not in self._registered:
                self._registered.append(name)

    def unregister(self, *names):
        """Stop saving the named objects."""
        for name in names:
            if name not in self._registered:
                raise ValueError(f"'{name}' is not registered")
            self._registered.remove(name)

    def get_registered_objects(self):
        """Registered names, in registration order."""
        return list(self._registered)

    # --- files ------------------------------------------------------------
    def _indices(self):
        try:
            names = os.listdir(self.checkpoint_dir)
        except FileNotFoundError:
            return []
        return sorted(int(m.group(1)) for m in map(_FILE_RE.match, names) if m)

    def _path(self, index):
        return os.path.join(self.checkpoint_dir, f"{index}.checkpoint")

    def has_checkpoints(self):
        """True if this checkpoint_id has at least one checkpoint file."""
        return bool(self._indices())

    def get_last_checkpoint_index(self):
        """Largest index saved so far (CheckpointError if there is none)."""
        idx = self._indices()
        if not idx:
            raise CheckpointError(f"no checkpoints in '{self.checkpoint_dir}'")
        return idx[-1]

    def _check_index(self, checkpoint_index):
        if checkpoint_index is None:
            return None
        if isinstance(checkpoint_index, bool) or not isinstance(checkpoint_index, int) \
                or checkpoint_index < 0:
            raise ValueError("parameter 'checkpoint_index' must be an integer >= 0, got "
                             f"{checkpoint_index!r}")
        return checkpoint_index

    # --- save / load ------------------------------------------------------
    def save(self, checkpoint_index=None):
        """Save every registered object to ``<index>.checkpoint`` (default
        index: last + 1, or 0). Collective in an MPI run; rank 0 writes.
        Returns the index."""
        index = self._check_index(checkpoint_index)
        ns = self._ns()
        missing = [n for n in self._registered if n not in ns]
        if missing:
            raise ValueError(f"registered name(s) {missing} do not exist in the namespace")
        if not self._registered:
            raise ValueError("nothing is registered: call register('system', ...) first")
        if index is None:
            idx = self._indices()
            index = idx[-1] + 1 if idx else 0
        _marble.comm_barrier()  # every rank chose the index before rank 0 writes
        objects = {n: ns[n] for n in self._registered}
        payload = pickle.dumps({"systems": _systems_of(objects.values()), "objects": objects},
                               protocol=pickle.HIGHEST_PROTOCOL)
        err = ""
        if _marble.mpi_rank() == 0:
            try:
                _atomic_write(self._path(index), _pack(payload))
            except Exception as e:  # noqa: BLE001 (reported on every rank below)
                err = f"writing checkpoint '{self._path(index)}' failed: {type(e).__name__}: {e}"
        _marble.comm_throw_if_any(err)
        return index

    def load(self, checkpoint_index=None):
        """Restore the objects saved in ``<index>.checkpoint`` (default: the
        last one) into the namespace under their registered names (which are
        registered here too). The file is validated completely first; on any
        error (CheckpointError, a RuntimeError) the namespace is unchanged.
        Collective in an MPI run. On the number of ranks of the save the
        continuation is bit-exact; on another number the particles are
        redistributed to the new domains and it agrees to round-off."""
        index = self._check_index(checkpoint_index)
        if index is None:
            index = self.get_last_checkpoint_index()
        path = self._path(index)
        err = ""
        payload = None
        try:
            with open(path, "rb") as f:
                payload = _unpack(f.read(), path)
        except OSError as e:
            err = f"cannot read checkpoint '{path}': {e}"
        except CheckpointError as e:
            err = str(e)
        try:
            _marble.comm_throw_if_any(err)
        except RuntimeError as e:
            raise CheckpointError(str(e)) from None
        try:
            data = pickle.loads(payload)
        except RuntimeError as e:
            raise CheckpointError(f"'{path}': {e}") from None
        except Exception as e:  # noqa: BLE001
            raise CheckpointError(f"'{path}' could not be unpickled: {type(e).__name__}: {e}") \
                from None
        objects = data["objects"]
        self._ns().update(objects)
        for name in objects:
            if name not in self._registered:
                self._registered.append(name)
        return objects
