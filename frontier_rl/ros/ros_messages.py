"""The node's side of ROS messages: importing rospy, map messages to cells, quaternions to yaw, an
answer to RViz markers. rospy and the message packages come from the system's ROS (Debian's
python3-rospy and friends) when the environment has none of its own."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

from frontier_rl.errors import FrontierRLError
from frontier_rl.robot.answers import MapCells, marker_style
from frontier_rl.robot.answers import map_cells as accepted_map

_SYSTEM_PACKAGES = Path("/usr/lib/python3/dist-packages")


def import_rospy() -> Any:
    """rospy, from this environment or else from the system's ROS packages."""
    try:
        import rospy
    except ImportError:
        if _SYSTEM_PACKAGES.is_dir() and str(_SYSTEM_PACKAGES) not in sys.path:
            sys.path.append(str(_SYSTEM_PACKAGES))  # after the environment's own packages
        try:
            import rospy
        except ImportError:
            raise FrontierRLError(
                "rospy not found: install ROS 1 (Debian: apt-get install ros-core python3-rospy python3-nav-msgs "
                "python3-geometry-msgs python3-visualization-msgs python3-std-msgs)"
            ) from None
    return rospy


def map_cells(msg: Any, sequence: int, now_s: float) -> MapCells:
    """A ROS 1 ``nav_msgs/OccupancyGrid`` (its data a NumPy array with ``numpy_msg``, or a sequence)
    as the robot's ``sequence``-th good map (:func:`frontier_rl.robot.answers.map_cells`), stamped
    with its header's stamp or, when that is zero, with ``now_s`` (s)."""
    stamp_ns = int(msg.header.stamp.to_nsec()) or round(now_s * 1e9)
    return accepted_map(msg.info, str(msg.header.frame_id), msg.data, stamp_ns, sequence)


def answer_markers(answer: Any) -> Any:
    """The answer's poses as RViz spheres, green (best) to red, after a marker that clears the old ones."""
    from visualization_msgs.msg import Marker, MarkerArray

    markers = MarkerArray()
    clear = Marker()
    clear.action = Marker.DELETEALL
    markers.markers.append(clear)
    n = len(answer.poses)
    for i, pose in enumerate(answer.poses):
        m = Marker()
        m.header = answer.header
        m.ns, m.id, m.type, m.action = "frontiers", i, Marker.SPHERE, Marker.ADD
        m.pose = pose
        size, m.color.g, m.color.r = marker_style(i, n)
        m.scale.x = m.scale.y = m.scale.z = size
        m.color.a = 0.9
        markers.markers.append(m)
    return markers
