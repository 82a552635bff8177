"""Differential-drive robot: pose, limits (TurtleBot3 Burger defaults) and motion primitives."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from frontier_rl.errors import ConfigError, short_repr


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


#: Largest heading (rad, either sign) a pose from user input may have: near it floats are 1.2e-10
#: rad apart, while a heading of 1e17 rad cannot name a direction at all (floats there are 16 rad
#: apart) and leaves the robot unable to turn.
MAX_HEADING_RAD = 1e6


def checked_pose(pose: Pose, what: str = "pose") -> Pose:
    """``pose`` (m, m, rad) checked as user input, its heading wrapped into [-pi, pi).

    A heading already in [-pi, pi) is kept bit for bit.

    Raises:
        ConfigError: a non-finite coordinate, or a heading beyond +-:data:`MAX_HEADING_RAD`;
            the message starts with ``what``.
    """
    try:
        x, y, theta = (float(v) for v in pose)
    except (TypeError, ValueError):
        raise ConfigError(f"{what} must be a Pose (x, y, theta) in m, m and rad, got {short_repr(pose)}") from None
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ConfigError(f"{what} ({x}, {y}) must have finite coordinates in metres")
    if not (math.isfinite(theta) and abs(theta) <= MAX_HEADING_RAD):
        raise ConfigError(f"{what} heading must be a finite angle within +-{MAX_HEADING_RAD:g} rad, got {theta!r}")
    return Pose(x, y, theta if -math.pi <= theta < math.pi else wrap_angle(theta))


def parse_pose(text: str) -> Pose:
    """A pose from "x,y" or "x,y,theta" (m, m, rad): finite, the heading within +-1e6 rad and
    wrapped into [-pi, pi) (:func:`~frontier_rl.core.world.robot.checked_pose`).

    Raises:
        ConfigError: anything else, quoting ``text`` (cut to 80 characters).
    """
    usage = f"start pose must be 'x,y' or 'x,y,theta' in metres/radians, got {short_repr(text)}"
    parts = text.split(",")
    if len(parts) not in (2, 3):
        raise ConfigError(usage)
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise ConfigError(usage) from None
    if not all(math.isfinite(v) for v in values):
        raise ConfigError(usage)
    return checked_pose(Pose(*values), f"start pose {short_repr(text)}")
