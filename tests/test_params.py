"""Parameter dataclasses: canonical order, validation messages, presets, conversions."""

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest
from _rules import Failures
from numpy.testing import assert_allclose

from walker.params import (
    HAS_EVENTS,
    HAS_STRIDES,
    MODELS,
    PARAMS,
    STATE_NAMES,
    STATE_UNITS,
    CompassCoulombParams,
    CompassParams,
    DoublePendulumParams,
    FiveLinkParams,
    KneedParams,
    ModelSpec,
    RimlessWheelParams,
    SimplestParams,
    ThreeLinkParams,
    params_class,
)
from walker.symbolic.actuated import THREE_LINK_PARAMS

ROOT = Path(__file__).resolve().parents[1]

ALL_PRESETS = [(cls, name) for cls in PARAMS.values() for name in cls.PRESETS]
FIELDS = [(cls, f) for cls in PARAMS.values() for f in dataclasses.fields(cls)]


def _base(cls):
    return cls.preset(cls.PRESETS[0])


# ---- canonical order and metadata --------------------------------------------------------
def _kernel_order(module: str) -> tuple:
    """The parameter vector's order that the generated C kernels of ``module`` take (the
    same in each): the ``p = [...]`` lines of the argument order in its header."""
    header = Path(__file__).resolve().parents[1] / "walker" / "_generated" / f"{module}.h"
    orders = {
        tuple(line.split("[", 1)[1].rstrip("]").split(", "))
        for line in header.read_text().splitlines()
        if line.startswith(" *   p = [")
    }
    assert len(orders) == 1, orders
    return orders.pop()


def test_field_order_is_the_kernel_order():
    assert SimplestParams.names() == ("slope", "g", "leg_length", "damping_ankle")
    # the passive walkers' and the double pendulum's: the order every generated kernel takes
    assert CompassParams.names() == _kernel_order("compass")
    # the compass block is a prefix, so that ``p[:n]`` of compass_coulomb is a compass vector
    assert CompassCoulombParams.names() == (*CompassParams.names(), "coulomb_ankle", "coulomb_hip")
    assert KneedParams.names() == _kernel_order("kneed")
    assert DoublePendulumParams.names() == _kernel_order("double_pendulum")
    # the physical parameters first, in the order the generated kernels take them
    assert ThreeLinkParams.names()[: len(THREE_LINK_PARAMS)] == THREE_LINK_PARAMS
    assert ThreeLinkParams.names()[len(THREE_LINK_PARAMS) :] == (
        "friction",
        "controller",
        "kp",
        "kd",
        "torque_limit",
        "theta_plus",
        "theta_minus",
        *(f"bezier_swing_{k}" for k in range(5)),
        *(f"bezier_torso_{k}" for k in range(5)),
        # the finite-time controller (controller 3) and the step event
        "step_event",
        "ft_alpha",
        "ft_epsilon",
        *(f"poly_swing_{k}" for k in range(6)),
        *(f"poly_torso_{k}" for k in range(6)),
        "damping_hip",
        "coulomb_hip",
    )
    # joint friction is appended after the controller block (its offset stays valid)
    assert FiveLinkParams.names()[-5:] == (
        "bezier_tibia_4",
        "damping_hip",
        "damping_knee",
        "coulomb_hip",
        "coulomb_knee",
    )


def test_every_field_has_unit_doc_bounds_and_no_default():
    fails = Failures("every field is made by _param: unit, doc, (lo, hi), bool openness")
    for cls, f in FIELDS:
        m = f.metadata
        fails.check(
            f"{cls.__name__}.{f.name}",
            f.default is dataclasses.MISSING
            and f.default_factory is dataclasses.MISSING
            and bool(m.get("unit"))
            and bool(m.get("doc"))
            and len(m.get("bounds", ())) == 2
            and isinstance(m.get("lo_open"), bool)
            and isinstance(m.get("hi_open"), bool),
            f"default={f.default!r}, metadata={dict(m)!r}",
        )
    fails.assert_none(at_least=len(PARAMS))


