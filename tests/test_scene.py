"""Scene files: the shipped gaits load, and every malformed file fails with a pinned message."""

import math
import re
from pathlib import Path

import numpy as np
import pytest
from _rules import Failures
from numpy.testing import assert_allclose

from walker.models import MODEL_NAMES, get_model
from walker.params import HAS_STRIDES, STATE_NAMES, CompassParams, KneedParams, ThreeLinkParams
from walker.scene import ComputeSettings, Scene, load_scene
from walker.status import METHOD_DOP853, METHOD_DP5, METHOD_EULER, METHOD_RK4

GAITS = Path(__file__).resolve().parent.parent / "gaits"
# The scenes are the files in gaits/ (a new scene needs no edit here); those carrying walker's
# own high-accuracy [reference] values found by a plain text scan, which the loader's parse
# must agree with (test_shipped_scenes_load).
SHIPPED = sorted(p.stem for p in GAITS.glob("*.toml"))
WITH_REFERENCE = [
    name
    for name in SHIPPED
    if re.search(r"^\[reference\]", (GAITS / f"{name}.toml").read_text(encoding="utf-8"), re.M)
]


def test_every_model_has_a_shipped_scene():
    assert {load_scene(GAITS / f"{name}.toml").model for name in SHIPPED} == set(MODEL_NAMES)
    walkers = {m for m in MODEL_NAMES if HAS_STRIDES[m]}  # a gait to refer to
    assert {load_scene(GAITS / f"{n}.toml").model for n in WITH_REFERENCE} == walkers


COMPASS_FULL = """\
mass_hip = 10.0
mass_leg = 5.0
com_from_foot = 0.5
com_to_hip = 0.5
inertia_leg = 0.0
foot_radius = 0.0
damping_hip = 0.0
damping_ankle = 0.0
slope = 0.05
g = 9.8"""

BASE = {
    "scene": 'model = "compass"\ndescription = "test"',
    "parameters": COMPASS_FULL,
    "initial": "state = [0.2187, -0.3234, -1.0918, -0.3772]",
}


def _text(sections):
    return "\n".join(f"[{name}]\n{body}\n" for name, body in sections.items() if body is not None)


def _write(tmp_path, sections=None, raw=None, name="x.toml"):
    """Write BASE updated with ``sections`` (None drops a table), or ``raw`` text."""
    path = tmp_path / name
    path.write_text(raw if raw is not None else _text({**BASE, **(sections or {})}))
    return path


def _fails(tmp_path, message, sections=None, raw=None, overrides=None):
    """Assert load_scene raises ValueError: '<path>: ' + message (a regex)."""
    path = _write(tmp_path, sections, raw)
    with pytest.raises(ValueError, match="^" + re.escape(str(path)) + ": " + message):
        load_scene(path, overrides=overrides)


def _check_fails(tmp_path, rule, cases):
    """For each ``(label, message, sections)`` of ``cases``: load_scene of BASE updated
    with ``sections`` raises ValueError '<path>: ' + message (a regex); report every case
    that does not."""
    fails = Failures(rule)
    for label, message, sections in cases:
        path = _write(tmp_path, sections)
        fails.raises(
            label, ValueError, "^" + re.escape(str(path)) + ": " + message, load_scene, path
        )
    fails.assert_none(at_least=len(cases))


# ---- shipped scenes ----------------------------------------------------------------------
@pytest.mark.parametrize("name", SHIPPED)
def test_shipped_scenes_load(name):
    scene = load_scene(GAITS / f"{name}.toml")
    assert isinstance(scene, Scene)
    assert scene.name == name
    assert scene.path == GAITS / f"{name}.toml"
    assert scene.state.shape == (len(STATE_NAMES[scene.model]),)
    assert scene.state.dtype == np.float64
    assert scene.description and scene.source
    assert (scene.reference is not None) == (name in WITH_REFERENCE)
    assert type(scene.params).MODEL == scene.model


