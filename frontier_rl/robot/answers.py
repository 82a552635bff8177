"""What the frontier node decides before and after ranking, without ROS: where a map lies, whether
a request can be answered (robot known, map there and fresh enough, pose finite and on the map),
the status line that goes with every answer and how its frontiers are drawn. Its settings are
checked in :mod:`frontier_rl.robot.node_settings`."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass
from enum import StrEnum
from typing import Any

import numpy as np
from numpy.typing import NDArray

from frontier_rl.errors import MapError
from frontier_rl.io.loaded_map import MAX_COORDINATE_M
from frontier_rl.robot.map_message import check_map_message, yaw_of
from frontier_rl.robot.node_settings import StaleMapAnswer


@dataclass(frozen=True)
class MapFrame:
    """A map's placement: its frame and the origin (m) and yaw (rad) of its cell (0, 0) corner."""

    frame_id: str
    x: float
    y: float
    yaw: float

    def to_grid(self, x: float, y: float) -> tuple[float, float]:
        """A point of the map frame in the grid's own frame (m from the corner, along its axes)."""
        dx, dy = x - self.x, y - self.y
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return c * dx + s * dy, -s * dx + c * dy

    def to_map(self, x: float, y: float) -> tuple[float, float]:
        """A point of the grid's frame in the map frame."""
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        return self.x + c * x - s * y, self.y + s * x + c * y


@dataclass(frozen=True)
class MapInfo:
    """The last good map of a robot, as the node keeps it beside the cells its worker holds.

    Attributes:
        frame: where the map lies.
        width, height: cells.
        resolution: m per cell.
        stamp_ns: the map message's stamp (ns, as the message carries it, so that an answer's
            header holds the very same stamp); the time it arrived when the stamp is zero.
        sequence: how many good maps of this robot came before it.
    """

    frame: MapFrame
    width: int
    height: int
    resolution: float
    stamp_ns: int
    sequence: int = 0

    @property
    def stamp_s(self) -> float:
        """The map's stamp (s)."""
        return self.stamp_ns / 1e9

    def contains(self, x: float, y: float) -> bool:
        """Whether the map-frame point (m) lies on the map."""
        gx, gy = self.frame.to_grid(x, y)
        return 0.0 <= gx < self.width * self.resolution and 0.0 <= gy < self.height * self.resolution

    def age_s(self, now_s: float) -> float:
        """Seconds since the map's stamp."""
        return max(0.0, now_s - self.stamp_s)


class Problem(StrEnum):
    """What is wrong with a request or its answer, of a kind: a robot's warnings are throttled per
    kind, however their texts differ (a pose off the map names the pose)."""

    UNKNOWN_ROBOT = "unknown robot"
    NO_MAP = "no map"
    NO_POSE = "no pose"
    POSE_NOT_FINITE = "pose not finite"
    POSE_OFF_MAP = "pose off the map"
    STALE_MAP = "stale map"
    BUSY = "requests queued"
    FAILED = "request failed"
    MAP_REJECTED = "map rejected"


@dataclass(frozen=True)
class Note:
    """What an answer says besides its frontiers: why it is empty, or what to know of it
    (``text``, "" if nothing), and the kind of problem (None if nothing)."""

    text: str = ""
    problem: Problem | None = None


@dataclass(frozen=True)
class Verdict:
    """Whether to rank (``rank``: a stale map served as configured is ranked all the same), and
    what to say of the request (``note``)."""

    rank: bool
    note: Note = Note()

    @property
    def reason(self) -> str:
        """What is wrong or notable ("" if nothing)."""
        return self.note.text


def check_request(
    robot: str,
    robots: list[str],
    info: MapInfo | None,
    pose: tuple[float, float, float] | None,
    now_s: float,
    max_map_age_s: float,
    stale: StaleMapAnswer,
) -> Verdict:
    """Whether ``robot``'s request can be ranked: a known robot with a map, a finite pose on the
    map, and a map no older than ``max_map_age_s`` (0: any age), or one served stale as configured."""
    if robot not in robots:
        known = ", ".join(map(repr, robots))
        return Verdict(False, Note(f"unknown robot {robot!r} (known: {known})", Problem.UNKNOWN_ROBOT))
    if info is None:
        return Verdict(False, Note(f"no usable map of {robot!r} yet", Problem.NO_MAP))
    if pose is None:
        return Verdict(False, Note(f"no pose of {robot!r} yet", Problem.NO_POSE))
    if not all(math.isfinite(v) for v in pose):
        text = f"pose of {robot!r} is not finite: {pose[0]!r}, {pose[1]!r}, yaw {pose[2]!r}"
        return Verdict(False, Note(text, Problem.POSE_NOT_FINITE))
    if not info.contains(pose[0], pose[1]):
        text = f"pose of {robot!r} ({pose[0]:.2f}, {pose[1]:.2f}) lies outside its map"
        return Verdict(False, Note(text, Problem.POSE_OFF_MAP))
    reason = stale_reason(robot, info, now_s, max_map_age_s)
    if not reason:
        return Verdict(True)
    return Verdict(stale is StaleMapAnswer.STALE, Note(reason, Problem.STALE_MAP))


