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

Each takes ``--json`` (strict JSON, one object) except ``scene new``, which writes TOML.
:class:`HelpFormatter` is the help layout the subcommands share (``formatter_class``): it
shows each option's default.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import tempfile
import textwrap
from pathlib import Path
from typing import NamedTuple

from ._common import EXIT_OK, UsageError, _check_out, _json


class HelpFormatter(argparse.HelpFormatter):
    """Help that shows every option's default.

    A required option, and one whose help already says ``default``, is left as written (for a
    default of None the help must say what it means, e.g. "default: the scene's strides"); a flag
    (``store_true``) shows ``(default: off)``; a repeatable option without a default shows
    ``(default: none)``; any other default is appended as ``(default: VALUE)``.
    """

    def _get_help_string(self, action: argparse.Action) -> str:
        text = action.help or ""
        if (
            not action.option_strings
            or action.required
            or "default" in text
            or action.default is argparse.SUPPRESS
            or isinstance(action, argparse._HelpAction | argparse._VersionAction)
        ):
            return text
        if isinstance(action, argparse._StoreTrueAction):
            shown = "off"
        elif isinstance(action, argparse._StoreFalseAction):
            shown = "on"
        elif action.default is None:
            if not isinstance(action, argparse._AppendAction):
                return text
            shown = "none"
        else:
            shown = "%(default)s"
        return f"{text} (default: {shown})" if text else f"default: {shown}"


def add_parser(sub, name: str, help_: str, description: str | None = None):
    """A subcommand parser with :class:`HelpFormatter`."""
    return sub.add_parser(
        name, help=help_, description=description or help_, formatter_class=HelpFormatter
    )


# ---- what the commands describe ---------------------------------------------------------------
MODEL_SUMMARIES = {
    "simplest": "Garcia's simplest walker: a point mass at the hip on massless legs with point "
    "feet (the compass gait's limit of vanishing leg mass).",
    "compass": "Compass gait: two rigid legs hinged at a hip mass, point or round feet, "
    "optional viscous hip and ankle dampers.",
    "kneed": "Kneed walker: a hip mass, thigh and shank on each leg, a swing knee that locks "
    "straight, point or round feet.",
    "double_pendulum": "Planar double pendulum with viscous and dry joint friction; not a "
    "walker (no strides, no section): run it with `walker run`.",
    "three_link": "Three-link walker: two legs and a torso, two hip actuators under "
    "virtual-constraint (hybrid zero dynamics) control.",
    "five_link": "Five-link walker like RABBIT: torso, femurs and tibias, hip and knee "
    "actuators under virtual-constraint control.",
    "compass_coulomb": "Compass gait with dry (Coulomb) friction at the stance ankle and the "
    "hip: each joint slips forward, slips backward or sticks (the phases).",
    "kneed_coulomb": "Kneed walker with dry (Coulomb) friction at the stance ankle, the hip and "
    "the swing knee, as stick and slip phases.",
    "rimless_wheel": "Rimless wheel: a point mass at the hub on equally spaced massless spokes, "
    "rolling down the slope from spoke to spoke.",
}
"""Model name -> one line on what it is."""

SECTION_WHERE = {
    "rimless_wheel": "just after a spoke's impact (theta = pi/spokes there)",
    "double_pendulum": "none: the model has no strides",
}
"""Where a model's Poincare section lies, where it is not "just after heel strike"."""


class Start(NamedTuple):
    """What ``walker scene new`` writes for a model and preset besides the parameters."""

    state: tuple[float, ...]
    """the full state of ``[initial]``."""
    note: str
    """where the state comes from (a comment in the file)."""
    source: str
    """``[scene] source``: citation of the parameters and the state."""
    walks: bool
    """``walker find`` (``walker run`` for a model without strides) succeeds from it."""


_GOSWAMI = "A. Goswami, B. Thuilot, B. Espiau, INRIA RR-2996, 1996; IJRR 17(12), 1998 (parameters)"
_HSU_CHEN = 'Hsu Chen, "Passive Dynamic Walking with Knees: A Point Foot Model", M.Eng. thesis, '
_HSU_CHEN += "MIT, 2007"
_MCGEER = 'T. McGeer, "Passive walking with knees", Proc. IEEE ICRA, 1990 (parameters)'
_MCGEER_GUESS = (
    "a rough guess, not a known gait: Hsu Chen's point-foot gait with its rates divided by "
    "sqrt(9.8) (McGeer's time unit); `walker find` ends TRIPPED from it, so bring your own "
    "state"
)
_COMPASS_GAIT = (0.218668802939019, -0.323388558058679, -1.09182667748965, -0.377181558403111)
_KNEED_GAIT = (
    0.188165653505079,
    -0.288902687312574,
    -0.288902687312574,
    -1.10894729114406,
    -0.0577178265800133,
    -0.0577178265800133,
)
_MCGEER_STATE = (
    0.1877,
    -0.2884,
    -0.2884,
    -0.35182932434546693,
    -0.0127455874717488,
    -0.0127455874717488,
)

