"""Physical parameters of each model: frozen dataclasses with units, bounds and validation.

Every field is a physical quantity with a unit, a one-line doc and admissible bounds, stored
in the field's ``metadata``; none has a default. The order of the fields is the canonical
order of the parameter vector ``p`` that the generated kernels take: ``params.as_array()``
builds it and ``cls.from_array(p)`` reads it back.

Validation runs in ``__post_init__``, before anything uses the values:

1. every value is a real, finite number (``TypeError`` for ``bool``, ``str``, complex and other
   non-numbers; ``ValueError`` for NaN and infinities); values are stored as ``float``;
2. every value lies inside its bounds (``ValueError`` naming the field, the rule and the unit);
3. cross-field rules of each model (a centre of mass inside its link, a foot radius smaller
   than the segment it sits on).

Published parameter sets are classmethods (``CompassParams.goswami()``), each citing its
source, and are listed in the class attribute ``PRESETS``.

Models and their state vectors (absolute angles from the vertical, counterclockwise positive,
unless stated otherwise) are listed in the model registry :data:`MODELS`, one
:class:`ModelSpec` a model (parameter class, state names and units, whether it has strides);
:data:`PARAMS`, :data:`STATE_NAMES`, :data:`STATE_UNITS` and :data:`HAS_STRIDES` are its
views by model name.

The package is split by kind, and this module re-exports every public name:

- ``_base.py``: the field helper ``_param``, the checks and the base class ``_Params``;
- ``passive.py``: simplest walker, compass gait, kneed walker, double pendulum, rimless wheel;
- ``coulomb.py``: the compass gait and the kneed walker with Coulomb joint friction;
- ``actuated.py``: the three-link and five-link walkers with their controller block, their
  presets' numbers in ``_actuated_presets.py``;
- ``registry.py``: the model registry.

Examples
--------
>>> from walker.params import CompassParams
>>> p = CompassParams.goswami()
>>> p.names()[:3]
('mass_hip', 'mass_leg', 'com_from_foot')
>>> p.leg_length
1.0
>>> CompassParams.from_array(p.as_array()) == p
True
>>> p.replace(mass_hip=-1.0)
Traceback (most recent call last):
...
ValueError: `mass_hip` must be > 0 [kg], got -1.0
"""

# the base class and the bound checks, for walker.analysis.sweep_grid and walker.cli
from walker.params._base import _check_bounds, _Params, _rule_text  # noqa: F401
from walker.params.actuated import FiveLinkParams, ThreeLinkParams
from walker.params.coulomb import CompassCoulombParams, KneedCoulombParams
from walker.params.passive import (
    CompassParams,
    DoublePendulumParams,
    KneedParams,
    RimlessWheelParams,
    SimplestParams,
)
from walker.params.registry import (
    HAS_EVENTS,
    HAS_STRIDES,
    MODELS,
    PARAMS,
    STATE_NAMES,
    STATE_UNITS,
    ModelSpec,
    params_class,
)

__all__ = [
    "MODELS",
    "ModelSpec",
    "PARAMS",
    "STATE_NAMES",
    "HAS_STRIDES",
    "HAS_EVENTS",
    "STATE_UNITS",
    "SimplestParams",
    "CompassParams",
    "CompassCoulombParams",
    "KneedParams",
    "KneedCoulombParams",
    "DoublePendulumParams",
    "ThreeLinkParams",
    "FiveLinkParams",
    "RimlessWheelParams",
    "params_class",
]
