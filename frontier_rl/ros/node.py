"""The ROS 1 frontier node: the thesis's ``/frontier_request`` → ``/frontier_list`` interface.

Subscribes to each robot's map (``/<ns>/map``, ``nav_msgs/OccupancyGrid``) and pose
(``/<ns>/robot_pose``, ``geometry_msgs/PoseStamped`` in the map frame; or, without it, the TF
transform map → ``~base_frame`` when tf2_ros is installed). A ``std_msgs/String`` on
``/frontier_request`` naming a namespace is answered on ``/frontier_list`` with that robot's top
frontier centres as a ``geometry_msgs/PoseArray`` in its map frame; ``/frontier_markers``
(``visualization_msgs/MarkerArray``) shows them in RViz and ``/frontier_weight`` (``std_msgs/Float32``)
the weight in use. A request for an unknown namespace, before a map arrived, or on a malformed map
is logged and answered with an empty list; the node keeps serving.

Parameters (private): ``~robots`` (namespaces, a list or a comma string; default one robot with no
namespace), ``~weight`` (eq. 3.1's w, default 0.75), ``~model`` (a model file of ``frontier-rl train``;
replaces the weight), ``~top_k`` (10), ``~min_cluster_size`` (cells, 4), ``~pose_topic``
(``robot_pose``), ``~base_frame`` (``base_footprint``).

Run: ``python -m frontier_rl.ros.node _robots:=tb3_0,tb3_1 _weight:=0.75``. rospy comes from the
system's ROS (Debian's python3-rospy) when the environment has none of its own.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

from frontier_rl.core.frontiers.ranking import THESIS_WEIGHT
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import FrontierRLError
from frontier_rl.policies import make_policy
from frontier_rl.policies.frontier_request import RankedFrontier, grid_from_message, rank_frontiers

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


def _yaw(q: Any) -> float:
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class _Frame:
    """A map's placement: origin (m) and yaw (rad) of its cell (0, 0) corner in its frame."""

    def __init__(self, frame_id: str, x: float, y: float, yaw: float) -> None:
        self.frame_id, self.x, self.y = frame_id, x, y
        self.cos, self.sin = math.cos(yaw), math.sin(yaw)

    def to_grid(self, x: float, y: float) -> tuple[float, float]:
        dx, dy = x - self.x, y - self.y
        return self.cos * dx + self.sin * dy, -self.sin * dx + self.cos * dy

    def to_map(self, x: float, y: float) -> tuple[float, float]:
        return self.x + self.cos * x - self.sin * y, self.y + self.sin * x + self.cos * y


