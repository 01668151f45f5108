"""Bad input everywhere public: each raises ValueError/TypeError naming the argument, before
any work; the CLI turns it into one ``walker: error: ...`` line and exit status 2.
"""

import numpy as np
import pytest
from _rules import Failures

from walker import StrideMap, find_fixed_point, load_scene, simulate, storage
from walker.analysis.basin import basin_map
from walker.analysis.continuation import continue_branch
from walker.analysis.sweep import sweep
from walker.cli import main
from walker.params import CompassParams, KneedParams
from walker.simulation.integrate import hybrid_solve

SCENE = "gaits/compass_goswami.toml"
NAN3 = [np.nan, 0.0, 0.0]


@pytest.fixture(scope="module")
def setup():
    scene = load_scene(SCENE)
    P = StrideMap("compass", scene.params, rtol=1e-10, atol=1e-10)
    fp = find_fixed_point(P, P.project(scene.reference["state"]), tol=1e-9)
    assert fp.success
    return scene.params, np.array(scene.reference["state"]), P, fp


def _simulate(**options):
    """The call of a case that simulates the compass gait from ``x`` with ``options``."""
    return lambda prm, x, P, fp: simulate("compass", prm, x, **options)


# (label, call(prm, x, P, fp), exception, message pattern)
CASES = [
    (
        "simulate nan x0",
        lambda prm, x, P, fp: simulate("compass", prm, [np.nan, 0, 0, 0]),
        ValueError,
        "`x0` must be finite",
    ),
    (
        "simulate inf x0",
        lambda prm, x, P, fp: simulate("compass", prm, [np.inf, 0, 0, 0]),
        ValueError,
        "`x0` must be finite",
    ),
    (
        "simulate short x0",
        lambda prm, x, P, fp: simulate("compass", prm, [0, 0, 0]),
        ValueError,
        r"`x0` must be 1-D of length n_x = 4, got shape \(3,\)",
    ),
    (
        "simulate 2-D x0",
        lambda prm, x, P, fp: simulate("compass", prm, np.zeros((2, 4))),
        ValueError,
        r"`x0` must be 1-D",
    ),
    ("simulate rtol<0", _simulate(rtol=-1e-6), ValueError, "`rtol` must be positive"),
    ("simulate atol<0", _simulate(atol=-1.0), ValueError, "`atol` must be positive"),
    ("simulate rtol nan", _simulate(rtol=np.nan), ValueError, "`rtol` must be positive and finite"),
    ("simulate rtol below 100 eps", _simulate(rtol=1e-15), ValueError, "`rtol` must be >= 100"),
    ("simulate t_max 0", _simulate(t_max=0.0), ValueError, "`t_max` must be greater than `t0`"),
    ("simulate t_max<0", _simulate(t_max=-1.0), ValueError, "`t_max` must be greater than `t0`"),
    ("simulate t_max nan", _simulate(t_max=np.nan), ValueError, "`t_max` must be finite"),
    ("simulate method", _simulate(method="RK99"), ValueError, "`method` must be one of"),
    ("simulate output", _simulate(output="all"), ValueError, "`output` must be one of"),
    (
        "simulate model",
        lambda prm, x, P, fp: simulate("compas", prm, x),
        ValueError,
        "`model` must be one of",
    ),
    (
        "simulate params class",
        lambda prm, x, P, fp: simulate("kneed", prm, x),
        TypeError,
        "`params` must be a KneedParams",
    ),
    ("simulate n_strides<0", _simulate(n_strides=-1), ValueError, "`n_strides` must be >= 0"),
    ("simulate n_strides float", _simulate(n_strides=1.5), TypeError, "`n_strides` must be an int"),
    ("simulate phase0", _simulate(phase0=3), ValueError, "`phase0` must be < n_phases"),
    ("simulate max_steps", _simulate(max_steps=0), ValueError, "`max_steps` must be >= 1"),
    (
        "simulate samples missing",
        _simulate(output="samples"),
        ValueError,
        "`sample_times` is required",
    ),
    (
        "StrideMap parameter_name",
        lambda prm, x, P, fp: StrideMap("compass", prm, parameter_name="mass"),
        ValueError,
        "`parameter_name` must be a parameter",
    ),
    (
        "StrideMap model",
        lambda prm, x, P, fp: StrideMap("foo", prm),
        ValueError,
        "`model` must be one of",
    ),
    (
        "StrideMap params",
        lambda prm, x, P, fp: StrideMap("kneed", prm),
        TypeError,
        "`params` must be a KneedParams",
    ),
    (
        "StrideMap() z shape",
        lambda prm, x, P, fp: P([0.0, 0.0]),
        ValueError,
        r"`z` must have shape \(3,\)",
    ),
    (
        "StrideMap() parameter nan",
        lambda prm, x, P, fp: P(fp.section, parameter=np.nan),
        ValueError,
        "`slope` must be finite",
    ),
    (
        "hybrid_solve p nan",
        lambda prm, x, P, fp: hybrid_solve(
            P.model.system, x, np.full(P.params.as_array().size, np.nan)
        ),
        ValueError,
        "`p` must be finite",
    ),
    (
        "hybrid_solve p 2-D",
        lambda prm, x, P, fp: hybrid_solve(P.model.system, x, np.zeros((2, 4))),
        ValueError,
        "`p` must be 1-D",
    ),
    (
        "hybrid_solve system",
        lambda prm, x, P, fp: hybrid_solve("compass", x, prm.as_array()),
        TypeError,
        "`system` must be a HybridSystem",
    ),
    (
        "hybrid_solve method case",
        lambda prm, x, P, fp: hybrid_solve(P.model.system, x, prm.as_array(), method="rk45"),
        ValueError,
        "`method` must be",
    ),
    (
        "hybrid_solve n_interior",
        lambda prm, x, P, fp: hybrid_solve(P.model.system, x, prm.as_array(), n_interior=-1),
        ValueError,
        "`n_interior`",
    ),
    (
        "hybrid_solve max_step",
        lambda prm, x, P, fp: hybrid_solve(P.model.system, x, prm.as_array(), max_step=-1.0),
        ValueError,
        "`max_step`",
    ),
    (
        "hybrid_solve RK4 without step",
        lambda prm, x, P, fp: hybrid_solve(P.model.system, x, prm.as_array(), method="RK4"),
        ValueError,
        "`first_step` must",
    ),
    (
        "find_fixed_point nan",
        lambda prm, x, P, fp: find_fixed_point(P, NAN3),
        ValueError,
        "`z0` must be finite",
    ),
    (
        "find_fixed_point shape",
        lambda prm, x, P, fp: find_fixed_point(P, [0.0, 0.0]),
        ValueError,
        r"`z0` must have shape \(3,\)",
    ),
    (
        "find_fixed_point tol",
        lambda prm, x, P, fp: find_fixed_point(P, fp.section, tol=-1),
        ValueError,
        "`tol` must be positive",
    ),
    (
        "find_fixed_point jacobian",
        lambda prm, x, P, fp: find_fixed_point(P, fp.section, jacobian="exactly"),
        ValueError,
        "`jacobian` must be one of",
    ),
    (
        "find_fixed_point period",
        lambda prm, x, P, fp: find_fixed_point(P, fp.section, period=0),
        ValueError,
        "`period` must be an integer >= 1",
    ),
    (
        "continue_branch nan",
        lambda prm, x, P, fp: continue_branch(P, NAN3, to=0.06),
        ValueError,
        "`z0` must be finite",
    ),
    (
        "continue_branch to",
        lambda prm, x, P, fp: continue_branch(P, fp.section, to=np.nan),
        ValueError,
        "`to` must be finite",
    ),
    (
        "continue_branch method",
        lambda prm, x, P, fp: continue_branch(P, fp.section, to=0.06, method="foo"),
        ValueError,
        "`method` must be one of",
    ),
    (
        "continue_branch step",
        lambda prm, x, P, fp: continue_branch(P, fp.section, to=0.06, step=-1.0),
        ValueError,
        "`step` must be positive",
    ),
    (
        "basin_map axes",
        lambda prm, x, P, fp: basin_map(P, fp, axes=(0, 0), ranges=((0, 1), (0, 1)), n=(2, 2)),
        ValueError,
        "`axes` must be two distinct",
    ),
    (
        "basin_map ranges nan",
        lambda prm, x, P, fp: basin_map(P, fp, ranges=((np.nan, 1), (0, 1)), n=(2, 2)),
        ValueError,
        "`ranges` must be finite",
    ),
    (
        "basin_map ranges shape",
        lambda prm, x, P, fp: basin_map(P, fp, ranges=((0, 1),), n=(2, 2)),
        ValueError,
        "`ranges` must be",
    ),
    (
        "basin_map n",
        lambda prm, x, P, fp: basin_map(P, fp, ranges=((0, 1), (0, 1)), n=(0, 2)),
        ValueError,
        "`n` must be at least",
    ),
    (
        "basin_map tol",
        lambda prm, x, P, fp: basin_map(P, fp, ranges=((0, 1), (0, 1)), n=(2, 2), tol=-1.0),
        ValueError,
        "`tol` must be positive",
    ),
    (
        "basin_map executor",
        lambda prm, x, P, fp: basin_map(P, fp, ranges=((0, 1), (0, 1)), n=(2, 2), executor="foo"),
        ValueError,
        "`executor` must be",
    ),
    (
        "sweep kind",
        lambda prm, x, P, fp: sweep(P, {"slope": [0.05]}, kind="foo", z0=fp.section),
        ValueError,
        "`kind` must be one of",
    ),
    (
        "sweep unknown parameter",
        lambda prm, x, P, fp: sweep(P, {"slop": [0.05]}, z0=fp.section),
        ValueError,
        "unknown parameter `slop`",
    ),
    (
        "sweep nan value",
        lambda prm, x, P, fp: sweep(P, {"slope": [np.nan]}, z0=fp.section),
        ValueError,
        "`slope` in `ranges` must all be finite",
    ),
    (
        "sweep z0 nan",
        lambda prm, x, P, fp: sweep(P, {"slope": [0.05]}, z0=NAN3),
        ValueError,
        "`z0` must be finite",
    ),
    (
        "sweep malformed range",
        lambda prm, x, P, fp: sweep(P, "slope=0.01:0.02:x", z0=fp.section),
        ValueError,
        "bad parameter range",
    ),
    (
        "sweep tol",
        lambda prm, x, P, fp: sweep(P, {"slope": [0.05]}, z0=fp.section, tol=-1.0),
        ValueError,
        "`tol` must be positive",
    ),
    (
        "load_scene unknown override",
        lambda prm, x, P, fp: load_scene(SCENE, overrides={"mas": 1.0}),
        ValueError,
        "unknown parameter `mas`",
    ),
    (
        "load_scene nan override",
        lambda prm, x, P, fp: load_scene(SCENE, overrides={"g": float("nan")}),
        ValueError,
        "`g` must be finite",
    ),
    (
        "load_scene negative g",
        lambda prm, x, P, fp: load_scene(SCENE, overrides={"g": -1.0}),
        ValueError,
        r"`g` must be > 0 \[m/s\^2\]",
    ),
    (
        "storage.write result",
        lambda prm, x, P, fp: storage.write("/tmp/v/never.h5", 3, provenance={}),
        TypeError,
        "`result` must be one of",
    ),
    (
        "storage.write provenance",
        lambda prm, x, P, fp: storage.write("/tmp/v/never.h5", fp, provenance=3),
        TypeError,
        "`provenance` must be a dict",
    ),
    ("params nan", lambda prm, x, P, fp: prm.replace(g=np.nan), ValueError, "`g` must be finite"),
    (
        "params inf",
        lambda prm, x, P, fp: prm.replace(mass_leg=np.inf),
        ValueError,
        "`mass_leg` must be finite",
    ),
    (
        "params str",
        lambda prm, x, P, fp: prm.replace(g="9.8"),
        TypeError,
        "`g` must be a real number",
    ),
    (
        "params bool",
        lambda prm, x, P, fp: prm.replace(g=True),
        TypeError,
        "`g` must be a real number",
    ),
    ("params negative", lambda prm, x, P, fp: prm.replace(g=-1.0), ValueError, r"`g` must be > 0"),
    (
        "params unknown",
        lambda prm, x, P, fp: prm.replace(gg=1.0),
        ValueError,
        "unknown CompassParams parameter",
    ),
    (
        "params slope",
        lambda prm, x, P, fp: prm.replace(slope=2.0),
        ValueError,
        r"`slope` must be in \(-pi/2, pi/2\)",
    ),
    (
        "params from_array",
        lambda prm, x, P, fp: CompassParams.from_array(np.zeros(3)),
        ValueError,
        r"`p` must have shape \(10,\)",
    ),
    (
        "kneed params nan",
        lambda prm, x, P, fp: KneedParams.hsu_chen().replace(mass_shank=np.nan),
        ValueError,
        "`mass_shank` must be finite",
    ),
]


