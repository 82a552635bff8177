"""The thesis's commander/explorer rendezvous cycle.

The commander (robot 0, or the lowest-numbered one still working) picks the meeting point: the
frontier at the top of its own ranking, which it then drives to. Every robot explores on its own
for ``explore_period`` seconds, then drives to the meeting point; once all working robots are
within ``meeting_radius`` of it or in contact with one already there (or the meeting is
``meeting_timeout`` late), the robots there
merge their maps and the commander picks the next meeting point. A robot whose way to the point
ends short of it (its leg aborted, or the point lies beyond what its map lets it plan to) waits
where it stands and merges only if it is within communication range of the group at the point.
Between meetings, robots share only when they happen to come within communication range. A robot
left alone (a team of one, or the others failed) explores as a single robot does.
"""

from __future__ import annotations

import math
from enum import Enum
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from frontier_rl.swarm.team import TeamRobot, TeamSimulator


class Phase(Enum):
    """Where a robot is in the rendezvous cycle (always EXPLORE for the other strategies)."""

    EXPLORE = "explore"
    TO_MEETING = "to_meeting"
    WAITING = "waiting"


class RendezvousCycle:
    """The meeting point and schedule of a team, and the phase changes of its robots."""

    def __init__(self, team: TeamSimulator) -> None:
        self.team = team
        self.point: tuple[float, float] | None = None  # the next meeting point (m), once picked
        self.due = math.inf  # when the robots head for it (s)
        self.needs_point = True  # the commander picks the first one at the start
        self.meetings: list[tuple[float, tuple[float, float], tuple[int, ...]]] = []  # (time, point, robots)

    @property
    def commander(self) -> TeamRobot | None:
        """The robot that picks the meeting points: the lowest-numbered working one."""
        alive = self.team.alive
        return alive[0] if alive else None

    def commander_to_decide(self) -> TeamRobot | None:
        """The commander, when it must pick the next meeting point now (before anyone else moves)."""
        commander = self.commander
        if self._end_if_alone() or not self.needs_point or commander is None or commander.leg is not None:
            return None
        if len(commander.sim.frontiers()) == 0:  # nothing left on its map: meet where it stands
            self._set_point(commander.xy, commander.sim.sim_time)
            return None
        return commander

    def decided(self, robot: TeamRobot) -> None:
        """``robot`` has just started a leg: the commander's first choice is the meeting point."""
        if self.needs_point and robot is self.commander:
            target = robot.sim.target
            self._set_point(target if target is not None else robot.xy, robot.sim.sim_time)

    def _set_point(self, xy: tuple[float, float], now: float) -> None:
        self.point = (float(xy[0]), float(xy[1]))
        self.due = now + self.team.team.explore_period
        self.needs_point = False

    def before_step(self, robot: TeamRobot) -> None:
        """Move ``robot`` on in the cycle before its next step (and hold the meeting when due)."""
        if self._end_if_alone():
            if robot.phase is not Phase.EXPLORE:  # on its way to a meeting, or waiting at one
                robot.drop_leg()
                robot.phase = Phase.EXPLORE
            return
        point = self.point
        if point is None:
            return
        config = self.team.team
        sim = robot.sim
        if robot.phase is Phase.EXPLORE and sim.sim_time >= self.due:
            robot.drop_leg()
            robot.phase = Phase.TO_MEETING
            robot.leg = sim.go_to_steps(*point)
        if robot.phase is Phase.TO_MEETING and (
            math.dist(robot.xy, point) <= config.meeting_radius or robot.leg is None or self._joined(robot)
        ):  # there, or as close as its map lets it get, or at the group round the point
            robot.drop_leg()
            robot.phase = Phase.WAITING
        if robot.phase is Phase.WAITING:
            alive = self.team.alive
            late = sim.sim_time >= self.due + config.meeting_timeout
            if late or all(r.phase is Phase.WAITING for r in alive):
                self._meet(self._gathered(self.team.team.range_m))
            elif robot.leg is None:
                robot.leg = sim.wait_steps()

    def _end_if_alone(self) -> bool:
        """End the cycle for good when at most one robot works (no one to meet: no meeting point,
        none to pick); whether it has ended."""
        if len(self.team.alive) > 1:
            return False
        self.point, self.due, self.needs_point = None, math.inf, False
        return True

    def _joined(self, robot: TeamRobot) -> bool:
        """Whether ``robot`` is in contact with a robot of the group waiting at the meeting: robots
        that gather round the point stand in each other's way, so one that reaches the group has
        arrived."""
        contact = robot.sim.nearby_robots.contact_distance
        return any(math.dist(robot.xy, other.xy) <= contact for other in self._gathered(0.0) if other is not robot)

    def _gathered(self, reach: float) -> list[TeamRobot]:
        """The waiting robots at the meeting, in index order: those within ``meeting_radius`` of the
        point, and by a chain of links those within ``reach`` (m) or in contact of one of them."""
        assert self.point is not None
        point = self.point
        waiting = [r for r in self.team.alive if r.phase is Phase.WAITING]
        if not waiting:
            return []
        link = max(reach, waiting[0].sim.nearby_robots.contact_distance)
        group = [r for r in waiting if math.dist(r.xy, point) <= self.team.team.meeting_radius]
        for member in group:  # grows while it is walked: a breadth-first closure
            group += [r for r in waiting if r not in group and math.dist(r.xy, member.xy) <= link]
        return sorted(group, key=lambda r: r.index)

    def _meet(self, present: list[TeamRobot]) -> None:
        """The robots ``present`` (none when a late meeting finds nobody at the point) merge their
        maps; everyone goes back to exploring."""
        if present:
            present[0].sim.mapper.merge_both_ways([other.sim.mapper for other in present[1:]])
        for robot in self.team.alive:
            robot.drop_leg()
            robot.sim.refresh()
            robot.phase = Phase.EXPLORE
        assert self.point is not None
        self.meetings.append((self.team.sim_time, self.point, tuple(r.index for r in present)))
        self.point = None
        self.due = math.inf
        self.needs_point = True
