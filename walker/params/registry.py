"""The model registry: one record a model (:class:`ModelSpec`), by name, in :data:`MODELS`.

Each record holds what walker knows of a model without loading its compiled functions: its
parameter class, the names and units of its full state, and whether it has strides.  Each
fact is written here once; the model modules (``walker/models/<name>.py``) read their
``STATE_NAMES`` from it, :data:`walker.models.MODEL_NAMES` lists its keys, and
:class:`walker.models.WalkerModel` answers ``params_class``, ``state_names``,
``state_units`` and ``has_strides`` from it (``tests/test_models.py`` checks every model's
compiled description against its record).  :data:`PARAMS`, :data:`STATE_NAMES`,
:data:`STATE_UNITS` and :data:`HAS_STRIDES` are views of :data:`MODELS` by model name.

Examples
--------
>>> from walker.params import MODELS
>>> spec = MODELS["compass"]
>>> spec.params_class.__name__, spec.n_x, spec.has_strides
('CompassParams', 4, True)
>>> MODELS["double_pendulum"].has_strides
False
"""

from __future__ import annotations

import dataclasses

from walker._suggest import did_you_mean
from walker.params._base import _Params
from walker.params.actuated import FiveLinkParams, ThreeLinkParams
from walker.params.coulomb import CompassCoulombParams, KneedCoulombParams
from walker.params.passive import (
    CompassParams,
    DoublePendulumParams,
    KneedParams,
    RimlessWheelParams,
    SimplestParams,
)

__all__ = [
    "ModelSpec",
    "MODELS",
    "PARAMS",
    "STATE_NAMES",
    "STATE_UNITS",
    "HAS_STRIDES",
    "HAS_EVENTS",
    "params_class",
]


@dataclasses.dataclass(frozen=True)
class ModelSpec:
    """One model's record in :data:`MODELS`.

    Attributes
    ----------
    params_class : type
        the model's parameter dataclass; its ``MODEL`` is the model's name.
    state_names : tuple of str, shape (n_x,)
        names of the full state's components, in order.
    state_units : tuple of str, shape (n_x,)
        unit of each component of the full state, parallel to ``state_names``.
    has_strides : bool
        whether the model walks: it has heel strikes, so runs count strides and it has a
        Poincare section (the double pendulum has events too, its joint-friction mode
        switches, but no strides).
    summary : str
        one line on what the model is (``walker models``, ``walker scene new``).
    section_where : str
        where its Poincare section lies (``walker models --json``); by default just after
        heel strike.
    """

    params_class: type[_Params]
    state_names: tuple[str, ...]
    state_units: tuple[str, ...]
    has_strides: bool
    summary: str
    section_where: str = "just after heel strike"

    def __post_init__(self) -> None:
        if len(self.state_units) != len(self.state_names):
            raise ValueError(
                f"`state_units` must have one unit per state component "
                f"({len(self.state_names)}) for model {self.name}, got {len(self.state_units)}"
            )

    @property
    def name(self) -> str:
        """The model's name, its parameter class's ``MODEL``."""
        return self.params_class.MODEL

    @property
    def n_x(self) -> int:
        """Length of the full state."""
        return len(self.state_names)


def _angles_and_rates(n_angles: int, extra: tuple[str, ...] = ()) -> tuple[str, ...]:
    return ("rad",) * n_angles + ("rad/s",) * n_angles + extra


# absolute angles from vertical, counterclockwise positive
_COMPASS_STATE = ("q_stance", "q_swing", "qd_stance", "qd_swing")
# q1 stance leg, q2 swing thigh, q3 swing shank; absolute, counterclockwise positive
_KNEED_STATE = ("q1", "q2", "q3", "qd1", "qd2", "qd3")

