"""``walker models``, ``walker params``, ``walker scene new`` and the help of every subcommand."""

import argparse
import json
import math
import re
import tomllib

import pytest

from walker.cli import build_parser, main
from walker.cli._catalog import STARTS
from walker.cli._help import HelpFormatter
from walker.models import MODEL_NAMES, get_model
from walker.params import HAS_STRIDES, PARAMS, STATE_NAMES, STATE_UNITS
from walker.scene import ComputeSettings, load_scene

PRESETS = [(model, preset) for model, cls in PARAMS.items() for preset in cls.PRESETS]


def _strict_loads(text):
    """json.loads that refuses NaN and infinities (not JSON, RFC 8259)."""

    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _usage_error(capsys, argv) -> str:
    """Run ``argv``, expecting exit status 2; the error output."""
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse's own usage errors
        code = exc.code
    assert code == 2
    return capsys.readouterr().err


def test_strict_loads_refuses_nan():
    with pytest.raises(ValueError, match="NaN"):
        _strict_loads('{"x": NaN}')


# ---- state units ------------------------------------------------------------------------------
def _expected_unit(name: str) -> str:
    if name == "actuator_work":
        return "J"
    if name == "saturated_time":
        return "s"
    if name.startswith("qd") or name.endswith("_dot"):
        return "rad/s"
    return "rad"


@pytest.mark.parametrize("model", list(STATE_NAMES))
def test_state_units_follow_the_state_names(model):
    names, units = STATE_NAMES[model], STATE_UNITS[model]
    assert len(units) == len(names)
    assert list(units) == [_expected_unit(n) for n in names]


# ---- walker models ------------------------------------------------------------------------------
def test_models_json_describes_every_model(capsys):
    code, out, _ = _run(capsys, ["models", "--json"])
    assert code == 0
    records = _strict_loads(out)["models"]
    assert [r["name"] for r in records] == list(MODEL_NAMES)
    for rec in records:
        model = get_model(rec["name"])
        assert [s["name"] for s in rec["state"]] == list(STATE_NAMES[rec["name"]])
        assert [s["unit"] for s in rec["state"]] == list(STATE_UNITS[rec["name"]])
        assert rec["phases"] == list(model.phase_names)
        assert rec["guards"] == list(model.guard_names)
        assert [s["name"] for s in rec["section"]] == list(model.section_names)
        assert [s["index"] for s in rec["section"]] == list(range(model.n_z))
        assert rec["parameter_class"] == PARAMS[rec["name"]].__name__
        assert rec["presets"] == list(PARAMS[rec["name"]].PRESETS)
        assert rec["walker"] == HAS_STRIDES[rec["name"]]


def test_models_json_section_units_are_the_state_units(capsys):
    _, out, _ = _run(capsys, ["models", "kneed", "--json"])
    (rec,) = _strict_loads(out)["models"]
    assert [(s["name"], s["unit"]) for s in rec["section"]] == [
        ("q1", "rad"),
        ("qd1", "rad/s"),
        ("qd2", "rad/s"),
    ]
    assert rec["swing_scuff"] == ["trip", "ignore"]


def test_models_text_gives_the_section_indices_basin_axes_takes(capsys):
    code, out, _ = _run(capsys, ["models"])
    assert code == 0
    assert "0 q_stance [rad], 1 qd_stance [rad/s], 2 qd_swing [rad/s]" in out
    assert "0 theta_dot [rad/s]" in out  # the rimless wheel's one coordinate
    for name in MODEL_NAMES:
        assert re.search(rf"^{name}: ", out, re.MULTILINE)


def test_models_lists_every_phase_of_one_model_only_on_request(capsys):
    _, overview, _ = _run(capsys, ["models"])
    _, full, _ = _run(capsys, ["models", "five_link"])
    last = get_model("five_link").phase_names[-1]
    assert last not in overview and "81:" in overview
    assert re.search(rf"^\s+80  {re.escape(last)}$", full, re.MULTILINE)
    assert re.search(r"^\s+14  knee_swing_stick_breaks$", full, re.MULTILINE)


def test_models_refuses_an_unknown_model(capsys):
    err = _usage_error(capsys, ["models", "kneeded"])
    assert "kneeded" in err and "compass" in err


