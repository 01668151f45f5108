"""Which parameter class, state and strides each model has, by model name."""

from __future__ import annotations

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

__all__ = ["PARAMS", "STATE_NAMES", "STATE_UNITS", "HAS_EVENTS", "params_class"]

PARAMS: dict[str, type[_Params]] = {
    "simplest": SimplestParams,
    "compass": CompassParams,
    "kneed": KneedParams,
    "double_pendulum": DoublePendulumParams,
    "three_link": ThreeLinkParams,
    "five_link": FiveLinkParams,
    "compass_coulomb": CompassCoulombParams,
    "kneed_coulomb": KneedCoulombParams,
    "rimless_wheel": RimlessWheelParams,
}
"""Model name -> parameter class."""

STATE_NAMES: dict[str, tuple[str, ...]] = {
    # Garcia et al. 1998: theta stance angle from the slope normal, phi swing relative to stance.
    "simplest": ("theta", "phi", "theta_dot", "phi_dot"),
    # absolute angles from vertical, counterclockwise positive
    "compass": ("q_stance", "q_swing", "qd_stance", "qd_swing"),
    # q1 stance leg, q2 swing thigh, q3 swing shank; absolute, counterclockwise positive
    "kneed": ("q1", "q2", "q3", "qd1", "qd2", "qd3"),
    # q1 link 1, q2 link 2 (the model module states whether q2 is absolute or relative)
    "double_pendulum": ("q1", "q2", "qd1", "qd2"),
    # stance leg, swing leg, torso (absolute, counterclockwise positive); then the actuator
    # work since t0 [J] and the time spent with a saturated torque [s]
    "three_link": (
        "q_stance",
        "q_swing",
        "q_torso",
        "qd_stance",
        "qd_swing",
        "qd_torso",
        "actuator_work",
        "saturated_time",
    ),
    # mean stance-leg angle, stance-knee flexion, torso, swing femur, swing tibia
    # (walker.symbolic.five_link); then the actuator work [J] and saturated time [s]
    "five_link": (
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
    # as the compass gait; the hip's stick/slip state is the phase, not a state component
    "compass_coulomb": ("q_stance", "q_swing", "qd_stance", "qd_swing"),
    "kneed_coulomb": ("q1", "q2", "q3", "qd1", "qd2", "qd3"),
    # stance spoke's angle from the slope normal (counterclockwise positive) and its rate
    "rimless_wheel": ("theta", "theta_dot"),
}
"""Model name -> names of the full state's components, in order."""


def _angles_and_rates(n_angles: int, extra: tuple[str, ...] = ()) -> tuple[str, ...]:
    return ("rad",) * n_angles + ("rad/s",) * n_angles + extra


STATE_UNITS: dict[str, tuple[str, ...]] = {
    "simplest": _angles_and_rates(2),
    "compass": _angles_and_rates(2),
    "kneed": _angles_and_rates(3),
    "double_pendulum": _angles_and_rates(2),
    # the two accumulators: actuator work [J] and time with a saturated torque [s]
    "three_link": _angles_and_rates(3, ("J", "s")),
    "five_link": _angles_and_rates(5, ("J", "s")),
    "compass_coulomb": _angles_and_rates(2),
    "kneed_coulomb": _angles_and_rates(3),
    "rimless_wheel": _angles_and_rates(1),
}
"""Model name -> unit of each component of the full state, parallel to :data:`STATE_NAMES`
(angles [rad], their rates [rad/s]; the simplest walker's time unit is ``sqrt(l/g)`` when
``g = leg_length = 1``, as in its ``garcia`` preset)."""

HAS_EVENTS: dict[str, bool] = {
    "simplest": True,
    "compass": True,
    "kneed": True,
    "double_pendulum": False,
    "three_link": True,
    "five_link": True,
    "compass_coulomb": True,
    "kneed_coulomb": True,
    "rimless_wheel": True,
}
"""Model name -> whether the model walks: it has heel strikes, so runs count strides (the
double pendulum has events too, its joint-friction mode switches, but no strides)."""


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
            f"unknown model {model_name!r}; valid models: {', '.join(PARAMS)}"
        ) from None