@pytest.mark.parametrize("name", WITH_REFERENCE)
def test_shipped_references(name):
    """Each [reference] holds a full state on the Poincare section, one multiplier per
    section coordinate (a conjugate-closed set: the stride map is real), a positive step time
    and tolerance, and a note saying how the values were computed."""
    scene = load_scene(GAITS / f"{name}.toml")
    ref = scene.reference
    model = get_model(scene.model)
    n_x, n_z = len(STATE_NAMES[scene.model]), model.n_z
    assert set(ref) >= {"state", "multipliers", "step_time", "tolerance", "note"}
    assert ref["state"].shape == (n_x,) and ref["state"].dtype == np.float64
    assert ref["multipliers"].shape == (n_z,) and ref["multipliers"].dtype == np.complex128
    mult = ref["multipliers"]
    assert_allclose(np.sort_complex(mult.conj()), np.sort_complex(mult), rtol=0, atol=0)
    # every shipped gait is described as stable: all multipliers inside the unit circle
    assert np.abs(mult).max() < 1.0
    assert ref["step_time"] > 0.0 and 0.0 < ref["tolerance"] < 1e-5 and ref["note"]
    # the state is just after heel strike: lifting its section coordinates gives it back
    z = model.project(ref["state"], scene.params)
    assert z.shape == (n_z,)
    assert_allclose(model.lift(z, scene.params), ref["state"], rtol=0, atol=1e-15)
    if "section" in ref:
        assert ref["section"].shape == (n_z,) and ref["section"].dtype == np.float64
        assert_allclose(ref["section"], z, rtol=0, atol=0)


def test_references_agree_with_published_digits():
    # Garcia et al. 1998 give theta, theta_dot to 14 digits; walker's values differ by < 1e-10
    s = load_scene(GAITS / "simplest_garcia.toml")
    assert_allclose(s.reference["state"][[0, 2]], s.state[[0, 2]], rtol=0, atol=1e-10)
    # Spong et al. 2007 round the compass-gait cycle to 4 decimals: agree to half a unit
    c = load_scene(GAITS / "compass_goswami.toml")
    assert_allclose(c.reference["state"], c.state, rtol=0, atol=5e-5)


def test_shipped_scene_contents():
    s = load_scene(GAITS / "simplest_garcia.toml")
    assert s.params.slope == 0.009 and s.params.g == 1.0
    theta, phi, theta_dot, phi_dot = s.state
    # Garcia et al. 1998 stable gait at gamma = 0.009
    assert (theta, theta_dot) == (0.20031090049483, -0.19983247291764)
    # the state is the image of a heel strike (Garcia's transition rule) from theta_minus
    theta_minus = -theta
    theta_dot_minus = theta_dot / math.cos(2 * theta_minus)
    c = math.cos(2 * theta_minus)
    assert_allclose(phi, -2 * theta_minus, rtol=1e-15, atol=0)
    assert_allclose(phi_dot, c * (1 - c) * theta_dot_minus, rtol=1e-14, atol=0)

    c = load_scene(GAITS / "compass_goswami.toml")
    assert c.params == CompassParams.goswami()
    assert_allclose(c.state, [0.2187, -0.3234, -1.0918, -0.3772], rtol=0, atol=0)  # Spong 2007

    k = load_scene(GAITS / "kneed_hsu.toml")
    assert k.params == KneedParams.hsu_chen()
    # Hsu Chen 2007 thesis fixed point
    assert_allclose(k.state, [0.1877, -0.2884, -0.2884, -1.1014, -0.0399, -0.0399], rtol=0, atol=0)

    m = load_scene(GAITS / "kneed_mcgeer_roundfoot.toml")
    assert m.params == KneedParams.mcgeer()
    assert "GUESS" in m.description
    assert_allclose(m.state[:3], k.state[:3], rtol=0, atol=0)
    assert_allclose(m.state[3:], k.state[3:] / math.sqrt(9.8), rtol=1e-15, atol=0)

    d = load_scene(GAITS / "double_pendulum.toml")
    # the course's [pi/2 - 0.1, pi] in walker's coordinates (tests/test_reference_runs.py)
    assert_allclose(d.state, [-0.1, math.pi / 2 + 0.1, 0.0, 0.0], rtol=1e-16, atol=0)
    assert (d.compute.task, d.compute.strides, d.compute.t_max) == ("simulate", 0, 10.0)

    t = load_scene(GAITS / "three_link_grizzle.toml")
    p = t.params
    assert p == ThreeLinkParams.grizzle()
    assert (t.compute.task, t.compute.strides, t.phase) == ("fixed_point", 1, 0)
    # walker's own fixed point; the initial state is the reference state
    assert_allclose(t.state, t.reference["state"], rtol=0, atol=0)
    # at heel strike the outputs vanish (phase s = 0): stance at theta_plus, swing and torso
    # at their first Bezier coefficients; no actuator work or saturation yet
    on_surface = [p.theta_plus, p.bezier_swing_0, p.bezier_torso_0]
    assert_allclose(t.state[:3], on_surface, rtol=0, atol=1e-12)
    assert_allclose(t.state[6:], [0.0, 0.0], rtol=0, atol=0)


