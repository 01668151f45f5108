"""Early classification of basin points inside the gait's contraction ball.

The ball of :func:`walker.analysis.basin_radius.contraction_ball` claims: for every ``z`` with
``||W (z - z*)||_2 <= r``, ``||W (F(z) - z*)||_2 <= kappa ||W (z - z*)||_2`` with
``kappa < 1``.  The toys check the claim against the maps themselves (a linear map, whose
contraction norm is its spectral radius in closed form, and a quadratic map whose
iterates are computed directly); the compass check compares every point's early outcome with
the full 20-stride run at the scene's rtol 1e-12, the issue's acceptance rule.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest

from walker.analysis.basin import basin_chunk, basin_map
from walker.analysis.basin_radius import SAMPLE_RADIUS, contraction_ball
from walker.analysis.fixedpoint import find_fixed_point
from walker.results import BASIN_CONVERGED, BASIN_UNDECIDED, MapResult
from walker.status import Status

# A non-normal linear part: multipliers 0.6 e^{+-0.9i} and -0.3 (spectral radius 0.6), with
# a shear that makes ||A||_2 > 1, so the plain max norm would not show a contraction.
_BLOCK = 0.6 * np.array([[np.cos(0.9), -np.sin(0.9)], [np.sin(0.9), np.cos(0.9)]])
_T = np.array([[1.0, 4.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.0, 1.0]])
A = _T @ np.block([[_BLOCK, np.zeros((2, 1))], [np.zeros((1, 2)), np.array([[-0.3]])]])
A = A @ np.linalg.inv(_T)
CENTER = np.array([0.2, -1.0, 0.4])


@dataclass(frozen=True)
class QuadraticMap:
    """``F(z) = c + A w + quad * (w_0^2, w_1 w_2, w_2^2)``, ``w = z - c``; falls (forward)
    when ``max|w| > 1``."""

    quad: float = 0.0
    n_z: int = 3
    section_names: tuple[str, ...] = ("a", "b", "c")
    parameter_name: str = "p"
    parameter_value: float = 0.0

    def _one(self, w):
        q = np.array([w[0] ** 2, w[1] * w[2], w[2] ** 2])
        dq = np.array([[2 * w[0], 0, 0], [0, w[2], w[1]], [0, 0, 2 * w[2]]])
        return A @ w + self.quad * q, A + self.quad * dq

    def __call__(self, z, *, jacobian=False, n_strides=1, parameter=None):
        w = np.asarray(z, dtype=float) - CENTER
        jac = np.eye(3)
        for k in range(n_strides):
            if np.max(np.abs(w)) > 1:
                nan = np.full(3, np.nan)
                return MapResult(Status.FELL_FORWARD, nan, None, float(k), nan)
            w, dw = self._one(w)
            jac = dw @ jac
        z = CENTER + w
        return MapResult(Status.COMPLETED, z, jac if jacobian else None, float(n_strides), z)

    def lift(self, z):
        return np.asarray(z, dtype=float)

    def with_parameter(self, value):
        return self


def _fixed_point(m):
    fp = find_fixed_point(m, CENTER + 1e-3)
    assert fp.success
    return fp


def test_linear_map_norm_is_its_spectral_radius():
    # closed form: in the real eigenbasis, ||A||_W = max |multiplier| = 0.6 (A non-normal:
    # its 2-norm exceeds 1); a linear map has no second derivative, so the ball is the whole
    # sample radius.
    assert np.linalg.norm(A, 2) > 1
    weight, radius, info = contraction_ball(QuadraticMap(0.0), _fixed_point(QuadraticMap(0.0)))
    assert info["weighting"] == "eigenbasis"
    np.testing.assert_allclose(info["contraction"], 0.6, rtol=1e-12, atol=0)
    np.testing.assert_allclose(np.linalg.svd(weight, compute_uv=False).min(), 1.0, rtol=1e-12)
    assert radius == SAMPLE_RADIUS and info["lipschitz"] < 1e-9


@pytest.mark.parametrize("quad", [0.5, 5.0, 50.0])
def test_every_point_of_the_ball_contracts_under_the_map_itself(quad):
    m = QuadraticMap(quad)
    weight, radius, info = contraction_ball(m, _fixed_point(m))
    assert 0 < radius <= SAMPLE_RADIUS and info["kappa"] < 1
    # a stronger curvature gives a smaller ball: M = |quad| sup ||Dq(w)||_W / ||w||_W
    if quad == 50.0:
        assert radius < SAMPLE_RADIUS
    rng = np.random.default_rng(1)
    inv = np.linalg.inv(weight)
    d = rng.standard_normal((400, 3))
    d /= np.linalg.norm(d, axis=1)[:, None]
    d *= rng.uniform(0, 1, 400)[:, None] ** (1 / 3) * radius
    d[:50] *= radius / np.linalg.norm(d[:50], axis=1)[:, None]  # and on the sphere
    for e in d:
        z = CENTER + inv @ e
        before = np.linalg.norm(weight @ (z - CENTER))
        after = np.linalg.norm(weight @ (m(z).z - CENTER))
        assert after <= info["kappa"] * before * (1 + 1e-12) + 1e-15
    # also: ball inside the max-norm box of half-width r
    assert np.max(np.abs(inv @ d.T)) <= radius * (1 + 1e-12)


def test_unstable_gait_has_no_ball():
    @dataclass(frozen=True)
    class Expanding(QuadraticMap):
        def _one(self, w):
            return 1.5 * w, 1.5 * np.eye(3)

    m = Expanding()
    fp = find_fixed_point(m, CENTER + 1e-3)
    _, radius, info = contraction_ball(m, fp)
    assert radius == 0.0 and "unstable" in info["reason"]


def test_early_stop_on_toy_changes_only_undecided_to_converged():
    m = QuadraticMap(5.0)
    fp = _fixed_point(m)
    kw = dict(
        axes=(0, 1),
        ranges=((CENTER[0] - 0.05, CENTER[0] + 0.05), (CENTER[1] - 0.01, CENTER[1] + 0.01)),
        n=(15, 13),
        n_strides=12,
        executor="serial",
        progress=False,
    )
    full = basin_map(m, fp, **kw)
    early = basin_map(m, fp, converge_radius="auto", **kw)
    assert early.classification["converge_radius"] > 0
    same = full.outcome == early.outcome
    assert np.all(same | ((full.outcome == BASIN_UNDECIDED) & (early.outcome == BASIN_CONVERGED)))
    assert np.all(early.strides <= full.strides)
    assert (~same).any() and np.all(early.strides[~same] <= 12)
    assert full.classification == {"tol": 1e-6, "converge_radius": 0.0}


def test_converge_radius_is_checked():
    m = QuadraticMap(0.0)
    fp = _fixed_point(m)
    for bad in ("big", -1.0, float("nan"), None):
        with pytest.raises(ValueError, match="`converge_radius` must be"):
            basin_map(m, fp, ranges=((0, 1), (0, 1)), n=(2, 2), converge_radius=bad)


def _compass(rtol):
    from walker import load_scene
    from walker.simulation.stride import StrideMap

    s = load_scene("gaits/compass_goswami.toml")
    c = s.compute
    P = StrideMap(s.model, s.params, method=c.method, rtol=c.rtol, atol=c.atol, t_max=c.t_max)
    fp = find_fixed_point(P, P.project(s.state))
    return P, fp


def test_compiled_loop_with_a_radius_gives_the_python_loops_outcomes():
    P, fp = _compass(1e-12)
    weight, radius, _ = contraction_ball(P, fp)

    class PythonLoop:  # the same map without basin_batch
        n_z = P.n_z

        def __call__(self, z, **kwargs):
            return P(z, **kwargs)

    z = np.asarray(fp.section)
    x = z[0] + np.linspace(-0.01, 0.01, 5)
    y = z[1] + np.linspace(-0.05, 0.05, 4)
    args = (z, z, (0, 1), x, y, 20, 1, 1e-6)
    compiled = basin_chunk(P, *args, weight=weight, radius=radius)
    python = basin_chunk(PythonLoop(), *args, weight=weight, radius=radius)
    np.testing.assert_array_equal(compiled[0], python[0])
    np.testing.assert_array_equal(compiled[1], python[1])
    assert (compiled[0] == BASIN_CONVERGED).sum() > (basin_chunk(P, *args)[0] == -1).sum()


def test_compass_walking_slice_early_equals_full_run_but_undecided_to_converged():
    # The acceptance rule of issue 30: every point's outcome at the default early
    # classification, strides at rtol 1e-9, equals a full 20-stride run at the scene's
    # rtol 1e-12 without it, except undecided -> converged (the walking slice of
    # scripts/bench_basin.py, span 0.05, on 30 x 30 points).
    P, fp = _compass(1e-12)
    ranges = tuple(
        (fp.section[a] - 0.05 * max(abs(fp.section[a]), 0.1),
         fp.section[a] + 0.05 * max(abs(fp.section[a]), 0.1))
        for a in (0, 1)
    )  # fmt: skip
    kw = dict(ranges=ranges, n=(30, 30), n_strides=20, progress=False, jobs=2)
    full = basin_map(P, fp, **kw)
    early = basin_map(P.with_tolerance(1e-9, 1e-9), fp, converge_radius="auto", **kw)
    assert early.classification["converge_radius"] > 1e-3
    same = full.outcome == early.outcome
    changed = (full.outcome == BASIN_UNDECIDED) & (early.outcome == BASIN_CONVERGED)
    assert np.all(same | changed)
    assert changed.sum() > 0.3 * full.outcome.size  # the slice has many undecided points
    assert (full.outcome > 0).sum() > 0  # and falls, which stay falls
    both = full.outcome == BASIN_CONVERGED
    assert np.all(early.strides[both] <= full.strides[both])


def test_the_file_records_the_classification_and_resume_checks_it(tmp_path):
    from walker.storage import CheckpointMismatch, read

    m = QuadraticMap(5.0)
    fp = _fixed_point(m)
    kw = dict(ranges=((0.15, 0.25), (-1.01, -0.99)), n=(4, 3), n_strides=5, progress=False)
    out = tmp_path / "b.h5"
    b = basin_map(m, fp, converge_radius="auto", out=out, executor="serial", **kw)
    stored = read(out)[0]
    assert stored.classification == b.classification
    assert stored.classification["converge_radius"] == b.classification["certified_radius"] > 0
    np.testing.assert_array_equal(np.array(stored.classification["weight"]).shape, (3, 3))
    with pytest.raises(CheckpointMismatch, match="converge_radius"):
        basin_map(m, fp, converge_radius=0.0, out=out, executor="serial", **kw)
    again = basin_map(m, fp, converge_radius="auto", out=out, executor="serial", **kw)
    np.testing.assert_array_equal(again.outcome, b.outcome)
    assert again.classification == stored.classification  # the file's ball, kept


def test_a_file_without_the_classification_still_reads(tmp_path, monkeypatch):
    # a writer from before the field (its schema has no `classification`): read as {}
    from walker.results import BasinMap
    from walker.storage import read, schema, write

    b = BasinMap(("a", "b"), np.arange(2.0), np.arange(3.0), np.full((3, 2), -1),
                 np.zeros((3, 2), dtype=np.int64), np.zeros(2), np.zeros(2), 5)  # fmt: skip
    with monkeypatch.context() as mp:
        mp.delitem(schema._SPECS[BasinMap], "classification")
        write(tmp_path / "old.h5", b, provenance={})
    import h5py

    with h5py.File(tmp_path / "old.h5", "r") as f:
        assert "classification" not in f["result"].attrs
    old = read(tmp_path / "old.h5")[0]
    assert old.classification == {} and old.outcome.tolist() == b.outcome.tolist()


def test_cli_converge_radius(tmp_path, capsys):
    from walker.cli import main
    from walker.storage import read

    base = ["basin", "gaits/compass_goswami.toml", "--n", "3", "--strides", "3", "--quiet"]
    base += ["--jobs", "1"]
    assert main([*base, "--out", str(tmp_path / "a.h5")]) == 0
    auto = read(tmp_path / "a.h5")[0].classification
    assert auto["converge_radius_rule"] == "auto" and auto["converge_radius"] > 0
    assert main([*base, "--converge-radius", "0", "--out", str(tmp_path / "b.h5")]) == 0
    assert read(tmp_path / "b.h5")[0].classification == {"tol": 1e-6, "converge_radius": 0.0}
    for bad in ("-1", "nan", "big"):
        code = main([*base, f"--converge-radius={bad}", "--out", str(tmp_path / "c.h5")])
        assert code == 2 and "--converge-radius" in capsys.readouterr().err
        assert not (tmp_path / "c.h5").exists()
