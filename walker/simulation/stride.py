"""Simulating a walker and its stride (Poincare) map on the section just after heel strike.

:func:`simulate` runs a model from a full state; :class:`StrideMap` maps section coordinates
to the section coordinates one (or ``k``) strides later, with the exact Jacobian from the
variational equations and saltation matrices when asked.  It implements the
:class:`walker.analysis.fixedpoint.SectionMap` protocol the gait search works on.
"""

from __future__ import annotations

import copy
import math
import numbers
from dataclasses import dataclass

import numpy as np

from walker._checks import as_vector as _as_vector
from walker._checks import sample_rate as _sample_rate
from walker._checks import time_scale as _time_scale
from walker.results import MapResult, Solution
from walker.simulation import _section, _terrain_run
from walker.simulation.integrate import _STATUSES, PreparedRun, check_solver_settings
from walker.simulation.trajectory import _resolve, check_sample_count, simulate
from walker.status import Status

_frombuffer = np.frombuffer  # a float64 array on a bytearray of walker._hybrid, no copy

__all__ = ["SOLVER_SETTINGS", "StrideMap", "simulate", "solver_settings"]

#: The solver settings a run takes, as ``[compute]`` (:class:`walker.scene.ComputeSettings`)
#: and :class:`StrideMap` both name them.
SOLVER_SETTINGS = ("method", "rtol", "atol", "t_max", "first_step")


def solver_settings(source) -> dict:
    """The solver settings of ``source`` as keyword arguments: ``method``, ``rtol``, ``atol``,
    ``t_max`` and ``first_step`` (:data:`SOLVER_SETTINGS`).

    ``source`` is anything with those attributes: a scene's ``compute``
    (:class:`walker.scene.ComputeSettings`) or a :class:`StrideMap`.

    Examples
    --------
    >>> from walker import load_scene
    >>> solver_settings(load_scene("gaits/simplest_garcia.toml").compute)["method"]
    'DOP853'
    """
    return {name: getattr(source, name) for name in SOLVER_SETTINGS}


