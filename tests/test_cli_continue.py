"""``walker continue`` (period, both ways, folds, ``--switch``) and ``walker orbit-diagram``.

The library options behind them (``continue_branch(bounds=..., stop_at_fold=...)``) are
checked first on the Hénon map, whose fold and period doubling are known in closed form
(``tests/test_continuation.py``): a_fold = -(1 - b)^2 / 4, a_PD = 3 (1 - b)^2 / 4.  Then the
command line on the shipped walkers, with the values measured here:

* Hsu Chen's kneed walker (``gaits/kneed_hsu.toml``, slope 0.0504): going down, its
  period-one branch folds at slope 0.03178509468 (a multiplier through +1); beyond the fold
  it continues, unstable, back up the slope.
* Goswami's compass gait (``gaits/compass_goswami.toml``, slope 3 deg = 0.0524): going up,
  the period-one gait period-doubles at slope 0.07663563 rad (4.39 deg, a multiplier through
  -1, as in the README); the period-two branch born there is stable until it doubles again
  at 0.0857665.
"""

import json

import numpy as np
import pytest
from _toy_maps import HenonMap, henon_fixed_points, henon_two_cycle
from numpy.testing import assert_allclose

from walker import load_scene
from walker.analysis.continuation import continue_branch
from walker.analysis.fixedpoint import find_fixed_point
from walker.cli import main
from walker.cli.orbit import settled_period
from walker.simulation.stride import StrideMap
from walker.status import Status
from walker.storage import read

B = 0.3
A_PD = 3 * (1 - B) ** 2 / 4  # 0.3675
A_FOLD = -((1 - B) ** 2) / 4  # -0.1225
KNEED_FOLD = 0.03178509468  # measured, see the module docstring
COMPASS_PD = 0.0766356316  # measured; the README's 0.07664 rad


def _reject(token):
    raise ValueError(f"non-strict JSON constant {token}")


def _strict(text: str) -> dict:
    """Parse one JSON object, refusing NaN and Infinity (RFC 8259)."""
    return json.loads(text, parse_constant=_reject)


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _over_slopes(command, slopes, *options):
    """The arguments of ``walker <command>`` on the compass gait over the slope range
    ``slopes`` ("A:B"), then ``options``."""
    return [command, "gaits/compass_goswami.toml", "--range", slopes, *options]


def _orbit_diagram(slopes, n, transient, strides, out):
    """``walker orbit-diagram`` over ``slopes`` writing ``out``, ``--json`` last."""
    options = ["--n", n, "--transient", transient, "--strides", strides]
    return _over_slopes("orbit-diagram", slopes, *options, "--out", str(out), "--json")


# ---------------------------------------------------------------------------------------------
# continue_branch: both ways, stop at folds (Hénon map, closed forms)
# ---------------------------------------------------------------------------------------------


def test_bounds_go_both_ways_and_stop_at_the_fold():
    a0 = 0.1
    br = continue_branch(
        HenonMap(a0, B), henon_fixed_points(a0, B)[0], bounds=(-0.5, 0.6), stop_at_fold=True
    )
    assert br.status == Status.COMPLETED and br.success, br.message
    # one branch ordered along the curve: from the fold (reached going down) up to 0.6
    assert abs(br.parameter[0] - A_FOLD) <= 1e-8
    assert br.parameter[-1] == 0.6
    assert np.all(np.diff(br.parameter) > 0)
    assert np.any(br.parameter == a0)  # the start is inside, not an end
    assert "Going down: Fold reached" in br.message and "Going up: Reached a = 0.6" in br.message
    assert [b.kind for b in br.bifurcations] == ["fold", "period_doubling"]
    fold, pd = br.bifurcations
    assert abs(fold.parameter_value - A_FOLD) <= 1e-8 and abs(pd.parameter_value - A_PD) <= 1e-8
    # the fold orbit is the branch's first point: x = 2 / (1 - b) (multiplier +1)
    assert_allclose(br.sections[0], [2 / (1 - B), 2 * B / (1 - B)], rtol=0, atol=1e-4)
    for a, z in zip(br.parameter[1:], br.sections[1:], strict=True):
        assert_allclose(z, henon_fixed_points(a, B)[0], rtol=0, atol=1e-10)


