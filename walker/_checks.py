"""Checks and scales shared by the simulation and analysis layers (walker.simulation.stride,
walker.analysis.fixedpoint, walker.analysis.sweep): an argument as a float vector with an error
naming it, a value's short repr for one-line messages, a positive number, and a walker's natural
time unit.  Imports nothing of walker, so every layer may use it."""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = [
    "MAX_BUDGET",
    "MAX_FIXED_STEPS",
    "MAX_STRIDE_STEPS",
    "as_vector",
    "bounded_int",
    "positive",
    "sample_rate",
    "short_repr",
    "time_scale",
]

MAX_BUDGET = 10**7
"""Largest count a caller may give for an iteration, evaluation, stride or point budget
(``max_iter``, ``max_evals``, ``period``, ``max_points``...).  Far beyond any useful search
(one stride-map evaluation takes a millisecond or more), it keeps every size the compiled
core derives from a budget in range; the binding checks the same bound
(``WKPY_MAX_BUDGET`` in ``walker/_core/_hybridbinding.h``)."""

MAX_STRIDE_STEPS = 10**5
"""Largest step budget of one stride of a stride map with an adaptive method
(:func:`walker.simulation.region.stride_max_steps` clamps to it): the shipped scenes' strides take
17-83 steps and their budgets are 1000-4000, so it binds only for a ``t_max`` of thousands
of the walker's time units (e.g. ``g = 1e12``), where a stride past it is a runaway."""

MAX_FIXED_STEPS = 10**6
"""Most steps of a fixed-step method (Euler, RK4) in one stride: a ``first_step`` that
needs more to reach ``t_max`` is refused before any work (a ValueError naming it)."""


def as_vector(value, name: str, length: int | None = None) -> np.ndarray:
    """``value`` as a float array, or an error naming the argument: a TypeError for what is
    not an array of real numbers (complex values are refused, never truncated to their real
    part), a ValueError for a number too large for a float or (with ``length``) a shape other
    than ``(length,)``."""

    def bad_type() -> TypeError:
        return TypeError(f"`{name}` must be an array of real numbers, got {short_repr(value)}")

    arr = value if isinstance(value, np.ndarray) else None
    if arr is None or arr.dtype.kind not in "fiu":
        try:
            arr = np.asarray(value)
        except (TypeError, ValueError):
            raise bad_type() from None
        if arr.dtype.kind == "c":
            raise TypeError(
                f"`{name}` must be real, got complex values (the imaginary part would be lost)"
            )
        if arr.dtype.kind == "O":  # e.g. Python ints too large for a float, or mixed objects
            try:
                arr = np.asarray(value, dtype=float)
            except OverflowError:
                raise ValueError(
                    f"All components of `{name}` must be finite; a number in it is too large "
                    "for a float"
                ) from None
            except (TypeError, ValueError):
                raise bad_type() from None
        elif arr.dtype.kind not in "fiub":
            raise bad_type()
    arr = arr.astype(float, copy=False)
    if length is not None and arr.shape != (length,):
        raise ValueError(f"`{name}` must have shape ({length},), got {arr.shape}")
    return arr


def short_repr(value) -> str:
    """``value``'s repr for a one-line message, cut short."""
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def time_scale(params) -> float:
    """sqrt(leg length / g) [s], the natural time unit of a walker.

    Raises ValueError when it is not a positive finite float (the quotient under- or
    overflows: ``leg_length = 4e-208`` with ``g = 2e233``), since the step budgets, the
    walking region's rate scale and the search's tolerances are all measured in it.
    ``inf`` for ``g = 0`` (allowed for the double pendulum only).
    """
    length = getattr(params, "leg_length", None)
    name = "leg_length"
    if length is None:
        length = getattr(params, "length_1", 1.0) + getattr(params, "length_2", 0.0)
        name = "length_1 + length_2"
    if params.g == 0.0:  # allowed for the double pendulum: no gravity, no time unit
        return math.inf
    scale = float(np.sqrt(length / params.g))
    if not (math.isfinite(scale) and scale > 0.0):
        raise ValueError(
            f"`{name}` = {length:g} m and `g` = {params.g:g} m/s^2 give a time scale "
            f"sqrt({name} / g) = {scale:g} s, outside the floating-point range; bring them "
            f"closer together ({name} / g must lie between about 5e-324 and 1.8e308 s^2)"
        )
    return scale


def positive(value, name: str, unit: str = "") -> float:
    """``value`` as a positive finite float, or an error naming ``name``: a TypeError for what
    is not a real number, a ValueError otherwise (``unit``, e.g. ``" [Hz]"``, follows the
    rule in the message)."""
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(
            f"`{name}` must be a real number{unit}, got {type(value).__name__} {value!r}"
        )
    try:
        out = float(value)
    except OverflowError:
        raise ValueError(
            f"`{name}` must be positive and finite{unit}, got an integer too large for a float"
        ) from None
    if not (math.isfinite(out) and out > 0):
        raise ValueError(f"`{name}` must be positive and finite{unit}, got {out}")
    return out


def sample_rate(value) -> float:
    """``sample_rate`` [Hz] as a positive finite float, or an error naming it."""
    return positive(value, "sample_rate", " [Hz]")


def bounded_int(value, name: str, minimum: int, maximum: int = MAX_BUDGET) -> int:
    """``value`` as an int in ``[minimum, maximum]``, or a ValueError naming ``name`` and the
    range (a bool or a non-integer is refused too)."""
    if (
        isinstance(value, bool | np.bool_)
        or not isinstance(value, numbers.Integral)
        or not minimum <= value <= maximum
    ):
        raise ValueError(
            f"`{name}` must be an integer >= {minimum} and <= {maximum}, got {short_repr(value)}"
        )
    return int(value)