MODELS: dict[str, ModelSpec] = {
    spec.name: spec
    for spec in (
        # Garcia et al. 1998: theta stance angle from the slope normal, phi swing relative to
        # stance (the time unit is ``sqrt(l/g)`` when ``g = leg_length = 1``, as in its
        # ``garcia`` preset)
        ModelSpec(
            SimplestParams,
            ("theta", "phi", "theta_dot", "phi_dot"),
            _angles_and_rates(2),
            has_strides=True,
            summary=(
                "Garcia's simplest walker: a point mass at the hip on massless legs with point feet"
                " (the compass gait's limit of vanishing leg mass)."
            ),
        ),
        ModelSpec(
            CompassParams,
            _COMPASS_STATE,
            _angles_and_rates(2),
            has_strides=True,
            summary=(
                "Compass gait: two rigid legs hinged at a hip mass, point or round feet, optional "
                "viscous hip and ankle dampers."
            ),
        ),
        ModelSpec(
            KneedParams,
            _KNEED_STATE,
            _angles_and_rates(3),
            has_strides=True,
            summary=(
                "Kneed walker: a hip mass, thigh and shank on each leg, a swing knee that locks "
                "straight, point or round feet."
            ),
        ),
        # q1 link 1, q2 link 2 (the model module states whether q2 is absolute or relative)
        ModelSpec(
            DoublePendulumParams,
            ("q1", "q2", "qd1", "qd2"),
            _angles_and_rates(2),
            has_strides=False,
            summary=(
                "Planar double pendulum with viscous and dry joint friction; not a walker (no "
                "strides, no section): run it with `walker run`."
            ),
            section_where="none: the model has no strides",
        ),
        # stance leg, swing leg, torso (absolute, counterclockwise positive); then the
        # actuator work since t0 [J] and the time spent with a saturated torque [s]
        ModelSpec(
            ThreeLinkParams,
            (
                "q_stance",
                "q_swing",
                "q_torso",
                "qd_stance",
                "qd_swing",
                "qd_torso",
                "actuator_work",
                "saturated_time",
            ),
            _angles_and_rates(3, ("J", "s")),
            has_strides=True,
            summary=(
                "Three-link walker: two legs and a torso, two hip actuators under virtual-"
                "constraint (hybrid zero dynamics) control."
            ),
        ),
        # mean stance-leg angle, stance-knee flexion, torso, swing femur, swing tibia
        # (walker.symbolic.five_link); then the actuator work [J] and saturated time [s]
        ModelSpec(
            FiveLinkParams,
            (
                "q_leg",
                "q_knee",
                "q_torso",
                "q_femur_sw",
                "q_tibia_sw",
                "qd_leg",
                "qd_knee",
                "qd_torso",
                "qd_femur_sw",
                "qd_tibia_sw",
                "actuator_work",
                "saturated_time",
            ),
            _angles_and_rates(5, ("J", "s")),
            has_strides=True,
            summary=(
                "Five-link walker like RABBIT: torso, femurs and tibias, hip and knee actuators "
                "under virtual-constraint control."
            ),
        ),
        # as the compass gait and the kneed walker; a joint's stick/slip state is the phase,
        # not a state component
        ModelSpec(
            CompassCoulombParams,
            _COMPASS_STATE,
            _angles_and_rates(2),
            has_strides=True,
            summary=(
                "Compass gait with dry (Coulomb) friction at the stance ankle and the hip: each "
                "joint slips forward, slips backward or sticks (the phases)."
            ),
        ),
        ModelSpec(
            KneedCoulombParams,
            _KNEED_STATE,
            _angles_and_rates(3),
            has_strides=True,
            summary=(
                "Kneed walker with dry (Coulomb) friction at the stance ankle, the hip and the "
                "swing knee, as stick and slip phases."
            ),
        ),
        # stance spoke's angle from the slope normal (counterclockwise positive) and its rate
        ModelSpec(
            RimlessWheelParams,
            ("theta", "theta_dot"),
            _angles_and_rates(1),
            has_strides=True,
            summary=(
                "Rimless wheel: a point mass at the hub on equally spaced massless spokes, rolling "
                "down the slope from spoke to spoke."
            ),
            section_where="just after a spoke's impact (theta = pi/spokes there)",
        ),
    )
}
"""Model name -> its :class:`ModelSpec`, in the order of :data:`walker.models.MODEL_NAMES`."""

PARAMS: dict[str, type[_Params]] = {name: spec.params_class for name, spec in MODELS.items()}
"""Model name -> parameter class (a view of :data:`MODELS`)."""

STATE_NAMES: dict[str, tuple[str, ...]] = {name: spec.state_names for name, spec in MODELS.items()}
"""Model name -> names of the full state's components, in order (a view of :data:`MODELS`)."""

STATE_UNITS: dict[str, tuple[str, ...]] = {name: spec.state_units for name, spec in MODELS.items()}
"""Model name -> unit of each component of the full state, parallel to :data:`STATE_NAMES`
(angles [rad], their rates [rad/s]; a view of :data:`MODELS`)."""

HAS_STRIDES: dict[str, bool] = {name: spec.has_strides for name, spec in MODELS.items()}
"""Model name -> whether the model walks: it has heel strikes, so runs count strides (a view
of :data:`MODELS`; see :attr:`ModelSpec.has_strides`)."""

HAS_EVENTS = HAS_STRIDES
"""The former name of :data:`HAS_STRIDES`, kept for code that imports it."""


def params_class(model_name: str) -> type[_Params]:
    """The parameter class of ``model_name`` (a key of :data:`PARAMS`).

    Examples
    --------
    >>> params_class("compass").__name__
    'CompassParams'
    """
    try:
        return PARAMS[model_name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown model {model_name!r}{did_you_mean(model_name, PARAMS)}; "
            f"valid models: {', '.join(PARAMS)}"
        ) from None
