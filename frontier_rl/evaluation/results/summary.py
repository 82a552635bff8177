"""An experiment's ``summary.json`` as typed values: :class:`ExperimentSummary` and the summaries in it.

``frontier-rl evaluate`` writes the file (:mod:`frontier_rl.evaluation.statistics.analysis` lays it out);
:meth:`ExperimentSummary.load` reads it back, checking every field it reads, so that a script never
digs through nested dicts. Numbers the file leaves undefined (``null``: a p-value of two methods whose
times never differ, a ratio without the oracle) are None here; fields an older file lacks are None too.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any, TypeVar

from frontier_rl.checked_values import enum_member
from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.errors import ConfigError, short_path, short_repr
from frontier_rl.evaluation.statistics.paired import PairedStats
from frontier_rl.swarm.config import Strategy

SUMMARY_FILE = "summary.json"
"""The summary's file name in a results folder."""

_T = TypeVar("_T")


@dataclass(frozen=True)
class PairedSummary:
    """A method against the baseline on the episodes both ran (times in s; a positive saving means
    the method is faster).

    Attributes:
        n: paired episodes.
        mean_time_s: the method's mean exploration time (s).
        var_time_s: its sample variance (s²).
        mean_diff_s: mean of baseline − method (s).
        ci95_s: 95 % confidence interval of ``mean_diff_s`` (s), (low, high).
        p_one_tailed: paired t-test that the method is faster.
        p_two_tailed: paired t-test of any difference.
        p_wilcoxon: Wilcoxon signed-rank test, one-tailed.
        reduction_pct: 100 × mean saving / the baseline's mean time (%).
    """

    n: int
    mean_time_s: float | None
    var_time_s: float | None = None
    mean_diff_s: float | None = None
    ci95_s: tuple[float | None, float | None] = (None, None)
    p_one_tailed: float | None = None
    p_two_tailed: float | None = None
    p_wilcoxon: float | None = None
    reduction_pct: float | None = None

    @staticmethod
    def values_of(stats: PairedStats) -> dict[str, Any]:
        """The fields of :class:`PairedSummary` from ``stats``, undefined values (NaN) as None: the
        keyword arguments of a summary (of this class or a subclass) that starts from them."""
        low, high = stats.ci95_s
        return {
            "n": stats.n,
            "mean_time_s": defined(stats.mean_time_s),
            "var_time_s": defined(stats.var_time_s),
            "mean_diff_s": defined(stats.mean_diff_s),
            "ci95_s": (defined(low), defined(high)),
            "p_one_tailed": defined(stats.p_one_tailed),
            "p_two_tailed": defined(stats.p_two_tailed),
            "p_wilcoxon": defined(stats.p_wilcoxon),
            "reduction_pct": defined(stats.reduction_pct),
        }

    def to_json(self) -> dict[str, object]:
        """The entry ``summary.json`` holds: every field, in order (pairs as lists)."""
        return {f.name: _json_value(getattr(self, f.name)) for f in fields(self)}


@dataclass(frozen=True)
class MethodSummary(PairedSummary):
    """A method's results over all its episodes (or one world's): the paired comparison, then
    how the episodes went.

    Attributes:
        std_time_s: standard deviation of the exploration time (s).
        p_holm: ``p_one_tailed`` adjusted by Holm's method over the methods tested (None for the
            baseline and the oracle).
        median_time_s: median exploration time (s).
        oracle_ratio: mean time over the full-knowledge oracle's (None without the oracle).
        episodes_done: episodes that ended with the map explored.
        end_reasons: episodes per end reason (``explored``, ``unreachable``, ``time_cap``, ...).
        mean_coverage, min_coverage: mean and lowest share of the explorable space mapped.
        mean_free_coverage: mean share of all free cells mapped.
        mean_unknown_left_m2: mean unseen free area beside the frontiers left (m²).
        mean_path_length_m: mean distance driven (m; a team's, summed over its robots).
        mean_t90_s, mean_t99_s: mean time (s) to 90 % and 99 % coverage, over the episodes that reached it.
        mean_aborts: mean goals given up per episode.
        mean_weight: mean ranking weight chosen (None for methods without a weight).
        mean_wall_time_s: mean wall-clock time of an episode (s).
        robots: team size (1 for a single robot).
        mean_overlap: a team's mean share of cells seen by more than one robot.
    """

    std_time_s: float | None = None
    p_holm: float | None = None
    median_time_s: float | None = None
    oracle_ratio: float | None = None
    episodes_done: int | None = None
    end_reasons: Mapping[EndReason, int] | None = None
    mean_coverage: float | None = None
    min_coverage: float | None = None
    mean_free_coverage: float | None = None
    mean_unknown_left_m2: float | None = None
    mean_path_length_m: float | None = None
    mean_t90_s: float | None = None
    mean_t99_s: float | None = None
    mean_aborts: float | None = None
    mean_weight: float | None = None
    mean_wall_time_s: float | None = None
    robots: int = 1
    mean_overlap: float | None = None