def test_units_and_docs_follow_the_canonical_order():
    units = CompassParams.units()
    assert tuple(units) == CompassParams.names()
    assert units["mass_hip"] == "kg"
    assert units["inertia_leg"] == "kg m^2"
    assert units["slope"] == "rad"
    assert units["g"] == "m/s^2"
    assert tuple(KneedParams.docs()) == KneedParams.names()
    assert CompassParams.bounds()["mass_hip"] == (0.0, None)
    assert units["damping_hip"] == "N m s/rad"
    assert KneedParams.units()["damping_knee"] == "N m s/rad"
    assert units["damping_ankle"] == KneedParams.units()["damping_ankle"] == "N m s/rad"
    assert CompassParams.n_params() == 10
    assert KneedParams.n_params() == 17


def test_registry_tables_agree():
    assert set(PARAMS) == set(STATE_NAMES) == set(HAS_STRIDES)
    # The model list is the registry's, not restated here (issue 32): the registry's models
    # are the model modules in walker/models/, each state is angles then their rates (plus,
    # for the actuated walkers, the two accumulators), and a model has strides exactly when
    # its module declares a section.
    import importlib

    # a model module declares its phases; the helpers beside them (friction modes,
    # controllers, HZD) declare none
    modules = {
        p.stem
        for p in (ROOT / "walker" / "models").glob("*.py")
        if re.search(r"^PHASE_NAMES\b", p.read_text(), re.MULTILINE)
    }
    assert set(PARAMS) == {m for m in modules if not m.startswith("_")}
    for m in PARAMS:
        units = STATE_UNITS[m]
        n_angles = units.count("rad")
        assert units[: 2 * n_angles] == ("rad",) * n_angles + ("rad/s",) * n_angles
        assert len(STATE_NAMES[m]) == len(units)
        section = importlib.import_module(f"walker.models.{m}").SECTION_NAMES
        assert HAS_STRIDES[m] is (len(section) > 0)
    assert STATE_NAMES["five_link"][10:] == ("actuator_work", "saturated_time")
    assert STATE_NAMES["three_link"][6:] == ("actuator_work", "saturated_time")
    for model, cls in PARAMS.items():
        assert cls.MODEL == model
        assert params_class(model) is cls
    # the tables are views of the one registry; HAS_EVENTS is HAS_STRIDES's former name
    assert list(MODELS) == list(PARAMS)
    for model, spec in MODELS.items():
        assert spec.name == model and spec.params_class is PARAMS[model]
        assert spec.state_names is STATE_NAMES[model] and spec.n_x == len(STATE_NAMES[model])
        assert spec.has_strides is HAS_STRIDES[model]
    assert HAS_EVENTS is HAS_STRIDES


def test_model_spec_refuses_units_that_do_not_match_the_state():
    with pytest.raises(
        ValueError,
        match=r"^`state_units` must have one unit per state component \(2\) for model "
        r"rimless_wheel, got 1$",
    ):
        ModelSpec(RimlessWheelParams, ("theta", "theta_dot"), ("rad",), True, "a wheel")


def test_params_class_unknown_model():
    with pytest.raises(
        ValueError,
        match=r"^unknown model 'biped'; valid models: simplest, compass, kneed, double_pendulum, "
        r"three_link, five_link, compass_coulomb, kneed_coulomb, rimless_wheel$",
    ):
        params_class("biped")


# ---- presets -----------------------------------------------------------------------------
def _round_trip_problems(cls, preset):
    p = cls.preset(preset)
    arr = p.as_array()
    declared = tuple(f.name for f in dataclasses.fields(cls))
    problems = []
    if arr.dtype != np.float64 or arr.shape != (len(declared),) or cls.n_params() != len(declared):
        problems.append(f"as_array dtype {arr.dtype} shape {arr.shape}, {len(declared)} fields")
    elif [float(v) for v in arr] != [getattr(p, n) for n in declared]:
        problems.append("as_array is not in the declared field order")
    if cls.names() != declared:
        problems.append(f"names() {cls.names()} is not the declared order {declared}")
    if cls.from_array(arr) != p:
        problems.append("from_array(as_array()) differs")
    if cls.from_dict(p.to_dict()) != p:
        problems.append("from_dict(to_dict()) differs")
    if list(p.to_dict()) != list(declared):
        problems.append("to_dict keys are not in the declared order")
    if not all(type(v) is float for v in p.to_dict().values()):
        problems.append("a value is not stored as float")
    if getattr(cls, preset)() != p:
        problems.append("preset(name) differs from the classmethod")
    return problems


