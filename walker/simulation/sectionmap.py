"""The interface of the analysis layer to a section map, shared by every analysis module.

:mod:`walker.analysis.fixedpoint`, :mod:`walker.analysis.newton`, :mod:`walker.analysis.steppers`,
:mod:`walker.analysis.continuation` and :mod:`walker.analysis.basin` work on any
:class:`SectionMap` (a walker's :class:`~walker.simulation.stride.StrideMap`, or a toy map in the
tests) through the functions here:

* :func:`map_value` and :func:`map_jacobian`: the ``period``-fold map at a point, and with its
  Jacobian (the map's own, or central finite differences);
* :func:`eig_sorted`: Floquet multipliers sorted by decreasing modulus, with eigenvectors;
* the input checks of the public functions (``validate_*``, :func:`validate_positive`): they
  raise ``ValueError`` / ``TypeError`` naming the argument.
"""

from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import numpy as np

from walker._checks import MAX_BUDGET, as_vector, bounded_int
from walker._checks import positive as validate_positive
from walker.results import MapResult
from walker.status import Status

__all__ = [
    "JACOBIAN_MODES",
    "SectionMap",
    "eig_sorted",
    "map_jacobian",
    "map_value",
    "validate_int",
    "validate_jacobian_mode",
    "validate_max_evals",
    "validate_period",
    "validate_positive",
    "validate_section_map",
    "validate_z",
]

JACOBIAN_MODES = ("exact", "fd")


@runtime_checkable
class SectionMap(Protocol):
    """What the gait search needs from a section (stride) map.

    Rules an implementation must follow:

    1. ``n_z`` is the section dimension and ``section_names`` names its coordinates (length
       ``n_z``).
    2. ``section_map(z)`` with ``z`` of shape ``(n_z,)`` applies the map ``n_strides`` times and
       returns a :class:`~walker.results.MapResult`.  A failed stride has
       ``status != Status.COMPLETED`` and a NaN ``z``; it never raises for a state that merely
       does not walk.
    3. With ``jacobian=True`` the result carries ``jac``, the ``(n_z, n_z)`` derivative of the
       returned ``z`` with respect to the input ``z`` (for ``n_strides = k``: of the k-fold
       composition).
    4. ``parameter=value`` evaluates the map at another value of the continuation parameter
       without changing the object; ``None`` means ``parameter_value``.
    5. ``lift(z)`` gives the full state at the section point ``z``.
    6. ``parameter_name`` names the scalar continuation parameter (``"slope"`` for walkers),
       ``parameter_value`` is its current value, and ``with_parameter(value)`` returns a copy
       at another value.
    7. Instances should pickle (module-level classes) so that basin maps and sweeps can run on
       process pools.
    """

    n_z: int
    section_names: tuple[str, ...]
    parameter_name: str
    parameter_value: float

    def __call__(
        self,
        z: np.ndarray,
        *,
        jacobian: bool = False,
        n_strides: int = 1,
        parameter: float | None = None,
    ) -> MapResult: ...

    def lift(self, z: np.ndarray) -> np.ndarray: ...

    def with_parameter(self, value: float) -> SectionMap: ...


def validate_section_map(section_map) -> None:
    """A TypeError naming ``section_map`` when it lacks what :class:`SectionMap` requires."""
    missing = [
        name
        for name in ("n_z", "section_names", "lift", "with_parameter")
        if not hasattr(section_map, name)
    ]
    if not callable(section_map):
        missing.insert(0, "__call__")
    if missing:
        raise TypeError(
            f"`section_map` must be a SectionMap (such as walker.simulation.stride.StrideMap), got "
            f"{type(section_map).__name__} without {', '.join(missing)}"
        )


def validate_z(section_map: SectionMap, z: np.ndarray, name: str) -> np.ndarray:
    """``z`` as a finite float vector of shape ``(section_map.n_z,)``."""
    validate_section_map(section_map)
    z = as_vector(z, name)
    n_z = int(section_map.n_z)
    if z.shape != (n_z,):
        raise ValueError(f"`{name}` must have shape ({n_z},) (the map's n_z), got {z.shape}")
    if not all(map(math.isfinite, z.tolist())):
        raise ValueError(f"All components of `{name}` must be finite, got {z}")
    return z


