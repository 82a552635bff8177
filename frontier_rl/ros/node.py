"""The ROS 1 frontier node: the thesis's ``/frontier_request`` → ``/frontier_list`` interface.

Subscribes to each robot's map (``/<ns>/map``, ``nav_msgs/OccupancyGrid``) and pose
(``/<ns>/robot_pose``, ``geometry_msgs/PoseStamped`` in the map frame; or, without it, the TF
transform map → ``~base_frame`` when tf2_ros is installed). A ``std_msgs/String`` on
``/frontier_request`` naming a namespace (optionally followed by a request id) is answered on
``/frontier_list`` with that robot's top frontier centres as a ``geometry_msgs/PoseArray`` in its
map frame, stamped with the stamp of the map they were computed on. Every request is answered, an
empty list when it cannot be ranked, and each answer is followed by a JSON line on
``/frontier_status`` (robot, request id, frontiers, reason, policy, weight, map stamp and age,
latency); ``/frontier_weight`` (``std_msgs/Float32``) carries the weight of every answer (NaN for a
frontier-choice model) and ``/frontier_markers`` shows the answer in RViz.

Each robot's map and ranking live in a worker process of its own (:mod:`frontier_rl.robot.ranking_worker`),
so one robot's large map or slow model does not delay another. A malformed map is rejected and the
robot's last good map kept (``~keep_last_map``). When the master is restarted under it, the node
exits with status 3 (:mod:`frontier_rl.ros.master_watch`) so that ``respawn`` starts it again.

Parameters (private): ``~robots`` (namespaces, a list or a comma string; default one robot with no
namespace), ``~weight`` (eq. 3.1's w, default 0.75), ``~model`` (a model file of ``frontier-rl
train``; replaces the weight), ``~policy`` (any policy of ``frontier-rl explore`` but the oracle,
e.g. ``tour`` or ``learned:models/model7.zip``; replaces both), ``~top_k`` (10),
``~min_cluster_size`` (cells, 4), ``~pose_topic`` (``robot_pose``), ``~base_frame``
(``base_footprint``), ``~max_map_age`` (s, 30; 0: any age), ``~stale_map`` (``stale``: rank it and
say so, or ``empty``), ``~keep_last_map`` (true), ``~max_pending`` (requests queued per robot, 8),
``~master_check_period`` (s, 1.0, at most 3600). A parameter of the wrong kind or out of range
stops the node at once with one line naming it (exit status 2).

Run: ``python -m frontier_rl.ros _robots:=tb3_0,tb3_1 _weight:=0.75`` (or ``-m frontier_rl.ros.node``, where
a Ctrl-C in the first second or so prints a traceback: see :mod:`frontier_rl.ros.__main__`).
"""

from __future__ import annotations

import math
import os
from typing import Any

from frontier_rl.checked_values import coerce
from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.core.sim.config import MAX_FRONTIER_DROP_CELLS
from frontier_rl.errors import FrontierRLError
from frontier_rl.robot.answers import MapInfo
from frontier_rl.robot.map_message import yaw_of
from frontier_rl.robot.node_settings import (
    MAX_CHECK_PERIOD_S,
    count_parameter,
    flag_parameter,
    node_policy_spec,
    robot_namespaces,
    seconds_parameter,
    settings_named,
    stale_map_parameter,
)
from frontier_rl.robot.ranking_service import Answer, RankingService, RobotPose, ServiceSettings
from frontier_rl.ros.master_watch import EXIT_MASTER_RESTARTED, MasterWatch
from frontier_rl.ros.ros_messages import answer_markers, import_rospy, map_cells