def test_presets_are_valid_and_round_trip_in_the_declared_order():
    """Every preset builds (its values pass every rule), ``as_array`` follows the declared
    field order, and the array and dict conversions give the preset back."""
    fails = Failures("preset valid, as_array in declared order, conversions round-trip")
    for cls, preset in ALL_PRESETS:
        label = f"{cls.__name__}.{preset}"
        try:
            problems = _round_trip_problems(cls, preset)
        except Exception as err:  # noqa: BLE001 - reported with the preset's name
            problems = [f"raised {type(err).__name__}: {err}"]
        fails.check(label, not problems, "; ".join(problems))
    fails.assert_none(at_least=len(PARAMS))


def test_preset_unknown_name_and_overrides():
    with pytest.raises(
        ValueError,
        match=r"unknown KneedParams preset `hsu` \(did you mean `hsu_chen`\?\); valid presets: "
        r"hsu_chen, mcgeer",
    ):
        KneedParams.preset("hsu")
    assert KneedParams.preset("hsu_chen", slope=0.04).slope == 0.04
    with pytest.raises(ValueError, match=r"`slope` must be in \(-pi/2, pi/2\)"):
        KneedParams.preset("hsu_chen", slope=2.0)


def test_garcia_preset():
    # Garcia et al. 1998: g = l = 1, stable gait studied at gamma = 0.009
    assert SimplestParams.garcia() == SimplestParams(
        slope=0.009, g=1.0, leg_length=1.0, damping_ankle=0.0
    )
    assert SimplestParams.garcia(slope=0.01).slope == 0.01


def test_goswami_and_drake_presets():
    p = CompassParams.goswami()
    # Goswami, Thuilot, Espiau 1996: m_H = 10, m = 5, a = b = 0.5, 3 degrees; g = 9.8 (Spong 2007)
    assert (p.mass_hip, p.mass_leg, p.com_from_foot, p.com_to_hip) == (10.0, 5.0, 0.5, 0.5)
    assert (p.inertia_leg, p.foot_radius, p.g) == (0.0, 0.0, 9.8)
    assert_allclose(p.slope, 3.0 * math.pi / 180.0, rtol=1e-15, atol=0)
    assert p.leg_length == 1.0
    assert CompassParams.goswami(slope=0.06).slope == 0.06
    # Drake examples/compass_gait/compass_gait_params_named_vector.yaml
    d = CompassParams.drake()
    assert (d.mass_hip, d.mass_leg, d.leg_length, d.com_to_hip) == (10.0, 5.0, 1.0, 0.5)
    assert (d.slope, d.g) == (0.0525, 9.81)


def test_hsu_chen_preset():
    p = KneedParams.hsu_chen()
    # Hsu Chen 2007: l_s = l_t = 0.5, L = 1, slope asin(7.25/144) ~ 0.0504
    assert p.shank_length == 0.5 and p.thigh_length == 0.5 and p.leg_length == 1.0
    assert_allclose(p.slope, 0.0504, rtol=0, atol=5e-5)
    assert_allclose(math.sin(p.slope), 7.25 / 144, rtol=1e-15, atol=0)
    assert (p.mass_hip, p.mass_thigh, p.mass_shank, p.g) == (0.5, 0.5, 0.05, 9.8)


