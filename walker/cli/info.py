"""``walker models``, ``walker params``, ``walker scene new``: what walker offers, from the
command line.

* ``walker models [MODEL]``: every model (or one) with its state (names, units), phases,
  guards, section coordinates (the indices ``basin --axes`` takes), parameter class and
  presets.
* ``walker params MODEL``: every parameter of the model with its unit, allowed range and
  each preset's value.
* ``walker scene new MODEL [--preset NAME] [--out FILE]``: a scene file with every key and a
  comment on each, that ``walker find`` (``walker run`` for the double pendulum) accepts as
  it is.

Each takes ``--json`` (strict JSON, one object) except ``scene new``, which writes TOML
(:mod:`walker.cli.scene_new`).  The help layout the subcommands share is in
:mod:`walker.cli._help`.
"""

from __future__ import annotations

import dataclasses
import textwrap

from ._catalog import MODEL_SUMMARIES, SECTION_WHERE, STARTS
from ._common import EXIT_OK, _json, out_flags
from ._help import add_parser
from .scene_new import cmd_scene_new


# ---- walker models ------------------------------------------------------------------------------
def _named(names, units) -> list[dict]:
    return [
        {"index": i, "name": n, "unit": u}
        for i, (n, u) in enumerate(zip(names, units, strict=True))
    ]


def model_record(name: str) -> dict:
    """Everything ``walker models`` says about model ``name``, as plain data."""
    from walker.models import get_model

    model = get_model(name)
    units = dict(zip(model.state_names, model.state_units, strict=True))
    module = model.module
    return {
        "name": name,
        "summary": MODEL_SUMMARIES[name],
        "walker": model.has_strides,
        "state": _named(model.state_names, model.state_units),
        "phases": list(model.phase_names),
        "guards": list(model.guard_names),
        "section": _named(model.section_names, [units[n] for n in model.section_names]),
        "section_where": SECTION_WHERE.get(name, "just after heel strike"),
        "parameter_class": model.params_class.__name__,
        "n_parameters": model.params_class.n_params(),
        "presets": list(model.params_class.PRESETS),
        "swing_scuff": list(getattr(module, "SWING_SCUFF", ())),
    }


def _wrapped(label: str, text: str, width: int = 100) -> str:
    return textwrap.fill(
        text,
        width=width,
        initial_indent=f"  {label:<9s}",
        subsequent_indent=" " * 11,
        break_on_hyphens=False,
    )


def _listed(label: str, names: list[str], full: bool, model: str) -> list[str]:
    """``names`` with their indices: all of them one per line (``full``), else on one
    wrapped line, cut after a few."""
    if full:
        return [f"  {label:<9s}{len(names)}:"] + [
            f"{'':11s}{i:>2d}  {n}" for i, n in enumerate(names)
        ]
    if len(names) <= 4:
        shown = ", ".join(f"{i} {n}" for i, n in enumerate(names))
    else:
        shown = (
            ", ".join(f"{i} {n}" for i, n in enumerate(names[:2]))
            + f", ... (all with `walker models {model}`)"
        )
    return [_wrapped(label, f"{len(names)}: {shown}")]


def _print_model(rec: dict, full: bool) -> None:
    print(textwrap.fill(f"{rec['name']}: {rec['summary']}", width=100, subsequent_indent="  "))
    print(_wrapped("state", ", ".join(f"{s['name']} [{s['unit']}]" for s in rec["state"])))
    for line in _listed("phases", rec["phases"], full, rec["name"]):
        print(line)
    if full:
        for line in _listed("guards", rec["guards"], full, rec["name"]):
            print(line)
    else:
        print(_wrapped("guards", ", ".join(rec["guards"])))
    if rec["section"]:
        coords = ", ".join(f"{s['index']} {s['name']} [{s['unit']}]" for s in rec["section"])
        print(_wrapped("section", f"{coords}; {rec['section_where']}"))
    else:
        print(_wrapped("section", rec["section_where"]))
    presets = ", ".join(rec["presets"])
    print(
        _wrapped(
            "params",
            f"{rec['parameter_class']}, {rec['n_parameters']} parameters "
            f"(`walker params {rec['name']}`); presets: {presets}",
        )
    )
    if rec["swing_scuff"]:
        conventions = " or ".join(f'"{c}"' for c in rec["swing_scuff"])
        print(_wrapped("scuffing", f"[model] swing_scuff = {conventions} (default first)"))