class FrontierNode:
    """The node's messages and callbacks around a :class:`~frontier_rl.robot.ranking_service.RankingService`
    (call :func:`main` to run it)."""

    def __init__(self) -> None:
        """Read and check the parameters and load the policy (a bad one raises, naming it)."""
        self.rospy = rospy = import_rospy()
        robots = robot_namespaces(rospy.get_param("~robots", [""]))
        top_k = count_parameter("top_k", rospy.get_param("~top_k", ServiceSettings.top_k), 1)
        min_cells = count_parameter(
            "min_cluster_size",
            rospy.get_param("~min_cluster_size", ServiceSettings.min_cells),
            0,
            MAX_FRONTIER_DROP_CELLS,
        )
        self.base_frame = str(rospy.get_param("~base_frame", "base_footprint"))
        max_map_age = seconds_parameter(
            "max_map_age", rospy.get_param("~max_map_age", ServiceSettings.max_map_age), zero=True
        )
        stale = stale_map_parameter(rospy.get_param("~stale_map", ServiceSettings.stale.value))
        keep_last_map = flag_parameter(
            "keep_last_map", rospy.get_param("~keep_last_map", ServiceSettings.keep_last_map)
        )
        max_pending = count_parameter("max_pending", rospy.get_param("~max_pending", ServiceSettings.max_pending), 1)
        period = rospy.get_param("~master_check_period", 1.0)
        self.master_check_period = seconds_parameter("master_check_period", period, zero=False, most=MAX_CHECK_PERIOD_S)
        spec = node_policy_spec(
            str(rospy.get_param("~policy", "") or ""),
            str(rospy.get_param("~model", "") or ""),
            coerce(float, rospy.get_param("~weight", THESIS_WEIGHT), "~weight"),
        )
        settings = ServiceSettings(
            robots=tuple(robots),
            policy=spec,
            top_k=top_k,
            min_cells=min_cells,
            max_map_age=max_map_age,
            stale=stale,
            keep_last_map=keep_last_map,
            max_pending=max_pending,
        )
        self.service = RankingService(settings, self._publish, self._warn, rospy.get_time)
        self.robots = robots
        self.tf_buffer: Any = None

    def start(self) -> bool:
        """Start the workers, then publish and subscribe; False if the node was shut down first (a
        Ctrl-C while it started: it then has no topics, and its workers are stopped)."""
        from geometry_msgs.msg import PoseArray, PoseStamped
        from nav_msgs.msg import OccupancyGrid
        from rospy.numpy_msg import numpy_msg
        from std_msgs.msg import Float32, String
        from visualization_msgs.msg import MarkerArray

        rospy = self.rospy
        if rospy.is_shutdown():  # during the policy's loading (torch takes seconds)
            return False
        rospy.on_shutdown(self.close)  # a Ctrl-C from now on stops the workers at once, even while they start
        if not self.service.start(rospy.is_shutdown):
            return False
        self.list_pub = rospy.Publisher("/frontier_list", PoseArray, queue_size=100)
        self.marker_pub = rospy.Publisher("/frontier_markers", MarkerArray, queue_size=10)
        self.weight_pub = rospy.Publisher("/frontier_weight", Float32, queue_size=100, latch=True)
        self.status_pub = rospy.Publisher("/frontier_status", String, queue_size=100)
        fixed = self.service.fixed_weight
        self.weight_pub.publish(Float32(math.nan if fixed is None else fixed))
        self.tf_buffer = self._tf_buffer()
        pose_topic = str(rospy.get_param("~pose_topic", "robot_pose"))
        for ns in self.robots:
            rospy.Subscriber(
                _topic(ns, "map"),
                numpy_msg(OccupancyGrid),
                self._on_map,
                callback_args=ns,
                queue_size=1,
                buff_size=2**26,
            )
            rospy.Subscriber(_topic(ns, pose_topic), PoseStamped, self._on_pose, callback_args=ns, queue_size=1)
        rospy.Subscriber("/frontier_request", String, self._on_request, queue_size=100)
        top_k = self.service.settings.top_k
        rospy.loginfo("frontier_rl node: robots %s, policy %s, top %d", self.robots, self.service.policy_name, top_k)
        return True

    def close(self) -> None:
        """Stop every worker (none is started again)."""
        self.service.close()

    def _tf_buffer(self) -> Any:
        try:
            import tf2_ros
        except ImportError:
            return None
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        return buffer

    def _warn(self, text: str) -> None:
        self.rospy.logwarn("frontier_rl: %s", text)

    def _on_map(self, msg: Any, ns: str) -> None:
        now = self.rospy.get_time()
        self.service.on_map(ns, lambda sequence: map_cells(msg, sequence, now))

    def _on_pose(self, msg: Any, ns: str) -> None:
        p = msg.pose
        self.service.on_pose(ns, (p.position.x, p.position.y, yaw_of(p.orientation)))

    def _pose_from_tf(self, ns: str, info: MapInfo | None) -> RobotPose | None:
        if info is None or self.tf_buffer is None:
            return None
        base = f"{ns}/{self.base_frame}" if ns else self.base_frame
        try:
            t = self.tf_buffer.lookup_transform(info.frame.frame_id, base, self.rospy.Time(0)).transform
        except Exception:  # tf2's lookup errors share no base class worth naming here; no pose is the answer
            return None
        return t.translation.x, t.translation.y, yaw_of(t.rotation)

    def _on_request(self, msg: Any) -> None:
        self.service.on_request(str(msg.data), self._pose_from_tf)

    def _publish(self, answer: Answer) -> None:
        """Publish the answer, its markers, the weight and the status line (in that order)."""
        from geometry_msgs.msg import Pose, PoseArray
        from std_msgs.msg import Float32, String

        message = PoseArray()
        if answer.info is not None:
            message.header.frame_id = answer.info.frame.frame_id
            message.header.stamp = self.rospy.Time(*divmod(answer.info.stamp_ns, 10**9))
        for x, y in answer.centres:
            pose = Pose()
            pose.position.x, pose.position.y = x, y
            pose.orientation.w = 1.0
            message.poses.append(pose)
        self.list_pub.publish(message)
        self.marker_pub.publish(answer_markers(message))
        self.weight_pub.publish(Float32(math.nan if answer.weight is None else answer.weight))
        self.status_pub.publish(String(answer.status.to_json()))

    def on_master_restart(self, description: str) -> None:
        """Log and exit at once with :data:`EXIT_MASTER_RESTARTED`; the workers end with the pipe."""
        self.rospy.logfatal("frontier_rl: %s; exiting so that respawn registers the node again", description)
        os._exit(EXIT_MASTER_RESTARTED)  # rospy's threads would keep a normal exit waiting


def _topic(ns: str, name: str) -> str:
    return f"/{ns}/{name}" if ns else f"/{name}"


def main() -> None:
    """Run the node until shutdown."""
    rospy = import_rospy()
    try:
        rospy.init_node("frontier_rl")
    except rospy.exceptions.ROSInitException as exc:  # Ctrl-C while it registered: one line, not a traceback
        raise SystemExit(f"frontier_rl: {exc}") from None
    try:
        with settings_named(lambda setting: f"~{setting}"):
            node = FrontierNode()
    except (FrontierRLError, ValueError) as exc:  # a bad parameter: one line, not a traceback
        rospy.logfatal("frontier_rl: %s", exc)
        raise SystemExit(2) from None
    import rosgraph

    try:
        if node.start():
            watch = MasterWatch(
                rosgraph.get_master_uri(), rospy.get_name(), node.master_check_period, node.on_master_restart
            )
            watch.start()
            rospy.spin()
    except FrontierRLError as exc:  # a worker that did not start
        rospy.logfatal("frontier_rl: %s", exc)
        raise SystemExit(1) from None
    finally:
        node.close()


if __name__ == "__main__":
    main()