def test_mcgeer_preset():
    p = KneedParams.mcgeer()
    # McGeer 1990: total mass 1, leg length 1, thigh 0.46 / shank 0.54,
    # radii of gyration 0.135 (thigh) and 0.186 (shank)
    total = p.mass_hip + 2.0 * (p.mass_thigh + p.mass_shank)
    assert_allclose(total, 1.0, rtol=1e-15, atol=0)
    assert_allclose(
        [p.thigh_length, p.shank_length, p.leg_length], [0.46, 0.54, 1.0], rtol=1e-15, atol=0
    )
    assert_allclose(math.sqrt(p.inertia_thigh / p.mass_thigh), 0.135, rtol=1e-15, atol=0)
    assert_allclose(math.sqrt(p.inertia_shank / p.mass_shank), 0.186, rtol=1e-15, atol=0)
    assert (p.thigh_com_to_hip, p.shank_com_to_knee) == (0.20, 0.24)
    assert (p.offset_shank, p.offset_thigh, p.foot_radius, p.slope, p.g) == (
        0.01,
        0.0,
        0.2,
        0.0456,
        1.0,
    )


def test_grizzle_preset():
    p = ThreeLinkParams.grizzle()
    # Westervelt, Grizzle, Chevallereau, Choi, Morris 2007, model_params_three_link.m:
    # Mh = 15, m = 5, Mt = 10, r = 1 (leg masses at r/2), L = 0.5, g = 9.8, point masses
    assert (p.mass_hip, p.mass_leg, p.mass_torso) == (15.0, 5.0, 10.0)
    assert (p.torso_length, p.g) == (0.5, 9.8)
    assert (p.com_from_foot, p.com_to_hip, p.leg_length) == (0.5, 0.5, 1.0)
    assert (p.inertia_leg, p.inertia_torso, p.slope) == (0.0, 0.0, 0.0)
    # control_params_three_link.m: step angle pi/8, torso leaning forward by pi/6 (clockwise
    # in [3]; counterclockwise-positive here, so -pi/6)
    assert p.controller == 2.0 and p.theta_minus == -math.pi / 8
    assert (p.bezier_torso_2, p.bezier_torso_3, p.bezier_torso_4) == (-math.pi / 6,) * 3
    # keyword changes go through make_invariant, unlike preset(..., **changes)
    assert ThreeLinkParams.grizzle(kp=50.0).kp == 50.0
    assert ThreeLinkParams.preset("grizzle", torque_limit=80.0).torque_limit == 80.0
    with pytest.raises(
        ValueError, match=r"^unknown ThreeLinkParams preset `westervelt`; valid presets: grizzle$"
    ):
        ThreeLinkParams.preset("westervelt")


def test_bezier_degree_matches_the_controller():
    """The actuated walkers' Bezier fields have the degree walker.models.control evaluates."""
    from walker.models.control import BEZIER_DEGREE
    from walker.params.actuated import _BEZIER_DEGREE

    assert _BEZIER_DEGREE == BEZIER_DEGREE
    assert "bezier_swing_4" in ThreeLinkParams.names()
    assert f"bezier_swing_{BEZIER_DEGREE + 1}" not in ThreeLinkParams.names()


def test_polynomial_degree_matches_the_compiled_controller():
    """The book controller's polynomial fields have the degree walker/_core/wk_control.h
    evaluates (WK_CONTROL_POLY_DEGREE)."""
    import re
    from pathlib import Path

    import walker
    from walker.params.actuated import _POLY_DEGREE

    header = Path(walker.__file__).parent / "_core" / "wk_control.h"
    found = re.findall(r"#define WK_CONTROL_POLY_DEGREE (\d+)", header.read_text())
    assert found == [str(_POLY_DEGREE)]
    assert f"poly_swing_{_POLY_DEGREE}" in ThreeLinkParams.names()
    assert f"poly_swing_{_POLY_DEGREE + 1}" not in ThreeLinkParams.names()


def test_course_preset():
    p = DoublePendulumParams.course()
    # the course's pendulum has frictionless joints
    assert_allclose(p.as_array(), [1, 1, 0.5, 0.5, 1, 1, 0.5, 0.5, 10, 0, 0, 0, 0], rtol=0, atol=0)


# ---- type and finiteness: one test per rule, over every field ----------------------------
def test_nonfinite_rejected():
    fails = Failures("a NaN or infinite value is refused with ValueError naming the field")
    for cls, f in FIELDS:
        for bad in (math.nan, math.inf, -math.inf):
            fails.raises(
                f"{cls.__name__}.{f.name} = {bad!r}",
                ValueError,
                rf"^`{f.name}` must be finite, got {bad!r}$",
                _base(cls).replace,
                **{f.name: bad},
            )
    fails.assert_none(at_least=3 * len(FIELDS))


