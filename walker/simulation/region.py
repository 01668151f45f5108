"""Where a walker's stride map is worth evaluating, and how much work one stride may take.

:class:`WalkingRegion` is built from a walker model and its parameters: the scale of each
section coordinate (the trust region of the gait search, :mod:`walker.analysis.newton`), and the
tests that refuse a point without integrating it (stance leg past the fall angle, an angle
wound beyond pi, kinetic energy above a bound).  :func:`stride_max_steps` is the step budget
of one stride of a :class:`walker.simulation.stride.StrideMap`.  Both are re-exported by
:mod:`walker.analysis.fixedpoint`, where they were first defined.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import weakref

import numpy as np

from walker._checks import MAX_FIXED_STEPS, MAX_STRIDE_STEPS, time_scale

__all__ = ["WalkingRegion", "stride_max_steps"]

# Energy bound of the walking region: kinetic energy at the section at most KINETIC_FACTOR
# times (the guess's kinetic energy + the walker's standing potential energy).  A stride
# map refuses any state above KINETIC_LIMIT times the standing potential energy.
KINETIC_FACTOR = 4.0
KINETIC_LIMIT = 50.0
# Work of one stride (adaptive methods): at most STEPS_PER_TIME_UNIT steps per natural time
# unit sqrt(l / g) of the stride map's t_max, and never fewer than STRIDE_MIN_STEPS.
STEPS_PER_TIME_UNIT = 60
STRIDE_MIN_STEPS = 1000

# The regions built for an immutable map (a frozen dataclass, as StrideMap is), per value of
# its continuation parameter (None: its own), at most _CACHE_PER_MAP per map: a search from
# the same map starts from a copy instead of evaluating the walker's energies again.
_CACHE: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
_CACHE_PER_MAP = 8

# Why a point lies outside the walking region (WalkingRegion.describe; the codes of
# walker/_core/newton.h).
OUT_FALL, OUT_NONFINITE, OUT_WOUND, OUT_ENERGY = 1, 2, 3, 4

# Section coordinate 0 is the stance-leg angle of every shipped walker: name -> coefficient of
# the slope in its angle from the slope normal (Garcia's theta is measured from the normal;
# the others from the vertical, counterclockwise, so psi = q + slope).
_STANCE_ANGLE = {"theta": 0.0, "q_stance": 1.0, "q1": 1.0, "q_leg": 1.0}


def _is_rate(name: str) -> bool:
    return name.startswith("qd") or name.endswith("_dot")


class WalkingRegion:
    """Where a walker's stride map is worth evaluating, from the model's own functions.

    Built from a walker model and its parameters (``WalkingRegion.of(stride_map)``):

    * ``scale`` (n_z,): the unit of each section coordinate for the search's trust region:
      1 for an angle [rad], ``sqrt(g / l)`` for a rate [rad/s] (``l`` the leg length, as in
      :func:`walker._checks.time_scale`), so a step of 1 is one radian or one natural rate.
    * stance leg: section coordinate 0 is the stance-leg angle (``theta``, ``q_stance``,
      ``q1``, ``q_leg``); a point whose stance leg lies at ``FALL_ANGLE``
      (walker/models/_common.py, 70 degrees) or more from the slope normal has fallen.
    * wound angles: every angle of the lifted state (its first ``n_q`` components) must lie
      within ``pi + |slope|`` of zero, i.e. within pi of the slope normal for the absolute
      angles (relative angles, such as a knee's, are held to the same bound).
    * energy: ``potential_up`` is the potential energy of ``lift(0)`` — the walker standing
      straight over its stance foot, datum at the foot (``energy(lift(0))[1]``; 11.9 J for
      Hsu Chen's kneed walker).  It is about what the walker would release falling flat, more
      than one step down the slope releases (``M g s sin(slope)``, step ``s < 2 l``) on any
      slope a passive gait exists on.  A search allows a kinetic energy at the section of at
      most ``KINETIC_FACTOR * (KE(lift(z0)) + potential_up)`` (the guess's kinetic energy
      covers the actuated walkers' work per step), :meth:`with_guess`; a stride map refuses
      any state above ``KINETIC_LIMIT * potential_up`` (there the stance foot would have
      left the ground long before: the centripetal demand exceeds gravity from about
      ``potential_up / 2``).

    A point outside is refused with a reason (:meth:`outside`) and never integrated.
    """

    def __init__(self, model, params):
        from walker.models._common import FALL_ANGLE

        self.model = model
        names = tuple(model.section_names)
        self._rates = np.array([_is_rate(n) for n in names], dtype=bool)
        self.stance = _STANCE_ANGLE.get(names[0]) if names else None
        self.fall_angle = FALL_ANGLE
        self.n_q = int(getattr(model.module, "N_Q", model.n_x // 2))
        self.energy_address = model._state_fn("energy")
        self._set_params(params)

    def at(self, params, p=None) -> WalkingRegion:
        """The region of the same model at other parameters (an instance of the same
        class; ``p`` their vector when the caller has it): what does not depend on them is
        kept, the rest computed as :meth:`__init__` does (a sweep point's map,
        ``StrideMap._retargeted``)."""
        new = copy.copy(self)
        new._set_params(params, p)
        return new

    def _set_params(self, params, p=None) -> None:
        """The fields that depend on the parameters."""
        model = self.model
        self.params = params
        if p is None:
            p = params.as_array()
        self.p = np.ascontiguousarray(p, dtype=np.float64)
        self.slope = float(getattr(params, "slope", 0.0))
        self.time_scale = time_scale(params)
        rate = 1.0 / self.time_scale
        self.scale = np.where(self._rates, rate, 1.0)
        self.wound_limit = math.pi + abs(self.slope)
        try:
            up = self.kinetic_potential(model.lift(np.zeros(self._rates.size), self.p))[1]
        except (ValueError, ArithmeticError):
            up = float("nan")
        self.potential_up = float(up) if math.isfinite(up) and up > 0 else float("nan")
        self.kinetic_limit = (
            KINETIC_LIMIT * self.potential_up if math.isfinite(self.potential_up) else math.inf
        )
        self.kinetic_max = self.kinetic_limit

    @classmethod
    def of(cls, section_map, parameter: float | None = None) -> WalkingRegion | None:
        """The region of a walker's stride map (at ``parameter`` of its continuation
        parameter when given), or None for a map without a walker model.  A new object
        each call (:meth:`with_guess` changes it); for an immutable map (a frozen
        dataclass, such as :class:`walker.simulation.stride.StrideMap`) a copy of one kept per map
        and parameter value."""
        per_map = _cache_of(section_map)
        key = None if parameter is None else float(parameter)
        if per_map is not None and key in per_map:
            return copy.copy(per_map[key])
        region = cls._build(section_map, parameter)
        if per_map is not None and region is not None and len(per_map) < _CACHE_PER_MAP:
            per_map[key] = copy.copy(region)
        return region

    @classmethod
    def _build(cls, section_map, parameter: float | None) -> WalkingRegion | None:
        from walker.models import WalkerModel

        model = getattr(section_map, "model", None)
        params = getattr(section_map, "params", None)
        if not isinstance(model, WalkerModel) or not model.has_strides:
            return None
        if not hasattr(params, "as_array"):
            return None
        if parameter is not None and float(parameter) != float(section_map.parameter_value):
            try:
                params = params.replace(**{section_map.parameter_name: float(parameter)})
            except (ValueError, TypeError):
                return None
        return cls(model, params)

    def kinetic_potential(self, x) -> tuple[float, float]:
        """(kinetic, potential) energy of the full state ``x`` [J]."""
        if self.energy_address is not None:
            from walker import _hybrid

            x = np.ascontiguousarray(x, dtype=np.float64)
            kinetic, potential = _hybrid.call_state_fn(self.energy_address, x, self.p, 2)
            return float(kinetic), float(potential)
        kinetic, potential = self.model.energy(x, self.p)
        return float(kinetic), float(potential)

    def _lift(self, z) -> np.ndarray:
        """The full state at the section point ``z`` (a float vector of the section's length,
        as :meth:`outside` receives it): the model module's own lift, without the
        conversions of :meth:`WalkerModel.lift`, as a C-contiguous float64 array."""
        if z.__class__ is not np.ndarray or z.dtype != np.float64:
            return np.ascontiguousarray(self.model.lift(z, self.p), dtype=np.float64)
        return np.ascontiguousarray(self.model.module.lift(z, self.p), dtype=np.float64)

    def with_guess(self, z0) -> WalkingRegion:
        """Set the search's energy bound from the guess ``z0`` (see the class docstring)."""
        try:
            kinetic0 = self.kinetic_potential(self.model.lift(z0, self.p))[0]
        except (ValueError, ArithmeticError):
            kinetic0 = float("nan")
        if math.isfinite(kinetic0) and math.isfinite(self.potential_up):
            bound = KINETIC_FACTOR * (kinetic0 + self.potential_up)
            self.kinetic_max = min(bound, self.kinetic_limit)
        return self

    def outside(self, z) -> str | None:
        """Why the section point ``z`` lies outside the walking region, or None (inside)."""
        if self.stance is not None:
            psi = float(z[0]) + self.stance * self.slope
            if not abs(psi) < self.fall_angle:
                return self.describe(OUT_FALL, psi)
        try:
            x = self._lift(z)
        except (ValueError, ArithmeticError) as exc:
            return f"it has no full state ({exc})"
        xs = x.tolist()
        if not all(map(math.isfinite, xs)):
            return self.describe(OUT_NONFINITE)
        q = [abs(v) for v in xs[: self.n_q]]
        i = q.index(max(q))
        if q[i] > self.wound_limit:
            return self.describe(OUT_WOUND, xs[i], i)
        kinetic = self.kinetic_potential(x)[0]
        if not kinetic <= self.kinetic_max:
            return self.describe(OUT_ENERGY, kinetic)
        return None

    def describe(self, why: int, value: float = 0.0, index: int = 0) -> str:
        """The reason :meth:`outside` gives for the test ``why`` (``OUT_*``) that failed with
        ``value`` (the stance angle, the wound angle at state ``index``, the kinetic energy):
        also the words of the compiled gait search's refusals (walker/_core/newton.h)."""
        if why == OUT_FALL:
            return (
                f"the stance leg is {value:.4g} rad from the slope normal, beyond the fall "
                f"angle {self.fall_angle:.4g} rad"
            )
        if why == OUT_NONFINITE:
            return "its full state is not finite"
        if why == OUT_WOUND:
            name = self.model.state_names[index]
            return f"the angle {name} = {value:.4g} rad is wound beyond pi from the slope normal"
        return (
            f"its kinetic energy {value:.4g} J exceeds the bound {self.kinetic_max:.4g} J "
            "(rates far beyond any gait's)"
        )

    def compiled(self) -> dict | None:
        """The region as walker/_core/newton.h's ``wk_region`` reads it, by field name
        (keyword arguments of ``walker._hybrid.PreparedMap.search``), or None when the
        kinetic energy has no compiled function."""
        if self.energy_address is None or self.n_q < 1:
            return None
        stance = self.stance is not None
        return {
            "has_stance": stance,
            "stance_offset": float(self.stance * self.slope) if stance else 0.0,
            "fall_angle": float(self.fall_angle),
            "n_q": self.n_q,
            "wound_limit": float(self.wound_limit),
            "energy": int(self.energy_address),
            "kinetic_max": float(self.kinetic_max),
        }


def _cache_of(section_map) -> dict | None:
    """The region cache of an immutable map (a frozen dataclass that can be weakly
    referenced and hashed), or None."""
    if not dataclasses.is_dataclass(section_map) or not getattr(
        type(section_map).__dataclass_params__, "frozen", False
    ):
        return None
    try:
        return _CACHE.setdefault(section_map, {})
    except TypeError:  # no weak reference or no hash
        return None


def stride_max_steps(params, t_max: float, method: str, first_step: float | None) -> int:
    """Integration steps (accepted + rejected) one stride of a stride map may take.

    Adaptive methods: ``max(STRIDE_MIN_STEPS, ceil(STEPS_PER_TIME_UNIT * t_max / T))`` with
    ``T = sqrt(l / g)`` (:func:`walker._checks.time_scale`).  Measured on the shipped scenes'
    gaits with DOP853 at rtol = atol = 1e-12: a stride takes 17 (simplest) to 62 (five-link)
    steps over 1.7-3.9 T, i.e. 4-36 steps per T (83 steps, 49 per T, for the five-link walker
    at 1e-13); the kneed walker 37 steps.  With the scenes' ``t_max = 20 s`` (62.6 T) a stride
    may take 3757 steps, about 100 kneed strides; with the default ``t_max = 20 T``, 1200.  A
    walker swinging without a heel strike until ``t_max`` takes about 20 steps per T, well
    inside the budget; only states with rates far beyond any gait's (step sizes shrinking
    with the rates) run into it.  Fixed-step methods take ``ceil(t_max / first_step)``
    steps at most anyway; their budget is that plus two.  Computed in floating point: an
    adaptive budget is clamped to :data:`walker._checks.MAX_STRIDE_STEPS`, and a fixed step
    that needs more than :data:`walker._checks.MAX_FIXED_STEPS` is refused (ValueError).
    """
    from walker.simulation.integrate import check_solver_settings

    _, _, _, first_step, adaptive = check_solver_settings(method, 1e-6, 1e-6, first_step)
    # in floating point, clamped: parameters at their bounds (g = 1e300, a leg of 5e-324 m)
    # or t_max = 1e308 give budgets far beyond an int64
    if not adaptive:
        steps = t_max / first_step
        if not steps <= MAX_FIXED_STEPS:
            raise ValueError(
                f"`first_step` = {first_step:g} s needs {steps:.3g} {method} steps to reach "
                f"`t_max` = {t_max:g} s, more than the {MAX_FIXED_STEPS} a stride may take; "
                "raise `first_step` or lower `t_max`"
            )
        return int(math.ceil(steps)) + 2
    scale = time_scale(params)
    budget = STEPS_PER_TIME_UNIT * t_max / scale if scale > 0.0 else math.inf
    if not budget <= MAX_STRIDE_STEPS:
        return MAX_STRIDE_STEPS
    return max(STRIDE_MIN_STEPS, int(math.ceil(budget)))
