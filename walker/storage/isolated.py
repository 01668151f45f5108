"""The load in a child process (forked while this process runs one thread, else a new
interpreter) with a time and memory budget, so that a crash or a hang of the HDF5 library
on a damaged file is a StorageError; the tree comes back as JSON plus raw array bytes.

Memory: the child reads each dataset block by block as it sends it (walker.storage.blocks)
and the parent receives the bytes straight into one buffer sized from the header, so a read
holds the file's data about once, in the parent, plus blocks of a few MiB.
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

from walker.storage.blocks import _Pending
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


def _load_here(path: Path, file_size: int, budget: int, stream: bool = False) -> dict:
    """Open and load ``path`` in this process (StorageError on any problem).  With
    ``stream=True`` (the reading child) the datasets are :class:`_Pending`, read as the tree
    is sent: the file then stays open until this process exits."""
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
    keep_open = False
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_CLOEXEC", 0))
        raw = lambda offset, size: os.pread(fd, size, offset)  # noqa: E731
        tree = _Loader(f, path, file_size, budget, raw, stream=stream).run()
        keep_open = stream
        return tree
    except Exception as exc:  # noqa: BLE001 - h5py raises many types on damaged files
        raise _read_error(path, exc) from None
    finally:
        if not keep_open:
            f.close()
            if fd is not None:
                os.close(fd)


def _read_error(path: Path, exc: BaseException) -> BaseException:
    """The StorageError a failure while reading ``path`` is raised as."""
    if isinstance(exc, StorageError):
        return exc
    if isinstance(exc, MemoryError):
        return StorageError(f"cannot read '{path}': reading it needs more memory than is available")
    if isinstance(exc, RecursionError):
        return StorageError(f"cannot read '{path}': corrupted (nested too deeply)")
    reason = _first_line(exc)
    if not isinstance(exc, _Corrupt):
        reason = f"{type(exc).__name__}: {reason}"
    return StorageError(f"cannot read '{path}': corrupted or incomplete ({reason})")


def _pack(tree: dict) -> tuple[bytes, list[Any]]:
    """The tree as a JSON header a parent can read without unpickling (each array, or
    :class:`_Pending` dataset, as a reference: its dtype and shape) and the arrays and
    pending datasets in the header's order."""
    items: list[Any] = []

    def encode(value: Any) -> Any:
        if isinstance(value, dict):
            return {str(k): encode(v) for k, v in value.items()}
        if isinstance(value, np.ndarray | _Pending):
            items.append(value)
            return {"__a": [value.dtype.str, list(value.shape)]}
        if isinstance(value, _Opaque):
            return {"__o": value.what}
        if value is None or isinstance(value, str | int | float):
            return value
        raise TypeError(f"cannot pack {type(value).__name__}")

    return json.dumps(encode(tree)).encode("ascii"), items


def _frame(fd: int, tag: bytes, payload: Any = b"") -> None:
    """One frame to the parent: a tag byte, the payload's length (8 bytes), the payload."""
    view = memoryview(payload).cast("B")
    _write_all(fd, tag + len(view).to_bytes(8, "little"))
    if len(view):
        _write_all(fd, view)


def _send_tree(fd: int, tree: dict, path: Path) -> None:
    """The tree to the parent: its header (``H``), each array's bytes in frames (``D``) of
    at most one block of a dataset (pending datasets are read block by block here, so the
    child never holds one whole), then ``K``."""
    header, items = _pack(tree)
    _frame(fd, b"H", header)
    for item in items:
        pieces = item.pieces() if isinstance(item, _Pending) else iter((item,))
        while True:
            try:
                piece = next(pieces, None)
            except MemoryError:
                raise  # the child's address space is limited to the budget: "M"
            except Exception as exc:  # noqa: BLE001 - h5py raises many types on damaged files
                raise _read_error(path, exc) from None
            if piece is None:
                break
            arr = np.ascontiguousarray(piece, dtype=item.dtype)
            if arr.nbytes:
                _frame(fd, b"D", arr.reshape(-1).view(np.uint8))
    _frame(fd, b"K")


def _walk_header(value: Any, make: Any) -> Any:
    """The tree of a JSON header, each array reference replaced by ``make(dtype, shape)``;
    every dtype and shape is checked before use."""
    if isinstance(value, dict):
        if set(value) == {"__a"}:
            dtype_text, shape = value["__a"]
            dtype = np.dtype(dtype_text)
            if dtype.kind not in "biufc" or dtype.fields is not None:
                raise ValueError(f"bad dtype {dtype_text!r}")
            if not (isinstance(shape, list) and all(isinstance(n, int) and n >= 0 for n in shape)):
                raise ValueError(f"bad shape {shape!r}")
            return make(dtype, tuple(shape))
        if set(value) == {"__o"}:
            return _Opaque(str(value["__o"]))
        return {k: _walk_header(v, make) for k, v in value.items()}
    return value


_ALIGN = 64  # each array's offset in the receiving buffer is a multiple of this [bytes]


