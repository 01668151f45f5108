"""docs/own_system.md runs: its code blocks, in order, in one namespace (their asserts are
the checks: the kicked ball's closed-form fixed point v* = k/(1 - e), multiplier e, stride
time 2 v*/g), and the public names it uses are in walker.__all__."""

import re
from pathlib import Path

import pytest

import walker

DOC = Path(__file__).resolve().parents[1] / "docs" / "own_system.md"


def _blocks():
    return re.findall(r"```python\n(.*?)```", DOC.read_text(), flags=re.S)


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


def test_the_page_needs_only_public_names():
    for block in _blocks():
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
