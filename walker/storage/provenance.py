"""Provenance: what produced a result (:func:`scene_provenance`, :func:`solver_provenance`,
:func:`parameters_with_units`, :func:`walker_version`), and the JSON form of provenance
values with the checks made on writing and on reading.
"""

from __future__ import annotations

import math
import numbers
import os
from typing import Any

import numpy as np

from walker.status import Status
from walker.storage.schema import _CHECKSUM_ATTR, _RESERVED_ATTRS, AUTOMATIC_KEYS, _Corrupt


def walker_version() -> str:
    """``walker.__version__`` if set, else the installed ``walker-hybrid`` version, else
    ``"unknown"``."""
    import walker

    version = getattr(walker, "__version__", None)
    if isinstance(version, str) and version:
        return version
    try:
        from importlib.metadata import PackageNotFoundError
        from importlib.metadata import version as dist_version

        return dist_version("walker-hybrid")
    except (ImportError, PackageNotFoundError):
        return "unknown"


SCENE_TEXT_LIMIT = 32_768
"""Largest scene file (in characters) whose text a file's provenance holds in full
(``scene_text``); a larger one is recorded by its ``scene_sha256`` only."""

ENVIRONMENT_KEYS = (
    "command_line",
    "versions",
    "git_commit",
    "compiler_flags",
    "scene_text",
    "scene_sha256",
    "state_names",
    "state_units",
    "section_names",
)
"""Provenance keys that describe how and where a result was computed, not what: a
checkpoint resumed by another command line, another installation or from a file written
before these keys existed is still the same computation (they are left out of the
comparison on resuming)."""

_COMMAND_LINE: list[str] | None = None


def set_command_line(argv) -> None:
    """Record the command line of this process as the command-line interface received it
    (``walker`` followed by its arguments); :func:`environment_provenance` reports it."""
    global _COMMAND_LINE
    _COMMAND_LINE = None if argv is None else ["walker", *(str(a) for a in argv)]


def command_line() -> str:
    """The command line of this process, shell-quoted: the one :func:`set_command_line`
    recorded (``walker find gaits/kneed_hsu.toml --out gait.h5``), else ``sys.argv``
    (``walker`` in place of the program when that is walker's own entry point)."""
    import shlex
    import sys

    if _COMMAND_LINE is not None:
        return shlex.join(_COMMAND_LINE)
    argv = [str(a) for a in sys.argv] or [""]
    program = argv[0].replace("\\", "/")
    if program.endswith(("walker/__main__.py", "/walker")) or program == "walker":
        argv[0] = "walker"
    return shlex.join(argv)


def _version(name: str) -> str | None:
    try:
        from importlib.metadata import PackageNotFoundError
        from importlib.metadata import version as dist_version

        return dist_version(name)
    except (ImportError, PackageNotFoundError, ValueError):
        return None


def _git_commit() -> str | None:
    """The commit checked out in walker's source tree when walker runs from a git checkout
    (``git rev-parse HEAD`` there, with ``+dirty`` when tracked files differ from it);
    None when it is not a checkout, git is missing or fails: never an error."""
    import subprocess
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    if not (root / ".git").exists() or not (root / "walker" / "__init__.py").exists():
        return None
    try:

        def git(*args: str) -> str:
            done = subprocess.run(
                ["git", "-C", str(root), *args],
                capture_output=True,
                text=True,
                timeout=5,
                check=True,
            )
            return done.stdout.strip()

        commit = git("rev-parse", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError, ValueError):
        return None
    if len(commit) < 7 or not all(c in "0123456789abcdef" for c in commit):
        return None
    return commit + ("+dirty" if dirty else "")


_ENVIRONMENT: dict[str, Any] | None = None


