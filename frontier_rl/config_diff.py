"""What differs between two configurations, shown so that the two sides never read the same: a
results folder refuses a run whose settings differ from those its rows were made with, and a training
run one whose configuration differs from its own, and each says which settings differ and how."""

from __future__ import annotations

import json
from typing import Any

from frontier_rl.errors import short_text

_DIFFERENCES_SHOWN = 4
"""A refused configuration names at most this many differing settings."""

_VALUE_CHARS = 48
"""A differing setting's value is shown up to about this many characters."""

_PATH_CHARS = 60
"""A differing setting's dotted path is shown up to this many characters."""


class _Absent:
    """A setting one side of a comparison does not have."""

    def __repr__(self) -> str:
        return "(absent)"


ABSENT: Any = _Absent()


def differences_between(there: Any, now: Any, path: str) -> list[tuple[str, Any, Any]]:
    """The settings that differ between two JSON values, as (dotted path, value there, value
    now), down to the leaves of dicts and of lists of the same length; absent keys are
    ``(absent)``. Of two lists of texts of different lengths (the worlds of a folder whose maps
    changed), the items only one side has, each against ``(absent)``. Values whose JSON texts agree
    count as equal."""
    if isinstance(there, dict) and isinstance(now, dict):
        keys = [*there, *(k for k in now if k not in there)]
        return [d for k in keys for d in differences_between(there.get(k, ABSENT), now.get(k, ABSENT), f"{path}.{k}")]
    if isinstance(there, list) and isinstance(now, list) and len(there) == len(now):
        return [
            d
            for i, (a, b) in enumerate(zip(there, now, strict=True))
            for d in differences_between(a, b, f"{path}[{i}]")
        ]
    if isinstance(there, list) and isinstance(now, list) and all(isinstance(x, str) for x in [*there, *now]):
        gone, added = [x for x in there if x not in now], [x for x in now if x not in there]
        if gone or added:
            return [(path, x, ABSENT) for x in gone] + [(path, ABSENT, x) for x in added]
    if there == now or _show(there) == _show(now):
        return []
    return [(path, there, now)]


def describe_differences(differences: list[tuple[str, Any, Any]]) -> str:
    """``path: A there, B now`` for the first few differences, each value cut to about
    :data:`_VALUE_CHARS` characters around where the two differ (so they never read the same)."""
    shown = []
    for path, there, now in differences[:_DIFFERENCES_SHOWN]:
        a, b = contrast(there, now)
        shown.append(f"{short_text(path, _PATH_CHARS)}: {a} there, {b} now")
    more = len(differences) - _DIFFERENCES_SHOWN
    return "; ".join(shown) + (f"; and {more} more difference{'s' * (more > 1)}" if more > 0 else "")


def contrast(there: Any, now: Any, width: int = _VALUE_CHARS) -> tuple[str, str]:
    """Two values as JSON text, each cut to ``width`` characters around the first character where
    they differ; a cut text is marked with "…" and its full length. Two different texts stay
    different: the window holds the first differing character (or the end of the shorter text)."""
    a, b = _show(there), _show(now)
    if len(a) <= width and len(b) <= width:
        return a, b
    same = 0
    while same < min(len(a), len(b)) and a[same] == b[same]:
        same += 1
    start = max(0, same - width // 3)
    return _window(a, start, width), _window(b, start, width)


def _window(text: str, start: int, width: int) -> str:
    if len(text) <= width and start == 0:
        return text
    piece = text[start : start + width]
    return f"{'…' * (start > 0)}{piece}{'…' * (start + width < len(text))} ({len(text)} chars)"


def _show(value: Any) -> str:
    if value is ABSENT:
        return "(absent)"
    try:
        return json.dumps(value, sort_keys=True)
    except (TypeError, ValueError):
        return repr(value)
