"""ROS 2 messages to and from the engine's values: maps, poses, scans and markers.

Every function takes or returns the message classes of the ROS 2 wheels (``nav_msgs``,
``geometry_msgs``, ``sensor_msgs``, ``visualization_msgs``), imported here and nowhere above.
"""

from __future__ import annotations

import array
import math
from collections.abc import Sequence

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, Pose, PoseStamped, PoseWithCovarianceStamped, Quaternion, TransformStamped
from nav_msgs.msg import OccupancyGrid as GridMessage
from nav_msgs.msg import Odometry
from nav_msgs.msg import Path as PathMessage
from numpy.typing import NDArray
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from frontier_rl.core.sensing.lidar import Scan
from frontier_rl.core.world.grid import OccupancyGrid
from frontier_rl.core.world.robot import Pose as RobotPose
from frontier_rl.errors import MapError
from frontier_rl.robot.map_message import grid_from_message, yaw_of
from frontier_rl.robot.transforms import PlanarTransform

MAP_FRAME = "map"
MAP_QOS = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, reliability=ReliabilityPolicy.RELIABLE)
"""The map's QoS, as map_server and slam_toolbox publish it: a late subscriber gets the last map."""


def quaternion_of(yaw: float) -> Quaternion:
    """A rotation of ``yaw`` (rad) about z."""
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))


def pose_message(pose: RobotPose) -> Pose:
    """A ``geometry_msgs/Pose`` at ``pose`` (m, rad)."""
    return Pose(position=Point(x=pose.x, y=pose.y, z=0.0), orientation=quaternion_of(pose.theta))


def robot_pose(message: Pose) -> RobotPose:
    """The planar pose (m, rad) of a ``geometry_msgs/Pose``; a ``ValueError`` naming a value that
    is not a finite number."""
    values = (message.position.x, message.position.y, yaw_of(message.orientation))
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"pose ({values[0]!r}, {values[1]!r}, yaw {values[2]!r}) is not finite")
    return RobotPose(*values)


def grid_message(grid: OccupancyGrid, stamp: Time, frame: str = MAP_FRAME) -> GridMessage:
    """A ``nav_msgs/OccupancyGrid`` of ``grid`` (cells -1 unknown, 0 free, 100 occupied)."""
    message = GridMessage()
    message.header.stamp, message.header.frame_id = stamp, frame
    message.info.map_load_time = stamp
    message.info.resolution = float(grid.resolution)
    message.info.width, message.info.height = grid.width, grid.height
    message.info.origin = pose_message(RobotPose(grid.origin[0], grid.origin[1], 0.0))
    message.data = array.array("b", np.ascontiguousarray(grid.data, np.int8).tobytes())
    return message


def grid_of(message: GridMessage) -> OccupancyGrid:
    """The grid of a ``nav_msgs/OccupancyGrid`` in the map frame, thresholded as map_server does;
    a :class:`MapError` for a map of no cells, a bad resolution or data of the wrong size, or a
    rotated origin (which no map_server or slam_toolbox map has)."""
    info = message.info
    origin = info.origin
    if not (math.isfinite(origin.position.x) and math.isfinite(origin.position.y)):
        raise MapError(f"map origin ({origin.position.x!r}, {origin.position.y!r}) is not finite")
    if abs(yaw_of(origin.orientation)) > 1e-6:
        raise MapError(f"map origin is rotated by {yaw_of(origin.orientation):.3g} rad; only unrotated maps are read")
    data = np.frombuffer(memoryview(message.data), np.int8) if len(message.data) else np.zeros(0, np.int8)
    return grid_from_message(
        info.width, info.height, info.resolution, data, origin=(origin.position.x, origin.position.y)
    )


def pose_stamped(pose: RobotPose, stamp: Time, frame: str = MAP_FRAME) -> PoseStamped:
    """A ``geometry_msgs/PoseStamped`` at ``pose``."""
    message = PoseStamped(pose=pose_message(pose))
    message.header.stamp, message.header.frame_id = stamp, frame
    return message


def path_message(points: NDArray[np.float64], stamp: Time, frame: str = MAP_FRAME) -> PathMessage:
    """A ``nav_msgs/Path`` through ``points`` ((n, 2), m), each pose facing the next point (the
    last the one before it), as a planner's path is handed to Nav2's controller."""
    steps = np.diff(points, axis=0)
    yaws = np.arctan2(steps[:, 1], steps[:, 0]) if len(steps) else np.zeros(0)
    yaws = np.append(yaws, yaws[-1] if len(yaws) else 0.0)[: len(points)]
    message = PathMessage(
        poses=[
            pose_stamped(RobotPose(float(x), float(y), float(yaw)), stamp, frame)
            for (x, y), yaw in zip(points, yaws, strict=True)
        ]
    )
    message.header.stamp, message.header.frame_id = stamp, frame
    return message