def stale_reason(robot: str, info: MapInfo, now_s: float, max_map_age_s: float) -> str:
    """What to say of ``robot``'s map if it is older than ``max_map_age_s`` (0: any age), else ""."""
    age = info.age_s(now_s)
    if max_map_age_s > 0 and age > max_map_age_s:
        return f"map of {robot!r} is stale: {age:.1f} s old, more than ~max_map_age {max_map_age_s:g} s"
    return ""


@dataclass(frozen=True)
class Status:
    """The line published on ``/frontier_status`` with every answer (as JSON).

    Attributes:
        robot: the namespace asked for.
        request: the request's own id (the word after the namespace) or the node's count of requests.
        frontiers: how many frontiers the answer holds.
        reason: why the answer is empty, or what to know about it ("" when all is well).
        policy: the ranking policy (``fixed:0.75``, a model's file name).
        weight: the weight of eq. 3.1 used, or None (a frontier-choice model, or no ranking).
        map_stamp_s: the stamp of the map the answer was computed on (s), or None.
        map_age_s: that map's age when the request was taken (s), or None.
        latency_s: from the request's arrival to the answer (s).
    """

    robot: str
    request: str
    frontiers: int
    reason: str
    policy: str
    weight: float | None = None
    map_stamp_s: float | None = None
    map_age_s: float | None = None
    latency_s: float = 0.0

    def to_json(self) -> str:
        """One JSON object (NaN and infinities as null)."""
        values = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in asdict(self).items()}
        return json.dumps(values, sort_keys=True)


def parse_request(text: str, count: int) -> tuple[str, str]:
    """(namespace, request id) from a request's text: ``tb3_0`` or ``tb3_0 17``; for one robot without
    a namespace, ``17`` (no ROS name starts with a digit) or ``/ 17``. The id is the rest of the text
    after the namespace (``tb3_0 run 3 17``: ``run 3 17``), each run of spaces, tabs or line breaks
    one space; it defaults to the node's running ``count``."""
    words = text.split()
    if words and words[0][0].isdigit():
        words.insert(0, "")
    robot = words[0].strip("/") if words else ""
    return robot, (" ".join(words[1:]) if len(words) > 1 else str(count))


def marker_style(rank: int, count: int) -> tuple[float, float, float]:
    """How an answer's ``rank``-th of ``count`` frontiers is drawn in RViz: sphere size (m), green
    and red (the best large and green, the worst red)."""
    return 0.25 if rank == 0 else 0.15, 1.0 - rank / max(count, 1), rank / max(count, 1)


@dataclass(frozen=True)
class MapCells:
    """A map as the node accepted it: where it lies and when it was made, and its cells as the
    message carried them (row-major, -1 unknown, 0-100 occupancy)."""

    info: MapInfo
    data: NDArray[np.int8]


def map_cells(info: Any, frame_id: str, data: NDArray[np.int8], stamp_ns: int, sequence: int) -> MapCells:
    """A map message (ROS 1's or ROS 2's ``nav_msgs/OccupancyGrid``: its ``info``, header frame and
    data as int8 values) as the robot's ``sequence``-th good map, stamped ``stamp_ns`` (ns). A map of
    zero size, a resolution that is not a positive number, data that is not width × height long or
    an origin that is not finite or lies beyond :data:`MAX_COORDINATE_M` is a :class:`MapError`."""
    width, height, resolution = int(info.width), int(info.height), float(info.resolution)
    data = np.asarray(data, dtype=np.int8).reshape(-1)
    check_map_message(width, height, resolution, data.size)
    origin, q = info.origin.position, info.origin.orientation
    frame = MapFrame(frame_id, float(origin.x), float(origin.y), yaw_of(q))
    if not all(math.isfinite(v) for v in (frame.x, frame.y, frame.yaw)):
        raise MapError(f"map origin must be finite, got x {frame.x!r}, y {frame.y!r}, yaw {frame.yaw!r}")
    if max(abs(frame.x), abs(frame.y)) > MAX_COORDINATE_M:
        raise MapError(f"map origin must lie within +-{MAX_COORDINATE_M:g} m, got x {frame.x!r}, y {frame.y!r}")
    return MapCells(MapInfo(frame, width, height, resolution, stamp_ns, sequence), data)
