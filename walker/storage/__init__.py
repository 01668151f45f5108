"""HDF5 storage of results with provenance: atomic writes, checked reads, sweep checkpoints.

One file holds one result (one *kind*); :func:`write` stores it and :func:`read` gives back an
equal dataclass and the provenance.  The layout is described in ``docs/storage.md``
(schema version :data:`SCHEMA_VERSION`; files of version 1 are still read and resumed).

Rules this package keeps:

1. ``read(write(path, x, provenance=p)) == (x, p + automatic keys)`` field by field: arrays
   with their dtype and shape (empty arrays too), ``None`` fields, tuples of names,
   :class:`~walker.status.Status` members, dicts of parameters.
2. :func:`write` is atomic and survives the disk: the whole file is built in memory, the free
   space is checked, then it is written under a temporary name in the target directory
   (``.<name>.tmp-<pid>-<random>``) with plain ``os.write`` calls, fsynced and moved onto the
   target with one rename.  A failure at any point leaves no target and no temporary file; a
   full disk, a quota or a read-only file system is a :class:`StorageError` (one line).
   Temporary files of the same target whose writing process is gone are removed.  An
   existing target is never replaced unless ``overwrite=True``.
3. Invalid input raises before any file is touched (``TypeError``/``ValueError`` naming the
   field and the rule; ``FileNotFoundError`` for a missing directory; ``FileExistsError``).
4. Every stored number is checked: each non-empty dataset carries the HDF5 Fletcher-32
   checksum, the root attribute ``checksum`` is a SHA-256 of everything the file holds
   (attributes, names, dtypes, shapes, data), and each chunk of a checkpoint carries the
   SHA-256 of its rows.  Reading verifies all of them.
5. Reading trusts nothing: a file that is missing, not HDF5, truncated, corrupted, from a
   newer schema, of an unknown kind, that uses an HDF5 feature walker never writes (external
   storage or links, soft links, virtual datasets, foreign filters), declares more data than
   it can hold, or whose fields have the wrong types or shapes raises :class:`StorageError`
   (a ``ValueError``) with a one-line message naming the file and the object.  By default
   :func:`read` opens the file in a child process with a time and memory budget, so that a
   crash or a hang of the HDF5 library on a damaged file is a :class:`StorageError` too.
6. :class:`SweepStore` checkpoints a parameter sweep chunk by chunk, and :class:`BasinStore`
   a basin map rows by rows; see SweepStore's docstring for the guarantee both give when the
   process is killed (SIGKILL) or interrupted, and when a reader opens the file meanwhile.

Complex arrays (Floquet multipliers, eigenvectors) are stored as complex128 (or complex64)
datasets, which h5py writes as an HDF5 compound type with float members ``r`` and ``i``.

The package, by layer (each module imports only those above it):

==================  ==========================================================================
``schema``          version, limits, errors, the codec of every result field, shape rules
``provenance``      provenance builders, the JSON form of provenance values and its checks
``checksums``       Fletcher-32, the root ``checksum`` and the chunk SHA-256
``blocks``          a dataset checked but not yet read, and the blocks a streaming load
                    reads it in (the isolated reader's child)
``loader``          an open HDF5 file into a plain, checked tree (every HDF5 call of a read)
``disk``            atomic writing of a file built in memory (:func:`write_file` for any bytes:
                    figures, animations), free-space and disk-error checks
``encode``          dataclass -> tree -> HDF5 group, root attributes, :func:`write`
``isolated``        the load in a child process with a time and memory budget
``decode``          tree -> dataclass with types, shapes and checksums checked, :func:`read`
``checkpoint``      the stores' chunks, writes with ``os.pwrite``, chunk states, ``/checkpoint``
``sweep_store``     :class:`SweepStore`
``basin_store``     :class:`BasinStore`
``stream``          :class:`~walker.storage.stream.SolutionStream`: a long run, block by block
==================  ==========================================================================

Everything public is imported from ``walker.storage`` itself.

Examples
--------
>>> import tempfile, pathlib
>>> import numpy as np
>>> from walker.results import OrbitDiagram
>>> from walker.storage import read, write
>>> d = OrbitDiagram("slope", np.array([0.01, 0.02]), np.array([[0.2, 0.2], [0.3, 0.1]]))
>>> prov = {"model": "simplest", "method": "dop853", "rtol": 1e-10, "atol": 1e-12,
...         "parameters": {"slope": {"value": 0.01, "unit": "rad"}}}
>>> path = pathlib.Path(tempfile.mkdtemp()) / "orbit.h5"
>>> _ = write(path, d, provenance=prov)
>>> d2, p2 = read(path)
>>> bool(np.array_equal(d2.values, d.values)), p2["kind"], p2["rtol"]
(True, 'orbit_diagram', 1e-10)
"""

from __future__ import annotations

from walker.storage.basin_store import BASIN_DEFAULT_CHUNKS as BASIN_DEFAULT_CHUNKS
from walker.storage.basin_store import BasinStore
from walker.storage.checkpoint import checkpoint_progress
from walker.storage.checksums import _fletcher32 as _fletcher32
from walker.storage.decode import read
from walker.storage.disk import _write_all as _write_all
from walker.storage.disk import check_writable, write_file
from walker.storage.encode import _emit as _emit
from walker.storage.encode import _encode as _encode
from walker.storage.encode import _provenance_attrs as _provenance_attrs
from walker.storage.encode import write
from walker.storage.isolated import _can_fork as _can_fork
from walker.storage.isolated import _isolated_main as _isolated_main
from walker.storage.isolated import _load_here as _load_here
from walker.storage.loader import _fill_value as _fill_value
from walker.storage.provenance import _check_provenance as _check_provenance
from walker.storage.provenance import (
    parameters_with_units,
    scene_provenance,
    solver_provenance,
    walker_version,
)
from walker.storage.schema import _KIND_OF as _KIND_OF
from walker.storage.schema import AUTOMATIC_KEYS as AUTOMATIC_KEYS
from walker.storage.schema import (
    BASIN_NOT_COMPUTED,
    KINDS,
    MAX_COMPRESSION_RATIO,
    MAX_DECOMPRESSED_BYTES,
    MAX_PERIOD,
    READ_TIMEOUT,
    SCHEMA_VERSION,
    WRITE_ATTEMPTS,
    CheckpointMismatch,
    StorageError,
)
from walker.storage.sweep_store import SweepStore

__all__ = [
    "BASIN_NOT_COMPUTED",
    "KINDS",
    "MAX_COMPRESSION_RATIO",
    "MAX_DECOMPRESSED_BYTES",
    "MAX_PERIOD",
    "READ_TIMEOUT",
    "SCHEMA_VERSION",
    "WRITE_ATTEMPTS",
    "BasinStore",
    "CheckpointMismatch",
    "StorageError",
    "SweepStore",
    "check_writable",
    "checkpoint_progress",
    "parameters_with_units",
    "read",
    "scene_provenance",
    "solver_provenance",
    "walker_version",
    "write",
    "write_file",
]
