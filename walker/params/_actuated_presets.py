"""The numbers behind the actuated walkers' presets (pure data, no code): the three-link
``grizzle`` preset and the book's controller (:meth:`walker.params.ThreeLinkParams.grizzle`,
:meth:`~walker.params.ThreeLinkParams.westervelt_book`) and the five-link ``rabbit`` preset
(:meth:`walker.params.FiveLinkParams.rabbit`), each with its source.  The ``*_INVARIANT``
tables are the Bezier coefficients :func:`walker.models.hzd.make_invariant` gives the design,
stored as numbers so that :mod:`walker.params` imports no analysis code
(``tests/test_params.py`` recomputes them).
"""

from __future__ import annotations

import math

# must equal WK_CONTROL_POLY_DEGREE in walker/_core/wk_control.h (tests/test_params.py)
_POLY_DEGREE = 5


_GRIZZLE_DEFAULTS: dict[str, float] = {
    # Westervelt et al. 2007, model_params_three_link.m
    "mass_hip": 15.0,
    "mass_leg": 5.0,
    "mass_torso": 10.0,
    "com_from_foot": 0.5,
    "com_to_hip": 0.5,
    "torso_length": 0.5,
    "inertia_leg": 0.0,
    "inertia_torso": 0.0,
    "slope": 0.0,
    "g": 9.8,
    # model_params_three_link.m has no actuator rotors: the book's example model is rigid
    # links only, so no reflected rotor inertia
    "rotor_inertia": 0.0,
    # walker's choices: ground friction, output gains (Westervelt's epsilon = 0.1 gives
    # kp = 1/eps^2, kd = 2/eps), a torque limit that the gait never reaches
    "friction": 0.8,
    "controller": 2.0,
    "kp": 100.0,
    "kd": 20.0,
    "torque_limit": 150.0,
    # step angle pi/8 (control_params_three_link.m: th1d = pi/8); theta_plus, the first two
    # coefficients of each output and bezier_swing_4 are set by make_invariant
    "theta_plus": math.pi / 8,
    "theta_minus": -math.pi / 8,
    "bezier_swing_0": 0.0,
    "bezier_swing_1": 0.0,
    "bezier_swing_2": -0.1,
    "bezier_swing_3": 0.4,
    "bezier_swing_4": 0.0,
    # torso leaning forward by pi/6 (th3d = pi/6 in [3]_'s clockwise convention)
    "bezier_torso_0": 0.0,
    "bezier_torso_1": 0.0,
    "bezier_torso_2": -math.pi / 6,
    "bezier_torso_3": -math.pi / 6,
    "bezier_torso_4": -math.pi / 6,
    # walker's heel strike; the finite-time controller's settings are those of
    # control_params_three_link.m (alpha = 0.9, epsilon = 0.1), unused by controller 2
    "step_event": 0.0,
    "ft_alpha": 0.9,
    "ft_epsilon": 0.1,
    **{f"poly_{o}_{k}": 0.0 for o in ("swing", "torso") for k in range(_POLY_DEGREE + 1)},
    # the published model is frictionless
    "damping_hip": 0.0,
    "coulomb_hip": 0.0,
}

_GRIZZLE_INVARIANT: dict[str, float] = {
    # walker.models.hzd.make_invariant(ThreeLinkParams(**_GRIZZLE_DEFAULTS)), printed with repr
    # (tests/test_params.py recomputes them)
    "bezier_swing_0": -0.39269908169872414,
    "bezier_swing_1": -0.30240495072649726,
    "bezier_swing_4": 0.39269908169872414,
    "bezier_torso_0": -0.5235987755982988,
    "bezier_torso_1": -1.0141912081225373,
}


_BOOK_A = (0.512, 0.073, 0.035, -0.819, -2.27, 3.26, 3.11, 1.89)
"""The output coefficients ``a`` of Westervelt et al. 2007's three-link example (the book's
example code, ``walker_main.m``: ``a = [0.512 0.073 0.035 -0.819 -2.27 3.26 3.11 1.89]``)."""

_BOOK_DEFAULTS: dict[str, float] = {
    **_GRIZZLE_DEFAULTS,
    # the book's controller and event; its step angle and finite-time settings
    # (control_params_three_link.m: th1d = pi/8, alpha = 0.9, epsilon = 0.1) are those of
    # _GRIZZLE_DEFAULTS; the poly_* coefficients come from _BOOK_A
    "controller": 3.0,
    "step_event": 1.0,
    # the book's code has no torque limit and does not check the ground reaction: a limit
    # the gait never reaches, and walker's friction cone mu = 0.8 (which the gait satisfies)
    "torque_limit": 1000.0,
}


