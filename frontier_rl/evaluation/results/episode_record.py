"""An episode of a paired experiment as typed values: its row (a line of ``episodes.csv``) and its
trace (a line of ``traces.jsonl``), each with the one codec that writes and reads it back.

Every value read back is checked: a row's fields have their column's type (an empty field only
where a column may be undefined), a trace's curves are lists of one length, and every number is
finite and within :data:`MAX_MAGNITUDE`. A file is untrusted input; a bad line is one
:class:`~frontier_rl.errors.ConfigError` naming the field.
"""

from __future__ import annotations

import csv
import io
import math
import types
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from enum import Enum
from typing import Any, NamedTuple, get_args, get_type_hints

from frontier_rl.checked_values import enum_member
from frontier_rl.core.sim.leg_result import AbortCause
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.errors import ConfigError, short_repr


class EpisodeKey(NamedTuple):
    """An episode's identity in an experiment."""

    method: str
    world: str
    episode: int


MAX_MAGNITUDE = 1e12
"""Largest magnitude of a number in a row or a trace (s, m, ...): 30,000 years of sim time. Anyone
can re-sign an edited row, and a time of 1e308 s or NaN broke the report's plots."""


@dataclass(frozen=True)
class EpisodeRow:
    """One episode's scalars: a line of ``episodes.csv``, its columns in the order of the fields.

    Attributes:
        method, world, episode: which episode (the method as written, the world as given).
        seed: its seed.
        start_x_m, start_y_m, start_theta_rad: the start pose (m, m, rad).
        sim_time_s: exploration time (s; the cap for an episode cut at it).
        path_length_m: distance driven (m; a team's, summed over its robots).
        coverage: share of the explorable space mapped.
        t90_s, t99_s: time to 90 % and 99 % coverage (s; None if never reached).
        decisions: decisions taken.
        aborts: goals given up.
        done: the map was explored.
        truncated: cut at the sim-time cap.
        end_reason: why it ended, written as the reason's value (``explored``, ``unreachable``,
            ``time_cap``, a team's ``failed``; None in rows of before the end reasons).
        free_coverage: share of all free cells mapped.
        unknown_left_m2: unseen free area beside the frontiers left (m²).
        mean_weight: mean ranking weight chosen (None for methods without a weight).
        robots: team size (1 for a single robot).
        overlap: a team's share of cells seen by more than one robot (0 for one robot).
        wall_time_s: the episode's wall-clock time (s).
    """

    method: str
    world: str
    episode: int
    seed: int
    start_x_m: float
    start_y_m: float
    start_theta_rad: float
    sim_time_s: float
    path_length_m: float
    coverage: float
    t90_s: float | None
    t99_s: float | None
    decisions: int
    aborts: int
    done: bool
    truncated: bool
    end_reason: EndReason | None
    free_coverage: float
    unknown_left_m2: float
    mean_weight: float | None
    robots: int
    overlap: float
    wall_time_s: float

    @property
    def key(self) -> EpisodeKey:
        """(method, world, episode)."""
        return EpisodeKey(self.method, self.world, self.episode)

    def csv_line(self) -> str:
        """The row as one CSV line (no newline); None is an empty field."""
        buffer = io.StringIO()
        values = (getattr(self, column) for column in ROW_COLUMNS)
        csv.writer(buffer, lineterminator="").writerow(["" if value is None else value for value in values])
        return buffer.getvalue()

    @classmethod
    def from_csv_line(cls, line: str) -> EpisodeRow:
        """The row of one CSV line, every field checked against its column's type.

        Raises:
            ConfigError: the line is not a row (wrong field count, a value of the wrong kind).
        """
        try:
            values = next(csv.reader([line]), [])
        except csv.Error as exc:
            raise ConfigError(f"not a CSV row ({exc})") from None
        if len(values) != len(ROW_COLUMNS):
            raise ConfigError(f"a row has {len(values)} fields, expected {len(ROW_COLUMNS)}: {short_repr(line)}")
        return cls(**{column: _cell(column, text) for column, text in zip(ROW_COLUMNS, values, strict=True)})


