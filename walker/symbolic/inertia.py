"""Inertia tensors of simple bodies and the parallel-axis theorem (numeric, numpy only).

Conventions (after Craig, *Introduction to Robotics*, ch. 6 [1]_): the
inertia tensor of a body about a point is

    I = integral rho(r) (|r|^2 I_3 - r r^T) dV,

so its off-diagonal entries are the *negated* products of inertia, ``I[0, 1] = -int x y dm``.
Moved from the centre of mass ``C`` to a frame ``A`` parallel to it whose origin sees the
centre of mass at ``p`` (the parallel-axis theorem in matrix form)

    I_A = I_C + m (p^T p I_3 - p p^T).

Nothing here imports sympy; the functions are used by tests and by anyone lumping bodies.

References
----------
.. [1] J. J. Craig, *Introduction to Robotics: Mechanics and Control*, 3rd ed., section 6.3
   (inertia tensor of a box, parallel-axis theorem).
"""

from __future__ import annotations

import numpy as np

__all__ = ["rod_inertia", "box_inertia", "parallel_axis", "planar_parallel_axis"]


def _positive(name: str, value, unit: str) -> float:
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise ValueError(f"`{name}` must be a finite number > 0 [{unit}], got {value!r}")
    return value


def _nonnegative(name: str, value, unit: str) -> float:
    value = float(value)
    if not np.isfinite(value) or value < 0.0:
        raise ValueError(f"`{name}` must be a finite number >= 0 [{unit}], got {value!r}")
    return value


def _finite(name: str, value, unit: str) -> float:
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"`{name}` must be finite [{unit}], got {value!r}")
    return value


def rod_inertia(mass: float, length: float) -> np.ndarray:
    """Inertia tensor of a thin uniform rod along ``x`` about its centre of mass.

    Parameters
    ----------
    mass : float
        rod mass [kg], > 0.
    length : float
        rod length [m], >= 0 (zero gives a point mass).

    Returns
    -------
    ndarray, shape (3, 3)
        ``diag(0, m L^2 / 12, m L^2 / 12)`` [kg m^2].

    Examples
    --------
    >>> float(rod_inertia(3.0, 2.0)[2, 2])
    1.0
    """
    m = _positive("mass", mass, "kg")
    L = _nonnegative("length", length, "m")
    i = m * L * L / 12.0
    return np.diag([0.0, i, i])


def box_inertia(mass: float, lx: float, ly: float, lz: float) -> np.ndarray:
    """Inertia tensor of a uniform box about its centre of mass, edges along the axes.

    Parameters
    ----------
    mass : float
        [kg], > 0.
    lx, ly, lz : float
        edge lengths along ``x``, ``y``, ``z`` [m], >= 0.

    Returns
    -------
    ndarray, shape (3, 3)
        ``m/12 diag(ly^2 + lz^2, lx^2 + lz^2, lx^2 + ly^2)`` [kg m^2] (Craig [1]_, the
        box example with its width ``w`` along ``x``, length ``l`` along ``y`` and
        height ``h`` along ``z``).

    Examples
    --------
    >>> box_inertia(12.0, 1.0, 2.0, 3.0).diagonal().tolist()
    [13.0, 10.0, 5.0]
    """
    m = _positive("mass", mass, "kg")
    x = _nonnegative("lx", lx, "m")
    y = _nonnegative("ly", ly, "m")
    z = _nonnegative("lz", lz, "m")
    return m / 12.0 * np.diag([y * y + z * z, x * x + z * z, x * x + y * y])


def parallel_axis(inertia_com, mass: float, offset) -> np.ndarray:
    """Move an inertia tensor from the centre of mass to a parallel frame.

    Parameters
    ----------
    inertia_com : array_like, shape (3, 3)
        inertia tensor about the centre of mass [kg m^2]; symmetric.
    mass : float
        [kg], > 0.
    offset : array_like, shape (3,)
        position of the centre of mass in the new frame [m].

    Returns
    -------
    ndarray, shape (3, 3)
        ``I + m (|p|^2 I_3 - p p^T)`` [kg m^2].

    Examples
    --------
    >>> float(parallel_axis(rod_inertia(3.0, 2.0), 3.0, [1.0, 0.0, 0.0])[2, 2])
    4.0
    """
    inertia = np.asarray(inertia_com, dtype=float)
    if inertia.shape != (3, 3):
        raise ValueError(f"`inertia_com` must have shape (3, 3), got {inertia.shape}")
    if not np.all(np.isfinite(inertia)):
        raise ValueError("all entries of `inertia_com` must be finite")
    if not np.allclose(inertia, inertia.T, rtol=1e-12, atol=1e-15 * np.abs(inertia).max()):
        raise ValueError("`inertia_com` must be symmetric")
    m = _positive("mass", mass, "kg")
    p = np.asarray(offset, dtype=float)
    if p.shape != (3,):
        raise ValueError(f"`offset` must have shape (3,), got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError("all entries of `offset` must be finite")
    return inertia + m * (p @ p * np.eye(3) - np.outer(p, p))


def planar_parallel_axis(i_zz: float, mass: float, dx: float, dy: float) -> float:
    """Planar parallel-axis theorem: ``I_zz + m (dx^2 + dy^2)``.

    Parameters
    ----------
    i_zz : float
        moment of inertia about the centre of mass, about ``z`` [kg m^2], >= 0.
    mass : float
        [kg], > 0.
    dx, dy : float
        offset between the centre of mass and the new axis [m].

    Returns
    -------
    float
        moment of inertia about the new axis [kg m^2].

    Examples
    --------
    >>> planar_parallel_axis(0.5, 2.0, 0.3, 0.4)
    1.0
    """
    i = _nonnegative("i_zz", i_zz, "kg m^2")
    m = _positive("mass", mass, "kg")
    x = _finite("dx", dx, "m")
    y = _finite("dy", dy, "m")
    return i + m * (x * x + y * y)
