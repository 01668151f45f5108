"""The load in a child process (forked while this process runs one thread, else a new
interpreter) with a time and memory budget, so that a crash or a hang of the HDF5 library
on a damaged file is a StorageError; the tree comes back as JSON plus raw array bytes.
"""

from __future__ import annotations

import json
import math
import os
import select
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from walker.storage.disk import _ram_bytes, _write_all
from walker.storage.loader import _first_line, _Loader, _Opaque
from walker.storage.schema import READ_TIMEOUT, StorageError, _Corrupt


def _check_path(path: Any) -> Path:
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    path = Path(path)
    if not path.exists():
        raise StorageError(f"cannot read '{path}': no such file")
    if not path.is_file():
        raise StorageError(f"cannot read '{path}': not a regular file")
    return path


def _default_budget(file_size: int) -> int:
    """Memory a read may use [bytes]: 4x the file (at least 2 GiB), at most 80% of RAM."""
    return int(min(max(2 << 30, 4 * file_size), 0.8 * _ram_bytes()))


def _load_here(path: Path, file_size: int, budget: int) -> dict:
    """Open and load ``path`` in this process (StorageError on any problem)."""
    try:
        try:
            # No lock: the writer of a checkpoint takes none either (it uses os.pwrite).
            f = h5py.File(path, "r", locking=False)
        except OSError as exc:
            if "locking" not in str(exc):
                raise
            # This process has the file open already, with HDF5's lock: share that.
            f = h5py.File(path, "r")
    except Exception as exc:  # noqa: BLE001 - any failure to open is a bad file
        raise StorageError(
            f"cannot read '{path}': not an HDF5 file, or truncated/corrupted ({_first_line(exc)})"
        ) from None
    fd = None
    try:
        with f:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
            raw = lambda offset, size: os.pread(fd, size, offset)  # noqa: E731
            return _Loader(f, path, file_size, budget, raw).run()
    except StorageError:
        raise
    except MemoryError:
        raise StorageError(
            f"cannot read '{path}': reading it needs more memory than is available"
        ) from None
    except RecursionError:
        raise StorageError(f"cannot read '{path}': corrupted (nested too deeply)") from None
    except Exception as exc:  # noqa: BLE001 - h5py raises many types on damaged files
        reason = _first_line(exc)
        if not isinstance(exc, _Corrupt):
            reason = f"{type(exc).__name__}: {reason}"
        raise StorageError(f"cannot read '{path}': corrupted or incomplete ({reason})") from None
    finally:
        if fd is not None:
            os.close(fd)


def _pack(tree: dict) -> list[Any]:
    """The tree as bytes a parent can read back without unpickling: a JSON header (arrays
    as references) and the arrays' raw bytes."""
    blobs: list[np.ndarray] = []

    def encode(value: Any) -> Any:
        if isinstance(value, dict):
            return {str(k): encode(v) for k, v in value.items()}
        if isinstance(value, np.ndarray):
            arr = value if value.flags.c_contiguous else value.copy(order="C")
            blobs.append(arr)
            return {"__a": [arr.dtype.str, list(arr.shape)]}
        if isinstance(value, _Opaque):
            return {"__o": value.what}
        if value is None or isinstance(value, str | int | float):
            return value
        raise TypeError(f"cannot pack {type(value).__name__}")

    header = json.dumps(encode(tree)).encode("ascii")
    views = [memoryview(a.reshape(-1).view(np.uint8)) for a in blobs]
    return [len(header).to_bytes(8, "little"), header, *views]


