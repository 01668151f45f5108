"""``walker scene new MODEL [--preset NAME] [--out FILE]``: a scene file with every key and a
comment on each, that ``walker find`` (``walker run`` for the double pendulum) accepts as it
is (the state, note and citation it writes for each model and preset are
:data:`walker.cli._catalog.STARTS`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import os
import tempfile
import textwrap
from pathlib import Path

from ._catalog import MODEL_SUMMARIES, STARTS
from ._common import EXIT_OK, UsageError, _check_out

__all__ = ["cmd_scene_new", "scene_text"]


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
    from walker.params import _rule_text
    from walker.scene import METHODS, ComputeSettings

    walker_model = get_model(model)
    cls = walker_model.params_class
    params = cls.preset(preset)
    start = STARTS[(model, preset)]
    walks = walker_model.has_strides
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
    state_units = walker_model.state_units
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
    from walker._suggest import did_you_mean
    from walker.params import MODELS

    presets = MODELS[args.model].params_class.PRESETS
    preset = presets[0] if args.preset is None else args.preset
    if preset not in presets:
        raise UsageError(
            f"--preset must be one of {', '.join(presets)} for model {args.model}, "
            f"got {args.preset!r}{did_you_mean(args.preset, presets)}"
        )
    out = _check_out(args.out, overwrite=args.overwrite)
    text = scene_text(args.model, preset)
    _check_scene(text)
    if out is None:
        print(text, end="")
        return EXIT_OK
    _write_atomically(out, text, args.overwrite)
    command = "walker find" if MODELS[args.model].has_strides else "walker run"
    print(f"wrote {out}; next: {command} {out}")
    return EXIT_OK