NON_NUMBERS = (True, np.True_, "1.0", None, 1 + 0j, [1.0])


def test_non_numbers_rejected():
    """bool (Python and numpy), strings, None, complex and sequences are refused as types."""
    fails = Failures("a value that is not a real number is refused with TypeError naming it")
    for cls, f in FIELDS:
        for bad in NON_NUMBERS:
            fails.raises(
                f"{cls.__name__}.{f.name} = {bad!r}",
                TypeError,
                rf"^`{f.name}` must be a real number, got {type(bad).__name__} ",
                _base(cls).replace,
                **{f.name: bad},
            )
    fails.assert_none(at_least=len(NON_NUMBERS) * len(FIELDS))


def test_numpy_and_int_values_are_stored_as_float():
    p = CompassParams.goswami().replace(mass_hip=np.float32(2.0), mass_leg=3)
    assert type(p.mass_hip) is float and type(p.mass_leg) is float
    assert (p.mass_hip, p.mass_leg) == (2.0, 3.0)
    with pytest.raises(TypeError, match=r"`mass_hip` must be a real number, got bool np.True_"):
        p.replace(mass_hip=np.True_)


# ---- bounds: every bound of every field, from the field's metadata -----------------------
_NUMBER = {"pi/2": math.pi / 2, "-pi/2": -math.pi / 2}
_RULE = re.compile(
    r"^(?:(?P<op>>=|>|<=|<) (?P<num>\S+)"
    r"|in (?P<left>[\[(])(?P<lo>[^,]+), (?P<hi>[^\])]+)(?P<right>[\])]))$"
)


def _stated_bounds(rule: str):
    """``(lo, hi, lo_open, hi_open)`` that a message's rule (``>= 0``, ``in (0, 1)``, ...)
    states, or None if it is none of these forms."""
    m = _RULE.match(rule)
    if m is None:
        return None
    if m["op"]:
        x = _NUMBER.get(m["num"]) or float(m["num"])
        return (
            (x, None, m["op"] == ">", False) if ">" in m["op"] else (None, x, False, "<" == m["op"])
        )
    lo = _NUMBER.get(m["lo"]) or float(m["lo"])
    hi = _NUMBER.get(m["hi"]) or float(m["hi"])
    return lo, hi, m["left"] == "(", m["right"] == ")"


def _outside_values(meta):
    """One value just outside each bound: the bound itself where it is open, 0.1 beyond it
    where it is closed."""
    lo, hi = meta["bounds"]
    if lo is not None:
        yield lo if meta["lo_open"] else lo - 0.1
    if hi is not None:
        yield hi if meta["hi_open"] else hi + 0.1


def _same(a, b):
    return (a is None and b is None) or (
        a is not None and b is not None and math.isclose(a, b, rel_tol=1e-5, abs_tol=1e-12)
    )


def test_bounds():
    """A value just outside any bound is refused with a message naming the field, the rule
    (which must state the bound and openness the metadata holds), the unit and the value."""
    fails = Failures("a value outside a field's bounds is refused, stating them")
    for cls, f in FIELDS:
        meta = f.metadata
        for value in _outside_values(meta):
            label = f"{cls.__name__}.{f.name} = {value!r}"
            fails.n_checked += 1
            try:
                _base(cls).replace(**{f.name: value})
            except ValueError as err:
                pattern = rf"^`{f.name}` must be (.+) \[{re.escape(meta['unit'])}\], got (\S+)$"
                m = re.match(pattern, str(err))
                stated = _stated_bounds(m[1]) if m else None
                lo, hi = meta["bounds"]
                if m is None or float(m[2]) != value:
                    fails.items.append(f"{label}: message {str(err)!r} is not {pattern!r}")
                elif stated is None or not (
                    _same(stated[0], lo)
                    and _same(stated[1], hi)
                    and stated[2] == (lo is not None and meta["lo_open"])
                    and stated[3] == (hi is not None and meta["hi_open"])
                ):
                    fails.items.append(
                        f"{label}: rule {m[1]!r} does not state the metadata's bounds "
                        f"{(lo, hi)}, lo_open={meta['lo_open']}, hi_open={meta['hi_open']}"
                    )
            except Exception as err:  # noqa: BLE001 - reported with the field's name
                fails.items.append(f"{label}: raised {type(err).__name__}: {err}")
            else:
                fails.items.append(f"{label}: accepted")
    n_sides = sum(b is not None for _, f in FIELDS for b in f.metadata["bounds"])
    fails.assert_none(at_least=max(n_sides, len(PARAMS)))


