"""Drives the frontier node through the faults of a field robot (run by tests/ros/test_node_faults.py
over a real ROS master). ``python fault_client.py SCENARIO SCENE.npz [ARG]``, one JSON line per
result on stdout:

- ``faults``: a good map and pose, then a NaN, an infinite and an off-map pose, a stale map and a
  malformed map, then the map moved by MOVE, each followed by a request; prints each answer with
  its status line.
- ``big_maps``: robot tb3_1's SLAM: a 4000 × 4000 map each second and a request after each.
- ``latency``: robot tb3_0 asked 20 times a second; prints its answer latencies (s) measured here
  and in the node.
- ``first_answer``: publishes the map and pose and asks every 0.5 s until an answer holds
  frontiers; prints the time since ARG (a ``time.time()``), so that a test can time a recovery,
  and that answer with its status line.
"""

from __future__ import annotations

import json
import math
import queue
import sys
import threading
import time
from typing import Any

import numpy as np

from frontier_rl.ros.ros_messages import import_rospy

rospy = import_rospy()
from geometry_msgs.msg import PoseArray, PoseStamped  # noqa: E402
from nav_msgs.msg import OccupancyGrid  # noqa: E402
from rospy.numpy_msg import numpy_msg  # noqa: E402
from std_msgs.msg import String  # noqa: E402

BIG = 4000
MOVE = (1.5, -0.75)
"""How far the ``faults`` scenario moves its last map's origin (m)."""


class _Cells(np.ndarray):
    """Map data for ``numpy_msg``, whose generated code (Debian's) still calls ``tostring``,
    which NumPy 2 removed."""

    def tostring(self) -> bytes:  # type: ignore[override]
        return self.tobytes()


def _map(scene: Any, data: np.ndarray, frame: str, stamp: float | None = None, width: int | None = None,
         shift: tuple[float, float] = (0.0, 0.0)) -> Any:  # fmt: skip
    msg = numpy_msg(OccupancyGrid)()
    msg.header.frame_id = frame
    msg.header.stamp = rospy.Time.from_sec(time.time() if stamp is None else stamp)
    msg.info.resolution = float(scene["resolution"])
    msg.info.width = int(scene["width"]) if width is None else width
    msg.info.height = int(scene["height"]) if width is None else width
    msg.info.origin.position.x = float(scene["origin"][0]) + shift[0]
    msg.info.origin.position.y = float(scene["origin"][1]) + shift[1]
    msg.info.origin.orientation.w = 1.0
    msg.data = np.ascontiguousarray(data, dtype=np.int8).view(_Cells)
    return msg


def _pose(frame: str, x: float, y: float) -> Any:
    pose = PoseStamped()
    pose.header.frame_id = frame
    pose.pose.position.x, pose.pose.position.y = x, y
    pose.pose.orientation.w = 1.0
    return pose


class Client:
    """Publishers for the robots' maps and poses and the requests; queues of answers and statuses."""

    def __init__(self, robots: list[str]) -> None:
        rospy.init_node("frontier_fault_client", anonymous=True, disable_signals=True)
        self.answers: queue.Queue[Any] = queue.Queue()
        self.statuses: queue.Queue[dict[str, Any]] = queue.Queue()
        rospy.Subscriber("/frontier_list", PoseArray, self.answers.put)
        rospy.Subscriber("/frontier_status", String, lambda m: self.statuses.put(json.loads(m.data)))
        self.request = rospy.Publisher("/frontier_request", String, queue_size=100)
        self.maps = {
            r: rospy.Publisher(f"/{r}/map", numpy_msg(OccupancyGrid), queue_size=1, latch=True) for r in robots
        }
        self.poses = {r: rospy.Publisher(f"/{r}/robot_pose", PoseStamped, queue_size=1, latch=True) for r in robots}
        deadline = time.monotonic() + 60
        publishers = [self.request, *self.maps.values(), *self.poses.values()]
        while time.monotonic() < deadline and any(p.get_num_connections() == 0 for p in publishers):
            time.sleep(0.1)
        time.sleep(0.5)

    def ask(self, robot: str, request: str, timeout: float = 30.0) -> dict[str, Any]:
        self.request.publish(String(f"{robot} {request}"))
        answer = self.answers.get(timeout=timeout)
        status = self.statuses.get(timeout=timeout)
        return {"poses": [[p.position.x, p.position.y] for p in answer.poses], "frame": answer.header.frame_id,
                "stamp": answer.header.stamp.to_sec(), "stamp_ns": answer.header.stamp.to_nsec(),
                "status": status}  # fmt: skip


