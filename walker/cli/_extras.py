"""Optional dependencies on the command line: a missing one is one line naming the extra
that installs it, and exit 2 (``walker: error: ...``), never an internal error.

- ``distributed``, ``dask``: the extra ``dask`` (``walker sweep --scheduler``);
- ``numba``: the extra ``numba`` (the numba twins: torque figures, the HZD tools);
- ``heyoka``, ``pydrake``: the extra ``bench`` (the benchmark contenders in ``scripts/``);
- ``pandas``: no extra (``pip install pandas``).
"""

from __future__ import annotations

import importlib.util

EXTRAS = {
    "distributed": "dask",
    "dask": "dask",
    "numba": "numba",
    "heyoka": "bench",
    "pydrake": "bench",
    "pandas": None,
}
"""Top-level module -> the extra of ``walker-hybrid`` that installs it (None: no extra)."""


def _install_hint(module: str) -> str:
    extra = EXTRAS[module]
    if extra is None:
        return f"pip install {module}"
    return f"pip install 'walker-hybrid[{extra}]'"


def missing_extra_line(exc: BaseException) -> str | None:
    """The one line for an ImportError of an optional dependency, or None for any other
    exception (a module walker needs always, missing, is an internal error)."""
    if not isinstance(exc, ImportError):
        return None
    name = (getattr(exc, "name", None) or "").partition(".")[0]
    if name not in EXTRAS:
        return None
    extra = EXTRAS[name]
    what = f"the optional extra `{extra}`" if extra else f"the optional package `{name}`"
    return f"{what} is not installed (no module {name!r}); install it with {_install_hint(name)}"


def require(module: str, flag: str) -> None:
    """Raise ImportError (its ``name`` the module) when the optional ``module`` a ``flag``
    needs is not installed: checked before any work starts."""
    if importlib.util.find_spec(module) is None:
        raise ImportError(f"{flag} needs {module}", name=module)