def cmd_models(args) -> int:
    from walker.models import MODEL_NAMES

    names = [args.model] if args.model else list(MODEL_NAMES)
    records = [model_record(n) for n in names]
    if args.json:
        print(_json({"models": records}))
        return EXIT_OK
    if not args.model:
        print(
            f"{len(records)} models; `walker models NAME` shows one in full, "
            "`walker params NAME` its parameters, `walker scene new NAME` a scene file."
        )
        print("Angles in rad, counterclockwise positive: see docs/conventions.md.")
    for rec in records:
        print()
        _print_model(rec, full=bool(args.model))
    return EXIT_OK


# ---- walker params ------------------------------------------------------------------------------
def params_record(name: str) -> dict:
    """Everything ``walker params`` says about model ``name``'s parameters, as plain data."""
    from walker.params import PARAMS, _rule_text

    cls = PARAMS[name]
    presets = {p: cls.preset(p) for p in cls.PRESETS}
    rows = []
    for f in dataclasses.fields(cls):
        meta = f.metadata
        lo, hi = meta["bounds"]
        rows.append(
            {
                "name": f.name,
                "unit": meta["unit"],
                "doc": meta["doc"],
                "min": lo,
                "min_inclusive": lo is not None and not meta["lo_open"],
                "max": hi,
                "max_inclusive": hi is not None and not meta["hi_open"],
                "allowed": _rule_text(meta) or "any",
                "presets": {p: getattr(v, f.name) for p, v in presets.items()},
            }
        )
    return {
        "model": name,
        "parameter_class": cls.__name__,
        "presets": [
            {"name": p, "source": STARTS[(name, p)].source if (name, p) in STARTS else ""}
            for p in cls.PRESETS
        ],
        "parameters": rows,
    }


def _table(header: list[str], rows: list[list[str]]) -> list[str]:
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(len(header) - 1)]
    return [
        "  ".join(cell.ljust(w) for cell, w in zip(r[:-1], widths, strict=True)) + "  " + r[-1]
        for r in [header, *rows]
    ]


def cmd_params(args) -> int:
    rec = params_record(args.model)
    if args.json:
        print(_json(rec))
        return EXIT_OK
    presets = [p["name"] for p in rec["presets"]]
    print(
        f"{rec['model']}: {rec['parameter_class']}, {len(rec['parameters'])} parameters, SI "
        "units ([1]: dimensionless); a scene gives every one, or a preset and the ones it "
        "changes (`walker scene new`)."
    )
    rows = [
        [
            row["name"],
            row["unit"],
            row["allowed"],
            *(f"{row['presets'][p]:.10g}" for p in presets),
            row["doc"],
        ]
        for row in rec["parameters"]
    ]
    for line in _table(["name", "unit", "allowed", *presets, "meaning"], rows):
        print(line.rstrip())
    print("presets:")
    for p in rec["presets"]:
        print(f"  {p['name']}: {p['source']}")
    from walker.params import PARAMS, _Params

    if PARAMS[args.model]._check_relations is not _Params._check_relations:
        print(
            "Rules that join several values are checked too when a scene is loaded (see "
            f"help(walker.params.{rec['parameter_class']})); an error names the rule."
        )
    return EXIT_OK


# ---- the parsers --------------------------------------------------------------------------------
def _model_argument(p, *, optional: bool = False) -> None:
    from walker.models import MODEL_NAMES

    p.add_argument(
        "model",
        nargs="?" if optional else None,
        choices=MODEL_NAMES,
        metavar="MODEL",
        help=f"one of {', '.join(MODEL_NAMES)}" + ("; default: all" if optional else ""),
    )


def register(sub) -> None:
    p = add_parser(
        sub,
        "models",
        "list the models: state, phases, guards, section coordinates, presets",
    )
    _model_argument(p, optional=True)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_models)

    p = add_parser(sub, "params", "list a model's parameters: units, allowed ranges, presets")
    _model_argument(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=cmd_params)

    p = add_parser(sub, "scene", "write scene files")
    scene_sub = p.add_subparsers(dest="scene_command", required=True)
    p = add_parser(
        scene_sub,
        "new",
        "write a commented scene file for a model and preset",
        "Write a scene file with every key and a comment on each (unit, meaning, default) "
        "that `walker find` (`walker run` for a model without strides) accepts as it is.",
    )
    _model_argument(p)
    p.add_argument(
        "--preset",
        metavar="NAME",
        help="parameter preset (`walker params MODEL` lists them; default: the model's first)",
    )
    out_flags(p, "file to write (default: print the scene)")
    p.set_defaults(func=cmd_scene_new)
