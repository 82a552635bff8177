"""Differential-drive robot: pose, limits (TurtleBot3 Burger defaults) and motion primitives."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from frontier_rl.errors import ConfigError


class Pose(NamedTuple):
    """A planar pose: position (m) and heading (rad, counter-clockwise from +x)."""

    x: float
    y: float
    theta: float = 0.0


@dataclass(frozen=True)
class RobotConfig:
    """Physical limits of a differential-drive robot (TurtleBot3 Burger defaults).

    Attributes:
        radius: footprint radius (m).
        max_linear_speed: v_max (m/s).
        max_angular_speed: omega_max (rad/s).
        turn_in_place_angle: heading error (rad) above which the robot stops and turns in place.
    """

    radius: float = 0.105
    max_linear_speed: float = 0.22
    max_angular_speed: float = 2.84
    turn_in_place_angle: float = math.radians(30.0)

    def __post_init__(self) -> None:
        for name in ("radius", "max_linear_speed", "max_angular_speed", "turn_in_place_angle"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"RobotConfig.{name} must be positive, got {value!r}")


def wrap_angle(angle: float) -> float:
    """Angle wrapped to [-pi, pi) (rad)."""
    return (angle + math.pi) % (2.0 * math.pi) - math.pi