def test_bad_input_raises_naming_the_argument(setup):
    fails = Failures("bad input raises ValueError/TypeError naming the argument")
    for label, call, exc, match in CASES:
        fails.raises(label, exc, match, call, *setup)
    fails.assert_none(at_least=len(CASES))


def test_missing_files_raise(setup, tmp_path):
    fp = setup[3]
    with pytest.raises(FileNotFoundError, match="scene file not found"):
        load_scene("gaits/no_such_scene.toml")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        storage.write(tmp_path / "no_such_dir" / "a.h5", fp, provenance={})
    with pytest.raises(storage.StorageError, match="no such file"):
        storage.read(tmp_path / "no_such_file.h5")


def test_corrupted_hdf5_raises(tmp_path):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not an hdf5 file" * 8)
    with pytest.raises(storage.StorageError, match="not an HDF5 file"):
        storage.read(bad)


# ---------------------------------- rejected before any work (findings of the stress run)


def test_stride_map_rejects_negative_rtol_at_construction(setup):
    with pytest.raises(ValueError, match="`rtol` must be positive"):
        StrideMap("compass", setup[0], rtol=-1.0)


def test_stride_map_rejects_negative_t_max_at_construction(setup):
    with pytest.raises(ValueError, match="`t_max` must be"):
        StrideMap("compass", setup[0], t_max=-1.0)