def test_state_is_read_only():
    scene = load_scene(GAITS / "compass_goswami.toml")
    with pytest.raises(ValueError, match="read-only"):
        scene.state[0] = 1.0


# ---- parameters, presets, overrides ------------------------------------------------------
def test_full_parameters_table(tmp_path):
    scene = load_scene(_write(tmp_path))
    assert scene.params == CompassParams.goswami(slope=0.05)
    assert scene.compute == ComputeSettings()  # every default
    assert scene.phase is None and scene.source == "" and scene.description == "test"


def test_preset_with_table_overrides(tmp_path):
    path = _write(tmp_path, {"parameters": 'preset = "drake"\nmass_hip = 12'})
    assert load_scene(path).params == CompassParams.drake().replace(mass_hip=12.0)


def test_call_overrides_apply(tmp_path):
    path = _write(tmp_path)
    scene = load_scene(path, overrides={"slope": 0.06, "mass_leg": "4.5"})
    assert (scene.params.slope, scene.params.mass_leg) == (0.06, 4.5)
    assert load_scene(path, overrides={}).params.slope == 0.05


def test_overrides_can_repair_and_are_validated(tmp_path):
    path = _write(
        tmp_path, {"parameters": COMPASS_FULL.replace("mass_hip = 10.0", "mass_hip = -1")}
    )
    assert load_scene(path, overrides={"mass_hip": 3}).params.mass_hip == 3.0
    _fails(
        tmp_path,
        r"\[parameters\] \(with overrides `mass_hip`\) `mass_hip` must be > 0 \[kg\], got -2.0$",
        overrides={"mass_hip": -2.0},
    )
    _fails(
        tmp_path,
        r"\[overrides\] unknown parameter `mas_hip` for model compass "
        r"\(did you mean `mass_hip`\?\); valid names: mass_hip,",
        overrides={"mas_hip": 1.0},
    )
    _fails(
        tmp_path,
        r"\[overrides\] `slope` must be a number, got 'steep'$",
        overrides={"slope": "steep"},
    )
    _fails(
        tmp_path, r"\[overrides\] `slope` must be a number, got True$", overrides={"slope": True}
    )
    _fails(
        tmp_path,
        r"\[parameters\] \(with overrides `g`\) `g` must be finite",
        overrides={"g": "nan"},
    )
    with pytest.raises(TypeError, match=r"`overrides` must be a mapping"):
        load_scene(path, overrides=[("slope", 0.1)])


def test_replace_params(tmp_path):
    scene = load_scene(_write(tmp_path))
    other = scene.replace_params(slope=0.07)
    assert other.params.slope == 0.07 and scene.params.slope == 0.05
    assert other.state is scene.state and other.name == scene.name
    with pytest.raises(ValueError, match=r"`slope` must be in \(-pi/2, pi/2\)"):
        scene.replace_params(slope=3.0)
    with pytest.raises(ValueError, match=r"unknown CompassParams parameter\(s\) `slop`"):
        scene.replace_params(slop=0.1)


def test_state_names():
    assert load_scene(GAITS / "kneed_hsu.toml").state_names == (
        "q1",
        "q2",
        "q3",
        "qd1",
        "qd2",
        "qd3",
    )


