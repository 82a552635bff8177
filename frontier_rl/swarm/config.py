"""Team settings: size, coordination strategy, communication range and failures."""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass
from enum import StrEnum

from frontier_rl.errors import ConfigError
from frontier_rl.policies.spec import PolicySpec

MAX_ROBOTS = 8
"""The largest team (robots), in a simulated episode and in ``ros2 sim``."""


class Strategy(StrEnum):
    """How the robots of a team share the work.

    * ``uncoordinated``: each robot ranks the frontiers of its own (merged) map on its own.
    * ``coordinated``: Burgard et al. (2000): a frontier a teammate in contact is heading for drops
      in utility for the others (those near it less so the farther they are).
    * ``rendezvous``: the thesis's commander/explorer cycle: the commander (robot 0, or the lowest
      surviving) picks a meeting frontier from its ranking, all explore alone for
      ``explore_period``, then meet there, merge maps, and the cycle repeats.
    """

    UNCOORDINATED = "uncoordinated"
    COORDINATED = "coordinated"
    RENDEZVOUS = "rendezvous"


@dataclass(frozen=True)
class Failure:
    """A robot that stops for good at a sim time: ``robot`` None is drawn at random (seeded) among
    the team, ``time_s`` None uniformly in [0, ``TeamConfig.random_failure_horizon``]."""

    robot: int | None
    time_s: float | None

    def __post_init__(self) -> None:
        if self.robot is not None and self.robot < 0:
            raise ConfigError(f"failure robot id must be >= 0, got {self.robot!r}")
        if self.time_s is not None and not (math.isfinite(self.time_s) and self.time_s >= 0):
            raise ConfigError(f"failure time must be a non-negative number of seconds, got {self.time_s!r}")

    @classmethod
    def parse(cls, text: str) -> Failure:
        """``ROBOT@SECONDS``, where either may be ``random``; ``random`` alone is ``random@random``."""
        spec = text.strip().lower()
        robot_text, _, time_text = spec.partition("@")
        if spec == "random":
            time_text = "random"
        if not time_text:
            raise ConfigError(f"failure {text!r} must read ROBOT@SECONDS (e.g. 1@200, random@200, random)")
        try:
            robot = None if robot_text == "random" else int(robot_text)
            time_s = None if time_text == "random" else float(time_text)
        except ValueError:
            raise ConfigError(f"failure {text!r} must read ROBOT@SECONDS (e.g. 1@200, random@200, random)") from None
        return cls(robot, time_s)

    def __str__(self) -> str:
        robot = "random" if self.robot is None else str(self.robot)
        time_s = "random" if self.time_s is None else f"{self.time_s:g}"
        return f"{robot}@{time_s}"


@dataclass(frozen=True)
class TeamConfig:
    """A team of robots exploring one world together.

    Attributes:
        robots: team size, 1 to 8.
        strategy: how they share the work.
        comm_range: robots this close (m) merge maps and share their goals; None: unlimited for
            uncoordinated and coordinated, ``meeting_radius`` for rendezvous (which then shares
            only at meetings and chance encounters).
        failures: robots that stop for good mid-run; what they had not shared is lost.
        explore_period: rendezvous: how long (s) the robots explore alone between meetings.
        meeting_radius: rendezvous: a robot this close (m) to the meeting point has arrived.
        meeting_timeout: rendezvous: a meeting goes ahead without robots that have not arrived
            this long (s) after it was due.
        claim_radius: coordination: a frontier whose centre is this close (m) to a teammate's goal
            is that teammate's; a robot takes it only when no other is left.
        coordination_range: coordination: a teammate's goal lowers the utility of frontiers up to
            this far (m) from it, linearly (Burgard et al.'s P(d) = 1 - d / range).
        start_spacing: distance (m) between neighbouring robots' start positions; None: 0.5 m, or
            a robot's diameter and 0.1 m more where that is larger (:meth:`spacing_for`).
        random_failure_horizon: random failure times are drawn in [0, this] (s).
    """

    robots: int = 1
    strategy: Strategy = Strategy.UNCOORDINATED
    comm_range: float | None = None
    failures: tuple[Failure, ...] = ()
    explore_period: float = 120.0
    meeting_radius: float = 2.0
    meeting_timeout: float = 120.0
    claim_radius: float = 1.0
    coordination_range: float = 3.0
    start_spacing: float | None = None
    random_failure_horizon: float = 300.0

    def __post_init__(self) -> None:
        if not 1 <= self.robots <= MAX_ROBOTS:
            raise ConfigError(f"robots must be 1 to {MAX_ROBOTS}, got {self.robots!r}")
        if not isinstance(self.strategy, Strategy):
            object.__setattr__(self, "strategy", parse_strategy(str(self.strategy)))
        if self.comm_range is not None and not self.comm_range >= 0:
            raise ConfigError(f"comm_range must be >= 0 m, got {self.comm_range!r}")
        for name in (
            "explore_period",
            "meeting_radius",
            "meeting_timeout",
            "claim_radius",
            "coordination_range",
            "start_spacing",
            "random_failure_horizon",
        ):
            value = getattr(self, name)
            if value is not None and not (math.isfinite(value) and value > 0):
                raise ConfigError(f"TeamConfig.{name} must be a positive number, got {value!r}")
        for failure in self.failures:
            if failure.robot is not None and failure.robot >= self.robots:
                raise ConfigError(
                    f"failure {failure} names robot {failure.robot}, but the team has robots 0..{self.robots - 1}"
                )
        named = [f.robot for f in self.failures if f.robot is not None]
        if len(named) != len(set(named)):
            raise ConfigError(f"a robot can fail only once, got failures {', '.join(map(str, self.failures))}")
        if len(self.failures) > self.robots:
            raise ConfigError(f"{len(self.failures)} failures for a team of {self.robots}")

    def spacing_for(self, radius: float) -> float:
        """The start spacing (m) of robots of ``radius`` (m): ``start_spacing`` when set."""
        if self.start_spacing is not None:
            return self.start_spacing
        return max(0.5, 2.0 * radius + 0.1)  # a fixed 0.5 m left no team of robots 0.5 m across or more

    @property
    def range_m(self) -> float:
        """The communication range in effect (m; inf when unlimited)."""
        if self.comm_range is not None:
            return self.comm_range
        return self.meeting_radius if self.strategy is Strategy.RENDEZVOUS else math.inf