def _unpack(buf: memoryview) -> dict:
    """Inverse of :func:`_pack` (``buf`` a writable buffer the arrays then share); every
    dtype and shape is checked before use."""
    n = int.from_bytes(buf[:8], "little")
    header = json.loads(bytes(buf[8 : 8 + n]).decode("ascii"))
    pos = 8 + n

    def decode(value: Any) -> Any:
        nonlocal pos
        if isinstance(value, dict):
            if set(value) == {"__a"}:
                dtype_text, shape = value["__a"]
                dtype = np.dtype(dtype_text)
                if dtype.kind not in "biufc" or dtype.fields is not None:
                    raise ValueError(f"bad dtype {dtype_text!r}")
                if not all(isinstance(s, int) and s >= 0 for s in shape):
                    raise ValueError(f"bad shape {shape!r}")
                size = math.prod(shape) * dtype.itemsize
                if pos + size > len(buf):
                    raise ValueError("truncated")
                arr = np.frombuffer(buf, dtype=dtype, count=math.prod(shape), offset=pos)
                pos += size
                return arr.reshape(shape)
            if set(value) == {"__o"}:
                return _Opaque(str(value["__o"]))
            return {k: decode(v) for k, v in value.items()}
        return value

    return decode(header)


def _limit_memory(budget: int) -> None:
    """In the child: no core files, and an address-space limit of what is mapped now plus
    ``budget`` plus 1 GiB."""
    try:
        import resource
    except ImportError:  # pragma: no cover - not on POSIX
        return
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    try:
        with open("/proc/self/statm") as fh:
            mapped = int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    limit = mapped + budget + (1 << 30)
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))


def _child_load(path: str, fd: int, file_size: int, budget: int) -> None:
    """Body of the reading child: load, send the packed tree (``T``) or a StorageError's
    message (``E``) through ``fd``, exit.  Never returns."""
    code = 0
    try:
        signal.signal(signal.SIGINT, signal.SIG_DFL)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        import faulthandler

        faulthandler.disable()  # a crash is reported by the parent, in one line
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, 2)
        os.close(devnull)
        _limit_memory(budget)
        try:
            pieces = [b"T", *_pack(_load_here(Path(path), file_size, budget))]
        except StorageError as exc:
            pieces = [b"E", str(exc).encode("utf-8", "replace")]
        except MemoryError:
            pieces = [b"M"]
        for piece in pieces:
            _write_all(fd, piece)
    except BaseException:  # noqa: BLE001 - the parent reports the exit status
        code = 70
    finally:
        os._exit(code)


def _isolated_main(argv: list[str]) -> None:
    """Entry point of a spawned reading child: ``path fd file_size budget``."""
    path, fd, file_size, budget = argv
    _child_load(path, int(fd), int(file_size), int(budget))


def _can_fork() -> bool:
    """Fork is cheap (about 10 ms) but safe only while this process runs one thread."""
    return (
        hasattr(os, "fork") and sys.platform.startswith("linux") and threading.active_count() == 1
    )


