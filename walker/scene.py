"""Scenes: a model, its parameters, an initial state and what to compute, read from TOML.

A scene file (``gaits/*.toml``) has these tables; unknown tables or keys are errors.

.. code-block:: toml

    [scene]
    model = "kneed"              # required: a key of walker.params.PARAMS
    description = "..."          # optional str
    source = "..."               # optional str: citation of the parameters / state

    [model]                      # optional: conventions of the model
    swing_scuff = "trip"         # "trip" (default) or "ignore" (kneed): a swing foot touching
                                 # the ground with the knee bent trips, or passes through
                                 # (walker.models.kneed)

    [parameters]                 # required: every field of the model's parameter class, no
    mass_hip = 0.5               # others (see walker.params), in that class's units ...
    # ... OR a published set plus optional overrides of some of its fields:
    # preset = "hsu_chen"
    # slope = 0.05

    [initial]                    # required
    state = [0.1877, -0.2884, -0.2884, -1.1014, -0.0399, -0.0399]   # full state (below)
    phase = 0                    # optional int >= 0 (default: the model's phase for state)

    [compute]                    # optional; the defaults are shown
    task = "fixed_point"         # "fixed_point" or "simulate"
    strides = 1                  # int <= 1e6; fixed_point: the period (>= 1); simulate:
                                 # strides to run, 0 = integrate to t_max. Models without events
                                 # (double_pendulum) need task = "simulate" and strides = 0,
                                 # which is then their default.
    method = "DOP853"            # "DOP853", "RK45", "RK4" or "Euler"
    rtol = 1e-12                 # > 0
    atol = 1e-12                 # > 0
    t_max = 20.0                 # > 0 [s], per stride (the whole run when strides = 0)
    first_step = 1e-3            # optional > 0 [s]; required (the fixed step) for RK4 / Euler
    tol = 1e-12                  # > 0: fixed-point residual max|P^k(z) - z| (walker find --tol)

    [reference]                  # optional: our own high-accuracy values and their tolerance
    state = [...]                # full state on the orbit, length as [initial].state
    section = [...]              # section coordinates of the orbit
    multipliers = [[re, im], ...]  # Floquet multipliers as [real, imaginary] pairs
    step_time = 1.0              # > 0 [s], duration of `strides` strides
    tolerance = 1e-10            # required with [reference]: > 0, absolute
    note = "..."                 # optional str: how the values were obtained

The full state of each model is named in :data:`STATE_NAMES`: simplest
``(theta, phi, theta_dot, phi_dot)`` in Garcia's coordinates; compass
``(q_stance, q_swing, qd_stance, qd_swing)``; kneed ``(q1, q2, q3, qd1, qd2, qd3)`` (stance
leg, swing thigh, swing shank); double_pendulum ``(q1, q2, qd1, qd2)``. Angles in rad, rates in
rad/s.

Every error in a file is a one-line ``ValueError`` naming the file and the key path, e.g.
``gaits/x.toml: [parameters] unknown key `mas_hip`; valid keys: ...``; a missing file raises
``FileNotFoundError``.  Hostile files end the same way: a file larger than
:data:`MAX_SCENE_BYTES`, a dotted key of more than :data:`MAX_KEY_PARTS` parts (refused
before parsing, whose time grows with its square), tables nested too deeply for the TOML
parser, or an integer too large for a float are ``ValueError`` naming the file (and the key).

Examples
--------
>>> from walker.scene import load_scene
>>> scene = load_scene("gaits/compass_goswami.toml", overrides={"slope": 0.05})
>>> scene.model, scene.params.slope, scene.state.shape
('compass', 0.05, (4,))
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from walker._suggest import did_you_mean
from walker.params import HAS_STRIDES, PARAMS, STATE_NAMES
from walker.simulation.integrate import METHODS, check_solver_settings

__all__ = ["TASKS", "METHODS", "STATE_NAMES", "ComputeSettings", "Scene", "load_scene"]

TASKS = ("fixed_point", "simulate")
"""Valid values of ``[compute].task``."""

MAX_STRIDES = 1_000_000
"""Largest ``[compute].strides``."""

MAX_SCENE_BYTES = 1 << 20
"""Largest scene file read [bytes] (the shipped ones are about 2 KB)."""

MAX_KEY_PARTS = 32
"""Most dot-separated parts of a TOML key (``a.b.c`` has 3) a scene may have; a scene's keys
have at most 2.  The TOML parser's time grows with the square of a dotted key's parts (a
20 KB key ``a.a.a...`` took 41 s), so longer chains are refused before parsing."""

# MAX_KEY_PARTS or more dots joining key parts (bare or quoted, at most 256 characters),
# anywhere in the text.  Possessive quantifiers, and a start only where no part or dot
# precedes, keep the search linear in the text's length.
_LONG_DOTTED_KEY = re.compile(
    r"(?<![A-Za-z0-9_\-\"'.])"
    r"(?:(?:[A-Za-z0-9_-]++|\"[^\"\n]{0,256}+\"|'[^'\n]{0,256}+')[ \t]*+\.[ \t]*+)"
    rf"{{{MAX_KEY_PARTS},}}+"
)

_TABLES = {
    "scene": True,
    "model": False,
    "parameters": True,
    "initial": True,
    "compute": False,
    "reference": False,
    "terrain": False,
}
_SCENE_KEYS = ("model", "description", "source")
_INITIAL_KEYS = ("state", "phase")
_REFERENCE_KEYS = ("state", "section", "multipliers", "step_time", "tolerance", "note")


def _is_real(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _too_large(value: Any) -> bool:
    """An integer beyond the range of a float (TOML integers are unbounded)."""
    if not isinstance(value, int) or isinstance(value, bool) or value.bit_length() < 1000:
        return False
    try:
        float(value)
    except OverflowError:
        return True
    return False


def _digits(value: int) -> str:
    return f"an integer of about {int(value.bit_length() * 0.30103) + 1} digits"


@dataclasses.dataclass(frozen=True)
class ComputeSettings:
    """What to compute for a scene and how to integrate (the ``[compute]`` table).

    Attributes
    ----------
    task : str
        ``"fixed_point"`` or ``"simulate"``.
    strides : int
        fixed_point: the period (>= 1); simulate: strides to run (0: integrate to ``t_max``).
    method : str
        ``"DOP853"``, ``"RK45"``, ``"RK4"`` or ``"Euler"``.
    rtol, atol : float
        tolerances of the adaptive methods, > 0.
    t_max : float
        time limit per stride (the whole run when ``strides == 0``) [s], > 0.
    first_step : float or None
        initial step [s], > 0; the fixed step of ``"RK4"`` / ``"Euler"``, which require it.
    tol : float
        residual tolerance of the fixed-point search, max|P^k(z) - z| in section units, > 0
        (``walker find``; its ``--tol`` overrides it).
    """

    task: str = "fixed_point"
    strides: int = 1
    method: str = "DOP853"
    rtol: float = 1e-12
    atol: float = 1e-12
    t_max: float = 20.0
    first_step: float | None = None
    tol: float = 1e-12

    def __post_init__(self) -> None:
        if self.task not in TASKS:
            raise ValueError(f"`task` must be one of {', '.join(TASKS)}, got {self.task!r}")
        if not isinstance(self.strides, int) or isinstance(self.strides, bool):
            raise ValueError(f"`strides` must be an integer, got {self.strides!r}")
        if self.task == "fixed_point" and self.strides < 1:
            raise ValueError(
                f"`strides` (the period) must be >= 1 for task fixed_point, got {self.strides}"
            )
        if self.strides < 0:
            raise ValueError(f"`strides` must be >= 0, got {self.strides}")
        if self.strides > MAX_STRIDES:
            raise ValueError(f"`strides` must be <= {MAX_STRIDES:,}, got {self.strides}")
        if self.method not in METHODS:  # before the numbers: the message lists the methods
            check_solver_settings(self.method, 1.0, 1.0, 1.0)
        for name in ("rtol", "atol", "t_max", "tol"):
            value = getattr(self, name)
            if not _is_real(value) or not math.isfinite(value) or value <= 0:
                raise ValueError(f"`{name}` must be a finite number > 0, got {value!r}")
            object.__setattr__(self, name, float(value))
        if self.first_step is not None:
            v = self.first_step
            if not _is_real(v) or not math.isfinite(v) or v <= 0:
                raise ValueError(f"`first_step` must be a finite number > 0, got {v!r}")
            object.__setattr__(self, "first_step", float(v))
        # The solver's own rules (rtol >= 100 eps, a fixed step for RK4 and Euler) are the
        # integrator's, written once there: a scene is refused by the rule a run would apply.
        check_solver_settings(self.method, self.rtol, self.atol, self.first_step)

    @property
    def method_code(self) -> int:
        """Integer code of ``method`` used by the compiled integrator (walker.status)."""
        return METHODS[self.method]


@dataclasses.dataclass(frozen=True, eq=False)
class Scene:
    """A loaded scene; build with :func:`load_scene`.

    Compared by identity (it holds an array); compare ``params``, ``state`` etc. directly.

    Attributes
    ----------
    name : str
        file stem.
    path : pathlib.Path
    model : str
        key of :data:`walker.params.PARAMS`.
    description, source : str
        ``""`` when the file gives none.
    params : dataclass
        instance of the model's parameter class.
    state : ndarray, shape (n_x,)
        initial full state (read-only), order :data:`STATE_NAMES` ``[model]``.
    phase : int or None
        initial phase index; None when the file gives none (a run then starts in the
        model's phase for ``state``, :meth:`walker.models.WalkerModel.start_phase`).
    compute : ComputeSettings
    reference : dict or None
        ``[reference]`` with arrays for ``state``, ``section`` (float) and ``multipliers``
        (complex), floats for ``step_time`` and ``tolerance``.
    swing_scuff : str
        ``[model] swing_scuff``: ``"trip"`` (default) or ``"ignore"``; :attr:`walker_model`
        is the model under that convention.
    terrain_table : dict or None
        the ``[terrain]`` table as read (validated); None when the file has none.
    """

    name: str
    path: Path
    model: str
    description: str
    source: str
    params: Any
    state: np.ndarray
    phase: int | None
    compute: ComputeSettings
    reference: dict | None
    swing_scuff: str = "trip"
    terrain_table: dict | None = None

    @property
    def terrain(self):
        """The scene's ground, a :class:`walker.simulation.terrain.Terrain` from ``[terrain]``
        (``slope_mean`` defaulting to the parameters' slope); the plane without one."""
        from walker.simulation.terrain import Terrain

        return Terrain.from_table(
            self.terrain_table or {"kind": "plane"}, getattr(self.params, "slope", 0.0)
        )

    @property
    def state_names(self) -> tuple[str, ...]:
        """Names of the state components."""
        return STATE_NAMES[self.model]

    @property
    def walker_model(self):
        """The :class:`walker.models.WalkerModel` to run the scene with: ``model`` under the
        scene's conventions (``swing_scuff``)."""
        from walker.models import get_model

        return get_model(self.model, swing_scuff=self.swing_scuff)

    def replace_params(self, **changes: Any) -> Scene:
        """A copy whose parameters have ``changes`` applied (validated by the params class)."""
        return dataclasses.replace(self, params=self.params.replace(**changes))


# ---- loading ---------------------------------------------------------------------------------
def _shown(value: Any) -> str:
    """``value`` for a one-line message: its repr, cut short."""
    text = repr(value) if not _too_large(value) else _digits(value)
    return text if len(text) <= 80 else text[:77] + "..."


class _Reader:
    """Validates the parsed tables of one file, prefixing every error with the file name."""

    def __init__(self, path: str) -> None:
        self.path = path

    def error(self, where: str, message: str) -> ValueError:
        prefix = f"{self.path}: [{where}] " if where else f"{self.path}: "
        return ValueError(prefix + message)

    def table(self, doc: Mapping[str, Any], name: str) -> dict[str, Any] | None:
        if name not in doc:
            if _TABLES[name]:
                raise self.error("", f"missing required table [{name}]")
            return None
        value = doc[name]
        if not isinstance(value, dict):
            raise self.error("", f"`{name}` must be a table [{name}], got {type(value).__name__}")
        return value

    def keys(self, where: str, table: Mapping[str, Any], valid: tuple[str, ...]) -> None:
        unknown = [k for k in table if k not in valid]
        if unknown:
            raise self.error(
                where,
                f"unknown key{'s' if len(unknown) > 1 else ''} "
                f"{', '.join(f'`{k}`' for k in unknown)}{did_you_mean(unknown[0], valid)}; "
                f"valid keys: {', '.join(valid)}",
            )

    def string(self, where: str, table: Mapping[str, Any], key: str, required: bool) -> str:
        if key not in table:
            if required:
                raise self.error(where, f"missing required key `{key}`")
            return ""
        value = table[key]
        if not isinstance(value, str):
            raise self.error(where, f"`{key}` must be a string, got {value!r}")
        return value

    def number(self, where: str, key: str, value: Any, positive: bool = False) -> float:
        if not _is_real(value):
            raise self.error(where, f"`{key}` must be a number, got {_shown(value)}")
        if _too_large(value):
            raise self.error(where, f"`{key}` must be finite, got {_digits(value)}")
        value = float(value)
        if not math.isfinite(value):
            raise self.error(where, f"`{key}` must be finite, got {value!r}")
        if positive and value <= 0:
            raise self.error(where, f"`{key}` must be > 0, got {value!r}")
        return value

    def vector(self, where: str, key: str, value: Any, length: int | None) -> np.ndarray:
        if not isinstance(value, list):
            raise self.error(where, f"`{key}` must be an array of numbers, got {value!r}")
        out = np.array([self.number(where, f"{key}[{i}]", v) for i, v in enumerate(value)])
        if length is not None and out.shape != (length,):
            raise self.error(where, f"`{key}` must have {length} entries, got {len(value)}")
        return out


def _parameters(
    reader: _Reader, model: str, table: Mapping[str, Any], overrides: Mapping[str, Any]
) -> Any:
    cls = PARAMS[model]
    names = cls.names()
    values = dict(table)
    where = "parameters"
    if "preset" in values:
        preset = values.pop("preset")
        if not isinstance(preset, str) or preset not in cls.PRESETS:
            raise reader.error(
                where,
                f"`preset` must be one of {', '.join(cls.PRESETS)} for model {model}, "
                f"got {preset!r}{did_you_mean(preset, cls.PRESETS)}",
            )
        reader.keys(where, values, names)
        values = {**cls.preset(preset).to_dict(), **values}
    else:
        reader.keys(where, values, names + ("preset",))
        missing = [n for n in names if n not in values]
        if missing:
            raise reader.error(
                where,
                f"missing key{'s' if len(missing) > 1 else ''} "
                f"{', '.join(f'`{k}`' for k in missing)} (give every parameter of "
                f"{cls.__name__}, or `preset` = one of {', '.join(cls.PRESETS)})",
            )
    for name, value in values.items():
        if not _is_real(value):
            raise reader.error(where, f"`{name}` must be a number, got {_shown(value)}")
        if _too_large(value):
            raise reader.error(where, f"`{name}` must be finite, got {_digits(value)}")
    context = ""
    if overrides:
        context = f"(with overrides {', '.join(f'`{k}`' for k in overrides)}) "
        values.update(overrides)
    try:
        return cls.from_dict(values)
    except (TypeError, ValueError) as exc:
        raise reader.error(where, context + str(exc)) from None


def _overrides(reader: _Reader, model: str, overrides: Any) -> dict[str, float]:
    if overrides is None:
        return {}
    if not isinstance(overrides, Mapping):
        raise TypeError(f"`overrides` must be a mapping of name to value, got {overrides!r}")
    names = PARAMS[model].names()
    out = {}
    for name, value in overrides.items():
        if name not in names:
            raise reader.error(
                "overrides",
                f"unknown parameter `{name}` for model {model}{did_you_mean(name, names)}; "
                f"valid names: {', '.join(names)}",
            )
        if isinstance(value, str):
            try:
                value = float(value)
            except ValueError:
                raise reader.error(
                    "overrides", f"`{name}` must be a number, got {value!r}"
                ) from None
        elif not _is_real(value) and not isinstance(value, np.floating | np.integer):
            raise reader.error("overrides", f"`{name}` must be a number, got {_shown(value)}")
        if _too_large(value):
            raise reader.error("overrides", f"`{name}` must be finite, got {_digits(value)}")
        out[name] = float(value)
    return out


def _compute(reader: _Reader, model: str, table: Mapping[str, Any] | None) -> ComputeSettings:
    table = dict(table or {})
    valid = tuple(f.name for f in dataclasses.fields(ComputeSettings))
    reader.keys("compute", table, valid)
    for key, value in table.items():
        if _too_large(value):
            raise reader.error("compute", f"`{key}` must be finite, got {_digits(value)}")
    if not HAS_STRIDES[model]:
        table.setdefault("task", "simulate")
        table.setdefault("strides", 0)
        if table["task"] != "simulate" or table["strides"] != 0:
            raise reader.error(
                "compute",
                f'model {model} has no strides: use task = "simulate" and strides = 0 '
                f"(integrate to t_max), got task = {table['task']!r}, "
                f"strides = {table['strides']!r}",
            )
    try:
        return ComputeSettings(**table)
    except (TypeError, ValueError) as exc:
        raise reader.error("compute", str(exc)) from None


def _reference(reader: _Reader, n_x: int, table: Mapping[str, Any] | None) -> dict[str, Any] | None:
    if table is None:
        return None
    where = "reference"
    reader.keys(where, table, _REFERENCE_KEYS)
    if "tolerance" not in table:
        raise reader.error(where, "missing required key `tolerance`")
    out: dict[str, Any] = {"tolerance": reader.number(where, "tolerance", table["tolerance"], True)}
    if "state" in table:
        out["state"] = reader.vector(where, "state", table["state"], n_x)
    if "section" in table:
        out["section"] = reader.vector(where, "section", table["section"], None)
    if "multipliers" in table:
        pairs = table["multipliers"]
        if not isinstance(pairs, list) or not all(
            isinstance(p, list) and len(p) == 2 for p in pairs
        ):
            raise reader.error(
                where, f"`multipliers` must be an array of [re, im] pairs, got {pairs!r}"
            )
        out["multipliers"] = np.array(
            [
                complex(
                    reader.number(where, f"multipliers[{i}][0]", re),
                    reader.number(where, f"multipliers[{i}][1]", im),
                )
                for i, (re, im) in enumerate(pairs)
            ],
            dtype=np.complex128,
        )
    if "step_time" in table:
        out["step_time"] = reader.number(where, "step_time", table["step_time"], True)
    if "note" in table:
        out["note"] = reader.string(where, table, "note", required=False)
    return out


def _phase_list(phases: tuple[str, ...]) -> str:
    listed = ", ".join(f"{i} {name!r}" for i, name in enumerate(phases[:4]))
    return listed + (f", ... ({len(phases)} phases)" if len(phases) > 4 else "")


def load_scene(path: str | os.PathLike, overrides: Mapping[str, Any] | None = None) -> Scene:
    """Read and validate a scene file.

    Parameters
    ----------
    path : str or path-like
        the TOML file.
    overrides : mapping of str to float or str, optional
        parameter name -> value applied on top of ``[parameters]`` (e.g. from the CLI's
        ``--set NAME=VALUE``; strings are parsed as numbers). Validated with the rest.

    Returns
    -------
    Scene

    Raises
    ------
    TypeError
        ``path`` is not a str or path-like.
    FileNotFoundError
        ``path`` does not exist.
    OSError
        ``path`` cannot be read (its ``filename`` names it), e.g. a name too long, or is not a
        regular file (a directory, a device, a FIFO: the message says which).
    ValueError
        invalid TOML or an invalid scene (the message names the file and the key path).

    Examples
    --------
    >>> scene = load_scene("gaits/kneed_hsu.toml")
    >>> scene.params.mass_hip, scene.state_names[:3]
    (0.5, ('q1', 'q2', 'q3'))
    """
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`path` must be a str or os.PathLike, got {type(path).__name__}")
    path_obj = Path(path)
    shown = os.fspath(path)
    if not isinstance(shown, str):
        raise TypeError(f"`path` must name a file as str, got {type(shown).__name__}")
    if not path_obj.is_file():  # OSError (a name too long, ...) names the path
        if not path_obj.exists():
            raise FileNotFoundError(f"scene file not found: {shown}")
        raise _not_a_file(path_obj, shown)
    reader = _Reader(shown)
    with path_obj.open("rb") as fh:
        data = fh.read(MAX_SCENE_BYTES + 1)
    if len(data) > MAX_SCENE_BYTES:
        raise reader.error(
            "", f"a scene file has at most {MAX_SCENE_BYTES:,} bytes; this is larger"
        )
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise reader.error(
            "", f"invalid TOML: not UTF-8 text ({exc.reason} at byte {exc.start})"
        ) from None
    long_key = _LONG_DOTTED_KEY.search(text)
    if long_key is not None:
        line = text.count("\n", 0, long_key.start()) + 1
        raise reader.error(
            "",
            f"a dotted key of more than {MAX_KEY_PARTS} parts at line {line}; refused before "
            "parsing (a scene's keys have at most 2)",
        )
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise reader.error("", f"invalid TOML: {exc}") from None
    except RecursionError:
        raise reader.error("", "invalid TOML: arrays or inline tables nested too deeply") from None
    except ValueError as exc:  # e.g. an integer beyond Python's digit limit
        raise reader.error("", f"invalid TOML: {str(exc).splitlines()[0]}") from None

    unknown = [k for k in doc if k not in _TABLES]
    if unknown:
        raise reader.error(
            "",
            f"unknown table{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(f'[{k}]' for k in unknown)}{did_you_mean(unknown[0], _TABLES)}; "
            "valid tables: "
            f"{', '.join(f'[{k}]' for k in _TABLES)}",
        )
    scene_t = reader.table(doc, "scene")
    params_t = reader.table(doc, "parameters")
    initial_t = reader.table(doc, "initial")
    compute_t = reader.table(doc, "compute")
    reference_t = reader.table(doc, "reference")
    model_t = reader.table(doc, "model") or {}

    reader.keys("scene", scene_t, _SCENE_KEYS)
    model = reader.string("scene", scene_t, "model", required=True)
    if model not in PARAMS:
        raise reader.error(
            "scene",
            f"`model` must be one of {', '.join(PARAMS)}, got {model!r}"
            f"{did_you_mean(model, PARAMS)}",
        )
    description = reader.string("scene", scene_t, "description", required=False)
    source = reader.string("scene", scene_t, "source", required=False)

    params = _parameters(reader, model, params_t, _overrides(reader, model, overrides))

    n_x = len(STATE_NAMES[model])
    reader.keys("initial", initial_t, _INITIAL_KEYS)
    if "state" not in initial_t:
        raise reader.error("initial", "missing required key `state`")
    state = reader.vector("initial", "state", initial_t["state"], n_x)
    state.setflags(write=False)
    phase = initial_t.get("phase")
    if phase is not None:
        from walker.models import get_model

        if not isinstance(phase, int) or isinstance(phase, bool) or phase < 0:
            raise reader.error("initial", f"`phase` must be an integer >= 0, got {_shown(phase)}")
        phases = get_model(model).phase_names
        if phase >= len(phases):
            raise reader.error(
                "initial",
                f"`phase` must be < {len(phases)}, the number of phases of model {model} "
                f"({_phase_list(phases)}), got {_shown(phase)}",
            )

    return Scene(
        name=path_obj.stem,
        path=path_obj,
        model=model,
        description=description,
        source=source,
        params=params,
        state=state,
        phase=phase,
        compute=_compute(reader, model, compute_t),
        reference=_reference(reader, n_x, reference_t),
        swing_scuff=_swing_scuff(reader, model, model_t),
        terrain_table=_terrain(reader, params, reader.table(doc, "terrain")),
    )


def _not_a_file(path: Path, shown: str) -> OSError:
    """The error for a scene path that exists but is not a regular file (never opened: a
    FIFO would block), saying what it is."""
    import errno
    import stat

    mode = path.stat().st_mode
    kinds = (
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISSOCK, "a socket"),
    )
    kind = next((name for test, name in kinds if test(mode)), "a special file")
    code = errno.EISDIR if stat.S_ISDIR(mode) else errno.EINVAL
    return OSError(code, f"is {kind}, not a regular file", shown)


def _terrain(reader: _Reader, params: Any, table: Mapping[str, Any] | None) -> dict | None:
    """The ``[terrain]`` table, checked by building its
    :class:`walker.simulation.terrain.Terrain`."""
    if table is None:
        return None
    from walker.simulation.terrain import Terrain

    try:
        Terrain.from_table(dict(table), getattr(params, "slope", 0.0))
    except (TypeError, ValueError) as exc:
        raise reader.error("terrain", str(exc)) from None
    return dict(table)


def _swing_scuff(reader: _Reader, model: str, table: Mapping[str, Any]) -> str:
    from walker.models import get_model

    reader.keys("model", table, ("swing_scuff",))
    value = table.get("swing_scuff", "trip")
    try:
        get_model(model, swing_scuff=value)
    except (TypeError, ValueError) as exc:
        raise reader.error("model", str(exc)) from None
    return value
