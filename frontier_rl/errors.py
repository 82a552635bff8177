"""Exception types: every error a user can cause names the bad value in one line, and the
helpers that quote an untrusted value in a message with a bound on its length."""

from __future__ import annotations

import reprlib

QUOTE_LIMIT = 80
"""Default bound (characters) on a value quoted in an error message."""


class FrontierRLError(Exception):
    """Base class of the errors frontier_rl raises for bad input."""


class MapError(FrontierRLError, ValueError):
    """A map file or grid that cannot be used (malformed, truncated, no free space)."""


class ConfigError(FrontierRLError, ValueError):
    """A configuration value out of range or of the wrong kind (a weight outside [0, 1], ...)."""


class SettingError(ConfigError):
    """A setting out of its range, its name (``setting``, a field name such as ``planner_frequency``)
    kept apart from what is wrong (``problem``), so that a command line can name it as its option
    (``--planner-frequency``) and a ROS node as its parameter, without reading the message back."""

    def __init__(self, setting: str, problem: str) -> None:
        super().__init__(f"{setting} {problem}")
        self.setting = setting
        self.problem = problem


class TrainingDivergedError(FrontierRLError, RuntimeError):
    """A training run whose updates left the policy with NaN or infinite weights."""


class PolicyError(FrontierRLError, RuntimeError):
    """A policy that failed during an episode: its ``rank()`` returned something the simulator cannot
    follow (not a :class:`~frontier_rl.core.sim.episode.Ranking`, an index that is no candidate's, ...),
    or the user's code of a policy raised."""


class MapWarning(UserWarning):
    """A map file whose fields say something its author probably did not mean (``map_saver``'s grey
    unknown that its thresholds read as free space, read as unknown instead; a field ``map_server``
    does not read)."""


class UnknownNameError(FrontierRLError, KeyError):
    """A world, policy or method name that does not exist."""

    def __str__(self) -> str:  # KeyError quotes its argument; keep the message readable
        return str(self.args[0]) if self.args else ""


class _ShortRepr(reprlib.Repr):
    """``reprlib`` with its size bounds set from one character limit: twice the limit, so that the
    cut :func:`short_text` makes at the limit (marked with an ellipsis) comes first."""

    def __init__(self, limit: int) -> None:
        super().__init__()
        self.maxstring = self.maxother = self.maxlong = max(2 * limit, 8)
        self.maxlevel = 3
        self.maxlist = self.maxtuple = self.maxdict = self.maxset = self.maxfrozenset = self.maxdeque = 6

    def repr_int(self, x: int, level: int) -> str:
        if x.bit_length() > 4 * self.maxlong:  # str() of a huge int is slow, and refused beyond 4300 digits
            return f"<an integer of {x.bit_length()} bits>"
        return super().repr_int(x, level)


def short_text(text: str, limit: int = 200) -> str:
    """``text`` on one line (runs of whitespace become one space), cut to at most ``limit`` characters."""
    flat = " ".join(text[: 4 * limit].split())
    return flat if len(flat) <= limit else flat[: max(limit - 1, 0)] + "…"


def short_repr(value: object, limit: int = QUOTE_LIMIT) -> str:
    """``repr(value)`` for an error message: one line of at most ``limit`` characters, computed without
    expanding a large (or deeply shared) value in full."""
    try:
        text = _ShortRepr(limit).repr(value)
    except Exception:  # a hostile __repr__ must not hide the error being reported
        text = f"<{type(value).__name__}>"
    return short_text(text, limit)


def short_path(path: object, limit: int = QUOTE_LIMIT) -> str:
    """A file path quoted for an error message in at most ``limit`` characters: when cut, the middle
    goes (marked with an ellipsis), so the file's name at the end stays readable."""
    text = str(path)
    whole = repr(text) if len(text) <= limit else ""
    return whole if whole and len(whole) <= limit else _cut_middle(text, limit)


def model_file_label(path: object) -> str:
    """How an error message names the model file at ``path`` (bounded; its file name kept)."""
    return f"model file {short_path(path)}"


def _cut_middle(text: str, limit: int) -> str:
    """``repr`` of ``text`` in ``limit`` characters: its first third and its end, joined by an ellipsis."""
    head_chars = max(limit // 3, 2)
    head = repr(text[:limit])[:head_chars]
    tail_chars = limit - head_chars - 1
    return head + "…" + (repr(text[-limit:])[-tail_chars:] if tail_chars > 0 else "")


def caused_by_interrupt(error: BaseException) -> bool:
    """Whether ``error`` is a Ctrl-C (``KeyboardInterrupt``) or was raised while handling one (numba
    turns an interrupt raised in a compiled kernel's callback into a ``SystemError``)."""
    seen: set[int] = set()
    current: BaseException | None = error
    while current is not None and id(current) not in seen:
        if isinstance(current, KeyboardInterrupt):
            return True
        seen.add(id(current))
        current = current.__cause__ or current.__context__
    return False