@dataclass(frozen=True, eq=False)
class StrideMap:
    """The stride map ``z -> P(z)`` of a walker on the section just after heel strike.

    Parameters
    ----------
    model : str or WalkerModel
    params : the model's parameter dataclass
    method : str
    rtol, atol : float
    t_max : float, optional
        time allowed per stride [s]; default ``20 sqrt(l/g)``.
    first_step : float, optional
        step for fixed-step methods.
    parameter_name : str
        the scalar parameter continuation varies (default ``"slope"``).

    Examples
    --------
    >>> from walker import StrideMap, load_scene
    >>> scene = load_scene("gaits/simplest_garcia.toml")
    >>> P = StrideMap("simplest", scene.params, rtol=1e-12)
    >>> r = P(P.project(scene.state))
    >>> r.status.name
    'COMPLETED'
    """

    model: object
    params: object
    method: str = "DOP853"
    rtol: float = 1e-12
    atol: float = 1e-12
    t_max: float | None = None
    first_step: float | None = None
    parameter_name: str = "slope"

    def __post_init__(self):
        model = _resolve(self.model, self.params)
        object.__setattr__(self, "model", model)
        if not model.has_strides:
            raise ValueError(f"`model` `{model.name}` has no heel strike, so no stride map")
        if self.parameter_name not in model.params_class.names():
            raise ValueError(
                f"`parameter_name` must be a parameter of `{model.name}` "
                f"({', '.join(model.params_class.names())}), got {self.parameter_name!r}"
            )
        check_solver_settings(self.method, self.rtol, self.atol, self.first_step)
        if self.t_max is None:
            object.__setattr__(self, "t_max", 20.0 * _time_scale(self.params))
        if isinstance(self.t_max, bool) or not isinstance(self.t_max, int | float | np.floating):
            raise TypeError(f"`t_max` must be a real number, got {type(self.t_max).__name__}")
        if not (np.isfinite(self.t_max) and self.t_max > 0):
            raise ValueError(f"`t_max` must be positive and finite, got {self.t_max!r}")
        # project() is a selection of state components: its matrix, for Jacobians.
        p = self.params.as_array()
        proj = np.array([model.project(e, p) for e in np.eye(model.n_x)]).T
        object.__setattr__(self, "_proj", proj)

    @classmethod
    def from_scene(cls, scene, parameter_name: str = "slope") -> StrideMap:
        """The stride map of a scene: its model under its conventions
        (``scene.walker_model``), its parameters and its ``[compute]`` solver settings.

        Examples
        --------
        >>> from walker import StrideMap, load_scene
        >>> P = StrideMap.from_scene(load_scene("gaits/simplest_garcia.toml"))
        >>> P.model.name, P.method
        ('simplest', 'DOP853')
        """
        return cls(
            scene.walker_model,
            scene.params,
            parameter_name=parameter_name,
            **solver_settings(scene.compute),
        )

    # --- the compiled run, prepared once per parameter set and process ---------------------
    def _prepared(self, n_strides: int = 1):
        """The compiled run for ``n_strides`` strides, the parameter vector and the guard on
        the start state: built on first use (and again after pickling or a parameter
        change), so a call validates nothing but ``z``.

        The run's step budget is ``n_strides`` times
        :func:`walker.analysis.fixedpoint.stride_max_steps` (tied to ``t_max`` in units of the
        model's time scale: about 100 typical strides with the scenes' ``t_max``).  The
        guard ``((offset, fall_angle), n_q, wound_limit, energy_fn, energy_address,
        kinetic_limit)`` stops a start state whose stance leg lies past the fall angle, an
        angle wound beyond pi from the slope normal or a kinetic energy far above the
        scene's (:class:`walker.analysis.fixedpoint.WalkingRegion`).  Built with them, when
        :func:`walker.simulation._section.compiled_call_fits`:
        ``walker._hybrid.PreparedMap(...).map``, the whole of :meth:`__call__` in one compiled call
        (``_run[6]``, else None)."""
        cached = self.__dict__.get("_run")
        if cached is None:
            from walker import _hybrid
            from walker.simulation.region import WalkingRegion, stride_max_steps

            p = np.ascontiguousarray(self.params.as_array(), dtype=np.float64)
            per_stride = stride_max_steps(self.params, self.t_max, self.method, self.first_step)
            guard = self._guard(WalkingRegion(self.model, self.params))
            fast = _section.fast_parts(self.model, p)
            cached = [{}, p, guard, per_stride, self.model.system_for(p), fast, None]
            run = self._new_run(cached, n_strides)
            if _section.compiled_call_fits(self.model, p, self.t_max, fast):
                # the whole call in C: lift, start checks, stride(s), projection
                args = _section.section_args(self.model, self.t_max, cached, run)
                cached[6] = _hybrid.PreparedMap(**args).map
            cached = tuple(cached)
            object.__setattr__(self, "_run", cached)
        runs = cached[0]
        run = runs.get(n_strides)
        if run is None:
            run = self._new_run(cached, n_strides)
        return run, cached[1], cached[2]

    def _guard(self, region, own: bool = False) -> tuple:
        """The start checks of :meth:`_prepared` from the map's walking region, which is
        kept as the map's own region (:meth:`walker.simulation.region.WalkingRegion.of`; a copy
        unless ``own``: the region is the map's alone), so a gait search on the map does not build
        it again."""
        from walker import _hybrid
        from walker.simulation.region import _cache_of

        per_map = _cache_of(self)
        if per_map is not None and None not in per_map:
            per_map[None] = region if own else copy.copy(region)
            # a map re-targeted from this one keeps its step budget while the time scale
            # (the budget's unit) is this map's
            per_map[None]._base_time_scale = region.time_scale
        address = region.energy_address if math.isfinite(region.kinetic_limit) else None
        stance = (
            (region.stance * region.slope, region.fall_angle)
            if region.stance is not None
            else (0.0, math.inf)
        )
        return (
            stance,
            region.n_q,
            region.wound_limit,
            _hybrid.call_state_fn,
            address,
            region.kinetic_limit,
        )

    def _retargeted(self, params) -> StrideMap:
        """A copy at ``params`` (a validated instance of the same class) whose compiled run
        is re-targeted from this map's, not rebuilt: what does not depend on the parameters
        (the model's system and compiled kernels, the solver settings, the runs per stride
        count, the projection's indices) is shared, and only what does is computed again
        (the parameter vector, the start checks, the lift).  The same numbers as
        ``_with_params_object(params)`` bit for bit, at a fraction of the set-up cost: a
        sweep point's (:func:`walker.analysis.sweep.sweep_chunk`).  Falls back to a plain copy
        (built on first use) when this map is not prepared yet or the parameters change what is
        shared (another kernel variant, another step budget, another projection)."""
        new = self._with_params_object(params)
        cached = self.__dict__.get("_run")
        if cached is None:
            return new
        from walker.simulation.region import _cache_of

        region = (_cache_of(self) or {}).get(None)
        fresh = _section.retarget(new, cached, region)
        if fresh is not None:
            object.__setattr__(new, "_run", fresh)
            new.__dict__["_origin"] = self  # with_tolerance re-targets the origin's copies
        return new

    def _new_run(self, cached, n_strides):
        """A PreparedRun for ``n_strides`` strides, kept for up to 16 stride counts."""
        runs = cached[0]
        run = PreparedRun(
            cached[4],
            method=self.method,
            rtol=self.rtol,
            atol=self.atol,
            first_step=self.first_step,
            max_steps=cached[3] * n_strides,
        )
        if len(runs) < 16:
            runs[n_strides] = run
        return run

    def basin_batch(self, period: int = 1):
        """The compiled loop of :func:`walker.analysis.basin.basin_chunk` for this map, or None.

        Returns ``run(z0, target, tol, n_strides, weight=None, radius=0.0) -> (outcome,
        strides)`` that iterates every row of ``z0`` (shape ``(m, n_z)``) in one compiled
        call without the GIL, with the operations of the Python loop (lift, start checks,
        stride, projection), so the outcomes are the same; ``radius > 0`` also stops a point
        with ``||weight (z - target)||_2 <= radius`` as converged (``weight`` (n_z, n_z),
        default the identity; :func:`walker.analysis.basin_radius.contraction_ball`).  None when the
        map has no compiled call (:func:`walker.simulation._section.compiled_call_fits`: a lift
        neither affine nor compiled, a projection that does more than select components, a start
        phase that is not compiled); the caller then runs the Python loop."""
        from walker import _hybrid

        run, _, _ = self._prepared(period)
        cached = self.__dict__["_run"]
        if cached[6] is None:  # no compiled call (walker.simulation._section.compiled_call_fits)
            return None
        args = _section.section_args(self.model, self.t_max, cached, run)

        def points(z0, target, tol, n_strides, weight=None, radius=0.0):
            z0 = np.ascontiguousarray(z0, dtype=np.float64)
            target = np.ascontiguousarray(target, dtype=np.float64)
            w = np.ascontiguousarray(np.eye(len(target)) if weight is None else weight, float)
            outcome, strides = _hybrid.basin_points(
                **args,
                z0=z0,
                target=target,
                tol=float(tol),
                n_strides=int(n_strides),
                period=int(period),
                weight=w,
                radius=float(radius),
            )
            return (
                np.frombuffer(outcome, dtype=np.int64).copy(),
                np.frombuffer(strides, dtype=np.int64).copy(),
            )

        return points

    # terrain (walker/simulation/_terrain_run.py): Monte-Carlo walks, and a walk from a full state
    ensemble = _terrain_run.ensemble_method
    walk = _terrain_run.walk

    def __getstate__(self):
        state = dict(self.__dict__)
        state.pop("_run", None)  # process-local addresses: rebuilt where it lands
        state.pop("_tolerances", None)
        state.pop("_terrain_args", None)
        state.pop("_origin", None)
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)

    # --- SectionMap protocol ------------------------------------------------------------
    @property
    def n_z(self) -> int:
        return self.model.n_z

    @property
    def section_names(self) -> tuple[str, ...]:
        return self.model.section_names

    @property
    def parameter_value(self) -> float:
        return float(getattr(self.params, self.parameter_name))

    def with_parameter(self, value: float) -> StrideMap:
        """A copy at another value of ``parameter_name`` (validated)."""
        return self.with_params(**{self.parameter_name: value})

    def with_params(self, **changes) -> StrideMap:
        """A copy with other parameters (validated)."""
        for name, value in changes.items():
            if isinstance(value, numbers.Integral) and not isinstance(value, bool | np.bool_):
                try:
                    float(value)
                except OverflowError:
                    raise ValueError(
                        f"`{name}` must be finite, got an integer too large for a float"
                    ) from None
        return self._with_params_object(self.params.replace(**changes))

    def _with_params_object(self, params) -> StrideMap:
        """A copy with ``params`` (already a validated instance of the same class): the solver
        settings and the projection need no re-checking, so a sweep point costs one copy."""
        if type(params) is not type(self.params):
            raise TypeError(
                f"`params` must be a {type(self.params).__name__}, got {type(params).__name__}"
            )
        return self._copy_with(params=params)

    def with_tolerance(self, rtol: float, atol: float) -> StrideMap:
        """A copy with other ``rtol`` and ``atol`` (validated), kept per map (at most 8):
        asking again for the same pair returns the same copy, its compiled run prepared once
        (the gait search's coarse early strides, :mod:`walker.analysis.newton`)."""
        check_solver_settings(self.method, rtol, atol, self.first_step)
        kept = self.__dict__.setdefault("_tolerances", {})
        key = (float(rtol), float(atol))
        new = kept.get(key)
        if new is None:
            origin = self.__dict__.get("_origin")
            if origin is not None:  # re-targeted: so is the copy, from the origin's copy
                new = origin.with_tolerance(*key)
                new._prepared()
                new = new._retargeted(self.params)
            else:
                new = self._copy_with(rtol=key[0], atol=key[1])
            if len(kept) < 8:
                kept[key] = new
        return new

    def _compiled_search(self):
        """``walker._hybrid.PreparedMap.search`` of this map's compiled call (the gait search
        of :mod:`walker.analysis.newton` in one compiled call), or None when the map has no compiled
        call, or when :meth:`__call__` is not this class's own (a subclass's, or a spy set on
        the class: the search must then see its strides)."""
        if type(self).__call__ is not _OWN_CALL:
            return None
        cached = self.__dict__.get("_run")
        if cached is None:
            self._prepared()
            cached = self.__dict__["_run"]
        call = cached[6]
        return None if call is None else call.__self__.search

    def _copy_with(self, **fields) -> StrideMap:
        """A copy with ``fields`` replaced (taken as valid), without the prepared run."""
        new = copy.copy(self)
        for name, value in fields.items():
            object.__setattr__(new, name, value)
        new.__dict__.pop("_run", None)
        new.__dict__.pop("_tolerances", None)
        new.__dict__.pop("_terrain_args", None)
        new.__dict__.pop("_origin", None)
        return new

    def _p(self) -> np.ndarray:
        """The parameter vector: the prepared run's once there is one, else built."""
        cached = self.__dict__.get("_run")
        return self.params.as_array() if cached is None else cached[1]

    def lift(self, z) -> np.ndarray:
        """The full state, shape ``(n_x,)``, at the section point ``z``, shape ``(n_z,)``."""
        return self.model.lift(_as_vector(z, "z", self.model.n_z), self._p())

    def project(self, x) -> np.ndarray:
        """The section point, shape ``(n_z,)``, of the full state ``x``, shape ``(n_x,)``."""
        return self.model.project(_as_vector(x, "x", self.model.n_x), self._p())

    def __call__(
        self,
        z,
        *,
        jacobian: bool = False,
        n_strides: int = 1,
        parameter: float | None = None,
        terrain=None,
    ) -> MapResult:
        """Apply the map ``n_strides`` times.

        ``terrain``: None, the scene's plane (this path); or array-like ``(n_strides, 2)``
        of each step's ``(slope [rad], drop [m])`` (:mod:`walker.simulation.terrain`), walked in one
        compiled call (``walker.simulation._terrain_run``); the start ``z`` is lifted on the scene's
        plane, the full state is carried from stride to stride, and with ``jacobian=True``
        the result's ``terrain_jac`` holds ``dz / d(slope_k, drop_k)`` (the strides then run
        one by one: ``z`` agrees with the call without the Jacobian to the tolerance, not
        bit for bit).  Rows equal to the plane give this path's numbers bit for bit.  A model
        without terrain functions raises a ValueError naming it.

        A stride's work is bounded: at most
        :func:`walker.analysis.fixedpoint.stride_max_steps` integration steps per stride (else
        ``MAX_STEPS``), and a start state outside the walking region is not integrated
        (``step_time`` 0): a stance leg at the fall angle or past it from the slope normal
        ends ``FELL_FORWARD`` / ``FELL_BACKWARD`` (as the fall guards would on reaching
        it), an angle wound beyond pi from the slope normal or a kinetic energy above
        ``KINETIC_LIMIT`` times the walker's standing potential energy
        ``OUTSIDE_WALKING_REGION`` (:class:`walker.analysis.fixedpoint.WalkingRegion`).

        For a model whose lift is affine (``LIFT_AFFINE``) the call is one compiled call,
        with the operations of the Python path (:meth:`_checked_call`): the same results
        bit for bit.

        Returns
        -------
        MapResult
            ``z`` is NaN and ``status`` says why when a stride fails.
        """
        if parameter is not None and parameter != self.parameter_value:
            return self.with_parameter(parameter)(
                z, jacobian=jacobian, n_strides=n_strides, terrain=terrain
            )
        if terrain is not None:
            return _terrain_run.terrain_call(self, z, jacobian, n_strides, terrain)
        cached = self.__dict__.get("_run")
        if cached is None:
            self._prepared()
            cached = self.__dict__["_run"]
        call = cached[6]
        # One compiled call when the model allows it (_section.compiled_call_fits) and the input is
        # plain (a finite float64 vector, an int, a bool); else, or to say what is wrong
        # with the input, the checked path.
        out = None if call is None else call(z, n_strides, jacobian)
        if out is None:
            return self._checked_call(z, jacobian, n_strides)
        status, t, z_new, x, jac = out  # z_new NaN unless completed; jac only then
        z_new = _frombuffer(z_new)
        if jac is not None:
            jac = _frombuffer(jac).reshape(z_new.shape[0], -1)
        return MapResult(_STATUSES[status], z_new, jac, t, _frombuffer(x))

    def _checked_call(self, z, jacobian, n_strides) -> MapResult:
        """:meth:`__call__` in Python around the compiled run (the reference of the compiled
        call, and the path of every model and input it does not take): the input checks,
        the model's lift, the start checks, :meth:`PreparedRun.map` and the projection."""
        if z.__class__ is not np.ndarray or z.dtype != np.float64:
            z = _as_vector(z, "z")
        model = self.model
        if z.shape != (model.n_z,):
            raise ValueError(f"`z` must have shape ({model.n_z},), got {z.shape}")
        if not all(map(math.isfinite, z.tolist())):
            raise ValueError("All components of the section point `z` must be finite.")
        if n_strides.__class__ is not int and (
            isinstance(n_strides, bool) or not isinstance(n_strides, int | np.integer)
        ):
            raise TypeError(f"`n_strides` must be an int, got {type(n_strides).__name__}")
        if n_strides < 1:
            raise ValueError(f"`n_strides` must be >= 1, got {n_strides}")
        if jacobian.__class__ is not bool:  # numpy's bool and ints count as bools
            if not isinstance(jacobian, int | np.integer | np.bool_):
                raise TypeError(f"`jacobian` must be a bool, got {type(jacobian).__name__}")
            jacobian = bool(jacobian)
        cached = self.__dict__.get("_run")
        if cached is not None and n_strides in cached[0]:
            run, p, guard = cached[0][n_strides], cached[1], cached[2]
        else:
            run, p, guard = self._prepared(n_strides)
            cached = self.__dict__["_run"]
        lift, project, lift_jac, start_phase = cached[5]
        (offset, fall_angle), n_q, wound, energy_fn, energy_address, kinetic_limit = guard
        x0 = np.ascontiguousarray(lift(z, p), dtype=np.float64)
        # A walker that starts past its fall guards is not integrated: a fall guard fires on
        # crossing its threshold, never for a stance leg already past it or an angle wound
        # round, and the steps of a state with rates far beyond any gait's shrink with them.
        psi = float(z[0]) + offset
        if not abs(psi) < fall_angle:
            nan = np.full(self.n_z, np.nan)
            fell = Status.FELL_FORWARD if psi < 0 else Status.FELL_BACKWARD
            return MapResult(fell, nan, None, 0.0, x0)
        if max(map(abs, x0[:n_q].tolist())) > wound or (
            energy_address is not None
            and not energy_fn(energy_address, x0, p, 2)[0] <= kinetic_limit
        ):
            nan = np.full(self.n_z, np.nan)
            return MapResult(Status.OUTSIDE_WALKING_REGION, nan, None, 0.0, x0)
        seed = None
        if jacobian:
            # The map's Jacobian is project . (d x / d x0) . lift_jacobian: the run carries
            # only the n_z columns (d x / d x0) . lift_jacobian of the sensitivities.
            seed = lift_jac
            if seed is None:
                seed = np.array(model.lift_jacobian(z, p), dtype=np.float64, order="C")
                if not np.isfinite(seed).all():
                    lift_jac, seed = seed, None  # the full sensitivities, times it below
        status, t, x, jac = run.map(
            x0,
            p,
            0 if start_phase is None else start_phase(x0, p),
            self.t_max * n_strides,
            n_strides,
            jacobian,
            seed,
        )
        if status != 0:
            nan = np.full(self.n_z, np.nan)
            return MapResult(Status(status), nan, None, float(t), x)
        jz = None
        if jacobian:
            if seed is None:
                jac = jac @ lift_jac
            jz = self._proj @ jac if project is None else jac[project]
        return MapResult(
            Status.COMPLETED,
            model.project(x, p) if project is None else x[project],
            jz,
            float(t),
            x,
        )

    def trajectory(self, z, *, n_strides: int = 1, sample_rate: float | None = None) -> Solution:
        """Simulate from section point ``z`` keeping events and samples (or every step).

        Parameters
        ----------
        z : array_like, shape (n_z,)
            section point to start from.
        n_strides : int
            strides to run, >= 1.
        sample_rate : float, optional
            samples per second [Hz], > 0: the states at ``0, 1/sample_rate, ...`` up to the
            end of the run; default every integration step.  The samples must fit in
            :func:`walker.results.memory_limit` (checked before they are allocated).

        Raises
        ------
        ValueError, TypeError
            a bad ``z``, ``n_strides`` or ``sample_rate``, or too many samples; before any
            work except the run that measures the duration for ``sample_rate``.
        """
        z = _as_vector(z, "z", self.model.n_z)
        if not all(map(math.isfinite, z.tolist())):
            raise ValueError("All components of the section point `z` must be finite.")
        if isinstance(n_strides, bool) or not isinstance(n_strides, int | np.integer):
            raise TypeError(f"`n_strides` must be an int, got {type(n_strides).__name__}")
        if n_strides < 1:
            raise ValueError(f"`n_strides` must be >= 1, got {n_strides}")
        if sample_rate is not None:
            sample_rate = _sample_rate(sample_rate)
        p = self.params.as_array()
        x0 = self.model.lift(z, p)
        run = {**solver_settings(self), "t_max": self.t_max * n_strides, "n_strides": n_strides}
        if sample_rate is None:
            return simulate(self.model, self.params, x0, output="full", **run)
        first = simulate(self.model, self.params, x0, **run)
        check_sample_count(first.t, sample_rate, self.model.n_x, "`sample_rate`")
        times = np.arange(0.0, first.t, 1.0 / sample_rate)
        return simulate(self.model, self.params, x0, output="samples", sample_times=times, **run)


# StrideMap.__call__ as defined above: the compiled gait search stands in for it only while
# it is the class's own (StrideMap._compiled_search).
_OWN_CALL = StrideMap.__call__
