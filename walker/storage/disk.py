"""Files onto the disk: a file is built in memory (HDF5 core driver), the free space checked,
then it is written under a temporary name with plain ``os.write``, fsynced and renamed; a
full disk, a quota or a read-only file system is a StorageError; temporary files of writers
that are gone are removed.
"""

from __future__ import annotations

import errno
import numbers
import os
import secrets
import shutil
import time
from pathlib import Path
from typing import Any

import h5py

from walker.storage.checksums import _content_digest
from walker.storage.loader import _Loader
from walker.storage.schema import _CHECKSUM_ATTR, StorageError

_STALE_TEMP_AGE = 10.0  # seconds without modification before a dead writer's temp is removed
_DISK_ERRNOS = {
    errno.ENOSPC: "no space left on the device",
    errno.EDQUOT: "disk quota exceeded",
    errno.EROFS: "read-only file system",
    errno.EFBIG: "file too large for the file system or the process limit",
    errno.EIO: "input/output error",
}
_PERMANENT_ERRNOS = frozenset(_DISK_ERRNOS) - {errno.EIO} | {
    errno.EACCES,
    errno.EPERM,
    errno.ENOENT,
    errno.EBADF,
    errno.EISDIR,
    errno.ENOTDIR,
}


def _check_target(path: Any, overwrite: bool) -> Path:
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")
    if path.exists() and not overwrite:
        raise _exists(path)
    return path


def _exists(path: Path) -> FileExistsError:
    """The error of an existing target; its ``filename`` is the path, so that the command
    line can say which flag named it and how to replace it."""
    exc = FileExistsError(f"'{path}' exists; pass overwrite=True to replace it")
    exc.filename = os.fspath(path)
    return exc


def _disk_error(exc: OSError, path: Path, what: str) -> StorageError:
    """The StorageError of a disk error ``exc`` (ENOSPC, EDQUOT, EROFS, EFBIG, EIO)."""
    name = errno.errorcode.get(exc.errno or 0, str(exc.errno))
    return StorageError(f"{what} '{path}': {_DISK_ERRNOS[exc.errno]} ({name})")


def check_writable(path: str | os.PathLike, n_bytes: int = 0) -> None:
    """Check, before any work, that a file of about ``n_bytes`` can be created at ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        the file to be written; its directory must exist.
    n_bytes : int
        estimated size of the file [bytes].

    Raises
    ------
    FileNotFoundError
        the directory does not exist.
    StorageError
        the directory is on a read-only file system, or its file system has fewer than
        ``n_bytes`` (plus 64 KiB) bytes free.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> check_writable(pathlib.Path(tempfile.mkdtemp()) / "x.h5", 10_000)
    """
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    if isinstance(n_bytes, bool) or not isinstance(n_bytes, numbers.Integral) or n_bytes < 0:
        raise ValueError(f"`n_bytes` must be a non-negative int, got {n_bytes!r}")
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"directory '{parent}' of `path` '{path}' does not exist")
    _check_space(parent, int(n_bytes), path)


def _check_space(directory: Path, n_bytes: int, path: Path) -> None:
    try:
        flags = os.statvfs(directory).f_flag
    except (OSError, AttributeError):
        flags = 0
    if flags & getattr(os, "ST_RDONLY", 1):
        raise StorageError(f"cannot write '{path}': read-only file system (EROFS)")
    try:
        free = shutil.disk_usage(directory).free
    except OSError:
        return
    if free < n_bytes + (1 << 16):
        raise StorageError(
            f"cannot write '{path}': it needs about {n_bytes} bytes, only {free} are free on "
            "its file system (ENOSPC)"
        )


def _temp_name(path: Path) -> Path:
    return path.with_name(f".{path.name}.tmp-{os.getpid()}-{secrets.token_hex(4)}")


def _process_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: it exists, owned by someone else
        return True
    return True


def _remove_stale_temps(path: Path) -> list[Path]:
    """Remove ``.<name>.tmp-<pid>-<hex>`` files of ``path`` whose writing process is gone
    (and that were not modified for ``_STALE_TEMP_AGE`` seconds); returns them."""
    parent = path.parent if str(path.parent) else Path(".")
    prefix = f".{path.name}.tmp-"
    removed = []
    try:
        entries = list(os.scandir(parent))
    except OSError:
        return removed
    now = time.time()
    for entry in entries:
        if not entry.name.startswith(prefix):
            continue
        pid_text, _, token = entry.name[len(prefix) :].partition("-")
        if not (
            pid_text.isdigit() and len(token) == 8 and all(c in "0123456789abcdef" for c in token)
        ):
            continue
        pid = int(pid_text)
        if pid == os.getpid() or pid <= 0 or _process_alive(pid):
            continue
        try:
            if not entry.is_file(follow_symlinks=False):
                continue
            if now - entry.stat(follow_symlinks=False).st_mtime < _STALE_TEMP_AGE:
                continue
            os.unlink(entry.path)
        except OSError:
            continue
        removed.append(Path(entry.path))
    return removed