def environment_provenance() -> dict[str, Any]:
    """How a result was computed: ``command_line`` (:func:`command_line`), ``versions``
    (``walker``, ``python``, ``numpy``, ``scipy``, ``h5py``), ``git_commit`` (only when
    walker runs from a git checkout) and ``compiler_flags`` (the compiler command the
    extension was built with, ``walker._hybrid.COMPILE_FLAGS``; ``"unknown"`` for an
    extension built before it was recorded).  Never raises."""
    global _ENVIRONMENT
    if _ENVIRONMENT is None:
        import platform

        env: dict[str, Any] = {
            "versions": {
                "walker": walker_version(),
                "python": platform.python_version(),
                **{name: _version(name) or "unknown" for name in ("numpy", "scipy", "h5py")},
            }
        }
        commit = _git_commit()
        if commit is not None:
            env["git_commit"] = commit
        try:
            from walker import _hybrid

            env["compiler_flags"] = str(getattr(_hybrid, "COMPILE_FLAGS", "unknown"))
        except ImportError:  # pragma: no cover - walker does not run without it
            env["compiler_flags"] = "unknown"
        _ENVIRONMENT = env
    return {"command_line": command_line(), **_ENVIRONMENT}


def parameters_with_units(params: Any) -> dict[str, dict[str, Any]]:
    """Provenance ``parameters`` entry from a :mod:`walker.params` dataclass.

    Parameters
    ----------
    params : object with ``to_dict()`` (name -> value) and ``units()`` (name -> unit)
        e.g. ``CompassParams.goswami()``.

    Returns
    -------
    dict
        ``{name: {"value": value, "unit": unit}}`` in the parameters' canonical order.

    Examples
    --------
    >>> from walker.params import SimplestParams
    >>> parameters_with_units(SimplestParams.garcia())["slope"]["unit"]
    'rad'
    """
    if not (hasattr(params, "to_dict") and hasattr(params, "units")):
        raise TypeError(
            f"`params` must have `to_dict()` and `units()` (a walker.params dataclass), "
            f"got {type(params).__name__}"
        )
    values = params.to_dict()
    units = params.units()
    return {
        name: {"value": float(value), "unit": str(units[name])} for name, value in values.items()
    }


def solver_provenance(
    model: Any,
    params: Any,
    *,
    method: str,
    rtol: float,
    atol: float,
    t_max: float,
    first_step: float | None,
) -> dict[str, Any]:
    """Provenance of a computation: the model, its parameters, the solver and the kernels.

    The one place where these keys are built: :func:`scene_provenance` (every file the
    command line writes) and :func:`walker.analysis.sweep.sweep` (a sweep's checkpoint) both use it.

    Parameters
    ----------
    model : walker model
        the model that ran (``scene.walker_model``, ``StrideMap.model``): its ``name``,
        ``conventions`` (e.g. ``{"swing_scuff": "ignore"}``) and ``kernel_hash``.
    params : walker.params dataclass
        the parameters (the base values, for a sweep).
    method, rtol, atol, t_max, first_step
        the solver settings (``first_step`` None: chosen by the integrator).

    Returns
    -------
    dict
        ``model``, ``parameters`` (:func:`parameters_with_units`), ``method``, ``rtol``,
        ``atol``, ``t_max``, ``first_step``, ``kernel_hash``, then one key per convention of
        the model (``swing_scuff`` for the kneed walkers), the state's ``state_names``,
        ``state_units`` and ``section_names``, and :func:`environment_provenance`
        (``command_line``, ``versions``, ``git_commit``, ``compiler_flags``).

    Examples
    --------
    >>> from walker.models import get_model
    >>> from walker.params import SimplestParams
    >>> prov = solver_provenance(get_model("simplest"), SimplestParams.garcia(),
    ...                          method="dop853", rtol=1e-10, atol=1e-12, t_max=20.0,
    ...                          first_step=None)
    >>> list(prov)[:8]
    ['model', 'parameters', 'method', 'rtol', 'atol', 't_max', 'first_step', 'kernel_hash']
    >>> prov["state_names"], prov["state_units"]
    (['theta', 'phi', 'theta_dot', 'phi_dot'], ['rad', 'rad', 'rad/s', 'rad/s'])
    >>> sorted(prov["versions"])
    ['h5py', 'numpy', 'python', 'scipy', 'walker']
    """
    prov = {
        "model": model.name,
        "parameters": parameters_with_units(params),
        "method": method,
        "rtol": float(rtol),
        "atol": float(atol),
        "t_max": float(t_max),
        "first_step": None if first_step is None else float(first_step),
        "kernel_hash": model.kernel_hash,
        **model.conventions,
    }
    names = getattr(model, "state_names", None)
    units = getattr(model, "state_units", None)
    if names is not None and units is not None:
        prov["state_names"] = [str(v) for v in names]
        prov["state_units"] = [str(v) for v in units]
        prov["section_names"] = [str(v) for v in getattr(model, "section_names", ())]
    prov.update(environment_provenance())
    return prov


