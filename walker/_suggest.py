"""'Did you mean' suggestions for misspelt names (models, parameters, presets, keys)."""

from __future__ import annotations

import difflib
from collections.abc import Iterable


def closest(name: object, choices: Iterable[object]) -> str | None:
    """The choice nearest to ``name`` (difflib's ratio at least 0.7, case ignored; else the
    only choice that shares its first three letters), or None."""
    options = [str(c) for c in choices]
    lowered = {o.lower(): o for o in options}
    key = str(name).lower()
    found = difflib.get_close_matches(key, list(lowered), n=1, cutoff=0.7)
    if found:
        return lowered[found[0]]
    # a name cut short or run on: the one choice it starts (or that starts it)
    near = [o for k, o in lowered.items() if len(key) >= 3 and (k.startswith(key[:3]))]
    return near[0] if len(near) == 1 else None


def did_you_mean(name: object, choices: Iterable[object], quote: str = "`") -> str:
    """``" (did you mean `slope`?)"`` for the choice nearest to ``name``, or ``""``.

    Examples
    --------
    >>> did_you_mean("slpe", ["slope", "g"])
    ' (did you mean `slope`?)'
    >>> did_you_mean("xyz", ["slope", "g"])
    ''
    """
    found = closest(name, choices)
    return f" (did you mean {quote}{found}{quote}?)" if found is not None else ""
