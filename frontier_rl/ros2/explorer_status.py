"""The ROS 2 explorer's state (:class:`ExplorerState`) and what it publishes of it on
``explore/status`` (:class:`ExplorerStatus`), with the line it ends with."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass
from enum import StrEnum

from frontier_rl.core.sim.metrics import EndReason
from frontier_rl.robot.explorer_decision import Finished


class ExplorerState(StrEnum):
    """What the explorer is doing; its value is what ``explore/status`` says."""

    WAITING = "waiting"  # for a map, a pose or Nav2
    EXPLORING = "exploring"
    RETURNING = "returning"  # to where it started (return_to_init)
    PAUSED = "paused"  # on explore/resume false, until true
    FINISHED = "finished"
    INTERRUPTED = "interrupted"  # stopped before it finished (Ctrl-C, a shutdown)


@dataclass(frozen=True)
class ExplorerStatus:
    """The explorer's state, published as JSON on ``explore/status`` after every change.

    Attributes:
        state: what it is doing (:class:`ExplorerState`).
        reason: the end reason once finished (``explored``, ``unreachable``, ``time_cap``), else None.
        time_s: time since the first tick (s, on the node's clock: simulated with ``use_sim_time``).
        goals: goals sent; given_up: of them blacklisted (rejected, aborted, no progress, or
            reached without seeing their frontier).
        frontiers_left: frontiers larger than a speck left at the end; unknown_m2: the unknown
            area beside them (m²); with_a_path: of them, those the map still has a path to;
            unrevealable: those reached twice without their frontier going away, or with no more
                than a speck of their unknown in sight of anywhere the robot can reach.
        coverage: the simulator's share of the explorable space mapped, when a simulator
            publishes it (``coverage``); None otherwise.
        detail: a sentence on what happened last.
    """

    state: ExplorerState
    reason: EndReason | None
    time_s: float
    goals: int
    given_up: int
    frontiers_left: int
    unknown_m2: float
    with_a_path: int
    unrevealable: int
    coverage: float | None
    detail: str

    @classmethod
    def of(
        cls,
        state: ExplorerState,
        detail: str,
        time_s: float,
        goals: int,
        given_up: int,
        finished: Finished | None,
        coverage: float | None,
    ) -> ExplorerStatus:
        """The status of an explorer in ``state`` after ``time_s`` (s) and ``goals`` (``given_up``
        of them given up), ``finished`` once it ended (None before), ``coverage`` the simulator's."""
        return cls(
            state=state,
            reason=None if finished is None else finished.reason,
            time_s=round(time_s, 3),
            goals=goals,
            given_up=given_up,
            frontiers_left=0 if finished is None else len(finished.left),
            unknown_m2=0.0 if finished is None else round(finished.unknown_beside_m2, 3),
            with_a_path=0 if finished is None else finished.with_a_path,
            unrevealable=0 if finished is None else finished.unrevealable,
            coverage=None if coverage is None else round(coverage, 5),
            detail=detail,
        )

    @classmethod
    def not_started(cls) -> ExplorerStatus:
        """The status of an explorer interrupted before it ran (a model loading, ROS starting)."""
        return cls(ExplorerState.INTERRUPTED, None, 0.0, 0, 0, 0, 0.0, 0, 0, None, "interrupted before it started")

    def to_json(self) -> str:
        """The status as one line of JSON (None as null)."""
        return json.dumps(asdict(self))

    def summary(self) -> str:
        """One line: how it ended, the time, the goals and what was left."""
        ended = self.state.value if self.reason is None else self.reason.value
        line = f"{ended} after {self.time_s:.1f} s, {self.goals} goals ({self.given_up} given up)"
        if self.coverage is not None:
            line += f", {100 * self.coverage:.1f} % of the explorable space (the simulator's)"
        if self.frontiers_left:
            line += (
                f"; {self.frontiers_left} frontiers left with {self.unknown_m2:.2f} m² unknown beside them"
                f" ({self.with_a_path} with a path on the map, {self.unrevealable} unrevealable)"
            )
        return line