STARTS: dict[tuple[str, str], Start] = {
    ("simplest", "garcia"): Start(
        (0.20031090049483, 0.40062180098966, -0.19983247291764, -0.015822999933693436),
        "Garcia et al.'s stable gait at slope 0.009 (theta, theta_dot to 1e-10); "
        "phi = 2 theta, phi_dot = (1 - cos 2 theta) theta_dot",
        "M. Garcia, A. Chatterjee, A. Ruina, M. Coleman, J. Biomech. Eng. 120(2):281-288, 1998",
        True,
    ),
    ("compass", "goswami"): Start(
        (0.2187, -0.3234, -1.0918, -0.3772),
        "the stable gait on the 3 degree slope to four digits (Spong et al. 2007)",
        _GOSWAMI + "; M. W. Spong, J. K. Holm, D. Lee, IEEE Robot. Autom. Mag. 14(2), 2007 (gait)",
        True,
    ),
    ("compass", "drake"): Start(
        (0.218774617980327, -0.323774617980327, -1.09286681058014, -0.37613459353082),
        "walker's own stable gait for these parameters (walker find, residual 8e-15)",
        "Parameters: the defaults of Drake's compass-gait example; gait: walker's own",
        True,
    ),
    ("kneed", "hsu_chen"): Start(
        (0.1877, -0.2884, -0.2884, -1.1014, -0.0399, -0.0399),
        "the thesis's stable gait (explicit Euler at dt = 1e-3, so the exact cycle differs "
        "at the 1e-3 level)",
        _HSU_CHEN,
        True,
    ),
    ("kneed", "mcgeer"): Start(_MCGEER_STATE, _MCGEER_GUESS, _MCGEER, False),
    ("double_pendulum", "course"): Start(
        (-0.1, 1.6707963267948966, 0.0, 0.0),
        "released from rest, link 1 0.1 rad below the +x axis and link 2 pointing straight up",
        "walker's energy-check pendulum: point-like links with m = 1 kg, I = 0.5 kg m^2, "
        "l = 1 m, centre of mass at 0.5 m, g = 10 m/s^2",
        True,
    ),
    ("three_link", "grizzle"): Start(
        (
            0.3926990816987121,
            -0.3926990816987121,
            -0.5235987755982919,
            -0.8098217763438416,
            0.37240806991969067,
            -2.0233937571181144,
            0.0,
            0.0,
        ),
        "walker's own stable period-one gait of this controller on level ground",
        "J. W. Grizzle, G. Abba, F. Plestan, IEEE TAC 46(1), 2001 (model); E. R. Westervelt, "
        "J. W. Grizzle, D. E. Koditschek, IEEE TAC 48(1), 2003 (virtual constraints); Bezier "
        "coefficients: walker's own",
        True,
    ),
    ("five_link", "rabbit"): Start(
        (
            0.19999999999998933,
            0.20000000000002266,
            -0.09999999999999978,
            -0.09999999999999253,
            -0.2999999999999956,
            -0.9462895915900675,
            0.5858767365469528,
            -0.19672505436634408,
            -0.8933072811252336,
            -0.8626230482131172,
            0.0,
            0.0,
        ),
        "walker's own stable period-one gait of this controller on level ground",
        "E. R. Westervelt, J. W. Grizzle, D. E. Koditschek, IEEE TAC 48(1), 2003 (model, "
        "Table I); C. Chevallereau et al., IEEE Control Systems Magazine 23(5), 2003 (RABBIT); "
        "Bezier coefficients: walker's own",
        True,
    ),
    ("compass_coulomb", "goswami"): Start(
        _COMPASS_GAIT,
        "the frictionless gait (the preset's dry frictions are 0; raise coulomb_ankle and "
        "coulomb_hip from there)",
        _GOSWAMI,
        True,
    ),
    ("kneed_coulomb", "hsu_chen"): Start(
        _KNEED_GAIT,
        "walker's frictionless gait of the preset (its dry frictions are 0)",
        _HSU_CHEN,
        True,
    ),
    ("kneed_coulomb", "mcgeer"): Start(_MCGEER_STATE, _MCGEER_GUESS, _MCGEER, False),
    ("rimless_wheel", "drake"): Start(
        (0.39269908169872414, -1.095462839647657),
        "the closed-form rolling gait: theta = alpha = pi/8, "
        "theta_dot = -cot(2 alpha) sqrt(4 (g/l) sin(alpha) sin(slope))",
        "Parameters: the defaults of Drake's rimless-wheel example; gait: T. McGeer, IJRR "
        "9(2), 1990, and M. J. Coleman, A. Chatterjee, A. Ruina, Dyn. Stab. Syst. 12(3), 1997",
        True,
    ),
}
"""(model, preset) -> the state, its note and the source ``walker scene new`` writes."""


