"""Results in notebooks (issue 31, item 8): short reprs and plain columns."""

import numpy as np
import pytest

from walker.results import BasinMap, Branch, SweepTable, Trajectory
from walker.status import Status


def _branch(n=2000, n_z=3):
    mu = np.linspace(0.0, 0.1, n)
    return Branch(
        "slope",
        mu,
        np.random.default_rng(0).normal(size=(n, n_z)),
        np.ones(n),
        np.full((n, n_z), 0.5 + 0.1j),
        np.ones(n, dtype=bool),
        [],
        Status.COMPLETED,
        "Going down: Reached slope = 0 in 1000 points. " * 20,
        True,
        measures={"step_length": np.full(n, 0.4), "speed": np.full(n, 0.7)},
    )


def test_a_large_branch_prints_short():
    text = repr(_branch())
    assert len(text) < 600, len(text)
    assert "<float64 array (2000, 3)>" in text and "status=COMPLETED" in text


def test_branch_to_dict_is_plain_columns():
    br = _branch(n=5)
    cols = br.to_dict(names=["q1", "qd1", "qd2"])
    assert list(cols)[:4] == ["slope", "section_q1", "section_qd1", "section_qd2"]
    assert all(isinstance(v, np.ndarray) and v.shape == (5,) for v in cols.values())
    np.testing.assert_array_equal(cols["section_qd1"], br.sections[:, 1])
    np.testing.assert_array_equal(cols["multiplier_0_im"], np.full(5, 0.1))
    assert cols["speed"][0] == 0.7
    cols["slope"][0] = 99.0  # a copy: the branch keeps its values
    assert br.parameter[0] == 0.0


def test_other_results_to_dict():
    traj = Trajectory(np.arange(3.0), np.ones((3, 2)), np.zeros(3, dtype=np.int64))
    assert list(traj.to_dict()) == ["t", "phase", "x_0", "x_1"]
    basin = BasinMap(
        ("q1", "qd1"),
        np.array([0.0, 1.0]),
        np.array([5.0, 6.0, 7.0]),
        np.arange(6).reshape(3, 2),
        np.ones((3, 2), dtype=np.int64),
        np.zeros(2),
        np.zeros(2),
        10,
    )
    cols = basin.to_dict()
    assert cols["q1"].tolist() == [0, 1, 0, 1, 0, 1] and cols["outcome"].tolist() == list(range(6))
    table = SweepTable(("slope",), np.array([[0.1], [0.2]]), {"section": np.ones((2, 3))})
    assert list(table.to_dict()) == ["slope", "section_0", "section_1", "section_2"]


def test_to_dataframe_names_the_extra_without_pandas():
    br = _branch(n=3)
    try:
        import pandas
    except ImportError:
        with pytest.raises(ImportError, match=r"walker-hybrid\[dataframe\]"):
            br.to_dataframe()
    else:
        frame = br.to_dataframe()
        assert isinstance(frame, pandas.DataFrame) and len(frame) == 3
