"""What the walkers' Python descriptions share: the fall threshold and the least step (the
compiled models use the same values, walker/_core/wk_common.h), the status values a reset
returns, the ground reaction of the actuated walkers read off their compiled guards, and the
public names of the models with joint friction."""

import sys

from walker.status import Status

JOINT_FRICTION_EXPORTS = (
    "N_X",
    "N_IMPULSE",
    "STATE_NAMES",
    "JOINTS",
    "PHASE_NAMES",
    "GUARD_NAMES",
    "DIRECTIONS",
    "I_COULOMB",
    "phase_of",
    "modes_of",
)
"""The public names of a model with dry joint friction (the start of its ``__all__``); its
phase functions are compiled (walker/_core/wk_friction.h)."""
BASE_EXPORTS = (
    "LIFT_AFFINE",
    "SECTION_NAMES",
    "SEGMENTS",
    "lift",
    "lift_jacobian",
    "project",
)
"""The public names a walker with joint friction takes unchanged from its base model (the
Poincare section and the drawing): :func:`joint_friction_walker`."""


def joint_friction_walker(module_name: str, base):
    """The ``__all__`` and the module ``__getattr__`` and ``__dir__`` (PEP 562) of the walker
    with joint friction ``module_name`` over its base model's module ``base``: its public
    names are :data:`JOINT_FRICTION_EXPORTS` and :data:`BASE_EXPORTS`, the latter ``base``'s
    own, which ``dir()`` (and so tab completion) lists with the module's own names."""

    def __getattr__(name: str):
        if name in BASE_EXPORTS:
            return getattr(base, name)
        raise AttributeError(f"module {module_name!r} has no attribute {name!r}")

    def __dir__():
        return sorted({*vars(sys.modules[module_name]), *BASE_EXPORTS})

    return [*JOINT_FRICTION_EXPORTS, *BASE_EXPORTS], __getattr__, __dir__


# The walker.status.Status values a reset map returns, as plain integers for compiled code.
FELL_BACKWARD = int(Status.FELL_BACKWARD)
FELL_FORWARD = int(Status.FELL_FORWARD)
TRIPPED = int(Status.TRIPPED)
NONPHYSICAL_IMPACT = int(Status.NONPHYSICAL_IMPACT)
LINEAR_SOLVE_FAILED = int(Status.LINEAR_SOLVE_FAILED)

# A stance leg this far from the slope normal [rad] (70 degrees) means the walker is falling:
# no passive gait comes near it, and stopping there saves integrating the whole fall.
FALL_ANGLE = 1.2217304763960306

MIN_STEP = 1e-8
"""A heel strike needs the swing foot ahead of the stance foot by more than ``MIN_STEP`` leg
lengths.  With straight rigid legs the foot height ``L (cos psi_stance - cos psi_swing)`` also
vanishes where the legs coincide (step length zero up to round-off): a swing leg passing
through the stance leg, which is a scuff, not a step.  A walker rocking back over its stance
foot crosses that zero with the height decreasing, and round-off decides the sign of the
step length there; the threshold makes it a scuff at every tolerance."""


def ground_reaction_at(name: str, x, p, phase=None) -> tuple[float, float]:
    """Ground force on the stance foot ``(F_t, F_n)`` [N] along and normal to the slope of
    actuated walker ``name`` at state ``x`` in ``phase`` (None: the phase consistent with
    ``x``), from its compiled guards ``slip_forward = mu F_n - F_t``, ``slip_backward = mu
    F_n + F_t`` and ``lift_off = F_n`` (the closed-loop accelerations of the phase)."""
    from walker.models import get_model

    model = get_model(name)
    if phase is None:
        phase = model.start_phase(x, p)
    g = model.guards(phase, x, p)
    names = model.guard_names
    forward, backward = g[names.index("slip_forward")], g[names.index("slip_backward")]
    return float(0.5 * (backward - forward)), float(g[names.index("lift_off")])
