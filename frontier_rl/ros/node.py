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

Each robot's map and ranking live in a worker process of its own (:mod:`frontier_rl.ros.robot_worker`),
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
import threading
import time
from typing import Any

from frontier_rl.config import coerce
from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.core.sim.config import MAX_FRONTIER_DROP_CELLS
from frontier_rl.errors import FrontierRLError, MapError
from frontier_rl.policies import make_policy
from frontier_rl.ros.answers import (
    MAX_CHECK_PERIOD_S,
    MapInfo,
    StaleMapAnswer,
    Status,
    ThrottledLog,
    check_node_policy,
    check_request,
    count_parameter,
    flag_parameter,
    node_policy_spec,
    parse_request,
    robot_namespaces,
    seconds_parameter,
    stale_reason,
)
from frontier_rl.ros.master_watch import EXIT_MASTER_RESTARTED, MasterWatch
from frontier_rl.ros.robot_worker import RankJob, RankResult, RobotWorker
from frontier_rl.ros.ros_messages import answer_markers, import_rospy, map_cells, yaw

_WORKER_START_S = 120.0
"""How long the node waits for its workers to load their policy and kernels (s)."""


class FrontierNode:
    """The node's state and callbacks (call :func:`main` to run it)."""

    def __init__(self) -> None:
        """Read and check the parameters and load the policy (a bad one raises, naming it)."""
        self.rospy = rospy = import_rospy()
        self.robots = robot_namespaces(rospy.get_param("~robots", [""]))
        self.top_k = count_parameter("top_k", rospy.get_param("~top_k", 10), 1)
        min_cells = count_parameter("min_cluster_size", rospy.get_param("~min_cluster_size", 4), 0,
                                    MAX_FRONTIER_DROP_CELLS)  # fmt: skip
        self.base_frame = str(rospy.get_param("~base_frame", "base_footprint"))
        self.max_map_age = seconds_parameter("max_map_age", rospy.get_param("~max_map_age", 30.0), zero=True)
        try:
            self.stale = StaleMapAnswer(str(rospy.get_param("~stale_map", "stale")))
        except ValueError:
            raise FrontierRLError("~stale_map must be 'stale' or 'empty'") from None
        self.keep_last_map = flag_parameter("keep_last_map", rospy.get_param("~keep_last_map", True))
        self.max_pending = count_parameter("max_pending", rospy.get_param("~max_pending", 8), 1)
        period = rospy.get_param("~master_check_period", 1.0)
        self.master_check_period = seconds_parameter("master_check_period", period, zero=False,
                                                     most=MAX_CHECK_PERIOD_S)  # fmt: skip
        spec = node_policy_spec(str(rospy.get_param("~policy", "") or ""), str(rospy.get_param("~model", "") or ""),
                                coerce(float, rospy.get_param("~weight", THESIS_WEIGHT), "~weight"))  # fmt: skip
        policy = make_policy(spec)  # a bad policy, weight or model file fails here, once, with its message
        check_node_policy(policy, spec)
        self.policy_name = policy.name
        fixed = getattr(policy, "weight", None)
        self.fixed_weight = float(fixed) if isinstance(fixed, float) else None
        self.maps: dict[str, MapInfo | None] = dict.fromkeys(self.robots)
        self.poses: dict[str, tuple[float, float, float]] = {}
        self.jobs: dict[int, tuple[str, str, int, str, float]] = {}
        """Jobs at the workers: robot, request id, sequence of the map checked, reason, arrival time."""
        self._job_count = self._request_count = 0
        self._lock = threading.Lock()  # the job table and the publishers' order (answer, then status)
        self.log = ThrottledLog()
        self._worker_args = (spec, self.top_k, min_cells)
        self.workers: dict[str, RobotWorker] = {}

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
        self.workers = {ns: RobotWorker(*self._worker_args, self._on_result) for ns in self.robots}
        rospy.on_shutdown(self.close)  # a Ctrl-C from now on stops the workers at once, even while they start
        if not self._workers_started():
            return False
        self.list_pub = rospy.Publisher("/frontier_list", PoseArray, queue_size=100)
        self.marker_pub = rospy.Publisher("/frontier_markers", MarkerArray, queue_size=10)
        self.weight_pub = rospy.Publisher("/frontier_weight", Float32, queue_size=100, latch=True)
        self.status_pub = rospy.Publisher("/frontier_status", String, queue_size=100)
        self.weight_pub.publish(Float32(math.nan if self.fixed_weight is None else self.fixed_weight))
        self.tf_buffer = self._tf_buffer()
        pose_topic = str(rospy.get_param("~pose_topic", "robot_pose"))
        for ns in self.robots:
            rospy.Subscriber(_topic(ns, "map"), numpy_msg(OccupancyGrid), self._on_map, callback_args=ns,
                             queue_size=1, buff_size=2**26)  # fmt: skip
            rospy.Subscriber(_topic(ns, pose_topic), PoseStamped, self._on_pose, callback_args=ns, queue_size=1)
        rospy.Subscriber("/frontier_request", String, self._on_request, queue_size=100)
        rospy.loginfo("frontier_rl node: robots %s, policy %s, top %d", self.robots, self.policy_name, self.top_k)
        return True

    def _workers_started(self) -> bool:
        """Wait for every worker to load its policy; False if the node is shut down meanwhile."""
        deadline = time.monotonic() + _WORKER_START_S
        for ns, worker in self.workers.items():
            while not worker.ready.wait(0.1):
                if self.rospy.is_shutdown():
                    return False
                if time.monotonic() > deadline:
                    raise FrontierRLError(f"the worker of robot {ns!r} did not start within {_WORKER_START_S:g} s")
        return True

    def close(self) -> None:
        """Stop every worker (none is started again)."""
        for worker in self.workers.values():
            worker.close()

    def _tf_buffer(self) -> Any:
        try:
            import tf2_ros
        except ImportError:
            return None
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        return buffer

    def _warn(self, ns: str, kind: str, text: str) -> None:
        if self.log.due(ns, kind, time.monotonic()):
            self.rospy.logwarn("frontier_rl: %s", text)

    def _on_map(self, msg: Any, ns: str) -> None:
        previous = self.maps[ns]
        try:
            cells = map_cells(msg, 0 if previous is None else previous.sequence + 1, self.rospy.get_time())
        except MapError as exc:
            kept = self.keep_last_map and previous is not None
            then = "the last good map is kept" if kept else "no map until a good one arrives"
            self._warn(ns, "map", f"map of {ns!r} rejected ({exc}); {then}")
            if not self.keep_last_map:
                self.maps[ns] = None
            return
        self.maps[ns] = cells.info
        self.workers[ns].send_map(cells)

    def _on_pose(self, msg: Any, ns: str) -> None:
        p = msg.pose
        self.poses[ns] = (p.position.x, p.position.y, yaw(p.orientation))

    def _pose(self, ns: str, info: MapInfo | None) -> tuple[float, float, float] | None:
        if ns in self.poses or info is None or self.tf_buffer is None:
            return self.poses.get(ns)
        base = f"{ns}/{self.base_frame}" if ns else self.base_frame
        try:
            t = self.tf_buffer.lookup_transform(info.frame.frame_id, base, self.rospy.Time(0)).transform
        except Exception:  # tf2's lookup errors share no base class worth naming here; no pose is the answer
            return None
        return t.translation.x, t.translation.y, yaw(t.rotation)

    def _on_request(self, msg: Any) -> None:
        arrived = time.monotonic()
        with self._lock:
            self._request_count += 1
            ns, request = parse_request(str(msg.data), self._request_count)
        try:
            info = self.maps.get(ns)
            pose = self._pose(ns, info)  # once: a new pose may arrive while the request is checked
            verdict = check_request(ns, self.robots, info, pose, self.rospy.get_time(), self.max_map_age, self.stale)
            if not verdict.rank or info is None or pose is None:
                self._answer(ns, request, info, (), None, verdict.reason, arrived)
                return
            if self.workers[ns].pending >= self.max_pending:
                busy = f"robot {ns!r} has {self.max_pending} requests queued (~max_pending)"
                self._answer(ns, request, info, (), None, busy, arrived)
                return
            with self._lock:
                self._job_count += 1
                job = self._job_count
                self.jobs[job] = (ns, request, info.sequence, verdict.reason, arrived)
            self.workers[ns].submit(RankJob(job, pose[0], pose[1]))
        except Exception as exc:  # every request gets an answer, whatever failed in preparing it
            self._answer(
                ns, request, self.maps.get(ns), (), None, f"request failed: {type(exc).__name__}: {exc}", arrived
            )

    def _on_result(self, result: RankResult) -> None:
        with self._lock:
            ns, request, checked, reason, arrived = self.jobs.pop(result.job)
        info = result.info or self.maps.get(ns)  # the map the worker ranked on, which may be newer than the request's
        if info is not None and info.sequence != checked:  # judged on the map that was ranked, not the one checked
            reason = stale_reason(ns, info, self.rospy.get_time(), self.max_map_age)
        notes = "; ".join(part for part in (reason, result.error) if part)
        self._answer(ns, request, info, result.centres, result.weight, notes, arrived)

    def _answer(
        self, ns: str, request: str, info: MapInfo | None, centres: tuple[tuple[float, float], ...],
        weight: float | None, reason: str, arrived: float,
    ) -> None:  # fmt: skip
        """Publish the answer, its markers, the weight and the status line (in that order)."""
        from geometry_msgs.msg import Pose, PoseArray
        from std_msgs.msg import Float32, String

        if reason and not centres:
            self._warn(ns, reason.split(":")[0][:40], f"request {request} of {ns!r} answered empty: {reason}")
        elif reason:
            self._warn(ns, reason.split(":")[0][:40], f"request {request} of {ns!r}: {reason}")
        answer = PoseArray()
        if info is not None:
            answer.header.frame_id = info.frame.frame_id
            answer.header.stamp = self.rospy.Time(*divmod(info.stamp_ns, 10**9))
        for x, y in centres:
            pose = Pose()
            pose.position.x, pose.position.y = x, y
            pose.orientation.w = 1.0
            answer.poses.append(pose)
        used = weight if weight is not None else (self.fixed_weight if centres else None)
        status = Status(ns, request, len(centres), reason, self.policy_name, used,
                        None if info is None else info.stamp_s,
                        None if info is None else info.age_s(self.rospy.get_time()),
                        time.monotonic() - arrived)  # fmt: skip
        with self._lock:
            self.list_pub.publish(answer)
            self.marker_pub.publish(answer_markers(answer))
            self.weight_pub.publish(Float32(math.nan if used is None else used))
            self.status_pub.publish(String(status.to_json()))

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
        node = FrontierNode()
    except (FrontierRLError, ValueError) as exc:  # a bad parameter: one line, not a traceback
        rospy.logfatal("frontier_rl: %s", exc)
        raise SystemExit(2) from None
    import rosgraph

    try:
        if node.start():
            watch = MasterWatch(rosgraph.get_master_uri(), rospy.get_name(), node.master_check_period,
                                node.on_master_restart)  # fmt: skip
            watch.start()
            rospy.spin()
    except FrontierRLError as exc:  # a worker that did not start
        rospy.logfatal("frontier_rl: %s", exc)
        raise SystemExit(1) from None
    finally:
        node.close()


if __name__ == "__main__":
    main()