def test_bound_messages_read_as_written():
    """A few messages spelled out, one for each form of the rule text."""
    cases = [
        (RimlessWheelParams, "spokes", 2.0, r"`spokes` must be >= 3 \[1\], got 2.0$"),
        (SimplestParams, "g", 0.0, r"`g` must be > 0 \[m/s\^2\], got 0.0$"),
        (KneedParams, "slope", -2.0, r"`slope` must be in \(-pi/2, pi/2\) \[rad\], got -2.0$"),
        (ThreeLinkParams, "controller", 4.0, r"`controller` must be in \[0, 3\] \[1\], got 4.0$"),
        (ThreeLinkParams, "ft_alpha", 1.0, r"`ft_alpha` must be in \(0, 1\) \[1\], got 1.0$"),
        (CompassParams, "inertia_leg", -1e-3, r"`inertia_leg` must be >= 0 \[kg m\^2\], got"),
    ]
    fails = Failures("bound messages as written")
    for cls, name, value, message in cases:
        fails.raises(
            f"{cls.__name__}.{name} = {value!r}",
            ValueError,
            "^" + message,
            _base(cls).replace,
            **{name: value},
        )
    fails.assert_none(at_least=len(cases))


# What bounds each kind of field must carry: the physics, by unit and name, not a list.
_UNBOUNDED_PREFIXES = ("offset_", "theta_", "bezier_", "poly_")


def _physical_bounds_rule(name, unit):
    """``(lo, hi, lo_open, hi_open)`` the physics asks of a field (None: only ``lo`` = 0 is
    required, either open or closed), or the string ``"unbounded"``, or ``"any"``."""
    if name == "slope":  # a ramp steeper than vertical is not a slope
        return (-math.pi / 2, math.pi / 2, True, True)
    if name.startswith(_UNBOUNDED_PREFIXES):  # angles, offsets, controller coefficients
        return "unbounded"
    if unit in ("kg m^2", "N m s/rad") or name.startswith("coulomb_"):
        return (0.0, None, False, False)  # inertias, viscous and dry friction: may vanish
    if unit == "kg" or name == "g" or name.startswith(("mass_", "length_")):
        return None  # masses, gravity, lengths: never negative
    return "any"


def test_bounds_follow_the_physics():
    """Inertias, dampings and dry friction are >= 0; masses, lengths and g have lower bound
    0; every slope is in (-pi/2, pi/2); angles, offsets and controller coefficients are the
    only unbounded fields."""
    fails = Failures("a field's bounds are what its physical kind asks")
    for cls, f in FIELDS:
        lo, hi = f.metadata["bounds"]
        openness = (f.metadata["lo_open"], f.metadata["hi_open"])
        rule = _physical_bounds_rule(f.name, f.metadata["unit"])
        label = f"{cls.__name__}.{f.name} [{f.metadata['unit']}] bounds {(lo, hi)} open {openness}"
        if rule == "unbounded":
            fails.check(label, lo is None and hi is None, "must be unbounded")
        elif rule is None:
            fails.check(label, lo == 0.0, "must have lower bound 0")
        elif rule == "any":
            fails.check(label, lo is not None or hi is not None, "an unbounded field not named so")
        else:
            fails.check(label, (lo, hi, *openness) == rule, f"must be {rule}")
    fails.assert_none(at_least=len(FIELDS))