def test_stride_map_rejects_unknown_method_at_construction(setup):
    with pytest.raises(ValueError, match="`method` must be one of"):
        StrideMap("compass", setup[0], method="foo")


def test_stride_map_call_nan_names_z(setup):
    with pytest.raises(ValueError, match="`z`"):
        setup[2](NAN3)


def test_stride_map_call_zero_strides_names_n_strides(setup):
    with pytest.raises(ValueError, match="`n_strides`"):
        setup[2](setup[3].section, n_strides=0)


def test_hybrid_solve_rejects_short_parameter_vector(setup):
    prm, x, P, fp = setup
    with pytest.raises(ValueError, match="`p`"):
        hybrid_solve(P.model.system, x, np.zeros(3))


def test_simulate_string_x0_names_x0(setup):
    with pytest.raises(TypeError, match="`x0`"):
        simulate("compass", setup[0], "abcd")


# Values next to the common case that walker.simulation.integrate's checks accept without further
# tests (an exact Python int >= the bound, a positive finite float, a bool): each must still go to
# the full check and fail there, naming the argument.
def test_simulate_checks_behind_the_common_case(setup):
    cases = [
        ({"n_strides": True}, TypeError, "`n_strides` must be an int"),
        ({"max_steps": False}, TypeError, "`max_steps` must be an int"),
        ({"rtol": True}, TypeError, "`rtol` must be a real number"),
        ({"rtol": np.inf}, ValueError, "`rtol` must be positive and finite"),
        ({"atol": -0.0}, ValueError, "`atol` must be positive"),
        ({"t_max": np.inf}, ValueError, "`t_max` must be finite"),
        ({"t_max": True}, TypeError, "`t_max` must be a real number"),
        ({"jacobian": 1}, TypeError, "`jacobian` must be a bool"),
    ]
    fails = Failures("a value next to the common case still fails the full check, named")
    for options, exc, match in cases:
        fails.raises(
            f"simulate(**{options})", exc, match, simulate, "compass", *setup[:2], **options
        )
    fails.assert_none(at_least=len(cases))


