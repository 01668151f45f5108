"""The help layout every ``walker`` subcommand shares: :class:`HelpFormatter` shows each
option's default; :func:`add_parser` makes a subcommand parser with it."""

from __future__ import annotations

import argparse

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


def add_parser(sub, name: str, help_: str, description: str | None = None):
    """A subcommand parser with :class:`HelpFormatter`."""
    return sub.add_parser(
        name, help=help_, description=description or help_, formatter_class=HelpFormatter
    )