_RABBIT_DEFAULTS: dict[str, float] = {
    # Westervelt, Grizzle, Koditschek 2003, Table I (RABBIT; also Chevallereau et al. 2003):
    # M_T = 12, M_f = 6.8, M_t = 3.2 kg; L_f = L_t = 0.4 m; p_MT = 0.24 (from the hip),
    # p_Mf = 0.11 (from the hip), p_Mt = 0.24 m (from the knee); I_T = 1.33, I_f = 0.47,
    # I_t = 0.20 kg m^2 (taken about the centres of mass); g = 9.81
    "mass_torso": 12.0,
    "mass_femur": 6.8,
    "mass_tibia": 3.2,
    "length_femur": 0.4,
    "length_tibia": 0.4,
    "com_torso": 0.24,
    "com_femur": 0.11,
    "com_tibia": 0.24,
    "inertia_torso": 1.33,
    "inertia_femur": 0.47,
    "inertia_tibia": 0.20,
    "slope": 0.0,
    "g": 9.81,
    # RABBIT's rotors (Chevallereau et al. 2003: gear ratio 50, rotor 3.32e-4 kg m^2) reflect
    # 50^2 * 3.32e-4 = 0.83 kg m^2 at each joint; the preset's gait (gaits/five_link_hzd.toml)
    # is for the link table of Westervelt et al. 2003 WITHOUT them: 0 here, RABBIT_ROTOR_INERTIA
    # below is the published value
    "rotor_inertia": 0.0,
    # walker's choices: ground friction, output gains, a torque limit (RABBIT's motors give
    # about 150 N m at the joints, Chevallereau et al. 2003) and the Bezier design below
    "friction": 0.8,
    "controller": 2.0,
    "kp": 400.0,
    "kd": 40.0,
    "torque_limit": 150.0,
    # theta_plus and the first two coefficients of every output, and the last two of the
    # swing femur and tibia, are set by make_invariant
    "theta_plus": 0.2,
    "theta_minus": -0.2,
    "bezier_knee_0": 0.0,
    "bezier_knee_1": 0.0,
    "bezier_knee_2": 0.3,
    "bezier_knee_3": 0.2,
    "bezier_knee_4": 0.2,
    "bezier_torso_0": 0.0,
    "bezier_torso_1": 0.0,
    "bezier_torso_2": -0.1,
    "bezier_torso_3": -0.1,
    "bezier_torso_4": -0.1,
    "bezier_femur_0": 0.0,
    "bezier_femur_1": 0.0,
    "bezier_femur_2": 0.2,
    "bezier_femur_3": 0.45,
    "bezier_femur_4": 0.0,
    "bezier_tibia_0": 0.0,
    "bezier_tibia_1": 0.0,
    "bezier_tibia_2": -0.6,
    "bezier_tibia_3": 0.2,
    "bezier_tibia_4": 0.0,
    # the published model is frictionless
    "damping_hip": 0.0,
    "damping_knee": 0.0,
    "coulomb_hip": 0.0,
    "coulomb_knee": 0.0,
}


_RABBIT_INVARIANT: dict[str, float] = {
    # walker.models.hzd.make_invariant(FiveLinkParams(**_RABBIT_DEFAULTS)), printed with repr
    # (tests/test_params.py recomputes them)
    "bezier_knee_0": 0.20000000000000004,
    "bezier_knee_1": 0.26191304879112004,
    "bezier_torso_0": -0.1,
    "bezier_torso_1": -0.12078909628878046,
    "bezier_femur_0": -0.1,
    "bezier_femur_1": -0.19440104689560306,
    "bezier_femur_4": 0.30000000000000004,
    "bezier_tibia_0": -0.30000000000000004,
    "bezier_tibia_1": -0.3911584631046911,
    "bezier_tibia_4": 0.1,
}


RABBIT_GEAR_RATIO = 50.0
"""RABBIT's joint gear ratio (Chevallereau et al., IEEE Control Systems Magazine 23(5), 2003)."""
RABBIT_ROTOR = 3.32e-4
"""Inertia of each of RABBIT's motor rotors [kg m^2] (same source)."""
RABBIT_ROTOR_INERTIA = RABBIT_GEAR_RATIO**2 * RABBIT_ROTOR
"""Rotor inertia reflected at each of RABBIT's joints, N^2 J_rotor = 0.83 kg m^2."""
