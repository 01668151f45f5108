"""Your own hybrid system as a section map: :class:`SystemMap` turns a
:class:`~walker.simulation.hybrid_system.HybridSystem` plus a lift (section point -> full state)
and a projection (full state -> section point) into a map that :func:`walker.find_fixed_point`,
:func:`walker.analysis.continuation.continue_branch` and :func:`walker.analysis.basin.basin_map`
take, as they take a walker's :class:`~walker.simulation.stride.StrideMap` (a parameter sweep is a
loop over :meth:`SystemMap.with_parameter`; :func:`walker.analysis.sweep.sweep` varies a walker's
named parameters and takes a ``StrideMap`` only).  ``docs/own_system.md`` walks through two
examples (a kicked bouncing ball; a user controller for the three-link walker) and states
what works for a custom system and what does not.

The map runs the system with :func:`walker.simulation.integrate.hybrid_solve` from ``lift(z, p)``
until ``n_strides`` events whose reset returns ``EVENT_STRIDE`` (walker.status), then projects.  Its
Jacobian is ``project_jacobian . (dx/dx0) . lift_jacobian``, with the integrator's
sensitivities through every phase and event (saltation matrices); without
``lift_jacobian`` it is a central finite difference of the map.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from walker.results import MapResult
from walker.simulation.hybrid_system import HybridSystem
from walker.status import Status

__all__ = ["SystemMap"]

FD_STEP = 1e-7
"""Relative step of the central finite differences of a map without ``lift_jacobian``."""


@dataclasses.dataclass(frozen=True, eq=False)
class SystemMap:
    """A section (Poincaré) map of a user's hybrid system.

    Parameters
    ----------
    system : HybridSystem
        the system: phases, guards, resets (a reset returning ``EVENT_STRIDE`` ends a
        stride).
    params : array_like, shape (n_p,)
        the parameter vector passed to every function of the system.
    to_state : callable ``(z, p) -> x``
        the lift: the full state (shape ``(n_x,)``) at section point ``z``.
    to_section : callable ``(x, p) -> z``, or a sequence of int
        the projection of a full state onto the section, or the indices of the state
        components that are the section coordinates.
    section_names : sequence of str
        one name per section coordinate.
    lift_jacobian : callable ``(z, p) -> ndarray (n_x, n_z)``, optional
        ``d to_state / d z``; with it (and an index projection, or ``project_jacobian``) the
        map's Jacobian is exact, else a finite difference.
    project_jacobian : callable ``(x, p) -> ndarray (n_z, n_x)``, optional
        ``d to_section / d x`` for a callable projection.
    parameter_index : int
        the entry of ``params`` that continuation varies.
    parameter_name : str
        its name.
    phase0 : int
        the phase a stride starts in.
    method, rtol, atol : as :func:`walker.simulation.integrate.hybrid_solve`
    t_max : float
        longest time of one stride [s]; a stride not ended by then fails with
        ``Status.NO_EVENT``.

    Examples
    --------
    See ``docs/own_system.md`` (a kicked bouncing ball, its fixed point and multiplier).
    """

    system: HybridSystem
    params: Any
    to_state: Callable
    to_section: Callable | Sequence[int]
    section_names: tuple[str, ...]
    lift_jacobian: Callable | None = None
    project_jacobian: Callable | None = None
    parameter_index: int = 0
    parameter_name: str = "p0"
    phase0: int = 0
    method: str = "DOP853"
    rtol: float = 1e-10
    atol: float = 1e-12
    t_max: float = 100.0

    def __post_init__(self):
        if not isinstance(self.system, HybridSystem):
            raise TypeError(f"`system` must be a HybridSystem, got {type(self.system).__name__}")
        p = np.array(self.params, dtype=np.float64).ravel()
        if not np.all(np.isfinite(p)):
            raise ValueError("All entries of `params` must be finite.")
        object.__setattr__(self, "params", p)
        if not callable(self.to_state):
            raise TypeError("`to_state` must be a callable (z, p) -> x")
        if not callable(self.to_section):
            index = [int(i) for i in self.to_section]
            if not all(0 <= i < self.system.n_x for i in index):
                raise ValueError(
                    f"`to_section` indices must lie in [0, {self.system.n_x}), got {index}"
                )
            object.__setattr__(self, "to_section", tuple(index))
        names = tuple(str(n) for n in self.section_names)
        object.__setattr__(self, "section_names", names)
        if not names:
            raise ValueError("`section_names` must name at least one section coordinate")
        if not callable(self.to_section) and len(self.to_section) != len(names):
            raise ValueError(
                f"`to_section` has {len(self.to_section)} indices but `section_names` "
                f"{len(names)} names"
            )
        if not 0 <= int(self.parameter_index) < p.size:
            raise ValueError(
                f"`parameter_index` must lie in [0, {p.size}), got {self.parameter_index}"
            )
        if not (math.isfinite(self.t_max) and self.t_max > 0):
            raise ValueError(f"`t_max` must be a positive number, got {self.t_max}")

    # -- the SectionMap protocol (walker.simulation.sectionmap)
    # -------------------------------------

    @property
    def n_z(self) -> int:
        return len(self.section_names)

    @property
    def parameter_value(self) -> float:
        return float(self.params[self.parameter_index])

    def with_parameter(self, value: float) -> SystemMap:
        """A copy with the continuation parameter at ``value``."""
        p = self.params.copy()
        p[self.parameter_index] = float(value)
        return dataclasses.replace(self, params=p)

    def lift(self, z, p=None) -> np.ndarray:
        """The full state at section point ``z``."""
        p = self.params if p is None else p
        x = np.ascontiguousarray(self.to_state(np.asarray(z, dtype=float), p), dtype=float)
        if x.shape != (self.system.n_x,):
            raise ValueError(f"`to_state` must return shape ({self.system.n_x},), got {x.shape}")
        return x

    def project(self, x, p=None) -> np.ndarray:
        """The section point of the full state ``x``."""
        p = self.params if p is None else p
        x = np.asarray(x, dtype=float)
        if callable(self.to_section):
            return np.asarray(self.to_section(x, p), dtype=float).reshape(self.n_z)
        return x[list(self.to_section)].copy()

    def __call__(
        self,
        z,
        *,
        jacobian: bool = False,
        n_strides: int = 1,
        parameter: float | None = None,
    ) -> MapResult:
        """Apply the map ``n_strides`` times from section point ``z`` (shape ``(n_z,)``);
        with ``jacobian`` also ``dz_next/dz``.  A stride that fails (no stride event before
        ``t_max``, a terminal event) gives its status and a NaN point, never an error."""
        from walker.simulation.integrate import hybrid_solve

        z = np.asarray(z, dtype=float)
        if z.shape != (self.n_z,):
            raise ValueError(f"`z` must have shape ({self.n_z},), got {z.shape}")
        if not np.all(np.isfinite(z)):
            raise ValueError("All components of the section point `z` must be finite.")
        if isinstance(n_strides, bool) or not isinstance(n_strides, int | np.integer):
            raise TypeError(f"`n_strides` must be an int, got {type(n_strides).__name__}")
        if n_strides < 1:
            raise ValueError(f"`n_strides` must be >= 1, got {n_strides}")
        p = self.params
        if parameter is not None:
            p = p.copy()
            p[self.parameter_index] = float(parameter)
        x0 = self.lift(z, p)
        exact = jacobian and self.lift_jacobian is not None
        exact = exact and (not callable(self.to_section) or self.project_jacobian is not None)
        sol = hybrid_solve(
            self.system,
            x0,
            p,
            phase0=self.phase0,
            t_max=self.t_max * n_strides,
            n_strides=n_strides,
            method=self.method,
            rtol=self.rtol,
            atol=self.atol,
            jacobian=bool(exact),
        )
        if sol.status != Status.COMPLETED or sol.n_strides < n_strides:
            status = sol.status if sol.status != Status.COMPLETED else Status.NO_EVENT
            return MapResult(status, np.full(self.n_z, np.nan), None, float(sol.t), sol.x)
        z_next = self.project(sol.x, p)
        jz = None
        if exact:
            lift_jac = np.asarray(self.lift_jacobian(z, p), dtype=float)
            if callable(self.to_section):
                proj_jac = np.asarray(self.project_jacobian(sol.x, p), dtype=float)
                jz = proj_jac @ sol.jac @ lift_jac
            else:
                jz = (sol.jac @ lift_jac)[list(self.to_section)]
        elif jacobian:
            jz = self._fd_jacobian(z, p, n_strides)
        return MapResult(Status.COMPLETED, z_next, jz, float(sol.t), sol.x)

    def _fd_jacobian(self, z, p, n_strides) -> np.ndarray | None:
        """Central finite differences of the map (None when a shifted stride fails)."""
        value = float(p[self.parameter_index])
        columns = []
        for j in range(self.n_z):
            h = FD_STEP * max(1.0, abs(float(z[j])))
            plus, minus = z.copy(), z.copy()
            plus[j] += h
            minus[j] -= h
            a = self(plus, n_strides=n_strides, parameter=value)
            b = self(minus, n_strides=n_strides, parameter=value)
            if not (a.success and b.success):
                return None
            columns.append((a.z - b.z) / (2 * h))
        return np.stack(columns, axis=1)