def test_bounds_through_the_fold_reach_the_other_bound():
    a0, top = -0.08, -0.05
    br = continue_branch(HenonMap(a0, B), henon_fixed_points(a0, B)[0], bounds=(-0.5, top))
    assert br.status == Status.COMPLETED, br.message
    # going down it rounds the fold onto the - root (a saddle) and leaves through a = top
    assert br.parameter[0] == top and br.parameter[-1] == top
    assert A_FOLD <= br.parameter.min() <= A_FOLD + 1e-4
    assert [b.kind for b in br.bifurcations] == ["fold"]
    assert_allclose(br.sections[0], henon_fixed_points(top, B)[1], rtol=0, atol=1e-9)
    assert_allclose(br.sections[-1], henon_fixed_points(top, B)[0], rtol=0, atol=1e-10)
    assert not br.stable[0] and br.stable[-1]


def test_start_on_a_bound_goes_one_way():
    a0 = 0.1
    br = continue_branch(HenonMap(a0, B), henon_fixed_points(a0, B)[0], bounds=(0.0, a0))
    assert br.status == Status.COMPLETED, br.message
    assert br.parameter[0] == 0.0 and br.parameter[-1] == a0
    assert br.message.startswith("Going down: Reached a = 0")


def test_period_two_both_ways():
    cycle = henon_two_cycle(0.6, B)[0]
    br = continue_branch(HenonMap(0.6, B), cycle, bounds=(0.5, 0.8), period=2)
    assert br.status == Status.COMPLETED and br.period == 2, br.message
    assert br.parameter[0] == 0.5 and br.parameter[-1] == 0.8
    for a, z in zip(br.parameter, br.sections, strict=True):
        assert min(np.max(np.abs(z - c)) for c in henon_two_cycle(a, B)) <= 1e-10


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({}, r"Give exactly one of `to` .* and `bounds`"),
        ({"to": 0.5, "bounds": (0.0, 0.5)}, r"Give exactly one of `to`"),
        ({"bounds": (0.2, 0.5)}, r"`bounds` \(0.2, 0.5\) must contain the map's parameter"),
        ({"bounds": (0.5, 0.0)}, r"`bounds` must satisfy lo < hi"),
        ({"bounds": (0.0, np.inf)}, r"`bounds` must be finite"),
        ({"bounds": 0.5}, r"`bounds` must be two numbers"),
    ],
)
def test_bounds_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        continue_branch(HenonMap(0.1, B), henon_fixed_points(0.1, B)[0], **kwargs)


# ---------------------------------------------------------------------------------------------
# walker continue
# ---------------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def period_two_scene(tmp_path_factory):
    """Goswami's compass gait at slope 0.08 (beyond its doubling) as a period-2 scene: the
    state on the stable period-two gait, reached by iterating the stride map."""
    scene = load_scene("gaits/compass_goswami.toml", overrides={"slope": 0.08})
    P = StrideMap("compass", scene.params, parameter_name="slope")
    z = P.project(scene.state)
    for _ in range(300):
        z = P(z).z
    two = find_fixed_point(P, z, period=2)
    assert two.success and two.stable and two.period == 2, two.message
    state = ", ".join(repr(float(v)) for v in two.state)
    path = tmp_path_factory.mktemp("scenes") / "compass_period2.toml"
    path.write_text(
        '[scene]\nmodel = "compass"\n\n[parameters]\npreset = "goswami"\nslope = 0.08\n\n'
        f'[initial]\nstate = [{state}]\n\n[compute]\ntask = "fixed_point"\nstrides = 2\n'
    )
    return path, P


def test_continue_follows_the_scenes_period(period_two_scene, tmp_path, capsys):
    scene, P = period_two_scene
    out = tmp_path / "p2.h5"
    argv = ["continue", str(scene), "--range", "0.079:0.081", "--json", "--out", str(out)]
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 0 and rec["status"] == "COMPLETED", rec["message"]
    assert rec["period"] == 2
    br, prov = read(out)
    assert br.period == 2 and prov["period"] == 2
    assert br.parameter.min() == 0.079 and br.parameter.max() == 0.081
    for mu, z in zip(br.parameter, br.sections, strict=True):
        Pm = P.with_parameter(mu)
        assert np.max(np.abs(Pm(z, n_strides=2).z - z)) <= 1e-10
        assert np.max(np.abs(Pm(z).z - z)) > 1e-3  # a genuine two-cycle, not the 1-cycle
    assert_allclose(br.step_times, br.step_times[0], rtol=0.05, atol=0)  # two strides each
    assert br.step_times[0] > 1.4

    # --period 1 overrides the scene: the (unstable) period-one gait at the same slopes
    code, text, _ = _run(
        capsys, ["continue", str(scene), "--range", "0.079:0.081", "--json", "--period", "1"]
    )
    rec1 = _strict(text)
    assert code == 0 and rec1["period"] == 1 and rec1["stable_parts"] == []


