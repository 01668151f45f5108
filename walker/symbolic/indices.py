"""Named indices of every model, printed for the compiled code and the model modules.

A model's parameter vector is its parameter class's fields in order
(:meth:`walker.params.KneedParams.names`, ...), its phases and guards are its module's
``PHASE_NAMES`` and ``GUARD_NAMES``.  Code that reads ``p[12]`` or tests ``phase == 0`` would
tie itself to an order that nothing checks; instead it reads the constants printed here:

* ``walker/_generated/indices.py``: ``KNEED_P_SLOPE = 12``, ``KNEED_N_P = 17``,
  ``KNEED_PHASE_LOCKED = 1``, ``KNEED_GUARD_KNEE_LOCK = 0``, ... (plain integers);
* ``walker/_generated/indices.h``: the same as ``#define WK_KNEED_P_SLOPE 12``, ...

Phases are printed for the models whose phase names are identifiers (the friction models
number their stick/slip phases by mode codes, :mod:`walker.models.friction`).  Both files are
written by ``python scripts/generate_kernels.py`` (``--indices`` writes only them) and checked
against these functions by ``tests/test_indices.py``, so a reordered field fails a test until
the files are printed again.

Examples
--------
>>> text = render_indices_py()
>>> "KNEED_P_SLOPE = 12" in text and "COMPASS_GUARD_HEEL_STRIKE = 0" in text
True
"""

from __future__ import annotations

from walker.models import MODEL_NAMES, get_model

__all__ = ["index_table", "render_indices_h", "render_indices_py"]

_HEADER = (
    "generated, do not edit: walker's named indices (parameters, phases, guards)",
    "from the parameter classes (walker.params) and the models' PHASE_NAMES / GUARD_NAMES;",
    "regenerate with `python scripts/generate_kernels.py --indices`",
)


def _constant(name: str) -> str:
    return name.upper()


def index_table() -> list[tuple[str, list[tuple[str, int]]]]:
    """Every model's named indices: ``[(model, [(NAME, value), ...]), ...]`` in
    :data:`walker.models.MODEL_NAMES` order; names without the model prefix (``P_SLOPE``,
    ``N_P``, ``PHASE_LOCKED``, ``GUARD_KNEE_LOCK``)."""
    out = []
    for model_name in MODEL_NAMES:
        model = get_model(model_name)
        names = model.params_class.names()
        rows = [("N_P", len(names))]
        rows += [(f"P_{_constant(n)}", i) for i, n in enumerate(names)]
        phases = tuple(model.module.PHASE_NAMES)
        if all(p.isidentifier() for p in phases):
            rows += [(f"PHASE_{_constant(p)}", i) for i, p in enumerate(phases)]
        guards = tuple(model.module.GUARD_NAMES)
        rows += [(f"GUARD_{_constant(g)}", i) for i, g in enumerate(guards) if g.isidentifier()]
        out.append((model_name, rows))
    return out


def render_indices_py() -> str:
    """The text of ``walker/_generated/indices.py``."""
    lines = [f"# {h}" for h in _HEADER]
    lines += ['"""Named indices of walker\'s models (generated; see walker.symbolic.indices)."""']
    for model_name, rows in index_table():
        lines.append("")
        lines.append(f"# {model_name}")
        lines += [f"{model_name.upper()}_{name} = {value}" for name, value in rows]
    return "\n".join(lines) + "\n"


def render_indices_h() -> str:
    """The text of ``walker/_generated/indices.h``."""
    lines = ["/* " + _HEADER[0]] + [" * " + h for h in _HEADER[1:]]
    lines[-1] += " */"
    lines += ["#ifndef WK_GENERATED_INDICES_H", "#define WK_GENERATED_INDICES_H"]
    for model_name, rows in index_table():
        lines.append("")
        lines.append(f"/* {model_name} */")
        lines += [f"#define WK_{model_name.upper()}_{name} {value}" for name, value in rows]
    lines += ["", "#endif"]
    return "\n".join(lines) + "\n"
