"""numba's ``njit``, applied on first call: importing walker does not import numba.

walker's runtime path is compiled C (:mod:`walker._hybrid`).  The ``@njit`` functions in the
model modules and in ``walker/_generated/*.py`` are the references the C ports are tested
against, the bridge for a model without a C port, and what the HZD tools and the actuated
walkers' torque figures call.  Importing numba takes about half a second, which every
command and every worker process paid whether or not it called one of them; finding gaits,
runs, basins, sweeps and continuation call none.

``njit(**options)(fn)`` returns a :class:`LazyJit` while numba is not in use.  The first call
of any of them (or the first read of a dispatcher attribute such as ``signatures``) imports
numba and turns *every* LazyJit made so far into its numba dispatcher, in the order they
were made, then replaces each LazyJit found in the globals of the loaded modules by its
dispatcher, before numba compiles anything: numba resolves a jitted function's globals when
it compiles it and must find dispatchers there.  From then on ``njit`` returns numba's
dispatcher directly.  numba's options (``cache=True`` and the rest) and its disk cache are
the same as with ``numba.njit`` at import time.

numba is an optional dependency (the ``numba`` extra; the ``test`` extra brings it too).
Without it the first call raises :class:`NumbaMissing`, an ImportError that names the
function and the command that installs numba; ``walker`` commands print it as one line.
"""

from __future__ import annotations

import functools
import sys
import threading

__all__ = ["LazyJit", "NumbaMissing", "njit", "dispatcher", "is_live"]

NUMBA_EXTRA = "python -m pip install 'walker-hybrid[numba]'"


class NumbaMissing(ImportError):
    """A numba function was called and numba is not installed (an optional dependency:
    walker's compiled path never needs it)."""


_LOCK = threading.RLock()
_PENDING: list[LazyJit] = []  # every LazyJit not yet turned into a dispatcher, in order
_LIVE = False  # numba imported and every LazyJit made so far turned into its dispatcher


class LazyJit:
    """A function to be compiled by ``numba.njit(**options)`` when first used.

    Calls go to the numba dispatcher; so does every attribute the LazyJit itself does not
    have (``signatures``, ``inspect_types``, ...).  ``py_func`` is the Python function.
    """

    def __init__(self, fn, options: dict):
        functools.update_wrapper(self, fn)
        self.py_func = fn
        self.options = dict(options)
        self._dispatcher = None

    def __call__(self, *args, **kwargs):
        return dispatcher(self)(*args, **kwargs)

    def __getattr__(self, name):
        if name.startswith("__") or name in ("py_func", "options", "_dispatcher"):
            raise AttributeError(name)
        return getattr(dispatcher(self), name)

    def __reduce__(self):
        # pickled by reference, as a module-level function is (whatever the name then holds)
        return (_by_name, (self.py_func.__module__, self.py_func.__qualname__))

    def __repr__(self):
        return f"<LazyJit {self.py_func.__module__}.{self.py_func.__qualname__}>"


def _by_name(module: str, qualname: str):
    import importlib

    obj = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    return obj


def is_live() -> bool:
    """Whether numba has been imported for walker's functions (by a first call)."""
    return _LIVE


def dispatcher(fn):
    """The numba dispatcher of ``fn`` (numba imported and every LazyJit compiled-on-call
    first, if that has not happened yet); anything that is not a LazyJit is returned as
    it is."""
    if not isinstance(fn, LazyJit):
        return fn
    if fn._dispatcher is None:
        _go_live(fn)
    if fn._dispatcher is None:  # a LazyJit made directly, not by njit, once numba is live
        with _LOCK:
            if fn._dispatcher is None:
                import numba  # imported already: _go_live

                fn._dispatcher = numba.njit(**fn.options)(fn.py_func)
    return fn._dispatcher


def _go_live(first: LazyJit) -> None:
    global _LIVE
    with _LOCK:
        if _LIVE:
            return
        try:
            import numba
        except ImportError as exc:
            name = f"{first.py_func.__module__}.{first.py_func.__qualname__}"
            raise NumbaMissing(
                f"{name} is compiled by numba, which is not installed: walker's compiled "
                f"path does not need it, this function does ({NUMBA_EXTRA})"
            ) from exc

        pending = list(_PENDING)
        made = {id(lazy): numba.njit(**lazy.options)(lazy.py_func) for lazy in pending}
        # Module globals: the functions' own modules, the modules that imported them by
        # name (tests included).  A LazyJit kept elsewhere (a list, a closure) still calls
        # through; only numba's typing of globals needs the dispatchers themselves.
        for module in list(sys.modules.values()):
            namespace = getattr(module, "__dict__", None)
            if not isinstance(namespace, dict):
                continue
            for key, value in list(namespace.items()):
                if type(value) is LazyJit and id(value) in made:
                    namespace[key] = made[id(value)]
        # Only now does a LazyJit hand out its dispatcher (read without the lock by
        # `dispatcher`): a call from another thread meanwhile waits here, so numba never
        # compiles a function while a global it reads is still a LazyJit.
        for lazy in pending:
            lazy._dispatcher = made[id(lazy)]
        _PENDING.clear()
        _LIVE = True


def njit(*args, **options):
    """``numba.njit`` applied when the function is first used (see the module docstring);
    ``@njit`` and ``@njit(**options)`` as with numba."""
    if args:
        if len(args) != 1 or not callable(args[0]) or options:
            raise TypeError("njit takes a function or keyword options only")
        return njit()(args[0])

    def decorate(fn):
        with _LOCK:
            if _LIVE:
                import numba  # imported already: _LIVE

                return numba.njit(**options)(fn)
            lazy = LazyJit(fn, options)
            _PENDING.append(lazy)
            return lazy

    return decorate