@pytest.mark.parametrize("period", ["0", "-2"])
def test_period_below_one_is_a_usage_error(period, capsys):
    code, out, err = _run(capsys, _over_slopes("continue", "0.05:0.06", "--period", period))
    assert code == 2 and out == ""
    assert f"--period must be an integer >= 1, got {period}" in err


def test_continue_goes_both_ways_by_default(tmp_path, capsys):
    out = tmp_path / "both.h5"
    argv = _over_slopes("continue", "0.045:0.06", "--json", "--out", str(out))
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 0 and rec["status"] == "COMPLETED", rec["message"]
    assert rec["parameter_range"] == [0.045, 0.06]
    assert [e["at"] for e in rec["ends"]] == ["bound", "bound"]
    br, prov = read(out)
    start = np.deg2rad(3.0)
    assert br.parameter[0] == 0.045 and br.parameter[-1] == 0.06
    assert np.all(np.diff(br.parameter) > 0)
    assert np.sum(br.parameter < start) >= 3 and np.sum(br.parameter > start) >= 3
    assert prov["range"] == [0.045, 0.06] and prov["start"] == pytest.approx(start)
    assert rec["stable_parts"] == [[0.045, 0.06]] and br.bifurcations == []


@pytest.mark.regression_pin
def test_kneed_stops_at_its_fold(capsys):
    """REGRESSION PIN: KNEED_FOLD (slope 0.03178509468) is walker's own, checked to 1e-8."""
    argv = ["continue", "gaits/kneed_hsu.toml", "--range", "0.02:0.06"]
    code, text, _ = _run(capsys, argv + ["--json"])
    rec = _strict(text)
    assert code == 0 and rec["status"] == "COMPLETED" and rec["success"], rec["message"]
    assert "Going down: Fold reached at slope = 0.0317850" in rec["message"]
    assert rec["ends"][0]["at"] == "fold" and rec["ends"][1] == {
        "parameter_value": 0.06,
        "at": "bound",
    }
    assert abs(rec["ends"][0]["parameter_value"] - KNEED_FOLD) <= 1e-8
    assert [b["kind"] for b in rec["bifurcations"]] == ["fold"]
    fold = rec["bifurcations"][0]
    assert abs(fold["parameter_value"] - KNEED_FOLD) <= 1e-8
    assert abs(fold["multipliers"][0][0] - 1.0) <= 1e-5  # a multiplier through +1
    assert rec["unstable_parts"] == []  # the stable side only
    assert rec["stable_parts"][0][0] == pytest.approx(KNEED_FOLD, abs=1e-8)
    # the text output says so, and names the option that goes on
    code, text, _ = _run(capsys, argv)
    assert code == 0 and "fold reached" in text.lower() and "--through-folds" in text
    assert "MAX_STEPS" not in text and "max_points" not in text


@pytest.mark.regression_pin
def test_kneed_through_folds_follows_the_unstable_branch(capsys):
    """REGRESSION PIN: KNEED_FOLD (slope 0.03178509468) is walker's own, checked to 1e-8."""
    argv = ["continue", "gaits/kneed_hsu.toml", "--range", "0.02:0.06", "--through-folds"]
    code, text, _ = _run(capsys, argv + ["--json"])
    rec = _strict(text)
    assert code == 0 and rec["status"] == "COMPLETED", rec["message"]
    # down to the fold, round it, and back up the slope to 0.06 on the unstable branch
    assert [e["at"] for e in rec["ends"]] == ["bound", "bound"]
    assert [e["parameter_value"] for e in rec["ends"]] == [0.06, 0.06]
    assert rec["parameter_range"][0] == pytest.approx(KNEED_FOLD, abs=1e-6)
    assert rec["unstable_parts"] and rec["unstable_parts"][0][1] == 0.06
    assert rec["unstable_parts"][0][0] == pytest.approx(KNEED_FOLD, abs=1e-8)
    assert [b["kind"] for b in rec["bifurcations"]] == ["fold"]


