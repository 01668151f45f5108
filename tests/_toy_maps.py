"""Toy section maps implementing :class:`walker.analysis.fixedpoint.SectionMap` for the gait-search
tests.

Module-level classes so that they pickle (process pools in the basin tests).  Each carries a
continuation parameter, a ``lift`` (here the section point itself with the stride count
appended, so that ``state`` differs from ``section`` in shape) and optional "falling" regions
that return a failure status and a NaN point, like a walker that falls.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from walker.results import MapResult
from walker.status import Status


def _fail(n_z: int, status: Status, n_done: int) -> MapResult:
    nan = np.full(n_z, np.nan)
    return MapResult(status, nan, None, float(n_done), np.full(n_z + 1, np.nan))


def _completed(section_map, z, jac, jacobian: bool, n_strides: int) -> MapResult:
    """``n_strides`` strides of ``section_map`` completed at section point ``z`` (state: its
    lift), with the Jacobian ``jac`` when ``jacobian`` asks for it."""
    return MapResult(
        Status.COMPLETED, z, jac if jacobian else None, float(n_strides), section_map.lift(z)
    )


class _Continued:
    """The continuation part of :class:`walker.analysis.fixedpoint.SectionMap` for a frozen
    dataclass whose field named ``parameter_name`` is the continuation parameter."""

    @property
    def parameter_value(self) -> float:
        return getattr(self, self.parameter_name)

    def with_parameter(self, value: float):
        return replace(self, **{self.parameter_name: float(value)})


@dataclass(frozen=True)
class HenonMap(_Continued):
    """Hénon map ``(x, y) -> (1 - a x^2 + y, b x)`` with continuation parameter ``a``.

    ``fall_radius``: a stride that starts with ``max|z| > fall_radius`` "falls forward".
    """

    a: float = 0.2
    b: float = 0.3
    fall_radius: float | None = None
    n_z: int = 2
    section_names: tuple[str, ...] = ("x", "y")
    parameter_name: str = "a"

    def lift(self, z):
        return np.append(np.asarray(z, dtype=float), 0.0)

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        a = self.a if parameter is None else float(parameter)
        b = self.b
        x, y = (float(v) for v in z)
        jac = np.eye(2)
        for k in range(n_strides):
            if self.fall_radius is not None and max(abs(x), abs(y)) > self.fall_radius:
                return _fail(2, Status.FELL_FORWARD, k)
            if jacobian:
                jac = np.array([[-2.0 * a * x, 1.0], [b, 0.0]]) @ jac
            x, y = 1.0 - a * x * x + y, b * x
        return _completed(self, np.array([x, y]), jac, jacobian, n_strides)


def henon_fixed_points(a: float, b: float) -> np.ndarray:
    """Both fixed points of the Hénon map, rows ``(x, y)``.

    From ``x = 1 - a x^2 + b x``, i.e. ``a x^2 + (1 - b) x - 1 = 0``:
    ``x = (-(1 - b) ± sqrt((1 - b)^2 + 4 a)) / (2 a)``, ``y = b x``.  First row: the ``+`` root
    (the one that tends to ``1 / (1 - b)`` as ``a -> 0``).
    """
    d = np.sqrt((1 - b) ** 2 + 4 * a)
    xs = np.array([(-(1 - b) + d) / (2 * a), (-(1 - b) - d) / (2 * a)])
    return np.column_stack([xs, b * xs])


def henon_two_cycle(a: float, b: float) -> np.ndarray:
    """The period-2 orbit of the Hénon map, rows ``(x1, y1)`` and ``(x2, y2)`` (x1 < x2).

    Derivation: a 2-cycle has ``x2 = 1 - a x1^2 + b x2`` and ``x1 = 1 - a x2^2 + b x1``
    (using ``y1 = b x2``, ``y2 = b x1``).  Subtracting gives ``(x2 - x1)(1 - b) =
    a (x2 - x1)(x1 + x2)``, so for ``x1 != x2``: ``S = x1 + x2 = (1 - b) / a``.  Adding gives
    ``(1 - b) S = 2 - a (S^2 - 2 Q)`` with ``Q = x1 x2``, hence ``Q = ((1 - b)^2 - a) / a^2``.
    ``x1, x2`` are the roots of ``x^2 - S x + Q``, real iff ``4 a > 3 (1 - b)^2`` — the
    period-doubling value of the fixed point.
    """
    s = (1 - b) / a
    q = ((1 - b) ** 2 - a) / a**2
    d = np.sqrt(s * s - 4 * q)
    x1, x2 = (s - d) / 2, (s + d) / 2
    return np.array([[x1, b * x2], [x2, b * x1]])


@dataclass(frozen=True)
class LogisticMap(_Continued):
    """Logistic map ``z -> r z (1 - z)`` (1-D), parameter ``r``; falls when z leaves [0, 1]."""

    r: float = 2.5
    n_z: int = 1
    section_names: tuple[str, ...] = ("z",)
    parameter_name: str = "r"

    def lift(self, z):
        return np.append(np.asarray(z, dtype=float), 0.0)

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        r = self.r if parameter is None else float(parameter)
        x = float(z[0])
        d = 1.0
        for k in range(n_strides):
            if not 0.0 <= x <= 1.0:
                return _fail(1, Status.FELL_FORWARD, k)
            d *= r * (1.0 - 2.0 * x)
            x = r * x * (1.0 - x)
        if not 0.0 <= x <= 1.0:
            return _fail(1, Status.FELL_FORWARD, n_strides)
        return _completed(self, np.array([x]), np.array([[d]]), jacobian, n_strides)


@dataclass(frozen=True)
class ShiftMap(_Continued):
    """``z -> z + shift + wiggle sin(z)`` (1-D): no fixed point when ``|shift| > |wiggle|``."""

    shift: float = 1.0
    wiggle: float = 0.0
    n_z: int = 1
    section_names: tuple[str, ...] = ("z",)
    parameter_name: str = "shift"

    def lift(self, z):
        return np.asarray(z, dtype=float).copy()

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        c = self.shift if parameter is None else float(parameter)
        x = float(z[0])
        d = 1.0
        for _ in range(n_strides):
            d *= 1.0 + self.wiggle * np.cos(x)
            x = x + c + self.wiggle * np.sin(x)
        return _completed(self, np.array([x]), np.array([[d]]), jacobian, n_strides)


@dataclass(frozen=True)
class CubicBasinMap(_Continued):
    """``z -> c + (z - c) |z - c|^2`` in ``n_z`` dimensions, centre ``c = center``.

    The centre is a superattracting fixed point whose basin is exactly the open unit ball
    around it: the distance ``r`` to the centre maps to ``r^3`` along the same ray.  A stride
    that would end farther than ``fall_radius`` from the centre falls: ``FELL_BACKWARD`` when
    the ray points to negative first coordinate (relative to the centre), else
    ``FELL_FORWARD``.  So outside the unit ball the outcome is known in closed form too.
    The parameter ``fall_radius`` is the continuation parameter (unused by the tests).
    """

    center: tuple[float, ...] = (0.3, -0.2, 0.1)
    fall_radius: float = 2.0
    section_names: tuple[str, ...] = ("u", "v", "w")
    parameter_name: str = "fall_radius"

    @property
    def n_z(self) -> int:
        return len(self.center)

    def lift(self, z):
        return np.asarray(z, dtype=float).copy()

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        limit = self.fall_radius if parameter is None else float(parameter)
        c = np.asarray(self.center, dtype=float)
        w = np.asarray(z, dtype=float) - c
        n = w.shape[0]
        jac = np.eye(n)
        for k in range(n_strides):
            r2 = float(w @ w)
            w_next = w * r2
            if np.sqrt(float(w_next @ w_next)) > limit:
                status = Status.FELL_BACKWARD if w[0] < 0 else Status.FELL_FORWARD
                return _fail(n, status, k)
            if jacobian:
                jac = (r2 * np.eye(n) + 2.0 * np.outer(w, w)) @ jac
            w = w_next
        return _completed(self, c + w, jac, jacobian, n_strides)


def cubic_basin_toy(center):
    """A :class:`CubicBasinMap` about ``center`` and its fixed point, found from
    ``center + 0.1`` (checked to converge)."""
    from walker.analysis.fixedpoint import find_fixed_point

    m = CubicBasinMap(center=tuple(center))
    fp = find_fixed_point(m, np.asarray(center) + 0.1)
    assert fp.success
    return m, fp