# ---- file-level errors -------------------------------------------------------------------
def test_missing_file(tmp_path):
    path = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError, match=re.escape(f"scene file not found: {path}")):
        load_scene(path)


def test_bad_toml(tmp_path):
    _fails(
        tmp_path, r"invalid TOML: .*\(at line 2, column \d+\)", raw='[scene]\nmodel = "compass\n'
    )


def test_unknown_table(tmp_path):
    _fails(
        tmp_path,
        r"unknown table \[output\]; valid tables: \[scene\], \[model\], \[parameters\], "
        r"\[initial\], \[compute\], \[reference\], \[terrain\]$",
        {"output": 'file = "x"'},
    )
    _fails(
        tmp_path,
        r"`model` must be a table \[model\], got str",
        raw='model = "compass"\n' + _text(BASE),
    )


def test_missing_required_table(tmp_path):
    _check_fails(
        tmp_path,
        "a missing required table is refused, named",
        [
            (f"no [{table}]", rf"missing required table \[{table}\]$", {table: None})
            for table in ("scene", "parameters", "initial")
        ],
    )


def test_table_of_wrong_type(tmp_path):
    raw = "scene = 3\n" + _text({k: v for k, v in BASE.items() if k != "scene"})
    _fails(tmp_path, r"`scene` must be a table \[scene\], got int$", raw=raw)


# ---- [scene] -----------------------------------------------------------------------------
def test_scene_table_errors(tmp_path):
    _fails(
        tmp_path,
        r"\[scene\] unknown key `name`; valid keys: model, description, source$",
        {"scene": 'model = "compass"\nname = "x"'},
    )
    _fails(tmp_path, r"\[scene\] missing required key `model`$", {"scene": 'description = "x"'})
    _fails(tmp_path, r"\[scene\] `model` must be a string, got 3$", {"scene": "model = 3"})
    _fails(
        tmp_path,
        r"\[scene\] `model` must be one of simplest, compass, kneed, "
        r"double_pendulum, three_link, five_link, compass_coulomb, kneed_coulomb, "
        r"rimless_wheel, got 'biped'$",
        {"scene": 'model = "biped"'},
    )
    _fails(
        tmp_path,
        r"\[scene\] `source` must be a string, got \[1\]$",
        {"scene": 'model = "compass"\nsource = [1]'},
    )


# ---- [model] -----------------------------------------------------------------------------
KNEED_BASE = {
    "scene": 'model = "kneed"',
    "parameters": 'preset = "hsu_chen"',
    "initial": "state = [0.1877, -0.2884, -0.2884, -1.1014, -0.0399, -0.0399]",
}


def test_swing_scuff_defaults_to_trip():
    fails = Failures("a shipped scene trips on a swing-foot scuff (but the point-mass McGeer)")
    for name in SHIPPED:
        got = load_scene(GAITS / f"{name}.toml").swing_scuff
        expected = "ignore" if name == "kneed_mcgeer_pointmass" else "trip"
        fails.check(name, got == expected, f"swing_scuff {got!r}, expected {expected!r}")
    fails.assert_none(at_least=len(SHIPPED))


def test_model_table_swing_scuff(tmp_path):
    for value in ("trip", "ignore"):
        path = _write(tmp_path, {**KNEED_BASE, "model": f'swing_scuff = "{value}"'})
        scene = load_scene(path)
        assert scene.swing_scuff == value
        model = get_model(scene.model, swing_scuff=scene.swing_scuff)
        assert model.swing_scuff == value
        expected = "kneed/plain" if value == "trip" else "kneed/plain/ignore_scuff"
        assert model.system_for(scene.params).name == expected
    # an empty [model] table is the default
    assert load_scene(_write(tmp_path, {**KNEED_BASE, "model": ""})).swing_scuff == "trip"