@dataclass(frozen=True)
class OutlierSummary(PairedSummary):
    """A method compared without the episodes (of it or of the baseline) above a time threshold.

    Attributes:
        excluded: pairs left out.
        baseline_mean_time_s: the baseline's mean time over the pairs kept (s).
    """

    excluded: int = 0
    baseline_mean_time_s: float | None = None


@dataclass(frozen=True)
class OutlierCut:
    """The comparison without the episodes above ``threshold_s`` (s)."""

    threshold_s: float
    methods: Mapping[str, OutlierSummary]


@dataclass(frozen=True)
class TeamPoint:
    """A policy's mean exploration time with a team of ``robots`` under ``strategy``.

    Attributes:
        policy: the policy every robot runs (a method without its team part).
        strategy: how the robots shared the work.
        robots: team size.
        method: the method that ran (``nearest@2:coordinated``; the policy alone for one robot).
        n: episodes.
        mean_time_s: mean exploration time (s).
        ci95_half_s: half-width of its 95 % confidence interval (s; None from one episode).
    """

    policy: str
    strategy: Strategy
    robots: int
    method: str
    n: int
    mean_time_s: float
    ci95_half_s: float | None


@dataclass(frozen=True)
class ExperimentSummary:
    """What a paired experiment found (its ``summary.json``).

    Attributes:
        baseline: the method every other is compared with.
        reference: the full-knowledge reference method (``oracle``) if it ran, else None.
        worlds: the worlds (generators, catalogue names, map files).
        episodes: episodes per world.
        seed: the first episode's seed.
        methods: every method's summary over all worlds, by method, in the experiment's order.
        outliers: the comparisons without the episodes above each outlier threshold.
        per_world: each world's method summaries (empty for a single world).
        teams: mean time against team size, per policy and strategy (empty without team methods).
    """

    baseline: str
    reference: str | None
    worlds: tuple[str, ...]
    episodes: int
    seed: int
    methods: Mapping[str, MethodSummary]
    outliers: tuple[OutlierCut, ...] = ()
    per_world: Mapping[str, Mapping[str, MethodSummary]] = field(default_factory=dict)
    teams: tuple[TeamPoint, ...] = ()

    def to_json(self) -> dict[str, object]:
        """The ``summary.json`` object of this summary (:meth:`from_json` reads it back); ``per_world``
        and ``teams`` only when they hold something, teams nested by policy, strategy and team size."""
        data: dict[str, object] = {
            "baseline": self.baseline,
            "reference": self.reference,
            "worlds": list(self.worlds),
            "episodes": self.episodes,
            "seed": self.seed,
            "methods": _methods_json(self.methods),
            "outliers": {f"{cut.threshold_s:g}": {"methods": _methods_json(cut.methods)} for cut in self.outliers},
        }
        if self.per_world:
            data["per_world"] = {world: {"methods": _methods_json(m)} for world, m in self.per_world.items()}
        if self.teams:
            teams: dict[str, dict[str, dict[str, object]]] = {}
            for point in self.teams:
                line = teams.setdefault(point.policy, {}).setdefault(point.strategy, {})
                line[str(point.robots)] = {
                    "method": point.method,
                    "n": point.n,
                    "mean_time_s": point.mean_time_s,
                    "ci95_half_s": point.ci95_half_s,
                }
            data["teams"] = teams
        return data

    @property
    def tested(self) -> tuple[str, ...]:
        """The methods compared with the baseline: all but the baseline and the reference."""
        return tuple(m for m in self.methods if m not in (self.baseline, self.reference))

    @classmethod
    def load(cls, path: str | Path) -> ExperimentSummary:
        """The summary in ``path``: a ``summary.json`` file or the results folder that holds one.

        Raises:
            ConfigError: no such file, or one that is not an experiment's summary (the bad field named).
        """
        file = Path(path)
        if file.is_dir():
            file = file / SUMMARY_FILE
        try:
            text = file.read_text(encoding="utf-8")
        except FileNotFoundError:
            raise ConfigError(f"no experiment summary at {short_path(file)}") from None
        except (OSError, UnicodeDecodeError) as exc:
            raise ConfigError(f"experiment summary {short_path(file)} cannot be read: {exc}") from None
        try:
            data = json.loads(text)
        except json.JSONDecodeError as exc:
            raise ConfigError(f"experiment summary {short_path(file)} is not JSON: {exc}") from None
        try:
            return cls.from_json(data)
        except ConfigError as exc:
            raise ConfigError(f"experiment summary {short_path(file)}: {exc}") from None

    @classmethod
    def from_json(cls, data: object) -> ExperimentSummary:
        """The summary of a parsed ``summary.json`` object.

        Raises:
            ConfigError: a missing or mistyped field, named.
        """
        top = _object(data, "the summary")
        outliers = _object(top.get("outliers", {}), "outliers")
        return cls(
            baseline=_value(top, "baseline", str),
            reference=_optional(top, "reference", str),
            worlds=tuple(_strings(top, "worlds")),
            episodes=_value(top, "episodes", int),
            seed=_value(top, "seed", int),
            methods=_methods(top, "methods", MethodSummary),
            outliers=tuple(_cut(key, value) for key, value in outliers.items()),
            per_world={
                world: _methods(_object(entry, world), "methods", MethodSummary)
                for world, entry in _object(top.get("per_world", {}), "per_world").items()
            },
            teams=_teams(_object(top.get("teams", {}), "teams")),
        )


