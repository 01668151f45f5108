"""What the informational commands describe, as data: a line on each model
(:data:`MODEL_SUMMARIES`), where a model's section lies when it is not just after heel strike
(:data:`SECTION_WHERE`), and for each model and preset the initial state, its note and the
citation ``walker scene new`` writes (:data:`STARTS`; ``walker params`` shows the citations).
"""

from __future__ import annotations

from typing import NamedTuple

from walker.params import MODELS

__all__ = ["MODEL_SUMMARIES", "SECTION_WHERE", "STARTS", "Start"]

MODEL_SUMMARIES = {name: spec.summary for name, spec in MODELS.items()}
"""Model name -> one line on what it is (the registry records' ``summary``)."""

SECTION_WHERE = {name: spec.section_where for name, spec in MODELS.items()}
"""Where each model's Poincare section lies (the registry records' ``section_where``)."""


class Start(NamedTuple):
    """What ``walker scene new`` writes for a model and preset besides the parameters."""

    state: tuple[float, ...]
    """the full state of ``[initial]``."""
    note: str
    """where the state comes from (a comment in the file)."""
    source: str
    """``[scene] source``: citation of the parameters and the state."""
    walks: bool
    """``walker find`` (``walker run`` for a model without strides) succeeds from it."""


_GOSWAMI = "A. Goswami, B. Thuilot, B. Espiau, INRIA RR-2996, 1996; IJRR 17(12), 1998 (parameters)"
_HSU_CHEN = 'Hsu Chen, "Passive Dynamic Walking with Knees: A Point Foot Model", M.Eng. thesis, '
_HSU_CHEN += "MIT, 2007"
_MCGEER = 'T. McGeer, "Passive walking with knees", Proc. IEEE ICRA, 1990 (parameters)'
_MCGEER_GUESS = (
    "a rough guess, not a known gait: Hsu Chen's point-foot gait with its rates divided by "
    "sqrt(9.8) (McGeer's time unit); `walker find` ends TRIPPED from it, so bring your own "
    "state"
)
_COMPASS_GAIT = (0.218668802939019, -0.323388558058679, -1.09182667748965, -0.377181558403111)
_KNEED_GAIT = (
    0.188165653505079,
    -0.288902687312574,
    -0.288902687312574,
    -1.10894729114406,
    -0.0577178265800133,
    -0.0577178265800133,
)
_MCGEER_STATE = (
    0.1877,
    -0.2884,
    -0.2884,
    -0.35182932434546693,
    -0.0127455874717488,
    -0.0127455874717488,
)

STARTS: dict[tuple[str, str], Start] = {
    ("simplest", "garcia"): Start(
        (0.20031090049483, 0.40062180098966, -0.19983247291764, -0.015822999933693436),
        "Garcia et al.'s stable gait at slope 0.009 (theta, theta_dot to 1e-10); "
        "phi = 2 theta, phi_dot = (1 - cos 2 theta) theta_dot",
        "M. Garcia, A. Chatterjee, A. Ruina, M. Coleman, J. Biomech. Eng. 120(2):281-288, 1998",
        True,
    ),
    ("compass", "goswami"): Start(
        (0.2187, -0.3234, -1.0918, -0.3772),
        "the stable gait on the 3 degree slope to four digits (Spong et al. 2007)",
        _GOSWAMI + "; M. W. Spong, J. K. Holm, D. Lee, IEEE Robot. Autom. Mag. 14(2), 2007 (gait)",
        True,
    ),
    ("compass", "drake"): Start(
        (0.218774617980327, -0.323774617980327, -1.09286681058014, -0.37613459353082),
        "walker's own stable gait for these parameters (walker find, residual 8e-15)",
        "Parameters: the defaults of Drake's compass-gait example; gait: walker's own",
        True,
    ),
    ("kneed", "hsu_chen"): Start(
        (0.1877, -0.2884, -0.2884, -1.1014, -0.0399, -0.0399),
        "the thesis's stable gait (explicit Euler at dt = 1e-3, so the exact cycle differs "
        "at the 1e-3 level)",
        _HSU_CHEN,
        True,
    ),
    ("kneed", "mcgeer"): Start(_MCGEER_STATE, _MCGEER_GUESS, _MCGEER, False),
    ("double_pendulum", "course"): Start(
        (-0.1, 1.6707963267948966, 0.0, 0.0),
        "released from rest, link 1 0.1 rad below the +x axis and link 2 pointing straight up",
        "walker's energy-check pendulum: point-like links with m = 1 kg, I = 0.5 kg m^2, "
        "l = 1 m, centre of mass at 0.5 m, g = 10 m/s^2",
        True,
    ),
    ("three_link", "grizzle"): Start(
        (
            0.3926990816987121,
            -0.3926990816987121,
            -0.5235987755982919,
            -0.8098217763438416,
            0.37240806991969067,
            -2.0233937571181144,
            0.0,
            0.0,
        ),
        "walker's own stable period-one gait of this controller on level ground",
        "J. W. Grizzle, G. Abba, F. Plestan, IEEE TAC 46(1), 2001 (model); E. R. Westervelt, "
        "J. W. Grizzle, D. E. Koditschek, IEEE TAC 48(1), 2003 (virtual constraints); Bezier "
        "coefficients: walker's own",
        True,
    ),
    ("five_link", "rabbit"): Start(
        (
            0.19999999999998933,
            0.20000000000002266,
            -0.09999999999999978,
            -0.09999999999999253,
            -0.2999999999999956,
            -0.9462895915900675,
            0.5858767365469528,
            -0.19672505436634408,
            -0.8933072811252336,
            -0.8626230482131172,
            0.0,
            0.0,
        ),
        "walker's own stable period-one gait of this controller on level ground",
        "E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, IEEE TAC 48(1), 2003 (model, "
        "Table I); C. Chevallereau et al., IEEE Control Systems Magazine 23(5), 2003 (RABBIT); "
        "Bezier coefficients: walker's own",
        True,
    ),
    ("compass_coulomb", "goswami"): Start(
        _COMPASS_GAIT,
        "the frictionless gait (the preset's dry frictions are 0; raise coulomb_ankle and "
        "coulomb_hip from there)",
        _GOSWAMI,
        True,
    ),
    ("kneed_coulomb", "hsu_chen"): Start(
        _KNEED_GAIT,
        "walker's frictionless gait of the preset (its dry frictions are 0)",
        _HSU_CHEN,
        True,
    ),
    ("kneed_coulomb", "mcgeer"): Start(_MCGEER_STATE, _MCGEER_GUESS, _MCGEER, False),
    ("rimless_wheel", "drake"): Start(
        (0.39269908169872414, -1.095462839647657),
        "the closed-form rolling gait: theta = alpha = pi/8, "
        "theta_dot = -cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(slope))",
        "Parameters: the defaults of Drake's rimless-wheel example; gait: T. McGeer, IJRR "
        "9(2), 1990, and M. J. Coleman, A. Chatterjee, A. Ruina, Dyn. Stab. Syst. 12(3), 1997",
        True,
    ),
}
"""(model, preset) -> the state, its note and the source ``walker scene new`` writes."""