@pytest.mark.regression_pin
def test_switch_follows_the_period_doubled_branch(tmp_path, capsys):
    """REGRESSION PIN: COMPASS_PD (slope 0.0766356316) is walker's own, checked to 1e-8 (Goswami
    et al. report only "near 4.4 deg": tests/test_gaits.py checks that to 5e-4).
    """
    out = tmp_path / "compass.h5"
    argv = _over_slopes("continue", "0.05:0.08", "--switch", "--out", str(out), "--json")
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 0, rec
    pds = [b for b in rec["bifurcations"] if b["kind"] == "period_doubling"]
    assert len(pds) == 1 and abs(pds[0]["parameter_value"] - COMPASS_PD) <= 1e-8
    assert abs(pds[0]["multipliers"][0][0] + 1.0) <= 1e-5  # a multiplier through -1
    sw = rec["period_doubled"]
    assert sw["period"] == 2 and sw["status"] == "COMPLETED", sw["message"]
    assert sw["doubling"] == pds[0]["parameter_value"]
    assert sw["ends"][1] == {"parameter_value": 0.08, "at": "bound"}
    # the period-2 branch, stored next to --out
    br1, prov1 = read(out)
    br2, prov2 = read(tmp_path / "compass_period2.h5")
    assert sw["out"] == str(tmp_path / "compass_period2.h5")
    assert prov1["switched_branch"] == "compass_period2.h5"
    assert prov2["switched_from"] == "compass.h5" and prov2["period"] == 2
    assert br1.period == 1 and br2.period == 2
    assert COMPASS_PD < br2.parameter[0] < COMPASS_PD + 1e-4 and br2.parameter[-1] == 0.08
    assert np.all(br2.stable)  # stable up to 0.0857665, beyond this range
    P = StrideMap("compass", load_scene("gaits/compass_goswami.toml").params)
    for mu, z in zip(br2.parameter[::10], br2.sections[::10], strict=True):
        Pm = P.with_parameter(mu)
        assert np.max(np.abs(Pm(z, n_strides=2).z - z)) <= 1e-10
    Pm = P.with_parameter(0.08)
    assert np.max(np.abs(Pm(br2.sections[-1]).z - br2.sections[-1])) > 1e-3


def test_switch_without_a_doubling_is_an_outcome(capsys):
    argv = _over_slopes("continue", "0.05:0.06", "--switch", "--json")
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 1 and rec["status"] == "COMPLETED"
    assert rec["period_doubled"]["status"] is None
    assert "no period doubling" in rec["period_doubled"]["message"]


def test_to_alone_still_goes_one_way(capsys):
    argv = ["continue", "gaits/simplest_garcia.toml", "--to", "0.012", "--json"]
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 0 and rec["parameter_range"] == [0.009, 0.012]
    assert [e["at"] for e in rec["ends"]] == ["start", "bound"]


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        ([], "give the interval to follow the branch over: --range A:B, or --to B"),
        (["--range", "0.05:0.06", "--to", "0.07"], "--range excludes --from and --to"),
        (
            ["--range", "0.06:0.07"],
            "lies outside [0.06, 0.07]; widen --range or start inside it with --set slope=...",
        ),
        (["--range", "0.05"], "--range expects A:B (two numbers), got '0.05'"),
        (["--range", "0.05:nan"], "--range must be finite"),
        (["--range", "0.05:0.06", "--param", "slop"], "--param must be a parameter of compass"),
        (["--range", "0.05:0.06", "--max-points", "1"], "--max-points must be an integer >= 2"),
    ],
)
def test_continue_usage_errors(extra, message, capsys):
    code, out, err = _run(capsys, ["continue", "gaits/compass_goswami.toml", *extra])
    assert code == 2 and out == ""
    assert message in err and err.startswith("walker: error: ")


def test_no_starting_gait_is_strict_json(capsys):
    # below the fold there is no kneed gait
    argv = [
        "continue",
        "gaits/kneed_hsu.toml",
        "--set",
        "slope=0.02",
        "--range",
        "0.01:0.03",
        "--json",
    ]
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 1 and not rec["success"] and "no starting gait" in rec["message"]