# ---- walker models ------------------------------------------------------------------------------
def _named(names, units) -> list[dict]:
    return [
        {"index": i, "name": n, "unit": u}
        for i, (n, u) in enumerate(zip(names, units, strict=True))
    ]


def model_record(name: str) -> dict:
    """Everything ``walker models`` says about model ``name``, as plain data."""
    from walker.models import get_model
    from walker.params import STATE_UNITS

    model = get_model(name)
    units = dict(zip(model.state_names, STATE_UNITS[name], strict=True))
    module = model.module
    return {
        "name": name,
        "summary": MODEL_SUMMARIES[name],
        "walker": model.is_walker,
        "state": _named(model.state_names, STATE_UNITS[name]),
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


# ---- walker scene new ---------------------------------------------------------------------------
def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, float):
        return repr(value)  # the shortest text that reads back to the same double
    if isinstance(value, int):
        return str(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"no TOML form for {value!r}")  # pragma: no cover - a bug here


def _choices(values) -> str:
    """``"a", "b" or "c"``."""
    quoted = [_toml_value(v) for v in values]
    return ", ".join(quoted[:-1]) + " or " + quoted[-1] if len(quoted) > 1 else quoted[0]


def _block(lines: list[tuple[str, str]]) -> list[str]:
    """``key = value`` lines with their comments aligned; the comment of a long line goes
    on the line above it."""
    short = [code for code, _ in lines if len(code) <= _COMMENT_COLUMN]
    width = max(map(len, short), default=0) + 2
    out = []
    for code, comment in lines:
        if len(code) > _COMMENT_COLUMN:
            out += [f"# {comment}", code]
        else:
            out.append(f"{code.ljust(width)}# {comment}")
    return out


_COMMENT_COLUMN = 44
"""Longest ``key = value`` line that keeps its comment on the same line."""


def scene_text(model: str, preset: str) -> str:
    """The commented scene file ``walker scene new MODEL --preset PRESET`` writes."""
    from walker.models import get_model
    from walker.params import HAS_EVENTS, PARAMS, STATE_UNITS, _rule_text
    from walker.scene import METHODS, ComputeSettings

    cls = PARAMS[model]
    params = cls.preset(preset)
    start = STARTS[(model, preset)]
    walker_model = get_model(model)
    walks = HAS_EVENTS[model]
    command = "walker find" if walks else "walker run"
    defaults = {f.name: f.default for f in dataclasses.fields(ComputeSettings)}
    out = [
        f"# A walker scene: model {model}, parameters of the preset {preset}.",
        f"# Written by `walker scene new {model} --preset {preset}`; run it with `{command} FILE`.",
        "# Every key is described in docs/scenes.md; `walker params MODEL` lists the parameters",
        "# and `walker models MODEL` the state, phases and section coordinates.",
        "",
        "[scene]",
        *_block(
            [
                (f"model = {_toml_value(model)}", "required: one of `walker models`"),
                (
                    f"description = {_toml_value(MODEL_SUMMARIES[model])}",
                    'optional free text (default "")',
                ),
                (
                    f"source = {_toml_value(start.source)}",
                    'optional: where the parameters and the state come from (default "")',
                ),
            ]
        ),
    ]
    scuff = getattr(walker_model.module, "SWING_SCUFF", ())
    if scuff:
        out += [
            "",
            "[model]",
            *_block(
                [
                    (
                        f"swing_scuff = {_toml_value(scuff[0])}",
                        f"{' or '.join(_toml_value(s) for s in scuff)} (default "
                        f"{_toml_value(scuff[0])}): a "
                        "swing foot touching the ground with the knee bent trips the walker, or "
                        "passes through the ground",
                    )
                ]
            ),
        ]
    units = cls.units()
    docs = cls.docs()
    fields = {f.name: f for f in dataclasses.fields(cls)}
    out += [
        "",
        "[parameters]",
        "# No defaults: every value below is the preset's and overrides it (delete a line to",
        "# keep the preset's value; drop `preset` and give every key for a set of your own).",
        *_block(
            [(f"preset = {_toml_value(preset)}", f"one of {', '.join(cls.PRESETS)}")]
            + [
                (
                    f"{name} = {_toml_value(value)}",
                    f"[{units[name]}] {docs[name]}; "
                    f"{_rule_text(fields[name].metadata) or 'any value'}",
                )
                for name, value in params.to_dict().items()
            ]
        ),
    ]
    names = walker_model.state_names
    state_units = STATE_UNITS[model]
    out += [
        "",
        "[initial]",
        "# The full state, in this order [unit]:",
        *textwrap.wrap(
            ", ".join(f"{n} [{u}]" for n, u in zip(names, state_units, strict=True)),
            width=90,
            initial_indent="#   ",
            subsequent_indent="#   ",
        ),
        *textwrap.wrap(
            f"Here: {start.note}.", width=90, initial_indent="# ", subsequent_indent="# "
        ),
        f"state = {_toml_value(list(start.state))}",
        "# phase = 0   # optional phase index (`walker models MODEL` lists them); default: the",
        "#             # phase consistent with the state",
    ]
    task = defaults["task"] if walks else "simulate"
    strides = defaults["strides"] if walks else 0
    out += [
        "",
        "[compute]",
        "# Optional table; each key's default is given.",
        *_block(
            [
                (
                    f"task = {_toml_value(task)}",
                    '"fixed_point" (the gait: walker find) or "simulate" (walker run); '
                    + (
                        f"default {_toml_value(defaults['task'])}"
                        if walks
                        else 'this model has no strides: "simulate" only'
                    ),
                ),
                (
                    f"strides = {strides}",
                    "fixed_point: the period, >= 1; simulate: strides to run, 0 = up to t_max; "
                    + (f"default {defaults['strides']}" if walks else "0 only for this model"),
                ),
                (
                    f"method = {_toml_value(defaults['method'])}",
                    f"{_choices(METHODS)}; default {_toml_value(defaults['method'])}",
                ),
                (
                    f"rtol = {defaults['rtol']!r}",
                    f"relative tolerance, > 0; default {defaults['rtol']!r}",
                ),
                (
                    f"atol = {defaults['atol']!r}",
                    f"absolute tolerance, > 0; default {defaults['atol']!r}",
                ),
                (
                    f"t_max = {defaults['t_max']!r}",
                    "[s] time limit per stride (the whole run when strides = 0), > 0; "
                    f"default {defaults['t_max']!r}",
                ),
                (
                    f"tol = {defaults['tol']!r}",
                    "fixed-point residual max|P^k(z) - z| (walker find --tol), > 0; "
                    f"default {defaults['tol']!r}",
                ),
            ]
        ),
        "# first_step = 0.001   # [s] optional first step, > 0 (default: chosen by the",
        "#                      # integrator); required by RK4 and Euler, as their fixed step",
        "",
        "# An optional [reference] table holds high-accuracy values of the orbit to test",
        "# against (docs/scenes.md).",
    ]
    return "\n".join(out) + "\n"