def path_points(message: PathMessage) -> NDArray[np.float64]:
    """The points ((n, 2), m) of a ``nav_msgs/Path``; a ``ValueError`` for an empty path or a
    point that is not finite."""
    points = np.array([(p.pose.position.x, p.pose.position.y) for p in message.poses], np.float64).reshape(-1, 2)
    if len(points) == 0:
        raise ValueError("path has no poses")
    if not np.isfinite(points).all():
        raise ValueError("path has a point that is not finite")
    return points


def pose_with_covariance(pose: RobotPose, stamp: Time, frame: str = MAP_FRAME) -> PoseWithCovarianceStamped:
    """A ``geometry_msgs/PoseWithCovarianceStamped`` at ``pose``, as slam_toolbox publishes on ``/pose``."""
    message = PoseWithCovarianceStamped()
    message.header.stamp, message.header.frame_id = stamp, frame
    message.pose.pose = pose_message(pose)
    return message


def odometry(pose: RobotPose, stamp: Time, frame: str = MAP_FRAME, child: str = "base_link") -> Odometry:
    """A ``nav_msgs/Odometry`` at ``pose`` (the simulated robot's odometry has no drift)."""
    message = Odometry(child_frame_id=child)
    message.header.stamp, message.header.frame_id = stamp, frame
    message.pose.pose = pose_message(pose)
    return message


def transform_stamped(parent: str, child: str, transform: PlanarTransform, stamp: Time) -> TransformStamped:
    """A ``geometry_msgs/TransformStamped``: ``child``'s pose in ``parent`` is ``transform`` (m, rad)."""
    message = TransformStamped(child_frame_id=child)
    message.header.stamp, message.header.frame_id = stamp, parent
    message.transform.translation.x, message.transform.translation.y = transform.x, transform.y
    message.transform.rotation = quaternion_of(transform.yaw)
    return message


def laser_scan(scan: Scan, min_range: float, max_range: float, stamp: Time, frame: str = "base_scan") -> LaserScan:
    """A ``sensor_msgs/LaserScan`` of ``scan`` in the robot's frame (beams counter-clockwise from
    its heading; no return is ``inf``, an invalid one ``nan``, as REP 117 has them)."""
    beams = len(scan.ranges)
    first = math.atan2(float(scan.dir_y[0]), float(scan.dir_x[0])) - scan.pose.theta
    message = LaserScan(
        angle_min=math.remainder(first, 2.0 * math.pi),
        angle_increment=2.0 * math.pi / beams,
        range_min=min_range,
        range_max=max_range,
    )
    message.angle_max = message.angle_min + message.angle_increment * (beams - 1)
    message.header.stamp, message.header.frame_id = stamp, frame
    message.ranges = array.array("f", scan.ranges.astype(np.float32).tobytes())
    return message


def frontier_markers(
    goals: Sequence[tuple[float, float]], chosen: tuple[float, float] | None, stamp: Time, frame: str = MAP_FRAME
) -> MarkerArray:
    """RViz markers: the candidate goals as small blue spheres, the chosen one as a large green one
    (the markers of the tick before are deleted first)."""
    clear = Marker(action=Marker.DELETEALL)
    points = Marker(ns="frontiers", id=0, type=Marker.SPHERE_LIST, action=Marker.ADD)
    points.points = [Point(x=float(x), y=float(y), z=0.05) for x, y in goals]
    points.scale.x = points.scale.y = points.scale.z = 0.15
    points.color = ColorRGBA(r=0.1, g=0.4, b=1.0, a=0.8)
    markers = [clear, points]
    if chosen is not None:
        goal = Marker(ns="goal", id=1, type=Marker.SPHERE, action=Marker.ADD)
        goal.pose = pose_message(RobotPose(chosen[0], chosen[1], 0.0))
        goal.scale.x = goal.scale.y = goal.scale.z = 0.3
        goal.color = ColorRGBA(r=0.1, g=0.9, b=0.2, a=0.9)
        markers.append(goal)
    points.pose.orientation.w = 1.0
    for marker in markers[1:]:
        marker.header.stamp, marker.header.frame_id = stamp, frame
    return MarkerArray(markers=markers)