def faults(scene: Any) -> None:
    client = Client(["tb3_0"])
    x, y = (float(v) for v in scene["pose"])
    client.poses["tb3_0"].publish(_pose("tb3_0/map", x, y))
    stamp = time.time()
    client.maps["tb3_0"].publish(_map(scene, scene["data"], "tb3_0/map", stamp))
    time.sleep(1.0)
    results = {"good": client.ask("tb3_0", "good"), "map_stamp": stamp,
               "map_stamp_ns": rospy.Time.from_sec(stamp).to_nsec()}  # fmt: skip
    for name, (px, py) in (("nan", (math.nan, y)), ("inf", (x, math.inf)), ("outside", (x + 1000.0, y))):
        client.poses["tb3_0"].publish(_pose("tb3_0/map", px, py))
        time.sleep(0.5)
        results[name] = client.ask("tb3_0", name)
    client.poses["tb3_0"].publish(_pose("tb3_0/map", x, y))
    client.maps["tb3_0"].publish(_map(scene, scene["data"], "tb3_0/map", time.time() - 100.0))
    time.sleep(1.0)
    results["stale"] = client.ask("tb3_0", "stale")
    client.maps["tb3_0"].publish(_map(scene, scene["data"][:-7], "tb3_0/map"))  # not width × height long
    time.sleep(1.0)
    results["malformed"] = client.ask("tb3_0", "malformed")
    moved_stamp = time.time()  # the same map, placed elsewhere in its frame (a SLAM map that grew)
    client.poses["tb3_0"].publish(_pose("tb3_0/map", x + MOVE[0], y + MOVE[1]))
    client.maps["tb3_0"].publish(_map(scene, scene["data"], "tb3_0/map", moved_stamp, shift=MOVE))
    time.sleep(1.0)
    results |= {"moved": client.ask("tb3_0", "moved"), "moved_stamp": moved_stamp, "move": MOVE}
    print(json.dumps(results))


def big_maps(scene: Any) -> None:
    """Robot tb3_1's SLAM, in a process of its own: a 4000 × 4000 map each second, and a request
    after each, for 12 s."""
    client = Client(["tb3_1"])
    big = np.full((BIG, BIG), -1, np.int8)
    big[100 : BIG - 100, 100 : BIG - 100] = 0  # a wide free hall with walls of unknown around it
    big[1000:1010, 100 : BIG - 100] = 100
    origin = [float(v) for v in scene["origin"]]
    client.poses["tb3_1"].publish(_pose("tb3_1/map", origin[0] + 10.0, origin[1] + 10.0))
    answered = threading.Event()
    rospy.Subscriber("/frontier_status", String,
                     lambda m: answered.set() if json.loads(m.data)["robot"] == "tb3_1" else None)  # fmt: skip
    print(json.dumps({"started": True}), flush=True)
    end = time.monotonic() + 12.0
    while time.monotonic() < end:
        client.maps["tb3_1"].publish(_map(scene, big.reshape(-1), "tb3_1/map", width=BIG))
        time.sleep(0.2)
        client.request.publish(String("tb3_1 big"))
        time.sleep(0.8)
    answered.wait(timeout=30)
    print(json.dumps({"big_answered": answered.is_set()}))


def latency(scene: Any) -> None:
    """Robot tb3_0's requester: 20 requests a second for 8 s; the latency of each answer (s)."""
    client = Client(["tb3_0"])
    x, y = (float(v) for v in scene["pose"])
    client.poses["tb3_0"].publish(_pose("tb3_0/map", x, y))
    client.maps["tb3_0"].publish(_map(scene, scene["data"], "tb3_0/map"))
    time.sleep(1.0)
    client.ask("tb3_0", "warm")
    times: dict[str, float] = {}
    latencies: list[float] = []
    node_latencies: list[float] = []

    def on_status(msg: Any) -> None:
        status = json.loads(msg.data)
        if status["robot"] == "tb3_0" and status["request"] in times:
            latencies.append(time.monotonic() - times.pop(status["request"]))
            node_latencies.append(status["latency_s"])

    rospy.Subscriber("/frontier_status", String, on_status)
    time.sleep(0.5)
    end, count = time.monotonic() + 8.0, 0
    while time.monotonic() < end:
        count += 1
        times[str(count)] = time.monotonic()
        client.request.publish(String(f"tb3_0 {count}"))
        time.sleep(0.05)
    time.sleep(2.0)
    print(json.dumps({"latencies": latencies, "node_latencies": node_latencies, "asked": count}))


def first_answer(scene: Any, since: float) -> None:
    client = Client(["tb3_0"])
    x, y = (float(v) for v in scene["pose"])
    client.poses["tb3_0"].publish(_pose("tb3_0/map", x, y))
    client.maps["tb3_0"].publish(_map(scene, scene["data"], "tb3_0/map"))
    while True:
        try:
            result = client.ask("tb3_0", "probe", timeout=0.5)
        except queue.Empty:
            continue
        if result["poses"]:
            print(json.dumps({"seconds": time.time() - since, "frontiers": len(result["poses"]),
                              "poses": result["poses"], "status": result["status"]}))  # fmt: skip
            return
        time.sleep(0.5)


if __name__ == "__main__":
    scenario, scene_file = sys.argv[1], np.load(sys.argv[2])
    if scenario == "faults":
        faults(scene_file)
    elif scenario == "latency":
        latency(scene_file)
    elif scenario == "big_maps":
        big_maps(scene_file)
    else:
        first_answer(scene_file, float(sys.argv[3]))