def _check_scene(text: str) -> None:
    """Load ``text`` as a scene: a file that does not load is a bug of ``scene new``."""
    from walker.scene import load_scene

    with tempfile.TemporaryDirectory(prefix="walker-scene-") as tmp:
        path = Path(tmp) / "scene.toml"
        path.write_text(text, encoding="utf-8")
        load_scene(path)


def _write_atomically(out: Path, text: str, overwrite: bool) -> None:
    """Write ``text`` to a new file next to ``out``, then move it into place: ``out`` is
    either absent, its old content, or the whole new text.  Without ``overwrite`` the move
    refuses an ``out`` that appeared meanwhile."""
    parent = out.parent if str(out.parent) else Path(".")
    fd, tmp = tempfile.mkstemp(dir=parent, prefix=f".{out.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as fh:
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())
        if overwrite:
            os.replace(tmp, out)
            return
        try:
            os.link(tmp, out)  # fails if out exists: no replacing a file made meanwhile
        except FileExistsError:
            raise UsageError(f"--out {out} exists; pass --overwrite to replace it") from None
        except OSError:  # no hard links on this file system
            if out.exists():
                raise UsageError(f"--out {out} exists; pass --overwrite to replace it") from None
            os.replace(tmp, out)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


def cmd_scene_new(args) -> int:
    from walker.params import PARAMS

    presets = PARAMS[args.model].PRESETS
    preset = presets[0] if args.preset is None else args.preset
    if preset not in presets:
        raise UsageError(
            f"--preset must be one of {', '.join(presets)} for model {args.model}, "
            f"got {args.preset!r}"
        )
    out = _check_out(args.out, overwrite=args.overwrite)
    text = scene_text(args.model, preset)
    _check_scene(text)
    if out is None:
        print(text, end="")
        return EXIT_OK
    _write_atomically(out, text, args.overwrite)
    from walker.params import HAS_EVENTS

    command = "walker find" if HAS_EVENTS[args.model] else "walker run"
    print(f"wrote {out}; next: {command} {out}")
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
    p.add_argument("--out", metavar="FILE", help="file to write (default: print the scene)")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    p.set_defaults(func=cmd_scene_new)
