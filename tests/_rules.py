"""Checking one rule over many cases in one test, reporting every case that breaks it.

A test that loops over cases stops at the first failed ``assert``; :class:`Failures`
instead collects each broken case with a label (e.g. ``CompassParams.mass_hip = -1.0``) and
:meth:`Failures.assert_none` reports them all in one message, so one test per rule reads
as well as one test per case.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any


class Failures:
    """The cases that broke one rule.

    Parameters
    ----------
    rule : str
        what every case must satisfy, printed at the head of the failure message.
    """

    def __init__(self, rule: str) -> None:
        self.rule = rule
        self.items: list[str] = []
        self.n_checked = 0

    def check(self, label: str, ok: bool, detail: str = "") -> None:
        """Record ``label`` as broken unless ``ok``; ``detail`` says what was seen."""
        self.n_checked += 1
        if not ok:
            self.items.append(f"{label}: {detail}" if detail else label)

    def raises(
        self,
        label: str,
        exc: type[BaseException] | tuple[type[BaseException], ...],
        pattern: str,
        func: Callable[..., Any],
        *args: Any,
        **kwargs: Any,
    ) -> None:
        """Record ``label`` as broken unless ``func(*args, **kwargs)`` raises ``exc`` with a
        message that ``re.search`` finds ``pattern`` in."""
        self.n_checked += 1
        try:
            func(*args, **kwargs)
        except exc as err:
            if re.search(pattern, str(err)) is None:
                self.items.append(
                    f"{label}: {type(err).__name__} message {str(err)!r} does not match {pattern!r}"
                )
        except Exception as err:  # noqa: BLE001 - any other exception is a failure to report
            self.items.append(f"{label}: raised {type(err).__name__}: {err}, not {exc}")
        else:
            self.items.append(f"{label}: raised nothing (expected {exc})")

    def accepts(self, label: str, func: Callable[..., Any], *args: Any, **kwargs: Any) -> None:
        """Record ``label`` as broken if ``func(*args, **kwargs)`` raises."""
        self.n_checked += 1
        try:
            func(*args, **kwargs)
        except Exception as err:  # noqa: BLE001 - reported, not swallowed
            self.items.append(f"{label}: refused with {type(err).__name__}: {err}")

    def assert_none(self, at_least: int = 1) -> None:
        """Fail listing every broken case; also fail if fewer than ``at_least`` cases were
        checked (a rule that applies to nothing checks nothing)."""
        assert self.n_checked >= at_least, (
            f"rule {self.rule!r} checked {self.n_checked} case(s), expected >= {at_least}"
        )
        assert not self.items, (
            f"{len(self.items)} of {self.n_checked} case(s) break the rule: {self.rule}\n  "
            + "\n  ".join(self.items)
        )
