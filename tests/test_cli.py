"""The ``walker`` command line, end to end on the shipped scenes."""

import json

import numpy as np
import pytest
from numpy.testing import assert_allclose

from walker.cli import main
from walker.storage import read


def _run(capsys, argv):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


def _serial_quiet(out):
    """The options of a run on one worker that prints no progress and writes ``out``."""
    return ["--jobs", "1", "--quiet", "--out", str(out)]


def test_find_json_has_the_documented_fields(capsys):
    code, out, _ = _run(capsys, ["find", "gaits/compass_goswami.toml", "--json"])
    assert code == 0
    rec = json.loads(out)
    for key in ("status", "section", "state", "step_time", "multipliers", "parameters"):
        assert key in rec
    assert rec["status"] == "COMPLETED"
    # Spong et al. (2007): [0.2187, -0.3234, -1.0918, -0.3772]
    assert_allclose(rec["state"], [0.2187, -0.3234, -1.0918, -0.3772], atol=5e-5)
    assert len(rec["multipliers"]) == 3 and all(len(m) == 2 for m in rec["multipliers"])
    assert rec["parameters"]["slope"] == pytest.approx(np.deg2rad(3.0))


def test_find_kneed_prints_the_gait(capsys):
    code, out, _ = _run(capsys, ["find", "gaits/kneed_hsu.toml"])
    assert code == 0
    assert "COMPLETED" in out and "Floquet multipliers" in out and "qd3" in out


def test_find_with_set_changes_the_parameter(capsys):
    code, out, _ = _run(
        capsys, ["find", "gaits/simplest_garcia.toml", "--set", "slope=0.012", "--json"]
    )
    rec = json.loads(out)
    assert code == 0 and rec["parameters"]["slope"] == 0.012
    assert rec["section"][0] > 0.2003  # a steeper slope gives a longer step


@pytest.mark.slow  # a run, its figures and its animation: the integration tier
def test_run_then_plot(tmp_path, capsys):
    out = tmp_path / "kneed.h5"
    argv = ["run", "gaits/kneed_hsu.toml", "--strides", "2", "--out", str(out)]
    code, text, _ = _run(capsys, [*argv, "--sample-rate", "60"])
    assert code == 0 and out.exists()
    sol, prov = read(out)
    assert sol.n_strides == 2 and prov["model"] == "kneed" and prov["kernel_hash"]
    # 60 Hz over the two strides (0.56 s each): the samples, and as many frames of the GIF
    assert sol.samples is not None and len(sol.samples) > 60
    figs = tmp_path / "figs"  # created by `walker plot`
    code, text, _ = _run(capsys, ["plot", str(out), "--out", str(figs), "--gif"])
    assert code == 0
    names = sorted(p.name for p in figs.iterdir())
    assert "kneed_angles.png" in names and "kneed_walk.gif" in names


def test_continue_reports_the_period_doubling(capsys):
    code, out, _ = _run(
        capsys,
        ["continue", "gaits/simplest_garcia.toml", "--param", "slope", "--to", "0.017", "--json"],
    )
    assert code == 0
    rec = json.loads(out)
    kinds = [b["kind"] for b in rec["bifurcations"]]
    assert "period_doubling" in kinds
    pd = rec["bifurcations"][kinds.index("period_doubling")]
    # Garcia, Chatterjee, Ruina, Coleman (1998): the period-one gait of the simplest walker
    # is stable up to gamma = 0.0151 (also tests/test_gaits.py), within the 1e-4 allowed here.
    assert abs(pd["parameter_value"] - 0.01509) < 1e-4


def test_basin_writes_a_map(tmp_path, capsys):
    out = tmp_path / "basin.h5"
    argv = ["basin", "gaits/compass_goswami.toml", "--n", "6", "--strides", "30", "--axes", "1,2"]
    code, text, _ = _run(capsys, [*argv, *_serial_quiet(out)])
    assert code == 0
    bm, _ = read(out)
    assert bm.outcome.shape == (6, 6)


def test_sweep_writes_a_table(tmp_path, capsys):
    out = tmp_path / "sweep.h5"
    argv = ["sweep", "gaits/compass_goswami.toml", "--param", "slope=0.04:0.06:4"]
    code, text, _ = _run(capsys, [*argv, *_serial_quiet(out)])
    assert code == 0
    table, _ = read(out)
    assert table.points.shape == (4, 1)
    assert np.all(table.columns["status"] == 0)


