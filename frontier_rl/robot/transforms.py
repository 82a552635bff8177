"""A robot's frames in the plane, as ROS's ``/tf`` and ``/tf_static`` describe them: each frame's
latest pose in its parent's frame, and the pose of one frame in an ancestor's (the robot's base in
the map: ``map`` → ``odom`` → ``base_footprint`` → ``base_link``).

ROS-free: the ROS 2 explorer feeds it the transforms it hears (``tf2_ros`` has no wheel). Only the
latest transform of each frame is kept, with no interpolation in time: a decision a second uses a
pose at most a few scans old, as move_base's costmaps do with their transform tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

MAX_CHAIN = 64
"""Most frames between a frame and the ancestor it is looked up in: a longer chain is a loop."""


@dataclass(frozen=True)
class PlanarTransform:
    """A frame's pose in its parent's frame: position (m) and heading (rad), in the plane."""

    x: float
    y: float
    yaw: float

    def then(self, child: PlanarTransform) -> PlanarTransform:
        """The pose in this transform's parent frame of ``child``, a pose in this transform's frame."""
        cos, sin = math.cos(self.yaw), math.sin(self.yaw)
        yaw = math.atan2(math.sin(self.yaw + child.yaw), math.cos(self.yaw + child.yaw))
        return PlanarTransform(self.x + cos * child.x - sin * child.y, self.y + sin * child.x + cos * child.y, yaw)

    def inverse(self) -> PlanarTransform:
        """The parent's pose in this frame."""
        cos, sin = math.cos(self.yaw), math.sin(self.yaw)
        return PlanarTransform(-cos * self.x - sin * self.y, sin * self.x - cos * self.y, -self.yaw)


IDENTITY = PlanarTransform(0.0, 0.0, 0.0)


class TransformTree:
    """The latest transform of each frame to its parent. Frame names are compared without a
    leading ``/`` (ROS 1's ``/map`` is ROS 2's ``map``)."""

    def __init__(self) -> None:
        self._parents: dict[str, tuple[str, PlanarTransform]] = {}

    def set(self, parent: str, child: str, transform: PlanarTransform) -> None:
        """``child``'s pose in ``parent`` is ``transform`` from now on (a frame has one parent: a
        new one replaces the old, as in tf).

        Raises:
            ValueError: a frame without a name, the same frame on both sides, or a transform that
                is not finite (each named).
        """
        parent, child = _name(parent), _name(child)
        if not parent or not child:
            raise ValueError(f"a transform from {parent!r} to {child!r} names no frame")
        if parent == child:
            raise ValueError(f"a transform from {parent!r} to itself")
        if not all(math.isfinite(v) for v in (transform.x, transform.y, transform.yaw)):
            raise ValueError(f"the transform from {parent!r} to {child!r} is not finite: {transform}")
        self._parents[child] = (parent, transform)

    def lookup(self, target: str, source: str) -> PlanarTransform:
        """The pose of frame ``source`` in frame ``target``, an ancestor of it.

        Raises:
            LookupError: no chain of transforms leads from ``source`` up to ``target`` (the
                message says where the chain ends), or the chain loops.
        """
        target, frame = _name(target), _name(source)
        pose = IDENTITY
        for _ in range(MAX_CHAIN):
            if frame == target:
                return pose
            link = self._parents.get(frame)
            if link is None:
                ends = f"{frame!r} has no parent" if frame != _name(source) else f"no transform of {frame!r} yet"
                raise LookupError(f"no transform from {target!r} to {_name(source)!r}: {ends}")
            frame, transform = link
            pose = transform.then(pose)
        raise LookupError(f"the transforms above {_name(source)!r} loop (more than {MAX_CHAIN} frames)")


def _name(frame: str) -> str:
    return frame.strip().lstrip("/")
