"""Brute-force orbit (bifurcation) diagrams: where iteration of a section map settles at each
parameter value.  Re-exported by :mod:`walker.analysis.continuation`, where it was first defined."""

from __future__ import annotations

import numpy as np

from walker.results import OrbitDiagram
from walker.simulation.sectionmap import SectionMap, map_value, validate_int, validate_z

__all__ = ["at_parameter", "orbit_diagram", "settle"]


def orbit_diagram(
    section_map: SectionMap,
    z0: np.ndarray,
    parameters: np.ndarray,
    *,
    n_transient: int = 200,
    n_keep: int = 32,
    coordinate: int = 0,
    warm_start: bool = True,
) -> OrbitDiagram:
    """Brute-force orbit (bifurcation) diagram: where iteration settles at each parameter.

    At each value ``parameters[i]`` (in the given order) the map is iterated ``n_transient``
    strides (one call with ``n_strides=n_transient``), then ``n_keep`` more strides whose
    coordinate ``coordinate`` is recorded.  A fall leaves the rest of the row NaN.

    Parameters
    ----------
    section_map : SectionMap
    z0 : ndarray, shape (n_z,)
        starting section point.
    parameters : array_like, shape (n,)
        parameter values.
    n_transient : int
        strides discarded before recording (>= 0).
    n_keep : int
        strides recorded (>= 1).
    coordinate : int
        index of the section coordinate recorded.
    warm_start : bool
        start each parameter from the last point of the previous one when that one did not
        fall (follows an attractor through the sweep); otherwise always from ``z0``.

    Returns
    -------
    OrbitDiagram
        ``values`` of shape ``(n, n_keep)``.

    Raises
    ------
    ValueError
        for an invalid ``z0``, non-finite or non-1-D ``parameters``, negative ``n_transient``,
        ``n_keep < 1`` or ``coordinate`` out of range.

    Examples
    --------
    >>> import numpy as np
    >>> from walker.results import MapResult
    >>> from walker.status import Status
    >>> class Logistic:
    ...     n_z, section_names, parameter_name, parameter_value = 1, ("x",), "r", 3.2
    ...     def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
    ...         x = float(z[0])
    ...         for _ in range(n_strides):
    ...             x = parameter * x * (1 - x)
    ...         return MapResult(Status.COMPLETED, np.array([x]), None, 1.0, np.array([x]))
    ...     def lift(self, z):
    ...         return z
    ...     def with_parameter(self, value):
    ...         return self
    >>> d = orbit_diagram(Logistic(), np.array([0.3]), [2.5, 3.2], n_keep=4)
    >>> [len(np.unique(np.round(row, 8))) for row in d.values]
    [1, 2]
    """
    z0 = validate_z(section_map, z0, "z0")
    params = np.asarray(parameters, dtype=float)
    if params.ndim != 1 or params.size == 0:
        raise ValueError(f"`parameters` must be a non-empty 1-D array, got shape {params.shape}")
    if not np.all(np.isfinite(params)):
        raise ValueError("All `parameters` must be finite")
    n_transient = validate_int(n_transient, "n_transient", 0)
    n_keep = validate_int(n_keep, "n_keep", 1)
    n_z = z0.shape[0]
    if (
        isinstance(coordinate, bool)
        or not isinstance(coordinate, int | np.integer)
        or not (0 <= coordinate < n_z)
    ):
        raise ValueError(f"`coordinate` must be an integer in [0, {n_z}), got {coordinate!r}")
    values = np.full((params.size, n_keep), np.nan)
    z_start = z0
    for i, mu in enumerate(params):
        z, fell = settle(
            section_map, z_start, float(mu), n_transient, n_keep, coordinate, values[i]
        )
        z_start = z if (warm_start and not fell) else z0
    return OrbitDiagram(
        parameter_name=section_map.parameter_name,
        parameter=params,
        values=values,
        coordinate=int(coordinate),
    )


def at_parameter(section_map, value: float):
    """The map at ``value`` of its continuation parameter: a stride map re-targeted from its
    prepared run (``StrideMap._retargeted``, the numbers of ``with_parameter`` bit for bit),
    else ``with_parameter(value)``."""
    if hasattr(section_map, "_retargeted") and hasattr(section_map, "_prepared"):
        params = section_map.params.replace(**{section_map.parameter_name: float(value)})
        section_map._prepared()
        return section_map._retargeted(params)
    return section_map.with_parameter(float(value))


def settle(section_map, z, mu, n_transient, n_keep, coordinate, row) -> tuple:
    """One parameter value of an orbit diagram: ``n_transient`` strides from ``z``, then
    ``n_keep`` strides whose coordinate ``coordinate`` is written into ``row`` (left NaN
    from a fall on).  Returns the last section point and whether the walker fell."""
    point_map = at_parameter(section_map, mu)
    fell = False
    if n_transient > 0:
        res = map_value(point_map, z, n_transient, mu)
        fell = not res.success
        z = res.z
    if not fell:
        for k in range(n_keep):
            res = map_value(point_map, z, 1, mu)
            if not res.success:
                fell = True
                break
            z = res.z
            row[k] = z[coordinate]
    return z, fell
