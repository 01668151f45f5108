"""docs/own_system.md runs: its code blocks, in order, in one namespace per walkthrough
(their asserts are the checks), and the public names it uses are in walker.__all__.

The kicked ball (numba, slow tier): its closed-form fixed point v* = k/(1 - e), multiplier e,
stride time 2 v*/g.  The three-link walker with a user controller (a ctypes callback, no
numba): with the built-in gains its gait is the built-in controller's to 1e-10; with other
gains the gait of the hybrid-invariant references is unchanged and the outputs follow the
closed form of y'' = -kp y - kd y' along a stride."""

import re
from pathlib import Path

import pytest

import walker

DOC = Path(__file__).resolve().parents[1] / "docs" / "own_system.md"


CONTROLLER = "## A user controller for the three-link walker"
"""The heading that starts the second walkthrough (its blocks run on their own)."""


def _blocks(part="ball"):
    """The code blocks of the kicked ball ("ball"), of the three-link controller
    ("controller"), or of the whole page ("all")."""
    text = DOC.read_text()
    ball, controller = text.split(CONTROLLER)
    text = {"ball": ball, "controller": controller, "all": text}[part]
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def _run_blocks(blocks, directory, name):
    """The code blocks as one module ``name`` written to ``directory`` and imported (numba
    needs a real module for the functions it compiles); returns the module."""
    import importlib.util
    import sys

    path = Path(directory) / f"{name}.py"
    path.write_text("\n\n".join(blocks))
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    finally:
        sys.modules.pop(name, None)
    return module


@pytest.mark.slow  # numba compiles the page's functions (about 10 s)
def test_the_page_runs(tmp_path):
    pytest.importorskip("numba")
    blocks = _blocks()
    assert len(blocks) >= 4
    page = _run_blocks(blocks, tmp_path, "own_system_page")
    assert page.fp.success


@pytest.mark.slow  # a walkthrough: the integration tier
def test_the_controller_walkthrough_runs(tmp_path, monkeypatch):
    """The three-link walker with a user controller through ctx, without numba (about 4 s:
    three gait searches with a Python torque callback)."""
    monkeypatch.chdir(DOC.parents[1])  # the page loads gaits/ by relative path
    blocks = _blocks("controller")
    assert len(blocks) >= 4
    page = _run_blocks(blocks, tmp_path, "own_system_controller")
    assert page.gait_same.success and page.gait_soft.success
    # the user controller acted: the transverse multipliers moved with the gains
    assert abs(page.gait_soft.multipliers[1] - page.gait_builtin.multipliers[1]) > 1e-3


def test_the_page_needs_only_public_names():
    for block in _blocks("all"):
        for module, names in re.findall(r"from (walker[\w.]*) import ([\w, ]+)", block):
            if module == "walker":
                for name in names.split(","):
                    assert name.strip() in walker.__all__, name


@pytest.mark.slow
def test_a_failed_stride_is_a_status(tmp_path):
    pytest.importorskip("numba")
    import numpy as np

    P = _run_blocks(_blocks()[:2], tmp_path, "own_system_map").P
    # thrown downward from the ground: the guard starts at zero and never crosses it again
    r = P(np.array([-1.0]))
    assert r.status == walker.Status.NO_EVENT and np.isnan(r.z).all()
    short = type(P)(P.system, P.params, P.to_state, P.to_section, P.section_names, t_max=1e-3)
    r = short(np.array([5.0]))
    assert r.status == walker.Status.NO_EVENT and np.isnan(r.z).all()


def test_the_route_is_public():
    """Everything the page's route takes is in walker.__all__ and resolves (the lazy names
    too)."""
    route = (
        "HybridSystem",
        "SystemMap",
        "MapResult",
        "Status",
        "EVENT_STRIDE",
        "find_fixed_point",
        "continue_branch",
        "hybrid_solve",
        "get_model",
        "StrideMap",
    )
    for name in route:
        assert name in walker.__all__, name
    for name in walker.__all__:
        assert getattr(walker, name) is not None, name