def test_sweep_with_set_sweeps_the_changed_walker(tmp_path, capsys):
    """``sweep --set`` changes a parameter for the whole sweep (issue 14): each point's gait
    is the one ``find --set`` gives for the same two parameters, and the file records it."""
    out = tmp_path / "sweep.h5"
    argv = ["sweep", "gaits/compass_goswami.toml", "--param", "slope=0.04,0.05"]
    argv += ["--set", "mass_hip=12", *_serial_quiet(out)]
    code, _, _ = _run(capsys, argv)
    assert code == 0
    table, provenance = read(out)
    assert provenance["parameters"]["mass_hip"]["value"] == 12.0
    find = ["find", "gaits/compass_goswami.toml", "--json"]
    for slope, step_time in zip(table.points[:, 0], table.columns["step_time"], strict=True):
        slope = f"slope={float(slope)!r}"
        code, text, _ = _run(capsys, [*find, "--set", "mass_hip=12", "--set", slope])
        assert code == 0
        assert json.loads(text)["step_time"] == pytest.approx(step_time, rel=1e-9)
    # and the hip mass matters: the scene's own walker steps differently
    code, text, _ = _run(capsys, [*find, "--set", "slope=0.04"])
    assert code == 0
    assert abs(json.loads(text)["step_time"] - table.columns["step_time"][0]) > 1e-3


def test_sweep_refuses_set_of_a_swept_parameter(tmp_path, capsys):
    argv = ["sweep", "gaits/compass_goswami.toml", "--param", "slope=0.04:0.06:3"]
    argv += ["--set", "slope=0.05", "--out", str(tmp_path / "s.h5")]
    code, _, err = _run(capsys, argv)
    assert code == 2
    assert "--set slope: the parameter is swept by --param" in err
    assert not (tmp_path / "s.h5").exists()


def test_plot_of_an_unreadable_file_leaves_no_figure_directory(tmp_path, capsys):
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not an HDF5 file")
    code, _, err = _run(capsys, ["plot", str(bad), "--out", str(tmp_path / "figs")])
    assert code == 2 and "not an HDF5 file" in err
    assert not (tmp_path / "figs").exists()
    (tmp_path / "kept").mkdir()  # a directory that existed before stays
    code, _, _ = _run(capsys, ["plot", str(bad), "--out", str(tmp_path / "kept")])
    assert code == 2 and (tmp_path / "kept").is_dir()


def test_basin_axes_by_name_or_index(tmp_path, capsys):
    base = ["basin", "gaits/compass_goswami.toml", "--n", "3", "--strides", "2", "--quiet"]
    code, _, _ = _run(
        capsys, [*base, "--axes", "qd_stance,qd_swing", "--out", str(tmp_path / "a.h5")]
    )
    assert code == 0
    assert read(tmp_path / "a.h5")[0].axis_names == ("qd_stance", "qd_swing")
    code, _, err = _run(capsys, [*base, "--axes", "q,2", "--out", str(tmp_path / "b.h5")])
    assert code == 2
    assert "by index or name (0 q_stance, 1 qd_stance, 2 qd_swing)" in err


def test_basin_rtol_sets_the_strides_tolerance_and_is_stored(tmp_path, capsys):
    base = ["basin", "gaits/compass_goswami.toml", "--n", "4", "--strides", "5", "--quiet"]
    base += ["--jobs", "1"]
    code, _, _ = _run(capsys, [*base, "--rtol", "1e-9", "--out", str(tmp_path / "a.h5")])
    assert code == 0
    coarse, prov = read(tmp_path / "a.h5")
    assert prov["basin_rtol"] == 1e-9 and prov["basin_atol"] == 1e-9
    assert prov["rtol"] == 1e-12  # the scene's, at which the gait was found
    code, _, _ = _run(capsys, [*base, "--out", str(tmp_path / "b.h5")])
    fine, prov_fine = read(tmp_path / "b.h5")
    assert code == 0 and "basin_rtol" not in prov_fine
    np.testing.assert_array_equal(coarse.outcome, fine.outcome)
    # resuming with another --rtol is refused (the checkpoint's provenance differs)
    code, _, err = _run(capsys, [*base, "--rtol", "1e-8", "--out", str(tmp_path / "a.h5")])
    assert code == 2 and "basin_rtol" in err
    for bad in ("0", "-1e-9", "nan", "1e-20"):
        code, _, err = _run(capsys, [*base, f"--rtol={bad}", "--out", str(tmp_path / "c.h5")])
        assert code == 2 and "--rtol" in err, (bad, err)
        assert not (tmp_path / "c.h5").exists()