def test_simulate_numpy_scalars_run_as_python_scalars(setup):
    """numpy scalars take the full checks, Python scalars the common case: the same run."""
    prm, x = setup[0], setup[1]
    plain = simulate("compass", prm, x, n_strides=2, t_max=5.0, rtol=1e-9, atol=1e-10)
    numpy = simulate(
        "compass",
        prm,
        x,
        n_strides=np.int64(2),
        t_max=np.float64(5.0),
        rtol=np.float64(1e-9),
        atol=np.float64(1e-10),
        jacobian=np.bool_(False),
    )
    assert plain.status == numpy.status
    assert plain.n_strides == numpy.n_strides == 2
    assert plain.t == numpy.t
    np.testing.assert_array_equal(plain.x, numpy.x)


# ------------------------------------------------------------------------------ the CLI


def _cli(capsys, argv):
    code = main(argv)
    err = capsys.readouterr().err
    return code, err


def _usage_error_problem(code, err, pattern):
    """What is wrong with a CLI answer that should be exit 2 and one error line holding
    ``pattern`` ("" if nothing)."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    if code != 2:
        return f"exit status {code}, not 2; stderr {err!r}"
    if len(lines) != 1 or not lines[0].startswith("walker: error: "):
        return f"stderr is not one 'walker: error: ' line: {err!r}"
    if pattern not in lines[0]:
        return f"{pattern!r} not in {lines[0]!r}"
    return ""


def _assert_usage_error(code, err, pattern):
    problem = _usage_error_problem(code, err, pattern)
    assert not problem, problem


def _check_usage_errors(capsys, rule, cases):
    """Run ``main(argv)`` for each ``(argv, pattern)`` of ``cases``; report every one that
    is not a one-line usage error (exit 2) holding ``pattern``."""
    fails = Failures(rule)
    for argv, pattern in cases:
        problem = _usage_error_problem(*_cli(capsys, argv), pattern)
        fails.check(" ".join(argv), not problem, problem)
    fails.assert_none(at_least=len(cases))


SCENE_CMDS = [
    ["find"],
    ["run", "--strides", "1"],
    ["continue", "--to", "0.06"],
    ["basin", "--out", "/tmp/v/basin.h5", "--n", "2", "--strides", "1"],
]


def test_cli_missing_scene(capsys):
    _check_usage_errors(
        capsys,
        "a missing scene is a usage error naming the file",
        [([cmd[0], "gaits/no_such.toml", *cmd[1:]], "no_such.toml") for cmd in SCENE_CMDS],
    )


def test_cli_sweep_missing_scene(capsys, tmp_path):
    out = str(tmp_path / "sweep.h5")
    code, err = _cli(
        capsys,
        ["sweep", "gaits/no_such.toml", "--param", "slope=0.01:0.02:2", "--out", out],
    )
    _assert_usage_error(code, err, "no_such.toml")


def test_cli_unknown_set_parameter(capsys):
    _check_usage_errors(
        capsys,
        "an unknown --set parameter is a usage error naming it",
        [([cmd[0], SCENE, *cmd[1:], "--set", "mas_hip=1"], "mas_hip") for cmd in SCENE_CMDS],
    )


def test_cli_malformed_set(capsys):
    _check_usage_errors(
        capsys,
        "a malformed --set is a usage error naming the flag",
        [(["find", SCENE, "--set", value], "--set") for value in ("slope", "=1", "slope=abc")],
    )


def test_cli_sweep_malformed_param(capsys):
    params = [
        "slope=0.01:0.02:x",
        "slope=0.01:0.02",
        "slope",
        "slop=0.01:0.02:3",
        "slope=nan:0.02:3",
    ]
    _check_usage_errors(
        capsys,
        "a malformed sweep --param is a usage error",
        [(["sweep", SCENE, "--param", p, "--out", "/tmp/v/sw.h5"], "") for p in params],
    )


def test_cli_out_in_missing_directory(capsys):
    out = ["--out", "/tmp/v/missing_dir/x.h5"]
    _check_usage_errors(
        capsys,
        "--out in a missing directory is a usage error naming it",
        [
            (["find", SCENE, *out], "missing_dir"),
            (["run", SCENE, "--strides", "1", *out], "missing_dir"),
            (["continue", SCENE, "--to", "0.06", *out], "missing_dir"),
            (["basin", SCENE, "--n", "2", "--strides", "1", *out], "missing_dir"),
            (["sweep", SCENE, "--param", "slope=0.01:0.02:2", *out], "missing_dir"),
        ],
    )


def test_cli_plot_corrupted_file(capsys, tmp_path):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"garbage" * 20)
    code, err = _cli(capsys, ["plot", str(bad), "--out", str(tmp_path)])
    _assert_usage_error(code, err, "bad.h5")


def test_cli_plot_missing_file(capsys, tmp_path):
    code, err = _cli(capsys, ["plot", str(tmp_path / "none.h5"), "--out", str(tmp_path)])
    _assert_usage_error(code, err, "none.h5")