# ---- walker params ------------------------------------------------------------------------------
@pytest.mark.parametrize("model", list(PARAMS))
def test_params_json_gives_units_bounds_and_preset_values(capsys, model):
    code, out, _ = _run(capsys, ["params", model, "--json"])
    assert code == 0
    rec = _strict_loads(out)
    cls = PARAMS[model]
    assert rec["model"] == model and rec["parameter_class"] == cls.__name__
    assert [r["name"] for r in rec["parameters"]] == list(cls.names())
    assert [p["name"] for p in rec["presets"]] == list(cls.PRESETS)
    assert all(p["source"] for p in rec["presets"])
    for row in rec["parameters"]:
        assert row["unit"] == cls.units()[row["name"]] and row["doc"]
        assert (row["min"], row["max"]) == tuple(cls.bounds()[row["name"]])
        for preset, value in row["presets"].items():
            assert value == getattr(cls.preset(preset), row["name"])  # exactly


def test_params_json_bounds_say_which_ends_are_allowed(capsys):
    _, out, _ = _run(capsys, ["params", "compass", "--json"])
    rows = {r["name"]: r for r in _strict_loads(out)["parameters"]}
    assert rows["mass_hip"]["min"] == 0.0 and not rows["mass_hip"]["min_inclusive"]
    assert rows["mass_hip"]["max"] is None and rows["mass_hip"]["allowed"] == "> 0"
    assert rows["inertia_leg"]["min_inclusive"] and rows["inertia_leg"]["allowed"] == ">= 0"
    slope = rows["slope"]
    assert slope["min"] == -math.pi / 2 and slope["max"] == math.pi / 2
    assert not slope["min_inclusive"] and not slope["max_inclusive"]
    assert rows["slope"]["presets"] == {"goswami": math.radians(3.0), "drake": 0.0525}


def test_params_text_is_a_table_with_every_preset(capsys):
    code, out, _ = _run(capsys, ["params", "kneed"])
    assert code == 0
    lines = out.splitlines()
    header = next(line for line in lines if line.startswith("name"))
    assert header.split()[:5] == ["name", "unit", "allowed", "hsu_chen", "mcgeer"]
    row = next(line for line in lines if line.startswith("mass_hip "))
    assert row.split()[:5] == ["mass_hip", "kg", ">", "0", "0.5"] and "0.676" in row
    assert re.search(r"^slope\s+rad\s+in \(-pi/2, pi/2\)\s+0\.0503685169\s+0\.0456\s", out, re.M)


def test_params_refuses_a_missing_model(capsys):
    assert "MODEL" in _usage_error(capsys, ["params"])


# ---- walker scene new ---------------------------------------------------------------------------
def test_every_preset_has_a_start():
    assert sorted(STARTS) == sorted(PRESETS)
    for (model, _), start in STARTS.items():
        assert len(start.state) == len(STATE_NAMES[model])


@pytest.mark.parametrize(("model", "preset"), PRESETS)
def test_scene_new_is_accepted_by_find_or_run(tmp_path, capsys, model, preset):
    path = tmp_path / f"{model}_{preset}.toml"
    code, out, _ = _run(capsys, ["scene", "new", model, "--preset", preset, "--out", str(path)])
    assert code == 0 and str(path) in out
    scene = load_scene(path)
    assert scene.model == model and scene.params == PARAMS[model].preset(preset)
    assert tuple(scene.state) == STARTS[(model, preset)].state
    command = "find" if HAS_STRIDES[model] else "run"
    code, out, err = _run(capsys, [command, str(path)])
    # 0: the gait (or the run); 1: an expected outcome, for the starts known not to walk
    assert code == (0 if STARTS[(model, preset)].walks else 1), (out, err)
    if code == 0:
        assert "COMPLETED" in out


def _keys_and_comments(text: str):
    """(table, key, has a comment) for every ``key = value`` line of ``text``."""
    table, previous, found = None, "", []
    for line in text.splitlines():
        if line.startswith("["):
            table = line.strip("[]")
        elif re.match(r"^\w+ = ", line):
            key = line.split(" = ")[0]
            found.append((table, key, " # " in line or previous.startswith("# ")))
        previous = line
    return found


@pytest.mark.parametrize(("model", "preset"), PRESETS)
def test_scene_new_gives_every_key_with_a_comment(capsys, model, preset):
    code, text, _ = _run(capsys, ["scene", "new", model, "--preset", preset])
    assert code == 0
    found = _keys_and_comments(text)
    assert all(commented for _, _, commented in found), found
    keys = {(t, k) for t, k, _ in found}
    cls = PARAMS[model]
    assert {("parameters", n) for n in (*cls.names(), "preset")} <= keys
    compute = {f.name for f in ComputeSettings.__dataclass_fields__.values()} - {"first_step"}
    assert {("compute", n) for n in compute} <= keys
    assert "# first_step = " in text and "# phase = " in text
    assert {("scene", "model"), ("scene", "description"), ("scene", "source")} <= keys
    assert ("initial", "state") in keys
    doc = tomllib.loads(text)
    assert doc["parameters"]["preset"] == preset