def _methods_json(methods: Mapping[str, PairedSummary]) -> dict[str, object]:
    return {name: summary.to_json() for name, summary in methods.items()}


def defined(value: float) -> float | None:
    """``value``, or None where it is undefined (NaN) or infinite: what a summary holds."""
    return value if math.isfinite(value) else None


def _json_value(value: object) -> object:
    """``value`` as JSON holds it: pairs as lists, mappings as objects, NaN and inf as null."""
    if isinstance(value, tuple):
        return [_json_value(v) for v in value]
    if isinstance(value, Mapping):
        return dict(value)
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _cut(key: str, value: object) -> OutlierCut:
    try:
        threshold = float(key)
    except ValueError:
        raise ConfigError(f"outlier threshold {short_repr(key)} is not a number of seconds") from None
    return OutlierCut(threshold, _methods(_object(value, f"outliers {key}"), "methods", OutlierSummary))


_S = TypeVar("_S", MethodSummary, OutlierSummary)


def _methods(parent: Mapping[str, Any], key: str, kind: type[_S]) -> dict[str, _S]:
    return {name: _summary(kind, _object(entry, name)) for name, entry in _object(parent.get(key), key).items()}


def _summary(kind: type[_S], entry: Mapping[str, Any]) -> _S:
    """A method's summary of type ``kind`` from its entry: every field the entry has, checked."""
    values: dict[str, Any] = {}
    for f in fields(kind):
        if f.name not in entry:
            continue
        if f.name == "ci95_s":
            pair = entry[f.name]
            if not (isinstance(pair, list) and len(pair) == 2):
                raise ConfigError(f"ci95_s must be a pair of numbers, got {short_repr(pair)}")
            values[f.name] = (_number(pair[0], f.name), _number(pair[1], f.name))
        elif f.name == "end_reasons":
            reasons = _object(entry[f.name], f.name)
            values[f.name] = {enum_member(EndReason, k, f.name): _value(reasons, k, int) for k in reasons}
        elif f.name in ("n", "episodes_done", "excluded", "robots"):
            values[f.name] = _value(entry, f.name, int)
        else:
            values[f.name] = _number(entry[f.name], f.name)
    missing = [name for name in ("n", "mean_time_s") if name not in values]
    if missing:
        raise ConfigError(f"a method entry lacks {', '.join(missing)}")
    return kind(**values)


def _teams(teams: Mapping[str, Any]) -> tuple[TeamPoint, ...]:
    return tuple(
        _team_point(policy, strategy, robots, _object(entry, f"teams {policy} {strategy} {robots}"))
        for policy, lines in teams.items()
        for strategy, line in _object(lines, f"teams {policy}").items()
        for robots, entry in _object(line, f"teams {policy} {strategy}").items()
    )


def _team_point(policy: str, strategy: str, robots: str, entry: Mapping[str, Any]) -> TeamPoint:
    mean = _number(entry.get("mean_time_s"), "mean_time_s")
    if mean is None or not robots.isdigit():
        raise ConfigError(f"team entry {policy} {strategy} {short_repr(robots)} is incomplete")
    method, n = _value(entry, "method", str), _value(entry, "n", int)
    kind = enum_member(Strategy, strategy, f"team entry {policy} strategy")
    return TeamPoint(policy, kind, int(robots), method, n, mean, _number(entry.get("ci95_half_s"), "ci95_half_s"))


def _object(value: object, what: str) -> Mapping[str, Any]:
    if not isinstance(value, dict):
        raise ConfigError(f"{what} must be a JSON object, got {short_repr(value)}")
    return value


def _value(entry: Mapping[str, Any], key: str, kind: type[_T]) -> _T:
    value = entry.get(key)
    if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
        raise ConfigError(f"{key} must be {'a whole number' if kind is int else 'text'}, got {short_repr(value)}")
    return value


def _optional(entry: Mapping[str, Any], key: str, kind: type[_T]) -> _T | None:
    return None if entry.get(key) is None else _value(entry, key, kind)


def _strings(entry: Mapping[str, Any], key: str) -> list[str]:
    value = entry.get(key)
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ConfigError(f"{key} must be a list of text, got {short_repr(value)}")
    return value


def _number(value: object, key: str) -> float | None:
    """A JSON number as a float (null and NaN as None)."""
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{key} must be a number, got {short_repr(value)}")
    return float(value) if math.isfinite(value) else None