def test_closed_bounds_are_accepted():
    CompassParams.goswami().replace(inertia_leg=0.0, foot_radius=0.0, com_to_hip=0.0)
    DoublePendulumParams.course().replace(g=0.0, com_1=0.0, com_2=1.0)
    KneedParams.hsu_chen().replace(offset_thigh=0.5, offset_shank=-0.5)
    SimplestParams.garcia(slope=-1.5)
    t = ThreeLinkParams.grizzle()
    t.replace(controller=0.0, mass_torso=0.0, inertia_torso=0.0, theta_minus=t.theta_plus)
    t.replace(controller=1.0, kp=0.0, kd=0.0, torso_length=0.0, inertia_leg=0.0)
    t.replace(mass_torso=0.0, inertia_torso=0.1)  # a torso with inertia only
    t.replace(theta_plus=-4.0, bezier_swing_2=10.0, bezier_torso_4=-10.0)  # unbounded


# ---- cross-field rules -------------------------------------------------------------------
CROSS_CASES = [
    (
        CompassParams,
        {"com_from_foot": 0.0, "com_to_hip": 0.0},
        r"leg length `com_from_foot \+ com_to_hip` must be > 0 \[m\], got 0.0",
    ),
    (
        CompassParams,
        {"foot_radius": 1.0},
        r"`foot_radius` must be < leg length `com_from_foot \+ com_to_hip` = 1.0 \[m\], got 1.0",
    ),
    (
        KneedParams,
        {"shank_com_from_foot": 0.0, "shank_com_to_knee": 0.0},
        r"shank length `shank_com_from_foot \+ shank_com_to_knee` must be > 0 \[m\], got 0.0",
    ),
    (
        KneedParams,
        {"thigh_com_from_knee": 0.0, "thigh_com_to_hip": 0.0},
        r"thigh length `thigh_com_from_knee \+ thigh_com_to_hip` must be > 0 \[m\], got 0.0",
    ),
    (
        KneedParams,
        {"offset_thigh": 0.6},
        r"\|`offset_thigh`\| must be <= thigh length 0.5 \[m\] .*, got 0.6",
    ),
    (
        KneedParams,
        {"offset_shank": -0.51},
        r"\|`offset_shank`\| must be <= shank length 0.5 \[m\] .*, got -0.51",
    ),
    (KneedParams, {"foot_radius": 0.5}, r"`foot_radius` must be < shank length 0.5 \[m\]"),
    (
        DoublePendulumParams,
        {"com_1": 1.5},
        r"`com_1` must be <= `length_1` = 1.0 \[m\] \(centre of mass inside its link\), got 1.5",
    ),
    (DoublePendulumParams, {"com_2": 1.01}, r"`com_2` must be <= `length_2` = 1.0 \[m\]"),
    (
        ThreeLinkParams,
        {"com_from_foot": 0.0, "com_to_hip": 0.0},
        r"leg length `com_from_foot \+ com_to_hip` must be > 0 \[m\], got 0.0$",
    ),
    (ThreeLinkParams, {"controller": 1.5}, r"`controller` must be 0, 1, 2 or 3, got 1.5$"),
    (
        ThreeLinkParams,
        {"controller": 1.0, "theta_plus": 0.3, "theta_minus": 0.3},
        r"`theta_minus` must differ from `theta_plus` when the controller is on, got 0.3$",
    ),
    (
        ThreeLinkParams,
        {"mass_torso": 0.0},
        r"`mass_torso` or `inertia_torso` must be > 0 when the controller is on, got 0.0$",
    ),
]


def test_cross_field_rules():
    fails = Failures("a broken cross-field rule is refused, naming the fields and the rule")
    for cls, changes, message in CROSS_CASES:
        fails.raises(
            f"{cls.__name__} with {changes}",
            ValueError,
            "^" + message,
            _base(cls).replace,
            **changes,
        )
    fails.assert_none(at_least=len(CROSS_CASES))


def test_foot_radius_may_exceed_com_from_foot():
    # only R < leg length is required, not R <= a
    p = CompassParams.goswami().replace(foot_radius=0.7)
    assert p.foot_radius > p.com_from_foot


def test_leg_length_after_change():
    p = KneedParams.hsu_chen().replace(shank_com_from_foot=0.5, thigh_com_to_hip=0.4)
    assert (p.shank_length, p.thigh_length, p.leg_length) == (0.625, 0.575, 1.2)