def scene_provenance(
    scene: Any, *, relative_to: str | os.PathLike | None = None, **extra: Any
) -> dict[str, Any]:
    """Provenance of a result computed from a scene, as the command line stores it.

    Parameters
    ----------
    scene : walker.scene.Scene
        the loaded scene (with any ``--set`` overrides applied).
    relative_to : str or path-like, optional
        the directory of the file the result goes to: ``scene`` is then recorded relative
        to it (``../gaits/kneed_hsu.toml``), so the file names no directory of the machine
        it was made on and stays right when the result and the scenes move together.
    **extra
        the caller's own keys (``status``, ``range``, ...), added last; a key of the same
        name as one below replaces it.

    Returns
    -------
    dict
        ``scene`` (the scene file's path, as given or relative to ``relative_to``), then
        :func:`solver_provenance` of the scene's model, parameters and ``[compute]``
        settings: ``model``, ``parameters``, ``method``, ``rtol``, ``atol``, ``t_max``,
        ``first_step``, ``kernel_hash``, the model's conventions (``swing_scuff``), the
        state's names and units and the environment (command line, versions, git commit,
        compiler flags); then ``scene_sha256`` and ``scene_text``, the scene file's text
        (up to :data:`SCENE_TEXT_LIMIT` characters); then ``extra``.

    Examples
    --------
    >>> from walker.scene import load_scene
    >>> prov = scene_provenance(load_scene("gaits/kneed_hsu.toml"), status="COMPLETED")
    >>> prov["scene"], prov["model"], prov["swing_scuff"], prov["status"]
    ('gaits/kneed_hsu.toml', 'kneed', 'trip', 'COMPLETED')
    """
    from walker.simulation.stride import solver_settings

    where = str(scene.path)
    if relative_to is not None:
        where = os.path.relpath(os.path.abspath(scene.path), os.path.abspath(relative_to))
    prov = {
        "scene": where,
        **solver_provenance(scene.walker_model, scene.params, **solver_settings(scene.compute)),
        **_scene_text(scene.path),
    }
    prov.update(extra)
    return prov


def _scene_text(path) -> dict[str, str]:
    """``scene_sha256`` of the scene file's bytes and, up to :data:`SCENE_TEXT_LIMIT`
    characters, its ``scene_text``; empty when the file cannot be read (never an error)."""
    import hashlib

    try:
        with open(path, "rb") as f:
            data = f.read(4 * SCENE_TEXT_LIMIT + 1)
        text = data.decode("utf-8")
    except (OSError, TypeError, ValueError):
        return {}
    out = {"scene_sha256": hashlib.sha256(data).hexdigest()}
    if len(text) <= SCENE_TEXT_LIMIT:
        out["scene_text"] = text
    return out


def _is_dunder(key: str) -> bool:
    return key.startswith("__") and key.endswith("__")