ROW_COLUMNS: tuple[str, ...] = tuple(f.name for f in fields(EpisodeRow))
"""The columns of ``episodes.csv``, in order."""

_COLUMN_TYPES: dict[str, tuple[type, bool]] = {
    name: (next(t for t in get_args(hint) or (hint,) if t is not types.NoneType), types.NoneType in get_args(hint))
    for name, hint in get_type_hints(EpisodeRow).items()
}
"""Each column's type, and whether it may be undefined (an empty field)."""


def _cell(column: str, text: str) -> Any:
    """The value of ``column`` written as ``text``."""
    kind, optional = _COLUMN_TYPES[column]
    if kind is str:
        return None if optional and text == "" else text
    if optional and text == "":
        return None
    if issubclass(kind, Enum):
        return enum_member(kind, text, column)
    try:
        if kind is bool:
            return {"True": True, "False": False}[text]
        if kind is int:
            return int(text)
        value = float(text)
        if is_number(value):
            return value
    except (ValueError, KeyError):
        pass
    expected = {bool: "True or False", int: "an integer"}.get(kind, f"a finite number within +-{MAX_MAGNITUDE:g}")
    raise ConfigError(f"{column} {short_repr(text)} is not valid (expected {expected})")


def is_number(value: object, none: bool = False) -> bool:
    """A finite int or float within :data:`MAX_MAGNITUDE` (or None, when ``none``)."""
    if value is None:
        return none
    return isinstance(value, int | float) and not isinstance(value, bool) and abs(value) <= MAX_MAGNITUDE


@dataclass(frozen=True)
class EpisodeTrace:
    """One episode's curves and diagnostics: a line of ``traces.jsonl``.

    Attributes:
        method, world, episode: which episode.
        coverage_t, coverage: the coverage curve, sampled (s; share of the explorable space).
        weight_t, weight: the ranking weight of every decision and its time (s); empty without weights.
        aborts_by_cause: goals given up, per cause.
        explorable_left_m2: the unseen explorable area left (m²; None in older traces).
        frontiers_with_path_left: frontiers left, not unrevealable, that the robot's final map had
            a path to, on the normal costmap or through walls the narrow-passage recovery thinned
            (the audit; None in older traces).
        frontiers_with_path_to_space_left: of them, those that leave space to explore (more than a
            speck's unseen free cells beside, or a room's behind: space given up; None in older traces).
        explorable_given_up_m2: the explorable area (m²) behind the frontiers left with a path: space
            given up that the robot could have seen on the true map (None in older traces).
        frontiers_with_path_on_map_left: of them, those with a path on the normal costmap, through
            the walls as mapped (None in older traces).
        frontiers_unrevealable_left: frontiers left whose goal was reached in vain, or of whose unknown
            no reachable cell sees more than a speck (None in older traces).
        robot_path_lengths_m, robot_coverage, failed_at_s: a team's, per robot (None for one robot;
            a failure time is None for a robot that did not fail).
    """

    method: str
    world: str
    episode: int
    coverage_t: tuple[float, ...]
    coverage: tuple[float, ...]
    weight_t: tuple[float, ...] = ()
    weight: tuple[float, ...] = ()
    aborts_by_cause: Mapping[AbortCause, int] = field(default_factory=dict)
    explorable_left_m2: float | None = None
    frontiers_with_path_left: int | None = None
    frontiers_with_path_to_space_left: int | None = None
    explorable_given_up_m2: float | None = None
    frontiers_with_path_on_map_left: int | None = None
    frontiers_unrevealable_left: int | None = None
    robot_path_lengths_m: tuple[float, ...] | None = None
    robot_coverage: tuple[float, ...] | None = None
    failed_at_s: tuple[float | None, ...] | None = None

    def to_json(self) -> dict[str, object]:
        """The trace's JSON object: every field in order, lists for the curves, without the
        fields that are None (a single robot's team lists, an older trace's diagnostics)."""
        values = ((f.name, getattr(self, f.name)) for f in fields(self))
        return {
            name: list(value) if isinstance(value, tuple) else _by_name(value) if isinstance(value, Mapping) else value
            for name, value in values
            if value is not None
        }

    @classmethod
    def from_json(cls, data: object) -> EpisodeTrace:
        """The trace of a parsed ``traces.jsonl`` line.

        Raises:
            ConfigError: what keeps it from the report (curves that are not lists of one length, an
                empty coverage curve, a number that is not finite, a field of the wrong type).
        """
        if not isinstance(data, dict):
            raise ConfigError(f"a trace must be a JSON object, got {short_repr(data)}")
        for times, values, least in (("coverage_t", "coverage", 1), ("weight_t", "weight", 0)):
            t, v = data.get(times, []), data.get(values, [])
            if not (isinstance(t, list) and isinstance(v, list) and len(t) == len(v) >= least):
                raise ConfigError(
                    f"{times} and {values} must be lists of one length" + (", not empty" if least else "")
                )
            if not all(is_number(x) for x in (*t, *v)):
                raise ConfigError(f"{times} and {values} must hold finite numbers within +-{MAX_MAGNITUDE:g}")
        team = {name: _numbers(data, name) for name in ("robot_path_lengths_m", "robot_coverage", "failed_at_s")}
        causes = data.get("aborts_by_cause", {})
        if not isinstance(causes, dict) or not all(type(n) is int for n in causes.values()):
            raise ConfigError(f"aborts_by_cause must map causes to whole numbers, got {short_repr(causes)}")
        causes = {enum_member(AbortCause, cause, "a cause of aborts_by_cause"): n for cause, n in causes.items()}
        return cls(
            method=_text(data, "method"),
            world=_text(data, "world"),
            episode=_whole(data, "episode"),
            coverage_t=tuple(data["coverage_t"]),
            coverage=tuple(data["coverage"]),
            weight_t=tuple(data.get("weight_t", [])),
            weight=tuple(data.get("weight", [])),
            aborts_by_cause=causes,
            explorable_left_m2=_measure(data, "explorable_left_m2"),
            frontiers_with_path_left=_whole(data, "frontiers_with_path_left", optional=True),
            frontiers_with_path_to_space_left=_whole(data, "frontiers_with_path_to_space_left", optional=True),
            explorable_given_up_m2=_measure(data, "explorable_given_up_m2"),
            frontiers_with_path_on_map_left=_whole(data, "frontiers_with_path_on_map_left", optional=True),
            frontiers_unrevealable_left=_whole(data, "frontiers_unrevealable_left", optional=True),
            **team,
        )