def test_model_table_errors(tmp_path):
    _fails(
        tmp_path,
        r"\[model\] unknown key `swing` \(did you mean `swing_scuff`\?\); valid keys: swing_scuff$",
        {**KNEED_BASE, "model": 'swing = "ignore"'},
    )
    _fails(
        tmp_path,
        r"\[model\] `swing_scuff` must be one of \['trip', 'ignore'\] for model kneed "
        r"\('ignore' is offered by kneed\), got 'never'$",
        {**KNEED_BASE, "model": 'swing_scuff = "never"'},
    )
    _fails(
        tmp_path,
        r"\[model\] `swing_scuff` must be a str, got 1$",
        {**KNEED_BASE, "model": "swing_scuff = 1"},
    )
    # a convention the model does not have is an error, not silently dropped
    _fails(
        tmp_path,
        r"\[model\] `swing_scuff` must be one of \['trip'\] for model compass \('ignore' is "
        r"offered by kneed\), got 'ignore'$",
        {"model": 'swing_scuff = "ignore"'},
    )


# ---- [parameters] ------------------------------------------------------------------------
def test_parameters_table_errors(tmp_path):
    _fails(
        tmp_path,
        r"\[parameters\] unknown key `mas_hip` \(did you mean `mass_hip`\?\); "
        r"valid keys: mass_hip, mass_leg, .*, g, "
        r"damping_hip, damping_ankle, preset$",
        {"parameters": COMPASS_FULL + "\nmas_hip = 1.0"},
    )
    _fails(
        tmp_path,
        r"\[parameters\] missing keys `slope`, `g` \(give every parameter of CompassParams, "
        r"or `preset` = one of goswami, drake\)$",
        {"parameters": COMPASS_FULL.rsplit("\nslope", 1)[0]},
    )
    _fails(
        tmp_path,
        r"\[parameters\] `preset` must be one of goswami, drake for model compass, got 'hsu_chen'$",
        {"parameters": 'preset = "hsu_chen"'},
    )
    _fails(
        tmp_path,
        r"\[parameters\] unknown key `knee`; valid keys: mass_hip,",
        {"parameters": 'preset = "goswami"\nknee = 1.0'},
    )
    _fails(
        tmp_path,
        r"\[parameters\] `mass_hip` must be a number, got '10'$",
        {"parameters": COMPASS_FULL.replace("10.0", '"10"')},
    )
    _fails(
        tmp_path,
        r"\[parameters\] `mass_leg` must be a number, got True$",
        {"parameters": 'preset = "goswami"\nmass_leg = true'},
    )
    _fails(
        tmp_path,
        r"\[parameters\] `g` must be finite, got nan$",
        {"parameters": 'preset = "goswami"\ng = nan'},
    )


def test_invalid_parameter_values_are_prefixed(tmp_path):
    _fails(
        tmp_path,
        r"\[parameters\] `mass_hip` must be > 0 \[kg\], got -1.0$",
        {"parameters": COMPASS_FULL.replace("mass_hip = 10.0", "mass_hip = -1.0")},
    )
    _fails(
        tmp_path,
        r"\[parameters\] `foot_radius` must be < leg length",
        {"parameters": 'preset = "goswami"\nfoot_radius = 1.5'},
    )
    _fails(
        tmp_path,
        r"\[parameters\] `slope` must be in \(-pi/2, pi/2\) \[rad\], got 2.0$",
        {"parameters": 'preset = "goswami"\nslope = 2.0'},
    )


# ---- [initial] ---------------------------------------------------------------------------
def test_initial_table_errors(tmp_path):
    _fails(
        tmp_path,
        r"\[initial\] `state` must have 4 entries, got 6$",
        {"initial": "state = [0, 0, 0, 0, 0, 0]"},
    )
    _fails(tmp_path, r"\[initial\] `state` must have 4 entries, got 0$", {"initial": "state = []"})
    _fails(
        tmp_path,
        r"\[initial\] `state` must be an array of numbers, got 0.1$",
        {"initial": "state = 0.1"},
    )
    _fails(
        tmp_path,
        r"\[initial\] `state\[2\]` must be a number, got 'a'$",
        {"initial": 'state = [0, 0, "a", 0]'},
    )
    _fails(
        tmp_path,
        r"\[initial\] `state\[1\]` must be a number, got \[0\]$",
        {"initial": "state = [0, [0], 0, 0]"},
    )
    _fails(
        tmp_path,
        r"\[initial\] `state\[3\]` must be finite, got inf$",
        {"initial": "state = [0, 0, 0, inf]"},
    )
    _fails(tmp_path, r"\[initial\] missing required key `state`$", {"initial": "phase = 0"})
    _fails(
        tmp_path,
        r"\[initial\] unknown key `time`; valid keys: state, phase$",
        {"initial": "state = [0, 0, 0, 0]\ntime = 0"},
    )
    for bad in ("-1", "1.0", "true", '"0"'):
        _fails(
            tmp_path,
            r"\[initial\] `phase` must be an integer >= 0, got ",
            {"initial": f"state = [0, 0, 0, 0]\nphase = {bad}"},
        )