def _spans(header: Any) -> list[tuple[int, int]]:
    """(offset, bytes) of each array of a header in one buffer, each offset aligned."""
    sizes: list[int] = []
    _walk_header(header, lambda dtype, shape: sizes.append(math.prod(shape) * dtype.itemsize))
    spans, offset = [], 0
    for size in sizes:
        spans.append((offset, size))
        offset += -(-size // _ALIGN) * _ALIGN
    return spans


def _arrays(header: Any, buf: np.ndarray, spans: list[tuple[int, int]]) -> dict:
    """The tree of a header, its arrays views of ``buf`` at ``spans``."""
    where = iter(spans)

    def take(dtype: np.dtype, shape: tuple) -> np.ndarray:
        offset, size = next(where)
        return buf[offset : offset + size].view(dtype).reshape(shape)

    return _walk_header(header, take)


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
    """Body of the reading child: load, send the tree (:func:`_send_tree`), or a
    StorageError's message (``E``) or a memory failure (``M``), through ``fd``; exit.
    Never returns."""
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
            _send_tree(fd, _load_here(Path(path), file_size, budget, stream=True), Path(path))
        except StorageError as exc:
            _frame(fd, b"E", str(exc).encode("utf-8", "replace"))
        except MemoryError:
            _frame(fd, b"M")
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


class _Receiver:
    """The parent's end of the pipe: frames read with the deadline, the arrays' bytes read
    straight into one buffer allocated once from the header (so a read holds the data once,
    never a list of pieces and a copy of it)."""

    def __init__(self, r: int, path: Path, budget: int, deadline: float, timeout: float):
        self.r, self.path, self.budget = r, path, budget
        self.deadline, self.timeout = deadline, timeout
        self.limit = budget + (1 << 24)  # bytes the child may send

    def fill(self, view: memoryview) -> bool:
        """Read exactly ``len(view)`` bytes into ``view``; False at the end of the pipe."""
        got = 0
        while got < len(view):
            remaining = self.deadline - time.monotonic()
            if remaining <= 0:
                raise StorageError(
                    f"cannot read '{self.path}': reading did not finish within "
                    f"{self.timeout:g} s (a damaged file makes the HDF5 library loop; pass a "
                    "larger `timeout` if the file is just large)"
                )
            ready, _, _ = select.select([self.r], [], [], min(remaining, 1.0))
            if not ready:
                continue
            n = os.readv(self.r, [view[got:]])
            if n == 0:
                return False
            got += n
        return True

    def too_much(self) -> StorageError:
        return StorageError(f"cannot read '{self.path}': the reader sent more than its budget")

    def run(self) -> tuple[bytes, Any]:
        """The child's answer: (``K``, tree), (``E``, message), (``M``, None) or (b"", None)
        when the pipe ended first.  ValueError: a malformed answer."""
        head = bytearray(9)
        tree = None
        spans: list[tuple[int, int]] = []
        buf = np.empty(0, dtype=np.uint8)
        view = memoryview(buf)
        at = filled = 0  # the array being received, and its bytes received
        while self.fill(memoryview(head)):
            tag, n = bytes(head[:1]), int.from_bytes(head[1:], "little")
            if tag in (b"H", b"E"):
                if n > self.limit:
                    raise self.too_much()
                payload = bytearray(n)
                if not self.fill(memoryview(payload)):
                    break
                if tag == b"E":
                    return b"E", bytes(payload).decode("utf-8", "replace")
                if tree is not None:
                    raise ValueError("a second header")
                tree = json.loads(payload.decode("ascii"))
                del payload
                spans = _spans(tree)
                total = spans[-1][0] + spans[-1][1] if spans else 0
                if total > self.limit:
                    raise self.too_much()
                buf = np.empty(total, dtype=np.uint8)
                view = memoryview(buf)
            elif tag == b"D":
                while at < len(spans) and filled == spans[at][1]:
                    at, filled = at + 1, 0
                if tree is None or at == len(spans) or n > spans[at][1] - filled:
                    raise ValueError("more array bytes than the header declares")
                start = spans[at][0] + filled
                if not self.fill(view[start : start + n]):
                    break
                filled += n
            elif tag == b"M":
                return b"M", None
            elif tag == b"K":
                while at < len(spans) and filled == spans[at][1]:
                    at, filled = at + 1, 0
                if tree is None or at != len(spans):
                    raise ValueError("fewer array bytes than the header declares")
                return b"K", _arrays(tree, buf, spans)
            else:
                raise ValueError(f"unknown frame {tag!r}")
        return b"", None


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
    status = None
    try:
        try:
            tag, answer = _Receiver(r, path, budget, deadline, timeout).run()
        except StorageError:
            raise  # a timeout, or more than the budget (a ValueError too)
        except (ValueError, TypeError, KeyError, UnicodeDecodeError, StopIteration) as exc:
            raise StorageError(
                f"cannot read '{path}': the reading process sent a malformed answer ({exc})"
            ) from None
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
    if status < 0:
        try:
            name = signal.Signals(-status).name
        except ValueError:
            name = f"signal {-status}"
        raise StorageError(
            f"cannot read '{path}': the HDF5 library crashed reading it (the reading process "
            f"was killed by {name}); the file is damaged"
        )
    if status != 0 or not tag:
        raise StorageError(f"cannot read '{path}': the reading process failed (exit {status})")
    if tag == b"E":
        raise StorageError(answer)
    if tag == b"M":
        raise StorageError(
            f"cannot read '{path}': reading it needs more than the memory budget of {budget} "
            "bytes; pass a larger `memory`"
        )
    return answer


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