class FrontierNode:
    """The node's state and callbacks (call :func:`main` to run it)."""

    def __init__(self) -> None:
        self.rospy = rospy = import_rospy()
        from geometry_msgs.msg import PoseArray, PoseStamped
        from nav_msgs.msg import OccupancyGrid as MapMessage
        from std_msgs.msg import Float32, String
        from visualization_msgs.msg import MarkerArray

        robots = rospy.get_param("~robots", [""])
        self.robots = [r.strip().strip("/") for r in (robots.split(",") if isinstance(robots, str) else robots)]
        self.top_k = int(rospy.get_param("~top_k", 10))
        self.min_cells = int(rospy.get_param("~min_cluster_size", 4))
        self.base_frame = str(rospy.get_param("~base_frame", "base_footprint"))
        model = str(rospy.get_param("~model", ""))
        self.policy = make_policy(
            f"learned:{model}" if model else f"fixed:{float(rospy.get_param('~weight', THESIS_WEIGHT))}"
        )
        self.maps: dict[str, Any] = {}  # namespace -> (grid, frame) or None after a malformed map
        self.poses: dict[str, tuple[float, float, float]] = {}  # namespace -> (x, y, yaw) in the map frame
        pose_topic = str(rospy.get_param("~pose_topic", "robot_pose"))
        for ns in self.robots:
            rospy.Subscriber(self._topic(ns, "map"), MapMessage, self._on_map, callback_args=ns, queue_size=1)
            rospy.Subscriber(self._topic(ns, pose_topic), PoseStamped, self._on_pose, callback_args=ns, queue_size=1)
        self.list_pub = rospy.Publisher("/frontier_list", PoseArray, queue_size=10)
        self.marker_pub = rospy.Publisher("/frontier_markers", MarkerArray, queue_size=10)
        self.weight_pub = rospy.Publisher("/frontier_weight", Float32, queue_size=10, latch=True)
        weight = getattr(self.policy, "weight", None)
        if isinstance(weight, float):  # a fixed weight is known before any request; a model's comes with each
            self.weight_pub.publish(Float32(weight))
        self.tf_buffer = self._tf_buffer()
        rospy.Subscriber("/frontier_request", String, self._on_request, queue_size=10)
        rospy.loginfo("frontier_rl node: robots %s, policy %s, top %d", self.robots, self.policy.name, self.top_k)

    @staticmethod
    def _topic(ns: str, name: str) -> str:
        return f"/{ns}/{name}" if ns else f"/{name}"

    def _tf_buffer(self) -> Any:
        try:
            import tf2_ros
        except ImportError:
            return None
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        return buffer

    def _on_map(self, msg: Any, ns: str) -> None:
        info = msg.info
        try:
            grid = grid_from_message(int(info.width), int(info.height), float(info.resolution), msg.data)
        except FrontierRLError as exc:
            self.rospy.logwarn("frontier_rl: map of %r rejected: %s", ns, exc)
            self.maps[ns] = None
            return
        origin = info.origin
        frame = _Frame(msg.header.frame_id, origin.position.x, origin.position.y, _yaw(origin.orientation))
        self.maps[ns] = (grid, frame)

    def _on_pose(self, msg: Any, ns: str) -> None:
        p = msg.pose
        self.poses[ns] = (p.position.x, p.position.y, _yaw(p.orientation))

    def _pose(self, ns: str, frame: _Frame) -> tuple[float, float, float] | None:
        if ns in self.poses:
            return self.poses[ns]
        if self.tf_buffer is None:
            return None
        base = f"{ns}/{self.base_frame}" if ns else self.base_frame
        try:
            t = self.tf_buffer.lookup_transform(frame.frame_id, base, self.rospy.Time(0)).transform
        except Exception as exc:  # tf2's lookup errors share no base class worth naming here
            self.rospy.logwarn("frontier_rl: no pose of %r (%s)", ns, exc)
            return None
        return t.translation.x, t.translation.y, _yaw(t.rotation)

    def _on_request(self, msg: Any) -> None:
        from geometry_msgs.msg import Pose as PoseMessage
        from geometry_msgs.msg import PoseArray

        ns = str(msg.data).strip().strip("/")
        answer = PoseArray()
        answer.header.stamp = self.rospy.Time.now()
        ranked: list[RankedFrontier] = []
        frame = _Frame("", 0.0, 0.0, 0.0)
        if ns not in self.robots:
            self.rospy.logwarn("frontier_rl: request for unknown robot %r (known: %s)", ns, self.robots)
        elif self.maps.get(ns) is None:
            self.rospy.logwarn("frontier_rl: no usable map of %r yet", ns)
        else:
            grid, frame = self.maps[ns]
            answer.header.frame_id = frame.frame_id
            pose = self._pose(ns, frame)
            if pose is None:
                self.rospy.logwarn("frontier_rl: no pose of %r yet", ns)
            else:
                gx, gy = frame.to_grid(pose[0], pose[1])
                try:
                    ranked, weight = rank_frontiers(grid, Pose(gx, gy, 0.0), self.policy, self.top_k, self.min_cells)
                except FrontierRLError as exc:
                    self.rospy.logwarn("frontier_rl: ranking for %r failed: %s", ns, exc)
                    ranked, weight = [], None
                if weight is not None:
                    from std_msgs.msg import Float32

                    self.weight_pub.publish(Float32(weight))
        for f in ranked:
            p = PoseMessage()
            p.position.x, p.position.y = frame.to_map(f.x, f.y)
            p.orientation.w = 1.0
            answer.poses.append(p)
        self.list_pub.publish(answer)
        self.marker_pub.publish(self._markers(answer))

    def _markers(self, answer: Any) -> Any:
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
            m.scale.x = m.scale.y = m.scale.z = 0.25 if i == 0 else 0.15
            m.color.a, m.color.g, m.color.r = 0.9, 1.0 - i / max(n, 1), i / max(n, 1)  # best green, worst red
            markers.markers.append(m)
        return markers


def main() -> None:
    """Run the node until shutdown."""
    rospy = import_rospy()
    rospy.init_node("frontier_rl")
    try:
        FrontierNode()
    except FrontierRLError as exc:  # a bad parameter: one line, not a traceback
        rospy.logfatal("frontier_rl: %s", exc)
        raise SystemExit(2) from None
    rospy.spin()


if __name__ == "__main__":
    main()