def test_scene_new_comments_give_units_and_defaults(capsys):
    _, text, _ = _run(capsys, ["scene", "new", "compass", "--preset", "goswami"])
    assert re.search(r"^mass_hip = 10\.0 +# \[kg\] point mass at the hip; > 0$", text, re.M)
    assert re.search(r"^slope = 0\.05235987755982989 +# \[rad\] .*in \(-pi/2, pi/2\)$", text, re.M)
    assert re.search(r'^method = "DOP853" +# .*default "DOP853"$', text, re.M)
    assert re.search(r"^t_max = 20\.0 +# \[s\] .*default 20\.0$", text, re.M)
    assert "q_stance [rad], q_swing [rad], qd_stance [rad/s], qd_swing [rad/s]" in text


def test_scene_new_default_preset_is_the_first(capsys):
    _, text, _ = _run(capsys, ["scene", "new", "kneed"])
    assert tomllib.loads(text)["parameters"]["preset"] == "hsu_chen"


def test_scene_new_double_pendulum_simulates(capsys):
    _, text, _ = _run(capsys, ["scene", "new", "double_pendulum"])
    compute = tomllib.loads(text)["compute"]
    assert compute["task"] == "simulate" and compute["strides"] == 0


def test_scene_new_refuses_an_unknown_preset(capsys):
    err = _usage_error(capsys, ["scene", "new", "compass", "--preset", "hsu_chen"])
    assert "--preset" in err and "goswami, drake" in err


def test_scene_new_refuses_an_existing_out_without_overwrite(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    path.write_text("keep me\n")
    err = _usage_error(capsys, ["scene", "new", "compass", "--out", str(path)])
    assert "--overwrite" in err and str(path) in err
    assert path.read_text() == "keep me\n"
    code, _, _ = _run(capsys, ["scene", "new", "compass", "--out", str(path), "--overwrite"])
    assert code == 0 and load_scene(path).model == "compass"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.toml"]  # no temporary left


def test_scene_new_refuses_a_missing_directory(tmp_path, capsys):
    err = _usage_error(capsys, ["scene", "new", "compass", "--out", str(tmp_path / "no" / "x")])
    assert "--out" in err and "does not exist" in err


# ---- help on every option -----------------------------------------------------------------------
def _subparsers(parser, prefix=()):
    """(command words, parser) of every subcommand, nested ones included."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield (*prefix, name), sub
                yield from _subparsers(sub, (*prefix, name))


def _options(parser):
    return [
        a
        for a in parser._actions
        if not isinstance(a, argparse._HelpAction | argparse._SubParsersAction)
    ]


SUBPARSERS = dict(_subparsers(build_parser()))
OWN = (
    "find",
    "run",
    "continue",
    "basin",
    "sweep",
    "plot",
    "models",
    "params",
    "scene",
    "orbit-diagram",
    "mfpt",
    "gsn",
    "stepdown",
)


def test_every_command_is_listed():
    assert {"models", "params", "scene", "scene new", "find", "orbit-diagram"} <= {
        " ".join(words) for words in SUBPARSERS
    }


@pytest.mark.parametrize("words", list(SUBPARSERS), ids=" ".join)
def test_every_option_has_help(words):
    parser = SUBPARSERS[words]
    for action in _options(parser):
        assert action.help and action.help.strip(), (words, action.dest)


@pytest.mark.parametrize("words", [w for w in SUBPARSERS if w[0] in OWN], ids=" ".join)
def test_every_option_shows_its_default(words):
    parser = SUBPARSERS[words]
    assert parser.formatter_class is HelpFormatter
    formatter = parser._get_formatter()
    for action in _options(parser):
        if not action.option_strings:
            continue
        shown = formatter._expand_help(action)
        assert "default" in shown or "(required)" in shown, (words, action.dest, shown)


def test_basin_axes_help_says_where_the_indices_are_listed():
    help_ = next(a.help for a in SUBPARSERS[("basin",)]._actions if a.dest == "axes")
    assert "walker models" in help_


def test_help_formatter_shows_flags_as_off_and_values_as_given():
    parser = argparse.ArgumentParser(prog="x", formatter_class=HelpFormatter)
    parser.add_argument("--flag", action="store_true", help="a flag")
    parser.add_argument("--n", type=int, default=7, help="a count")
    parser.add_argument("--maybe", help="a thing (default: something)")
    parser.add_argument("--many", action="append", help="repeatable")
    parser.add_argument("--unsaid", help="no default said")
    text = " ".join(parser.format_help().split())
    assert "a flag (default: off)" in text and "a count (default: 7)" in text
    assert "a thing (default: something)" in text and "repeatable (default: none)" in text
    assert "no default said" in text and "said (default" not in text