def test_initial_phase_and_integer_state(tmp_path):
    scene = load_scene(_write(tmp_path, {"initial": "state = [0, 1, 0, 0]\nphase = 0"}))
    assert scene.phase == 0
    assert scene.state.dtype == np.float64
    assert_allclose(scene.state, [0.0, 1.0, 0.0, 0.0], rtol=0, atol=0)


# ---- [compute] ---------------------------------------------------------------------------
def test_compute_settings(tmp_path):
    body = 'task = "simulate"\nstrides = 5\nmethod = "RK4"\nt_max = 3\nfirst_step = 1e-3'
    c = load_scene(_write(tmp_path, {"compute": body})).compute
    assert (c.task, c.strides, c.method, c.t_max, c.first_step) == ("simulate", 5, "RK4", 3.0, 1e-3)
    assert type(c.t_max) is float
    assert c.method_code == METHOD_RK4
    assert ComputeSettings().method_code == METHOD_DOP853
    assert ComputeSettings(method="RK45").method_code == METHOD_DP5
    assert ComputeSettings(method="Euler", first_step=0.01).method_code == METHOD_EULER
    assert ComputeSettings(task="simulate", strides=0).strides == 0


COMPUTE_CASES = [
    ('task = "walk"', r"`task` must be one of fixed_point, simulate, got 'walk'$"),
    ('method = "LSODA"', r"`method` must be one of DOP853, RK45, RK4, Euler, got 'LSODA'$"),
    ("strides = 0", r"`strides` \(the period\) must be >= 1 for task fixed_point, got 0$"),
    ('task = "simulate"\nstrides = -1', r"`strides` must be >= 0, got -1$"),
    ("strides = 1.5", r"`strides` must be an integer, got 1.5$"),
    ("strides = true", r"`strides` must be an integer, got True$"),
    ("rtol = 0", r"`rtol` must be a finite number > 0, got 0$"),
    ("atol = -1e-9", r"`atol` must be a finite number > 0, got -1e-09$"),
    ('rtol = "1e-9"', r"`rtol` must be a finite number > 0, got '1e-9'$"),
    ("t_max = inf", r"`t_max` must be a finite number > 0, got inf$"),
    (
        'method = "Euler"',
        r"`first_step` must be given \(a positive fixed step\) for method 'Euler'$",
    ),
    ('method = "RK4"', r"`first_step` must be given \(a positive fixed step\) for method 'RK4'$"),
    # the integrator's floor, refused with the file and key (it was accepted, then refused
    # by the run without either)
    ("rtol = 1e-15", r"`rtol` must be >= 100 \* eps = 2.22e-14, got 1e-15$"),
    ("first_step = -0.1", r"`first_step` must be a finite number > 0, got -0.1$"),
    (
        "tmax = 3",
        r"unknown key `tmax` \(did you mean `t_max`\?\); valid keys: task, strides, method, rtol, "
        r"atol, t_max, "
        r"first_step, tol$",
    ),
]


def test_compute_settings_direct_errors():
    with pytest.raises(ValueError, match=r"^`rtol` must be a finite number > 0, got nan$"):
        ComputeSettings(rtol=math.nan)
    with pytest.raises(ValueError, match=r"^`first_step` must be given .* for method 'RK4'$"):
        ComputeSettings(method="RK4")