def _text(data: Mapping[str, Any], name: str) -> str:
    value = data.get(name)
    if not isinstance(value, str):
        raise ConfigError(f"{name} must be text, got {short_repr(value)}")
    return value


def _whole(data: Mapping[str, Any], name: str, optional: bool = False) -> Any:
    value = data.get(name)
    if (value is None and optional) or type(value) is int:
        return value
    raise ConfigError(f"{name} must be a whole number, got {short_repr(value)}")


def _measure(data: Mapping[str, Any], name: str) -> float | None:
    """An optional diagnostic number (NaN allowed: an older trace's undefined value)."""
    value = data.get(name)
    if value is None or (isinstance(value, int | float) and not isinstance(value, bool)):
        return None if value is None else float(value) if math.isfinite(value) else math.nan
    raise ConfigError(f"{name} must be a number, got {short_repr(value)}")


def _numbers(data: Mapping[str, Any], name: str) -> Any:
    """A team's per-robot list (None when the trace has none; failure times may be null)."""
    items = data.get(name)
    if items is None:
        return None
    if not (isinstance(items, list) and all(is_number(x, none=name == "failed_at_s") for x in items)):
        raise ConfigError(f"{name} must be a list of finite numbers")
    return tuple(items)


@dataclass(frozen=True)
class EpisodeOutcome:
    """What running one episode of an experiment gives: its row and its trace."""

    row: EpisodeRow
    trace: EpisodeTrace


def _by_name(counts: Mapping[AbortCause, int]) -> dict[str, int]:
    """Counts by cause (the trace's one mapping), keyed by the causes' names: JSON's keys."""
    return {str(cause): n for cause, n in counts.items()}
