"""``frontier-rl ros2 sim``: the simulator as one or more ROS 2 robots in one world.

Each robot publishes what a robot with slam_toolbox publishes (the map it builds on ``map``,
transient local; its pose on ``pose`` and ``odom``; a ``scan``), the share of the world's explorable
space it has mapped on ``coverage``, and serves Nav2's ``navigate_to_pose`` and ``follow_path``
actions, driving with the engine's navigation; a team's robots do so in their namespaces and see
each other as obstacles. The simulated clock is published on ``/clock`` (for nodes with
``use_sim_time``). It runs while a robot drives for a goal, at ``rate`` times the wall clock (as
fast as it can with no rate), every robot on it (one without a goal stands still); with no goal
under way it stops, so that a decision costs no simulated time, as in an in-process episode.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence

from rclpy.clock import Clock as TimerClock
from rclpy.clock_type import ClockType
from rclpy.node import Node
from rosgraph_msgs.msg import Clock

from frontier_rl.robot.sim_robot import SimulatedRobot
from frontier_rl.ros2.sim_port import RobotPort, stamp_of

_STEP_PERIOD_S = 0.005
"""How often (wall s) the node looks whether the robots may drive on."""
_IDLE_PERIOD_S = 0.1
"""Robots without a goal publish their pose and scan this often (wall s)."""


class SimNode(Node):
    """Simulated robots as a ROS 2 node.

    Args:
        robots: each robot's namespace ("" for none) and the robot; a team's share one world.
        rate: simulated seconds per wall second; None for as fast as the node can step.
    """

    def __init__(self, robots: Sequence[tuple[str, SimulatedRobot]], rate: float | None = 1.0) -> None:
        super().__init__("frontier_rl_sim")
        if not robots:
            raise ValueError("a simulator needs at least one robot")
        self.rate = rate
        self.ports = [RobotPort(self, namespace, robot) for namespace, robot in robots]
        self._clock_pub = self.create_publisher(Clock, "/clock", 10)
        self._anchor = (time.monotonic(), self.sim_time)  # wall and sim time the drive is paced from
        self._idle_sent_at = -math.inf
        self._publish(with_map=True)
        # a steady timer: the node's own clock, with use_sim_time, would wait for the /clock it publishes
        self._timer = self.create_timer(_STEP_PERIOD_S, self._drive, clock=TimerClock(clock_type=ClockType.STEADY_TIME))

    @property
    def sim_time(self) -> float:
        """The team's clock (s): the robot furthest behind."""
        return min(port.robot.sim_time for port in self.ports)

    def _drive(self) -> None:
        """Step the robots as far as the pace allows, the one furthest behind first, publishing as
        they go."""
        for port in self.ports:
            port.check_cancel()
        if not any(port.busy for port in self.ports):
            self._anchor = (time.monotonic(), self.sim_time)
            if time.monotonic() - self._idle_sent_at >= _IDLE_PERIOD_S:
                self._publish(with_map=False)  # for late subscribers: the map is transient local already
                self._idle_sent_at = time.monotonic()
            return
        wall0, sim0 = self._anchor
        target = math.inf if self.rate is None else sim0 + self.rate * (time.monotonic() - wall0)
        stepped: set[int] = set()
        while (index := self._next_to_step()) is not None:
            port = self.ports[index]
            if port.robot.sim_time >= target or (self.rate is None and index in stepped):
                break  # as fast as it can: one step per robot per tick, the executor serves the rest between
            port.robot.see_teammates([other.robot for other in self.ports if other is not port])
            port.step(until=min(other.robot.sim_time for other in self.ports if other.busy))
            stepped.add(index)
        if stepped:
            self._publish(with_map=False)

    def _next_to_step(self) -> int | None:
        """The robot to step next: one without a goal that has fallen behind the driving robots
        (it stands still until their time), else the driving robot furthest behind; None when no
        robot drives."""
        busy = [i for i, port in enumerate(self.ports) if port.busy]
        if not busy:
            return None
        driving = min(self.ports[i].robot.sim_time for i in busy)
        behind = [
            i
            for i, port in enumerate(self.ports)
            if not port.busy and port.robot.sim_time < driving and not port.robot.sim.truncated
        ]
        return min(behind or busy, key=lambda i: self.ports[i].robot.sim_time)

    def _publish(self, with_map: bool) -> None:
        self._clock_pub.publish(Clock(clock=stamp_of(self.sim_time)))
        for port in self.ports:
            port.publish_state(with_map)