def parse_strategy(text: str) -> Strategy:
    """The strategy named ``text``; a one-line error listing the names otherwise."""
    try:
        return Strategy(text.strip().lower())
    except ValueError:
        names = ", ".join(s.value for s in Strategy)
        raise ConfigError(f"unknown strategy {text!r}: choose one of {names}") from None


_TEAM_SUFFIX = re.compile(r"^(?P<policy>.+)@(?P<robots>\d+)(?::(?P<strategy>[a-zA-Z]+))?$")


@dataclass(frozen=True)
class TeamMethod:
    """A method of an experiment: a policy, and the team that runs it (None: one robot alone).

    Written ``POLICY`` for one robot, ``POLICY@N`` for an uncoordinated team of N and
    ``POLICY@N:STRATEGY`` otherwise, e.g. ``fixed:0.75@4:coordinated``; parsed once
    (:meth:`parse`), and printed back as the same text (``str``).
    """

    policy: PolicySpec
    robots: int | None = None
    strategy: Strategy = Strategy.UNCOORDINATED

    @classmethod
    def parse(cls, method: str) -> TeamMethod:
        """The policy and team of ``method``; a bad policy, team size or strategy is a ConfigError
        (an unknown policy name an UnknownNameError)."""
        match = _TEAM_SUFFIX.match(method.strip())
        if match is None:
            return cls(PolicySpec.parse(method))
        robots = int(match["robots"])
        if _TEAM_SUFFIX.match(match["policy"]):  # else "unknown policy 'nearest@2'" for nearest@2@3
            raise ConfigError(f"method {method!r} names two team sizes; write POLICY@N[:STRATEGY]")
        if not 1 <= robots <= MAX_ROBOTS:
            raise ConfigError(f"method {method!r}: a team has 1 to {MAX_ROBOTS} robots, got {robots}")
        strategy = parse_strategy(match["strategy"]) if match["strategy"] else Strategy.UNCOORDINATED
        return cls(PolicySpec.parse(match["policy"]), robots, strategy)

    def __str__(self) -> str:
        return f"{self.policy}{self._team_suffix()}"

    @property
    def canonical(self) -> str:
        """The method written one way (its policy's :attr:`~frontier_rl.policies.spec.PolicySpec.canonical`):
        two methods with the same canonical text are one method written two ways."""
        return f"{self.policy.canonical}{self._team_suffix()}"

    def _team_suffix(self) -> str:
        """``@N`` or ``@N:STRATEGY`` for a team; "" for one robot."""
        if self.robots is None:
            return ""
        return f"@{self.robots}" + ("" if self.strategy is Strategy.UNCOORDINATED else f":{self.strategy.value}")

    def label(self, policy_label: str) -> str:
        """A display name from the policy's: ``fixed:0.75 ×4 coordinated``."""
        return policy_label if self.robots is None else f"{policy_label} ×{self.robots} {self.strategy.value}"


def one_robot_methods(methods: Iterable[str]) -> dict[str, str]:
    """The one-robot methods among ``methods``, by their policy's canonical text: the method a team
    of that policy is compared with (``fixed:0.5`` for ``fixed:0.50@2``)."""
    return {team.policy.canonical: method for method in methods if (team := TeamMethod.parse(method)).robots is None}
