"""The help layout every ``walker`` subcommand shares: :class:`HelpFormatter` shows each
option's default; :func:`add_parser` makes a subcommand parser with it."""

from __future__ import annotations

import argparse
import functools
import re

__all__ = ["HelpFormatter", "add_parser"]


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


_INVALID_CHOICE = re.compile(r"invalid choice: '(?P<name>[^']*)' \(choose from (?P<choices>.*)\)")


def _error_with_suggestion(parser: argparse.ArgumentParser, message: str):
    """``parser.error`` that adds a "did you mean" to an invalid choice (a misspelt model)."""
    from walker._suggest import did_you_mean

    found = _INVALID_CHOICE.search(message)
    if found:
        choices = [c.strip().strip("'") for c in found["choices"].split(",")]
        message += did_you_mean(found["name"], choices, quote="'")
    return argparse.ArgumentParser.error(parser, message)


def add_parser(sub, name: str, help_: str, description: str | None = None):
    """A subcommand parser with :class:`HelpFormatter`, whose error for an invalid choice
    suggests the nearest one."""
    parser = sub.add_parser(
        name, help=help_, description=description or help_, formatter_class=HelpFormatter
    )
    parser.error = functools.partial(_error_with_suggestion, parser)
    return parser