def _fsync_path(path: Path, directory: bool = False) -> None:
    flags = os.O_RDONLY | (getattr(os, "O_DIRECTORY", 0) if directory else 0)
    try:
        fd = os.open(path, flags)
    except OSError:
        if directory:  # some platforms cannot open directories; the data itself is synced
            return
        raise
    try:
        os.fsync(fd)
    except OSError:
        if not directory:
            raise
    finally:
        os.close(fd)


def _write_all(fd: int, data: Any, offset: int | None = None) -> None:
    """Write every byte of ``data`` to ``fd`` (at ``offset`` with pwrite, else at the current
    position); a short write is continued, an error raises OSError."""
    view = memoryview(data).cast("B")
    done = 0
    while done < len(view):
        if offset is None:
            n = os.write(fd, view[done:])
        else:
            n = os.pwrite(fd, view[done:], offset + done)
        if n <= 0:
            raise OSError(errno.EIO, "write returned no progress")
        done += n


def _build_image(fill: Any) -> tuple[bytes, dict]:
    """The bytes of a new file built by ``fill(h5file)`` in memory (HDF5 core driver, no
    backing store), with its ``checksum`` attribute; and the tree walker reads from it."""
    name = f"walker-{os.getpid()}-{secrets.token_hex(8)}.h5"
    # libver "earliest" keeps the oldest superblock, which has no "open for writing" flag.
    f = h5py.File(name, "w", driver="core", backing_store=False, libver="earliest")
    try:
        fill(f)
        f.flush()
        tree = _Loader(f, Path(name), None, None, raw=None, lazy=True).run()
        f.attrs[_CHECKSUM_ATTR] = _content_digest(tree)
        f.flush()
        image = f.id.get_file_image()
    finally:
        f.close()
    return image, tree


def _atomic_write(path: Path, image: bytes, overwrite: bool) -> Path:
    """Write ``image`` under a temporary name next to ``path``, fsync it and move it onto
    ``path`` (never replacing an existing file unless ``overwrite``)."""
    parent = path.parent if str(path.parent) else Path(".")
    _remove_stale_temps(path)
    _check_space(parent, len(image), path)
    tmp = _temp_name(path)
    fd = None
    try:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
        _write_all(fd, image)
        os.fsync(fd)
        os.close(fd)
        fd = None
        if overwrite:
            os.replace(tmp, path)
        else:
            # link() refuses an existing target atomically, unlike an exists() check.
            try:
                os.link(tmp, path)
            except FileExistsError:
                raise _exists(path) from None
            except OSError as exc:  # no hard links on this file system
                if exc.errno in _DISK_ERRNOS and exc.errno != errno.EIO:
                    raise
                if path.exists():
                    raise _exists(path) from None
                os.replace(tmp, path)
            else:
                os.unlink(tmp)
        _fsync_path(parent, directory=True)
    except BaseException as exc:
        if fd is not None:
            try:
                os.close(fd)
            except OSError:
                pass
        try:
            os.unlink(tmp)
        except OSError:
            pass
        if isinstance(exc, OSError) and exc.errno in _DISK_ERRNOS:
            raise _disk_error(exc, path, "cannot write") from None
        raise
    return path


def write_file(path: str | os.PathLike, data: bytes, *, overwrite: bool = True) -> Path:
    """Write the bytes ``data`` to ``path`` as :func:`walker.storage.write` writes a result:
    under a temporary name in the same directory, fsynced, then renamed onto ``path``.

    The rename replaces whatever is at ``path`` (with ``overwrite``), a symbolic link
    included: the link itself is replaced, its target is never written.  On any failure
    (a full disk, a read-only or missing directory) neither ``path`` nor a temporary file
    is left, and the error is a one-line :class:`StorageError` naming ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        the file to write (a figure, an animation); its directory must exist.
    data : bytes
        the whole content.
    overwrite : bool
        replace an existing ``path``; else an existing one raises ``FileExistsError``.

    Returns
    -------
    Path

    Examples
    --------
    >>> import tempfile, pathlib
    >>> p = write_file(pathlib.Path(tempfile.mkdtemp()) / "a.txt", b"walker")
    >>> p.read_bytes()
    b'walker'
    """
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    path = Path(path)
    try:
        return _atomic_write(path, memoryview(data), overwrite)
    except (StorageError, FileExistsError):
        raise
    except OSError as exc:
        reason = exc.strerror or _first_line_of(exc)
        raise StorageError(f"cannot write '{path}': {reason}") from None


def _first_line_of(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _atomic_create(path: Path, fill: Any, overwrite: bool) -> Path:
    """Build the file with ``fill(h5file)`` in memory, then write it onto ``path``."""
    image, _ = _build_image(fill)
    return _atomic_write(path, image, overwrite)


def _ram_bytes() -> int:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not on Linux
        return 16 << 30
