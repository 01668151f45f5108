"""The gallery's rimless-wheel and task-space figures (``scripts/gallery.py``), drawn on small
settings into a temporary directory: the files are PNG images, and the rimless wheel's
plotted gait is the closed form.

The closed form is written out here again, independently of the gallery's
``rimless_closed_form``: ``theta_dot* = -cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(gamma))``
with multiplier ``cos^2(2 alpha)`` (derived in tests/test_rimless_wheel.py).
"""

from __future__ import annotations

import importlib.util
import math
import struct
import sys
from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

ROOT = Path(__file__).resolve().parents[1]
_SPEC = importlib.util.spec_from_file_location(
    "walker_gallery_script", ROOT / "scripts" / "gallery.py"
)
gallery = importlib.util.module_from_spec(_SPEC)
sys.modules[_SPEC.name] = gallery
_SPEC.loader.exec_module(gallery)

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _png_size(path: Path) -> tuple[int, int]:
    """Width and height of a PNG file from its IHDR chunk; fails unless it is a PNG."""
    head = path.read_bytes()[:24]
    assert head[:8] == PNG_SIGNATURE, f"{path.name} is not a PNG file"
    assert head[12:16] == b"IHDR"
    return struct.unpack(">II", head[16:24])


def _closed_form(spokes, leg_length, g, slope):
    alpha = math.pi / spokes
    rate = -math.sqrt(4.0 * g / leg_length * math.sin(alpha) * math.sin(slope)) / math.tan(
        2.0 * alpha
    )
    return rate, math.cos(2.0 * alpha) ** 2


@pytest.fixture(scope="module")
def rimless(tmp_path_factory):
    out = tmp_path_factory.mktemp("gallery")
    return gallery.rimless_wheel_figure(out, n_strides=4, n_slopes=3, n_per_stride=10)


def test_rimless_wheel_figure_is_written(rimless):
    path, _ = rimless
    assert path.name == "rimless_wheel_rolling.png" and path.is_file()
    width, height = _png_size(path)
    assert width > 500 and height > 200


def test_rimless_wheel_figure_marks_the_closed_form_rate(rimless):
    _, data = rimless
    p = data["params"]
    assert (p.spokes, p.leg_length, p.g, p.slope) == (8, 1.0, 9.81, 0.08)  # the shipped scene
    rate, multiplier = _closed_form(p.spokes, p.leg_length, p.g, p.slope)
    assert abs(data["fixed_point_rate"] - rate) <= 1e-10
    assert abs(data["multiplier"] - multiplier) <= 1e-10
    # walker's own fixed point and multiplier agree with it
    assert abs(data["walker_fixed_point_rate"] - rate) <= 1e-10
    assert abs(data["walker_multiplier"] - multiplier) <= 1e-10


def test_rimless_wheel_figure_rates_against_slope_are_the_closed_form(rimless):
    _, data = rimless
    p = data["params"]
    assert len(data["walker_slopes"]) == 3
    for slope, after, before in zip(
        data["walker_slopes"], data["walker_rates"], data["walker_pre_impact_rates"], strict=True
    ):
        rate, _ = _closed_form(p.spokes, p.leg_length, p.g, slope)
        assert abs(after - rate) <= 1e-10
        assert abs(before - rate / math.cos(2 * math.pi / p.spokes)) <= 1e-10
    expected = [_closed_form(p.spokes, p.leg_length, p.g, s)[0] for s in data["slopes"]]
    assert_allclose(data["closed_form_rates"], expected, rtol=0, atol=1e-10)
    # the curve starts at the critical slope, where the gait just gets over the top
    alpha = math.pi / p.spokes
    w = _closed_form(p.spokes, p.leg_length, p.g, data["critical_slope"])[0]
    assert_allclose(
        w * w, 2 * p.g / p.leg_length * (1 - math.cos(alpha - data["critical_slope"])), rtol=1e-12
    )
    assert_allclose(data["critical_slope"], 0.06822945245228713, rtol=1e-12)


def test_rimless_wheel_figure_runs_converge_onto_the_gait(rimless):
    """Each stance arc runs from ``alpha`` to ``-alpha``; the post-impact rates approach the
    closed-form rate from both sides, by about ``cos^2(2 alpha)`` per stride."""
    _, data = rimless
    alpha = math.pi / data["params"].spokes
    rate = data["fixed_point_rate"]
    assert len(data["runs"]) == 2
    signs = set()
    for run in data["runs"]:
        assert len(run["arcs"]) == 4 and len(run["post_impact_rates"]) == 5
        for arc in run["arcs"]:
            assert arc[0, 0] == alpha and abs(arc[-1, 0] + alpha) <= 1e-12
            assert np.all(np.diff(arc[:, 0]) < 0)  # rolling downhill
        errors = run["post_impact_rates"] - rate
        signs.add(np.sign(errors[0]))
        assert np.all(np.abs(errors[1:]) < np.abs(errors[:-1]))
        assert_allclose(errors[-1] / errors[-2], data["multiplier"], rtol=0.1)
    assert signs == {-1.0, 1.0}


@pytest.mark.slow  # a figure job of the gallery: the integration tier
def test_taskspace_figure_is_written(tmp_path):
    path, run = gallery.taskspace_figure(tmp_path, t_final=0.5, n_samples=51)
    assert path == tmp_path / "taskspace_circle_tracking.png" and path.is_file()
    width, height = _png_size(path)
    assert width > 500 and height > 200
    assert run.success and run.t[-1] == 0.5 and len(run.t) == 51


def test_gallery_lists_the_new_jobs_and_the_readme_shows_them():
    assert {"rimless_wheel", "taskspace_circle"} <= set(gallery.JOBS)
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Gallery", 1)[1].split("\n## ", 1)[0]
    for name in ("rimless_wheel_rolling.png", "taskspace_circle_tracking.png"):
        assert f"(results/gallery/{name})" in section
        assert (ROOT / "results" / "gallery" / name).is_file()