def validate_period(period) -> int:
    """``period`` as an int in [1, :data:`walker._checks.MAX_BUDGET`]."""
    return bounded_int(period, "period", 1)


def validate_jacobian_mode(jacobian) -> str:
    """``jacobian``, one of :data:`JACOBIAN_MODES`."""
    if jacobian not in JACOBIAN_MODES:
        raise ValueError(f"`jacobian` must be one of {JACOBIAN_MODES}, got {jacobian!r}")
    return jacobian


def validate_max_evals(max_evals) -> int | None:
    """``max_evals`` as None or an int in [1, :data:`walker._checks.MAX_BUDGET`]."""
    if max_evals is None:
        return None
    if (
        isinstance(max_evals, bool)
        or not isinstance(max_evals, int | np.integer)
        or not 1 <= max_evals <= MAX_BUDGET
    ):
        raise ValueError(
            f"`max_evals` must be None or an integer >= 1 and <= {MAX_BUDGET}, got {max_evals!r}"
        )
    return int(max_evals)


def validate_int(value, name: str, minimum: int, maximum: int = MAX_BUDGET) -> int:
    """``value`` as an int in ``[minimum, maximum]`` (a budget: at most
    :data:`walker._checks.MAX_BUDGET` unless told)."""
    return bounded_int(value, name, minimum, maximum)


def map_value(section_map, z, period, parameter) -> MapResult:
    """The ``period``-fold map at ``z`` (at ``parameter``; None: the map's own value)."""
    return section_map(z, jacobian=False, n_strides=period, parameter=parameter)


def map_jacobian(section_map, z, period, parameter, mode, fd_step):
    """The ``period``-fold map at ``z`` and its Jacobian.

    Returns ``(result, jac, status)``; ``jac`` is None when a stride failed (``status`` says
    which).  ``mode="fd"`` uses central differences with step ``fd_step * max(1, |z_i|)``.
    """
    if mode == "exact":
        res = section_map(z, jacobian=True, n_strides=period, parameter=parameter)
        if not res.success:
            return res, None, res.status
        jac = np.asarray(res.jac, dtype=float)
        if not np.all(np.isfinite(jac)):
            return res, None, Status.NONFINITE
        return res, jac, Status.COMPLETED
    res = map_value(section_map, z, period, parameter)
    if not res.success:
        return res, None, res.status
    n = z.shape[0]
    jac = np.empty((n, n))
    for i in range(n):
        h = fd_step * max(1.0, abs(z[i]))
        zp = z.copy()
        zm = z.copy()
        zp[i] += h
        zm[i] -= h
        rp = map_value(section_map, zp, period, parameter)
        rm = map_value(section_map, zm, period, parameter)
        if not (rp.success and rm.success):
            return res, None, rp.status if not rp.success else rm.status
        jac[:, i] = (rp.z - rm.z) / (2.0 * h)
    return res, jac, Status.COMPLETED


# numpy's eigen-decomposition kernel (LAPACK geev), the one np.linalg.eig calls, without the
# checks and conversions around it (on a 3 x 3 matrix the kernel alone takes a quarter of
# np.linalg.eig's time); None where a numpy version does not have it.
_EIG = getattr(getattr(np.linalg, "_umath_linalg", None), "eig", None)


def eig_sorted(jac: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues (complex) sorted by decreasing modulus and the matching eigenvector columns.

    The values of ``np.linalg.eig``: for a finite float64 square matrix its kernel is called
    directly (complex results; ``np.linalg.eig`` would return real arrays where every
    eigenvalue is real, converted back to complex here), anything else goes through
    ``np.linalg.eig`` and its checks.
    """
    if (
        _EIG is not None
        and jac.__class__ is np.ndarray
        and jac.dtype == np.float64
        and jac.ndim == 2
        and jac.shape[0] == jac.shape[1] > 0
        and math.isfinite(float(jac.sum()))
    ):
        lam, vec = _EIG(jac, signature="d->DD")
        order = np.argsort(-np.abs(lam), kind="stable")
        return lam[order], vec[:, order]
    lam, vec = np.linalg.eig(jac)
    order = np.argsort(-np.abs(lam), kind="stable")
    if lam.dtype != np.complex128:  # real eigenvalues: numpy returns real arrays
        lam, vec = lam.astype(complex), vec.astype(complex)
    return lam[order], vec[:, order]
