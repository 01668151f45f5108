"""Your own hybrid system as a section map: :class:`SystemSectionMap`.

A :class:`~walker.integrate.HybridSystem` (your compiled vector field, guards and reset, see
``walker/_core/wk_system.h``) plus a *lift* (section point -> full state) and a
*projection* (full state -> section point) make a stride map that every analysis of walker
takes: :func:`walker.find_fixed_point`, :func:`walker.continuation.continue_branch`,
:func:`walker.basin.basin_map` and :func:`walker.sweep.sweep` (the latter two with
``executor="threads"``: C function pointers do not pickle).  One application runs the system
from ``lift(z)`` until ``n_strides`` events whose reset returns ``EVENT_STRIDE`` (one
compiled call, :func:`walker.integrate.hybrid_solve`) and projects the state reached.

The Jacobian of the map is the chain rule ``dP/dz = dproject/dx . dx_end/dx_0 .
dlift/dz``, the middle factor the integrator's exact sensitivity (with the saltation
matrices of the resets); ``dlift/dz`` and ``dproject/dx`` are the given functions' or,
without them, central differences.  ``docs/own_system.md`` walks through an example.
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Sequence

import numpy as np

from walker.integrate import HybridSystem, hybrid_solve
from walker.results import MapResult
from walker.status import Status

__all__ = ["SystemSectionMap"]

_FD_STEP = 1e-7


def _central_jacobian(f: Callable[[np.ndarray], np.ndarray], x: np.ndarray) -> np.ndarray:
    """``df/dx`` at ``x`` by central differences, step ``1e-7 max(1, |x_i|)``."""
    columns = []
    for i in range(x.size):
        h = _FD_STEP * max(1.0, abs(float(x[i])))
        up, down = x.copy(), x.copy()
        up[i] += h
        down[i] -= h
        columns.append((np.asarray(f(up), float) - np.asarray(f(down), float)) / (2.0 * h))
    return np.stack(columns, axis=1)


class SystemSectionMap:
    """The stride (Poincare) map of your own hybrid system, for walker's analyses
    (a :class:`walker.sectionmap.SectionMap`).

    Parameters
    ----------
    system : HybridSystem
        the compiled system; one *stride* ends at each reset that returns ``EVENT_STRIDE``.
    params : array_like, shape (n_p,)
        the parameter vector ``p`` handed to the system's functions.
    lift : callable ``lift(z, p) -> x``
        the full state, shape (n_x,), at section point ``z``, shape (n_z,).
    project : callable ``project(x, p) -> z``
        the section point of a state just after a stride's reset.
    section_names : sequence of str, length n_z
        names of the section coordinates (for results and figures).
    parameter_index : int, optional
        index in ``p`` of the continuation parameter; needed for
        :func:`~walker.continuation.continue_branch` and sweeps.
    parameter_name : str
        its name.
    lift_jacobian : callable ``lift_jacobian(z, p) -> ndarray (n_x, n_z)``, optional
        default: central differences of ``lift``.
    project_jacobian : callable ``project_jacobian(x, p) -> ndarray (n_z, n_x)``, optional
        default: central differences of ``project``.
    phase0 : int
        the system's phase at the section.
    t_max : float
        time limit of one application [s]; reaching it first is ``Status.NO_EVENT``.
    rtol, atol : float
        tolerances of the integrator.
    method : str
        integration method (:func:`~walker.integrate.hybrid_solve`).

    Raises
    ------
    TypeError
        ``system`` is not a HybridSystem, or ``lift``/``project`` is not callable.
    ValueError
        ``params`` is not a finite 1-D vector, ``section_names`` is empty or
        ``parameter_index`` is outside ``params``.

    Notes
    -----
    Calling the map never raises for a start that does not complete its strides: the
    :class:`~walker.results.MapResult` then has the run's status and a NaN ``z``.
    ``lift(z)`` and ``project(x)`` (one argument, the map's own parameters) are the
    methods the analyses call.
    """

    def __init__(
        self,
        system: HybridSystem,
        params,
        lift: Callable,
        project: Callable,
        section_names: Sequence[str],
        *,
        parameter_index: int | None = None,
        parameter_name: str = "parameter",
        lift_jacobian: Callable | None = None,
        project_jacobian: Callable | None = None,
        phase0: int = 0,
        t_max: float = 100.0,
        rtol: float = 1e-10,
        atol: float = 1e-12,
        method: str = "DOP853",
    ) -> None:
        if not isinstance(system, HybridSystem):
            raise TypeError(
                f"`system` must be a walker.integrate.HybridSystem, got {type(system).__name__}"
            )
        for name, value in (("lift", lift), ("project", project)):
            if not callable(value):
                raise TypeError(f"`{name}` must be callable")
        for name, value in (
            ("lift_jacobian", lift_jacobian),
            ("project_jacobian", project_jacobian),
        ):
            if value is not None and not callable(value):
                raise TypeError(f"`{name}` must be callable or None")
        p = np.array(params, dtype=float, copy=True)
        if p.ndim != 1 or not np.all(np.isfinite(p)):
            raise ValueError("`params` must be a finite 1-dimensional vector")
        names = tuple(str(n) for n in section_names)
        if not names:
            raise ValueError("`section_names` must name at least one section coordinate")
        if parameter_index is not None and not 0 <= int(parameter_index) < p.size:
            raise ValueError(
                f"`parameter_index` must be in [0, {p.size}) (an index of `params`), "
                f"got {parameter_index}"
            )
        p.setflags(write=False)
        self.system = system
        self.params = p
        self.section_names = names
        self.parameter_index = None if parameter_index is None else int(parameter_index)
        self.parameter_name = str(parameter_name)
        self._lift, self._project = lift, project
        self._lift_jacobian, self._project_jacobian = lift_jacobian, project_jacobian
        self.phase0, self.t_max, self.method = int(phase0), float(t_max), str(method)
        self.rtol, self.atol = float(rtol), float(atol)

    def lift(self, z) -> np.ndarray:
        """The full state at section point ``z`` (the given ``lift`` at this map's
        parameters)."""
        return np.asarray(self._lift(np.asarray(z, dtype=float), self.params), dtype=float)

    def project(self, x) -> np.ndarray:
        """The section point of the full state ``x``."""
        return np.asarray(self._project(np.asarray(x, dtype=float), self.params), dtype=float)

    def __repr__(self) -> str:
        return (
            f"SystemSectionMap({self.system.name!r}, section={self.section_names}, "
            f"{self.parameter_name}={self.parameter_value:.6g})"
        )

    @property
    def n_z(self) -> int:
        """Section dimension."""
        return len(self.section_names)

    @property
    def parameter_value(self) -> float:
        """Current value of the continuation parameter (NaN without ``parameter_index``)."""
        if self.parameter_index is None:
            return float("nan")
        return float(self.params[self.parameter_index])

    def with_parameter(self, value: float) -> SystemSectionMap:
        """A copy at another value of the continuation parameter."""
        other = copy.copy(self)
        other.params = self._params_at(value)
        return other

    def _params_at(self, value: float | None) -> np.ndarray:
        if value is None:
            return self.params
        if self.parameter_index is None:
            raise ValueError(
                "`parameter` needs a continuation parameter: give SystemSectionMap a "
                "`parameter_index`"
            )
        p = self.params.copy()
        p[self.parameter_index] = float(value)
        return p

    def __call__(
        self,
        z: Sequence[float] | np.ndarray,
        *,
        jacobian: bool = False,
        n_strides: int = 1,
        parameter: float | None = None,
    ) -> MapResult:
        """Apply the map ``n_strides`` times from section point ``z``.

        Returns
        -------
        MapResult
            ``status`` the run's (``Status.COMPLETED`` when every stride completed),
            ``z`` the section point reached (NaN otherwise), ``jac`` its derivative with
            respect to ``z`` when ``jacobian``, ``step_time`` the time taken [s] and
            ``state`` the full state reached.
        """
        p = self._params_at(parameter)
        z = np.asarray(z, dtype=float)
        if z.shape != (self.n_z,):
            raise ValueError(f"`z` must have shape ({self.n_z},), got {z.shape}")
        x0 = np.asarray(self._lift(z, p), dtype=float)
        sol = hybrid_solve(
            self.system,
            x0,
            p,
            phase0=self.phase0,
            t_max=self.t_max,
            n_strides=int(n_strides),
            method=self.method,
            rtol=self.rtol,
            atol=self.atol,
            jacobian=jacobian,
        )
        if sol.status != Status.COMPLETED:
            return MapResult(
                Status(sol.status), np.full(self.n_z, np.nan), None, float(sol.t), sol.x
            )
        z_next = np.asarray(self._project(sol.x, p), dtype=float)
        jac = None
        if jacobian:
            lift_j = (
                self._lift_jacobian(z, p)
                if self._lift_jacobian is not None
                else _central_jacobian(lambda v: self._lift(v, p), z)
            )
            x_end = np.asarray(sol.x, dtype=float)
            project_j = (
                self._project_jacobian(x_end, p)
                if self._project_jacobian is not None
                else _central_jacobian(lambda v: self._project(v, p), x_end)
            )
            jac = (
                np.asarray(project_j, float)
                @ np.asarray(sol.jac, float)
                @ np.asarray(lift_j, float)
            )
        return MapResult(Status.COMPLETED, z_next, jac, float(sol.t), sol.x)