def test_models_without_events(tmp_path):
    dp = (
        'preset = "course"',
        "state = [1.4707963267948965, 3.141592653589793, 0.0, 0.0]",
    )
    sections = {
        "scene": 'model = "double_pendulum"',
        "parameters": dp[0],
        "initial": dp[1],
    }
    c = load_scene(_write(tmp_path, sections)).compute
    assert (c.task, c.strides) == ("simulate", 0)  # defaults for a model without strides
    for body, got in [
        ("strides = 1", r"got task = 'simulate', strides = 1$"),
        ('task = "fixed_point"', r"got task = 'fixed_point', strides = 0$"),
    ]:
        _fails(
            tmp_path,
            r"\[compute\] model double_pendulum has no strides: use task = \"simulate\" and "
            r"strides = 0 \(integrate to t_max\), " + got,
            {**sections, "compute": body},
        )


# ---- [reference] -------------------------------------------------------------------------
def test_reference_table(tmp_path):
    body = (
        "state = [0.2, -0.3, -1.1, -0.4]\nsection = [1, 2, 3]\n"
        "multipliers = [[-0.19, 0.55], [-0.19, -0.55], [0, 0]]\n"
        'step_time = 0.73\ntolerance = 1e-10\nnote = "DOP853 rtol 1e-14"'
    )
    ref = load_scene(_write(tmp_path, {"reference": body})).reference
    assert_allclose(ref["state"], [0.2, -0.3, -1.1, -0.4], rtol=0, atol=0)
    assert_allclose(ref["section"], [1.0, 2.0, 3.0], rtol=0, atol=0)
    assert ref["multipliers"].dtype == np.complex128
    assert_allclose(ref["multipliers"], [-0.19 + 0.55j, -0.19 - 0.55j, 0], rtol=0, atol=0)
    assert (ref["step_time"], ref["tolerance"], ref["note"]) == (0.73, 1e-10, "DOP853 rtol 1e-14")


REFERENCE_CASES = [
    ("step_time = 1.0", r"missing required key `tolerance`$"),
    ("tolerance = 0", r"`tolerance` must be > 0, got 0.0$"),
    ("tolerance = 1e-9\nstate = [1, 2]", r"`state` must have 4 entries, got 2$"),
    (
        "tolerance = 1e-9\nmultipliers = [1, 2]",
        r"`multipliers` must be an array of \[re, im\] "
        r"pairs, got \[1, 2\]$",
    ),
    ("tolerance = 1e-9\nmultipliers = [[1, nan]]", r"`multipliers\[0\]\[1\]` must be finite"),
    ("tolerance = 1e-9\nstep_time = -1", r"`step_time` must be > 0, got -1.0$"),
    ("tolerance = 1e-9\nnote = 3", r"`note` must be a string, got 3$"),
    (
        "tolerance = 1e-9\nperiod = 2",
        r"unknown key `period`; valid keys: state, section, "
        r"multipliers, step_time, tolerance, note$",
    ),
]


# (table, body, message, id): the [compute] cases named by their body, the [reference]
# cases by their message
TABLE_CASES = [("compute", b, m, b) for b, m in COMPUTE_CASES]
TABLE_CASES += [("reference", b, m, m) for b, m in REFERENCE_CASES]


def test_table_errors(tmp_path):
    """A bad body of ``[table]`` is refused with the table's name and the message."""
    _check_fails(
        tmp_path,
        "a bad [compute] or [reference] body is refused with the table's name and the rule",
        [
            (f"[{table}] {name!r}", rf"\[{table}\] " + message, {table: body})
            for table, body, message, name in TABLE_CASES
        ],
    )


def test_compute_tol_is_read_and_checked(tmp_path):
    scene = load_scene(_write(tmp_path, {"compute": "tol = 1e-11"}))
    assert scene.compute.tol == 1e-11
    assert load_scene(_write(tmp_path, {})).compute.tol == 1e-12
    _fails(
        tmp_path, r"\[compute\] `tol` must be a finite number > 0, got 0", {"compute": "tol = 0"}
    )