def _to_json(value: Any, where: str) -> Any:
    """JSON-ready form of ``value``; Status members, tuples and arrays are tagged."""
    if value is None or isinstance(value, str | bool):
        return value
    if isinstance(value, Status):
        return {"__status__": value.name}
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if isinstance(value, numbers.Complex):
        return {"__complex__": [float(value.real), float(value.imag)]}
    if isinstance(value, tuple):
        return {"__tuple__": [_to_json(v, f"{where}[{i}]") for i, v in enumerate(value)]}
    if isinstance(value, list):
        return [_to_json(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, np.ndarray):
        if value.dtype.kind not in "biufc":
            raise TypeError(f"`{where}` must be a numeric array, got dtype {value.dtype}")
        arr = np.ascontiguousarray(value)
        flat = arr.view(arr.real.dtype) if arr.dtype.kind == "c" else arr
        return {
            "__ndarray__": {
                "dtype": arr.dtype.str,
                "shape": list(arr.shape),
                "data": flat.ravel().tolist(),
            }
        }
    if isinstance(value, dict):
        out = {}
        for key, v in value.items():
            if not isinstance(key, str):
                raise TypeError(f"keys of `{where}` must be str, got {key!r}")
            if _is_dunder(key):
                raise ValueError(f"keys of `{where}` must not look like '__x__', got {key!r}")
            out[key] = _to_json(v, f"{where}[{key!r}]")
        return out
    raise TypeError(
        f"`{where}` must be None, str, bool, a number, Status, list, tuple, dict or a numeric "
        f"ndarray, got {type(value).__name__}"
    )


def _is_real(value: Any) -> bool:
    """A real number (not a bool) that a float holds: an int beyond the float range (a
    400-digit integer in a file's JSON) is not."""
    if not isinstance(value, numbers.Real) or isinstance(value, bool | np.bool_):
        return False
    if isinstance(value, numbers.Integral):
        return abs(int(value)) <= _FLOAT_INT_MAX
    return True


_FLOAT_INT_MAX = int(np.finfo(np.float64).max)


def _from_json(value: Any, where: str = "provenance") -> Any:
    """Inverse of :func:`_to_json` for a parsed JSON value; raises _Corrupt naming ``where``
    when a tagged object is malformed."""
    if isinstance(value, list):
        return [_from_json(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if not isinstance(value, dict):
        return value
    tags = [key for key in value if _is_dunder(key)]
    if not tags:
        return {k: _from_json(v, f"{where}[{k!r}]") for k, v in value.items()}
    if len(value) != 1:
        raise _Corrupt(f"`{where}` mixes the tag {tags[0]!r} with other keys")
    ((tag, inner),) = value.items()
    if tag == "__status__":
        if not isinstance(inner, str) or inner not in Status.__members__:
            raise _Corrupt(f"`{where}` holds an unknown status {inner!r}")
        return Status[inner]
    if tag == "__tuple__":
        if not isinstance(inner, list):
            raise _Corrupt(f"`{where}`: '__tuple__' must hold a list, got {type(inner).__name__}")
        return tuple(_from_json(v, f"{where}[{i}]") for i, v in enumerate(inner))
    if tag == "__complex__":
        if not (isinstance(inner, list) and len(inner) == 2 and all(map(_is_real, inner))):
            raise _Corrupt(f"`{where}`: '__complex__' must hold [re, im], got {inner!r:.60}")
        return complex(inner[0], inner[1])
    if tag == "__ndarray__":
        return _ndarray_from_json(inner, where)
    raise _Corrupt(f"`{where}` holds an unknown tag {tag!r}")


def _ndarray_from_json(inner: Any, where: str) -> np.ndarray:
    if not isinstance(inner, dict) or set(inner) != {"dtype", "shape", "data"}:
        raise _Corrupt(f"`{where}`: '__ndarray__' must hold dtype, shape and data")
    try:
        dtype = np.dtype(inner["dtype"]) if isinstance(inner["dtype"], str) else None
    except TypeError:
        dtype = None
    if dtype is None or dtype.kind not in "biufc" or dtype.fields is not None:
        raise _Corrupt(f"`{where}`: '__ndarray__' has an invalid dtype {inner['dtype']!r:.40}")
    shape = inner["shape"]
    if not (
        isinstance(shape, list)
        and len(shape) <= 32
        and all(isinstance(s, int) and not isinstance(s, bool) and s >= 0 for s in shape)
    ):
        raise _Corrupt(f"`{where}`: '__ndarray__' has an invalid shape {shape!r:.40}")
    data = inner["data"]
    count = math.prod(shape) * (2 if dtype.kind == "c" else 1)
    if not isinstance(data, list) or len(data) != count:
        raise _Corrupt(f"`{where}`: '__ndarray__' data does not match its shape {shape}")
    if not all(isinstance(v, int | float) for v in data):  # bool is an int
        raise _Corrupt(f"`{where}`: '__ndarray__' data must be numbers")
    real = np.empty(0, dtype).real.dtype
    try:
        flat = np.array(data, dtype=real)
    except (OverflowError, ValueError, TypeError):
        raise _Corrupt(f"`{where}`: '__ndarray__' data do not fit {dtype}") from None
    if dtype.kind == "c":
        flat = flat.view(dtype)
    return flat.reshape(shape)


_PROVENANCE_RULES: dict[str, tuple[str, Any]] = {
    "scene": ("a str", lambda v: isinstance(v, str)),
    "model": ("a str", lambda v: isinstance(v, str)),
    "method": ("a str", lambda v: isinstance(v, str)),
    "kernel_hash": ("a str", lambda v: isinstance(v, str)),
    "sweep_kind": ("a str", lambda v: isinstance(v, str)),
    "rtol": ("a real number", _is_real),
    "atol": ("a real number", _is_real),
    "tol": ("a real number", _is_real),
    "t_max": ("a real number", _is_real),
    "first_step": ("a real number or null", lambda v: v is None or _is_real(v)),
    "n_strides": (
        "an int in [0, 2**62]",
        lambda v: isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 1 << 62,
    ),
    "status": ("a Status or a str", lambda v: isinstance(v, Status | str)),
    "z0": ("a list of real numbers", lambda v: isinstance(v, list) and all(map(_is_real, v))),
}
"""Provenance keys walker itself writes, and the type each must have when present."""


def _parameters_problem(parameters: Any) -> tuple[str | None, str] | None:
    """Why ``parameters`` is not ``{name: {"value": real, "unit": str}}``: (the entry's name
    or None for the whole, the rule), or None."""
    if not isinstance(parameters, dict):
        return None, (
            f"must be a dict name -> {{'value': v, 'unit': u}}, got {type(parameters).__name__}"
        )
    for name, entry in parameters.items():
        if (
            not isinstance(entry, dict)
            or set(entry) != {"value", "unit"}
            or not isinstance(entry["unit"], str)
            or not _is_real(entry["value"])
        ):
            return name, (
                "must be a dict with exactly the keys 'value' and 'unit' (a real number and a "
                f"str), got {entry!r:.80}"
            )
    return None


def _check_provenance(provenance: Any) -> dict[str, Any]:
    """Validate the caller's provenance and return its JSON-ready form."""
    if not isinstance(provenance, dict):
        raise TypeError(f"`provenance` must be a dict, got {type(provenance).__name__}")
    for key in provenance:
        if not isinstance(key, str):
            raise TypeError(f"keys of `provenance` must be str, got {key!r}")
        if key in _RESERVED_ATTRS or key.startswith("parameters."):
            raise ValueError(
                f"`provenance` must not set {key!r}: write() sets "
                f"{', '.join(AUTOMATIC_KEYS)} and {_CHECKSUM_ATTR!r} itself"
            )
    parameters = provenance.get("parameters")
    if parameters is not None:
        problem = _parameters_problem(parameters)
        if problem is not None:
            name, rule = problem
            if name is None:
                raise TypeError(f"`provenance['parameters']` {rule}")
            raise ValueError(f"`provenance['parameters'][{name!r}]` {rule}")
    prov_json = _to_json(provenance, "provenance")
    # What read() will check must hold now: a file walker writes always reads back.
    try:
        _check_provenance_types(_from_json(prov_json))
    except _Corrupt as exc:
        raise ValueError(str(exc)) from None
    return prov_json


def _check_provenance_types(provenance: dict[str, Any]) -> None:
    """Raise _Corrupt naming the first known provenance key with a wrong type."""
    for key, (rule, ok) in _PROVENANCE_RULES.items():
        if key in provenance and not ok(provenance[key]):
            raise _Corrupt(f"provenance key {key!r} must be {rule}, got {provenance[key]!r:.60}")
    if provenance.get("parameters") is not None:
        problem = _parameters_problem(provenance["parameters"])
        if problem is not None:
            name, rule = problem
            entry = "" if name is None else f" entry {name!r}"
            raise _Corrupt(f"provenance key 'parameters'{entry} {rule}")
