"""Drives the frontier node from outside over a real ROS master (run by tests/ros/test_node.py).

Reads the scenario (map arrays, pose) from an .npz given as argv[1], then, in order: a request
before any map, the map and pose, a request, a request for an unknown robot, a malformed map and a
request, the good map again and a request. Prints one JSON line per answer: the frame and the
(x, y) of every pose.
"""

from __future__ import annotations

import json
import queue
import sys
import time

import numpy as np

from frontier_rl.ros.ros_messages import import_rospy

rospy = import_rospy()
from geometry_msgs.msg import PoseArray, PoseStamped  # noqa: E402
from nav_msgs.msg import OccupancyGrid  # noqa: E402
from std_msgs.msg import Float32, String  # noqa: E402


def main() -> None:
    scene = np.load(sys.argv[1])
    rospy.init_node("frontier_test_client", anonymous=True, disable_signals=True)
    weights: queue.Queue[Float32] = queue.Queue()
    rospy.Subscriber("/frontier_weight", Float32, weights.put)  # latched: arrives on connecting
    answers: queue.Queue[PoseArray] = queue.Queue()
    rospy.Subscriber("/frontier_list", PoseArray, answers.put)
    request = rospy.Publisher("/frontier_request", String, queue_size=10)
    maps = rospy.Publisher("/tb3_0/map", OccupancyGrid, queue_size=1, latch=True)
    poses = rospy.Publisher("/tb3_0/robot_pose", PoseStamped, queue_size=1, latch=True)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline and (request.get_num_connections() == 0 or maps.get_num_connections() == 0):
        time.sleep(0.1)
    time.sleep(0.5)

    def ask(name: str) -> None:
        request.publish(String(name))
        answer = answers.get(timeout=20)
        print(
            json.dumps({"frame": answer.header.frame_id, "poses": [[p.position.x, p.position.y] for p in answer.poses]})
        )
        sys.stdout.flush()

    def publish_map(data: np.ndarray) -> None:
        msg = OccupancyGrid()
        msg.header.frame_id = "tb3_0/map"
        msg.info.resolution = float(scene["resolution"])
        msg.info.width, msg.info.height = int(scene["width"]), int(scene["height"])
        msg.info.origin.position.x, msg.info.origin.position.y = (float(v) for v in scene["origin"])
        msg.info.origin.orientation.w = 1.0
        msg.data = [int(v) for v in data]
        maps.publish(msg)
        time.sleep(1.0)

    print(json.dumps({"weight": weights.get(timeout=20).data}))
    ask("tb3_0")  # before any map
    pose = PoseStamped()
    pose.header.frame_id = "tb3_0/map"
    pose.pose.position.x, pose.pose.position.y = (float(v) for v in scene["pose"])
    pose.pose.orientation.w = 1.0
    poses.publish(pose)
    publish_map(scene["data"])
    ask("tb3_0")
    ask("nobody")
    publish_map(scene["data"][:-7])  # malformed: the data is not width × height long
    ask("tb3_0")
    publish_map(scene["data"])
    ask("tb3_0")


if __name__ == "__main__":
    main()
