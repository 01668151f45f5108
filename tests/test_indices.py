"""Named indices (walker/_generated/indices.py and .h, printed by walker.symbolic.indices):
the files are what the parameter classes and the models' phase and guard names give today,
the C and Python forms agree, and no model reads a parameter or writes a guard by a literal
index."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from walker._generated import indices as ix
from walker.models import MODEL_NAMES, get_model
from walker.symbolic.indices import index_table, render_indices_h, render_indices_py

ROOT = Path(__file__).resolve().parents[1]
GENERATED = ROOT / "walker" / "_generated"


def test_generated_files_are_current():
    """A reordered or renamed field, phase or guard fails here until
    ``python scripts/generate_kernels.py --indices`` prints the files again."""
    assert (GENERATED / "indices.py").read_text(encoding="utf-8") == render_indices_py()
    assert (GENERATED / "indices.h").read_text(encoding="utf-8") == render_indices_h()


def test_c_and_python_constants_agree():
    text = (GENERATED / "indices.h").read_text(encoding="utf-8")
    defines = dict(re.findall(r"#define WK_([A-Z0-9_]+) (\d+)", text))
    python = {k: v for k, v in vars(ix).items() if k.isupper()}
    assert len(python) > 200
    assert {k: int(v) for k, v in defines.items()} == python


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_indices_name_the_fields_phases_and_guards(name):
    model = get_model(name)
    prefix = name.upper()
    names = model.params_class.names()
    assert getattr(ix, f"{prefix}_N_P") == len(names)
    for i, field in enumerate(names):
        assert getattr(ix, f"{prefix}_P_{field.upper()}") == i
    for i, guard in enumerate(model.guard_names):
        if guard.isidentifier():
            assert getattr(ix, f"{prefix}_GUARD_{guard.upper()}") == i
    rows = dict(index_table())[name]
    assert len({value for key, value in rows if key.startswith("P_")}) == len(names)


def test_spot_values():
    # fixed by the parameter classes' documented order (walker.params)
    assert ix.KNEED_P_SLOPE == 12 and ix.KNEED_PHASE_LOCKED == 1
    assert ix.COMPASS_GUARD_HEEL_STRIKE == 0 and ix.THREE_LINK_P_CONTROLLER == 12


_LITERAL_PARAMETER = re.compile(r"\bp\[\d+\]")
_LITERAL_GUARD = re.compile(r"\bg\[\d+\]\s*=[^=]")


@pytest.mark.parametrize(
    "path",
    sorted((ROOT / "walker" / "models").glob("*.py"))
    + sorted((ROOT / "walker" / "_core").glob("model_*.c")),
    ids=lambda p: p.name,
)
def test_models_use_no_literal_parameter_or_guard_index(path):
    """Every parameter read and guard write in a model goes through a named index (comments
    and docstrings may still quote ``p[...]``)."""
    code = []
    for line in path.read_text(encoding="utf-8").splitlines():
        stripped = line.strip()
        if stripped.startswith(("#", "/*", "*", "``", '"""')) or "``" in line:
            continue
        code.append(line)
    text = "\n".join(code)
    assert not _LITERAL_PARAMETER.findall(text), path.name
    assert not _LITERAL_GUARD.findall(text), path.name