def _start_child(path: Path, fd: int, file_size: int, budget: int) -> Any:
    if _can_fork():
        pid = os.fork()
        if pid == 0:  # pragma: no cover - runs in the child, which exits
            _child_load(str(path), fd, file_size, budget)
        return pid
    return subprocess.Popen(
        [
            sys.executable,
            "-I",
            "-c",
            _spawn_code(),
            str(path),
            str(fd),
            str(file_size),
            str(budget),
        ],
        pass_fds=(fd,),
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


def _spawn_code() -> str:
    """The program of a spawned reading child.  It runs in isolated mode (``-I``: neither
    the current directory nor ``PYTHON*`` variables nor the user's site on ``sys.path``), so
    a ``json.py`` planted where the caller runs is never imported.  walker itself is loaded
    from this process's package directory by its path, and this process's other absolute
    ``sys.path`` entries (where numpy and h5py may live) are appended after the
    interpreter's own, so that they cannot shadow the standard library."""
    import walker

    package = Path(walker.__file__).resolve().parent
    extra = [
        p
        for p in sys.path
        if isinstance(p, str) and os.path.isabs(p) and Path(p).resolve() != package.parent
    ]
    return (
        "import sys, importlib.util\n"
        f"sys.path.extend(p for p in {extra!r} if p not in sys.path)\n"
        "spec = importlib.util.spec_from_file_location("
        f"'walker', {str(package / '__init__.py')!r}, "
        f"submodule_search_locations=[{str(package)!r}])\n"
        "module = importlib.util.module_from_spec(spec)\n"
        "sys.modules['walker'] = module\n"
        "spec.loader.exec_module(module)\n"
        "from walker.storage.isolated import _isolated_main\n"
        "_isolated_main(sys.argv[1:])\n"
    )


def _reap(child: Any, block: bool) -> int | None:
    """Exit code of the child (negative: killed by that signal), None while it runs."""
    if isinstance(child, subprocess.Popen):
        return child.wait() if block else child.poll()
    pid, status = os.waitpid(child, 0 if block else os.WNOHANG)
    return None if pid == 0 else os.waitstatus_to_exitcode(status)


def _kill(child: Any) -> None:
    try:
        if isinstance(child, subprocess.Popen):
            child.kill()
        else:
            os.kill(child, signal.SIGKILL)
    except OSError:  # already gone
        pass
    try:
        _reap(child, block=True)
    except ChildProcessError:  # already reaped
        pass


def _load_isolated(path: Path, file_size: int, budget: int, timeout: float) -> dict:
    """Load ``path`` in a child process (forked when this process has one thread, else a
    new interpreter) that has ``timeout`` seconds and ``budget`` bytes; its crash, hang or
    memory exhaustion is a StorageError naming what it died of."""
    r, w = os.pipe()
    try:
        child = _start_child(path, w, file_size, budget)
    except BaseException:
        os.close(r)
        os.close(w)
        raise
    os.close(w)
    deadline = time.monotonic() + timeout
    pieces: list[bytes] = []
    received = 0
    status = None
    try:
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise StorageError(
                    f"cannot read '{path}': reading did not finish within {timeout:g} s (a "
                    "damaged file makes the HDF5 library loop; pass a larger `timeout` if "
                    "the file is just large)"
                )
            ready, _, _ = select.select([r], [], [], min(remaining, 1.0))
            if not ready:
                continue
            piece = os.read(r, 1 << 20)
            if not piece:
                break
            received += len(piece)
            if received > budget + (1 << 24):
                raise StorageError(f"cannot read '{path}': the reader sent more than its budget")
            pieces.append(piece)
        while status is None:
            status = _reap(child, block=False)
            if status is None:
                if time.monotonic() > deadline:
                    raise StorageError(
                        f"cannot read '{path}': reading did not finish within {timeout:g} s"
                    )
                time.sleep(0.001)
    except BaseException:  # a timeout, or an interrupt of this process: no orphan left
        if status is None:
            _kill(child)
        raise
    finally:
        os.close(r)
    data = bytearray(received)
    at = 0
    for piece in pieces:
        data[at : at + len(piece)] = piece
        at += len(piece)
    del pieces
    if status < 0:
        try:
            name = signal.Signals(-status).name
        except ValueError:
            name = f"signal {-status}"
        raise StorageError(
            f"cannot read '{path}': the HDF5 library crashed reading it (the reading process "
            f"was killed by {name}); the file is damaged"
        )
    if status != 0 or not data:
        raise StorageError(f"cannot read '{path}': the reading process failed (exit {status})")
    if data[:1] == b"E":
        raise StorageError(bytes(data[1:]).decode("utf-8", "replace"))
    if data[:1] == b"M":
        raise StorageError(
            f"cannot read '{path}': reading it needs more than the memory budget of {budget} "
            "bytes; pass a larger `memory`"
        )
    try:
        return _unpack(memoryview(data)[1:])
    except (ValueError, TypeError, KeyError, UnicodeDecodeError) as exc:
        raise StorageError(
            f"cannot read '{path}': the reading process sent a malformed answer ({exc})"
        ) from None


def _load_tree(
    path: Path, *, isolate: bool, timeout: float | None = None, memory: int | None = None
) -> dict:
    file_size = path.stat().st_size
    budget = _default_budget(file_size) if memory is None else int(memory)
    if not isolate:
        return _load_here(path, file_size, budget)
    if timeout is None:
        timeout = READ_TIMEOUT + file_size / 50e6
    return _load_isolated(path, file_size, budget, float(timeout))