# ---------------------------------------------------------------------------------------------
# walker orbit-diagram
# ---------------------------------------------------------------------------------------------


def test_settled_period():
    i = np.arange(32)
    assert settled_period(np.full(32, 0.2)) == 1
    assert settled_period(0.2 + 0.01 * (-1.0) ** i) == 2
    assert settled_period(np.tile([0.1, 0.2, 0.25, 0.3], 8)) == 4
    assert settled_period(np.r_[np.full(31, 0.2), np.nan]) == 0
    # slowly approaching a period-one orbit (multiplier -0.97, as just before a doubling):
    # every second value agrees to 1e-8, but the alternation is a transient
    assert settled_period(0.2 + 1e-7 * (-0.97) ** i) is None
    assert settled_period(np.random.default_rng(0).random(32)) is None


def test_orbit_diagram_writes_a_file_that_reads_back(tmp_path, capsys):
    out = tmp_path / "orbits.h5"
    argv = _orbit_diagram("0.07:0.08", "5", "150", "8", out)
    code, text, _ = _run(capsys, argv)
    rec = _strict(text)
    assert code == 0 and rec["status"] == "COMPLETED"
    d, prov = read(out)
    assert d.parameter_name == "slope" and d.values.shape == (5, 8) and d.coordinate == 0
    assert_allclose(d.parameter, np.linspace(0.07, 0.08, 5), rtol=0, atol=0)
    assert prov["kind"] == "orbit_diagram" and prov["range"] == [0.07, 0.08]
    assert prov["n_transient"] == 150 and prov["coordinate_name"] == "q_stance"
    # below the doubling (0.0766) the gait is period one, at 0.08 period two
    assert rec["periods"][:2] == [1, 1] and rec["periods"][-1] == 2
    first = rec["runs"][0]
    assert first["kind"] == "periodic" and first["period"] == 1 and first["n_values"] == 3
    assert first["from"] == 0.07 and first["to"] == pytest.approx(0.075, abs=1e-15)
    assert len(np.unique(np.round(d.values[-1], 6))) == 2
    # the text summary
    out.unlink()
    code, text, _ = _run(capsys, argv[:-1])
    assert code == 0 and "period 1" in text and "period 2" in text and f"wrote {out}" in text


def test_orbit_diagram_where_it_always_falls_is_strict_json(tmp_path, capsys):
    out = tmp_path / "fall.h5"
    argv = _orbit_diagram("0.3:0.35", "2", "5", "2", out)
    code, text, err = _run(capsys, argv)
    rec = _strict(text)
    assert code == 1 and rec["status"] == "FELL" and rec["periods"] == [0, 0]
    assert rec["runs"][0]["kind"] == "fell" and "fell at every value" in err
    d, _ = read(out)
    assert np.all(np.isnan(d.values))


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--n", "1"], "--n must be an integer >= 2"),
        (["--strides", "0"], "--strides must be an integer >= 1"),
        (["--coordinate", "q_swing"], "--coordinate must be a section coordinate of compass"),
        (["--range", "0.05:0.05"], "--range needs two different values"),
        (["--range", "0.05:2"], "--range B = 2.0"),
    ],
)
def test_orbit_diagram_usage_errors(extra, message, tmp_path, capsys):
    argv = _over_slopes("orbit-diagram", "0.05:0.06", "--out", str(tmp_path / "x.h5"), *extra)
    code, out, err = _run(capsys, argv)
    assert code == 2 and out == "" and message in err
    assert not (tmp_path / "x.h5").exists()


def test_continue_messages_speak_in_flags(tmp_path, capsys):
    options = ["--max-points", "3", "--json", "--out", str(tmp_path / "c.h5")]
    code = main(_over_slopes("continue", "0.04:0.06", *options))
    rec = json.loads(capsys.readouterr().out)
    # a branch cut short by --max-points is still a result: exit 0 (issue 31)
    assert code == 0 and rec["status"] == "MAX_STEPS" and rec["ends"][1]["at"] == "max_points"
    assert "Increase --max-points." in rec["message"]
    assert "max_points" not in rec["message"] and "max_step" not in rec["message"]
