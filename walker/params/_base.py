"""What every parameter class shares: the field helper ``_param`` (unit, doc, bounds in the
field's metadata), the checks ``__post_init__`` runs (``_check_number``, ``_check_bounds``,
``_rule_text`` for the messages) and the base class :class:`_Params` (names, units, docs,
bounds, conversions to and from ``p``, presets).  The model classes live in
:mod:`walker.params.passive`, :mod:`walker.params.coulomb` and :mod:`walker.params.actuated`.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections.abc import Mapping
from typing import Any, ClassVar

import numpy as np

from walker._suggest import did_you_mean

_HALF_PI = 0.5 * math.pi


def _param(
    unit: str,
    doc: str,
    lo: float | None = None,
    hi: float | None = None,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    bounds_text: str | None = None,
) -> Any:
    """A dataclass field without default, carrying unit, doc and bounds in its metadata.

    ``bounds_text`` replaces the printed bounds in error messages (e.g. ``"pi/2"``).
    """
    return dataclasses.field(
        metadata={
            "unit": unit,
            "doc": doc,
            "bounds": (lo, hi),
            "lo_open": lo_open,
            "hi_open": hi_open,
            "bounds_text": bounds_text,
        }
    )


def _slope_field() -> Any:
    return _param(
        "rad",
        "ramp angle, positive downhill in the walking direction",
        -_HALF_PI,
        _HALF_PI,
        lo_open=True,
        hi_open=True,
        bounds_text="(-pi/2, pi/2)",
    )


def _damping_field(joint: str, rate: str) -> Any:
    return _param(
        "N m s/rad",
        f"viscous damping of the {joint} joint, torque -b ({rate}) on the distal link",
        0.0,
    )


def _check_number(name: str, value: Any) -> float:
    """Return ``value`` as a finite float, or raise naming ``name``."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"`{name}` must be a real number, got {type(value).__name__} {value!r}")
    try:
        value = float(value)
    except OverflowError:
        raise ValueError(f"`{name}` must be finite, got an integer too large for a float") from None
    if not math.isfinite(value):
        raise ValueError(f"`{name}` must be finite, got {value!r}")
    return value


def _rule_text(meta: Mapping[str, Any]) -> str:
    """Human-readable bound rule, e.g. ``"> 0"`` or ``"in (-pi/2, pi/2)"``."""
    lo, hi = meta["bounds"]
    if meta.get("bounds_text"):
        return "in " + meta["bounds_text"]
    if lo is not None and hi is not None:
        left = "(" if meta["lo_open"] else "["
        right = ")" if meta["hi_open"] else "]"
        return f"in {left}{lo:g}, {hi:g}{right}"
    if lo is not None:
        return f"{'>' if meta['lo_open'] else '>='} {lo:g}"
    if hi is not None:
        return f"{'<' if meta['hi_open'] else '<='} {hi:g}"
    return ""


def _check_bounds(name: str, value: float, meta: Mapping[str, Any]) -> None:
    lo, hi = meta["bounds"]
    bad = False
    if lo is not None:
        bad |= value <= lo if meta["lo_open"] else value < lo
    if hi is not None:
        bad |= value >= hi if meta["hi_open"] else value > hi
    if bad:
        raise ValueError(f"`{name}` must be {_rule_text(meta)} [{meta['unit']}], got {value!r}")


def _coulomb_field(joint: str, rate: str) -> Any:
    return _param(
        "N m",
        f"Coulomb (dry) friction torque of the {joint} joint: -F_s sgn({rate}) while it slips, "
        "up to F_s while it sticks",
        0.0,
    )