# ---- conversions -------------------------------------------------------------------------
def test_frozen_and_replace_copies():
    p = CompassParams.goswami()
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.mass_hip = 1.0  # type: ignore[misc]
    q = p.replace(mass_hip=2.0)
    assert q.mass_hip == 2.0 and p.mass_hip == 10.0
    assert q.as_array()[0] == 2.0


def test_replace_unknown_name():
    with pytest.raises(
        ValueError,
        match=r"unknown CompassParams parameter\(s\) `mas_hip` \(did you mean `mass_hip`\?\); "
        r"valid names: mass_hip, mass_leg,",
    ):
        CompassParams.goswami().replace(mas_hip=1.0)


def test_from_array_validates():
    good = CompassParams.goswami().as_array()
    with pytest.raises(
        ValueError,
        match=r"`p` must have shape \(10,\) for CompassParams .*"
        r"got shape \(9,\)",
    ):
        CompassParams.from_array(good[:9])  # a vector from before the ankle damper was added
    with pytest.raises(ValueError, match=r"`p` must have shape \(10,\).*got shape \(1, 10\)"):
        CompassParams.from_array(good[None, :])
    with pytest.raises(TypeError, match=r"`p` must hold real numbers, got dtype complex128"):
        CompassParams.from_array(good.astype(complex))
    bad = good.copy()
    bad[1] = -5.0
    with pytest.raises(ValueError, match=r"`mass_leg` must be > 0 \[kg\], got -5.0"):
        CompassParams.from_array(bad)
    bad[1] = np.nan
    with pytest.raises(ValueError, match=r"`mass_leg` must be finite, got nan"):
        CompassParams.from_array(bad)
    # the array is not aliased
    p = CompassParams.from_array(good)
    good[0] = 99.0
    assert p.mass_hip == 10.0


def test_from_dict_unknown_and_missing_keys():
    d = KneedParams.hsu_chen().to_dict()
    with pytest.raises(
        ValueError,
        match=r"unknown KneedParams key\(s\) `knee`; valid keys: "
        r"mass_hip, mass_thigh",
    ):
        KneedParams.from_dict({**d, "knee": 1.0})
    del d["g"], d["slope"]
    with pytest.raises(ValueError, match=r"missing KneedParams key\(s\) `slope`, `g`$"):
        KneedParams.from_dict(d)
    with pytest.raises(TypeError, match=r"`d` must be a mapping, got list"):
        KneedParams.from_dict([1.0])
    with pytest.raises(ValueError, match=r"`mass_hip` must be > 0 \[kg\], got -1.0"):
        KneedParams.from_dict({**KneedParams.hsu_chen().to_dict(), "mass_hip": -1.0})


def test_value_equality_and_hash():
    assert CompassParams.goswami() == CompassParams.goswami()
    assert hash(CompassParams.goswami()) == hash(CompassParams.goswami())
    assert CompassParams.goswami() != CompassParams.drake()


@pytest.mark.parametrize(
    ("cls", "preset", "defaults"),
    [
        (ThreeLinkParams, "grizzle", "_GRIZZLE_DEFAULTS"),
        (FiveLinkParams, "rabbit", "_RABBIT_DEFAULTS"),
    ],
)
def test_hzd_presets_store_the_invariant_design(cls, preset, defaults):
    """The presets' Bezier coefficients are stored as numbers (params imports no analysis
    code); they are what walker.models.hzd.make_invariant makes of the design, to the last bits."""
    import walker.params._actuated_presets as params_module
    from walker.models.hzd import make_invariant

    stored = getattr(cls, preset)()
    computed = make_invariant(cls(**getattr(params_module, defaults)))
    for name in cls.names():
        assert getattr(stored, name) == pytest.approx(getattr(computed, name), rel=4e-16, abs=1e-16)
    # changes the impact does not depend on are taken; the others are refused by name
    assert getattr(cls, preset)(kp=50.0, damping_hip=0.2).kp == 50.0
    with pytest.raises(ValueError, match=rf"`{preset}\(\)` changes may only set .* got `slope`"):
        getattr(cls, preset)(slope=0.01)