class _Params:
    """Behaviour shared by every parameter dataclass (subclasses are frozen dataclasses).

    Subclass contract:

    1. be decorated ``@dataclasses.dataclass(frozen=True)`` with every field made by
       ``_param`` (unit, doc, bounds; no default), in the canonical kernel order;
    2. set ``MODEL`` (the key in :data:`PARAMS`) and ``PRESETS`` (names of the preset
       classmethods, each callable with no argument);
    3. put cross-field rules in ``_check_relations``, raising ``ValueError`` that names the
       fields and the rule.
    """

    MODEL: ClassVar[str] = ""
    PRESETS: ClassVar[tuple[str, ...]] = ()

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            value = _check_number(f.name, getattr(self, f.name))
            _check_bounds(f.name, value, f.metadata)
            object.__setattr__(self, f.name, value)
        self._check_relations()

    def _check_relations(self) -> None:
        """Cross-field rules; the base class has none."""

    # ---- names, units, docs -------------------------------------------------------------
    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Field names in the canonical order of ``p`` (read once per class)."""
        names = cls.__dict__.get("_field_names")
        if names is None:
            names = tuple(f.name for f in dataclasses.fields(cls))  # type: ignore[arg-type]
            cls._field_names = names
        return names

    @classmethod
    def units(cls) -> dict[str, str]:
        """Field name -> unit, in canonical order."""
        return {f.name: f.metadata["unit"] for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def docs(cls) -> dict[str, str]:
        """Field name -> one-line description, in canonical order."""
        return {f.name: f.metadata["doc"] for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def bounds(cls) -> dict[str, tuple[float | None, float | None]]:
        """Field name -> ``(lo, hi)`` (``None`` where unbounded); see the metadata for openness."""
        return {f.name: f.metadata["bounds"] for f in dataclasses.fields(cls)}  # type: ignore[arg-type]

    @classmethod
    def n_params(cls) -> int:
        """Length of the parameter vector ``p``."""
        return len(dataclasses.fields(cls))  # type: ignore[arg-type]

    # ---- conversions --------------------------------------------------------------------
    def as_array(self) -> np.ndarray:
        """The parameter vector ``p``, shape ``(n_params,)``, float64, canonical order."""
        return np.array([getattr(self, n) for n in self.names()], dtype=np.float64)

    @classmethod
    def from_array(cls, p: Any):
        """Build from a parameter vector ``p`` of shape ``(n_params,)`` (validated)."""
        arr = np.asarray(p)
        n = cls.n_params()
        if arr.shape != (n,):
            raise ValueError(
                f"`p` must have shape ({n},) for {cls.__name__} "
                f"({', '.join(cls.names())}), got shape {arr.shape}"
            )
        if not np.issubdtype(arr.dtype, np.number) or np.issubdtype(arr.dtype, np.complexfloating):
            raise TypeError(f"`p` must hold real numbers, got dtype {arr.dtype}")
        return cls(*(float(v) for v in arr.astype(np.float64)))

    def to_dict(self) -> dict[str, float]:
        """Field name -> value (float), in canonical order."""
        return {n: getattr(self, n) for n in self.names()}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]):
        """Build from a mapping holding every field and nothing else (validated)."""
        if not isinstance(d, Mapping):
            raise TypeError(f"`d` must be a mapping, got {type(d).__name__}")
        names = cls.names()
        unknown = [k for k in d if k not in names]
        missing = [n for n in names if n not in d]
        if unknown:
            raise ValueError(
                f"unknown {cls.__name__} key(s) {', '.join(f'`{k}`' for k in unknown)}"
                f"{did_you_mean(unknown[0], names)}; valid keys: {', '.join(names)}"
            )
        if missing:
            raise ValueError(
                f"missing {cls.__name__} key(s) {', '.join(f'`{k}`' for k in missing)}"
            )
        return cls(**{n: d[n] for n in names})

    def replace(self, **changes: Any):
        """A copy with ``changes`` applied and validated; an unknown name raises ValueError."""
        names = self.names()
        unknown = [k for k in changes if k not in names]
        if unknown:
            raise ValueError(
                f"unknown {type(self).__name__} parameter(s) "
                f"{', '.join(f'`{k}`' for k in unknown)}{did_you_mean(unknown[0], names)}; "
                f"valid names: {', '.join(names)}"
            )
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]

    def _replace_validated(self, **changes: float):
        """A copy with ``changes`` applied WITHOUT validation, for values already validated
        by :meth:`replace` (a sweep validates every grid point before any work, then its
        workers rebuild the points cheaply).  Not for user input."""
        new = object.__new__(type(self))
        fields = new.__dict__
        own = self.__dict__
        for name in self.names():  # every field of a validated instance is a float already
            fields[name] = own[name]
        for name, value in changes.items():
            if name not in own:
                raise ValueError(f"unknown {type(self).__name__} parameter `{name}`")
            fields[name] = float(value)
        return new

    @classmethod
    def preset(cls, name: str, **changes: Any):
        """The published parameter set ``name`` (one of ``PRESETS``), with ``changes`` applied."""
        if name not in cls.PRESETS:
            raise ValueError(
                f"unknown {cls.__name__} preset `{name}`{did_you_mean(name, cls.PRESETS)}; "
                f"valid presets: {', '.join(cls.PRESETS)}"
            )
        base = getattr(cls, name)()
        return base.replace(**changes) if changes else base


def _relation_error(rule: str, got: str) -> ValueError:
    return ValueError(f"{rule}, got {got}")
