"""Latency of the ROS frontier node against a real roscore: 1 and 4 robots, each publishing its map
once a second and asking ``--rate`` times a second (10), on maps the package ships, with a fixed weight, model
5, ``tour`` and model 7. Prints one JSON line per run and a Markdown table (median and 99th percentile of the time
from publishing a request to receiving its status line, in the requesting process).

    .venv/bin/python benchmarks/ros_latency.py [--maps FOLDER] [--seconds 10] [--rate 10] [--robots 1,4]
        [--map-names turtlebot3_world,nav2_depot] [--policies "model 5"]
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
import xmlrpc.client
from pathlib import Path
from typing import Any

import numpy as np

from frontier_rl.io.catalogue import MAPS_DIR

REPO = Path(__file__).resolve().parents[1]
MAPS = {"turtlebot3_world": "turtlebot3_world/map.yaml", "nav2_depot": "nav2_depot/depot.yaml",
        "nav2_warehouse": "nav2_warehouse/warehouse.yaml"}  # fmt: skip
POLICIES = {
    "fixed:0.75": ["_weight:=0.75"],
    "model 5": ["_model:=models/model5.zip"],
    "tour": ["_policy:=tour"],
    "model 7": ["_policy:=learned:models/model7.zip"],
}
NODE_PARAMETERS = "/frontier_rl"
"""The node's private parameters (its name is ``frontier_rl``)."""
CLIENT_TIMEOUT_S = 600.0
SEEN_M = 3.0
"""The maps are published as seen within this distance of the robot (so that they have frontiers)."""


def _scene(map_file: Path, out: Path) -> Path:
    """The map seen within SEEN_M of its middle free cell, as a SLAM would publish it early on."""
    from frontier_rl.core.world.grid import CellState
    from frontier_rl.io import load_map

    grid = load_map(map_file).grid
    free = np.argwhere(grid.data == CellState.FREE)
    centre = free[len(free) // 2]
    rows, cols = np.indices(grid.shape)
    seen = np.hypot(rows - centre[0], cols - centre[1]) * grid.resolution <= SEEN_M
    values = np.where(seen & (grid.data == CellState.FREE), 0, -1)
    values = np.where(seen & (grid.data == CellState.OCCUPIED), 100, values).astype(np.int8)
    np.savez(out, width=grid.width, height=grid.height, resolution=grid.resolution, origin=np.array(grid.origin),
             pose=np.array(grid.cell_to_world(int(centre[0]), int(centre[1]))), data=values.reshape(-1))  # fmt: skip
    return out


def client(scene_file: str, robots: int, seconds: float, rate: float) -> None:
    """The robots' side: maps at 1 Hz and ``rate`` requests per second per robot; prints the latencies."""
    from frontier_rl.ros.ros_messages import import_rospy

    rospy = import_rospy()
    from geometry_msgs.msg import PoseStamped
    from nav_msgs.msg import OccupancyGrid
    from rospy.numpy_msg import numpy_msg
    from std_msgs.msg import String

    class Cells(np.ndarray):  # Debian's generated numpy_msg code still calls tostring (gone in NumPy 2)
        def tostring(self) -> bytes:  # type: ignore[override]
            return self.tobytes()

    scene = np.load(scene_file)
    rospy.init_node("latency_client", anonymous=True, disable_signals=True)
    names = [f"tb3_{i}" for i in range(robots)]
    sent: dict[str, float] = {}
    latencies: list[float] = []
    ranked: list[int] = []

    def on_status(msg: String) -> None:
        status = json.loads(msg.data)
        key = f"{status['robot']} {status['request']}"
        if key in sent:
            latencies.append(time.monotonic() - sent.pop(key))
            ranked.append(int(status["frontiers"] > 0))

    rospy.Subscriber("/frontier_status", String, on_status)
    request = rospy.Publisher("/frontier_request", String, queue_size=1000)
    maps = {n: rospy.Publisher(f"/{n}/map", numpy_msg(OccupancyGrid), queue_size=1, latch=True) for n in names}
    poses = {n: rospy.Publisher(f"/{n}/robot_pose", PoseStamped, queue_size=1, latch=True) for n in names}
    while any(p.get_num_connections() == 0 for p in [request, *maps.values(), *poses.values()]):
        time.sleep(0.1)

    def publish_maps() -> None:
        for name in names:
            msg = numpy_msg(OccupancyGrid)()
            msg.header.frame_id, msg.header.stamp = f"{name}/map", rospy.Time.now()
            msg.info.resolution = float(scene["resolution"])
            msg.info.width, msg.info.height = int(scene["width"]), int(scene["height"])
            msg.info.origin.position.x, msg.info.origin.position.y = (float(v) for v in scene["origin"])
            msg.info.origin.orientation.w = 1.0
            msg.data = scene["data"].view(Cells)
            maps[name].publish(msg)

    for name in names:
        pose = PoseStamped()
        pose.header.frame_id = f"{name}/map"
        pose.pose.position.x, pose.pose.position.y = (float(v) for v in scene["pose"])
        pose.pose.orientation.w = 1.0
        poses[name].publish(pose)
    publish_maps()
    time.sleep(2.0)
    start, count, next_map = time.monotonic(), 0, time.monotonic() + 1.0
    while time.monotonic() - start < seconds:
        count += 1
        for name in names:
            sent[f"{name} {count}"] = time.monotonic()
            request.publish(String(f"{name} {count}"))
        if time.monotonic() >= next_map:
            publish_maps()
            next_map += 1.0
        time.sleep(max(0.0, start + count / rate - time.monotonic()))
    time.sleep(3.0)
    print(json.dumps({"latencies": latencies, "ranked": sum(ranked), "asked": count * robots}))


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return int(s.getsockname()[1])


def _forget_node_parameters(env: dict[str, str]) -> None:
    """Delete the node's private parameters: the parameter server keeps them after a node exits, and
    the next row's node would read the last row's ``~model`` beside its own ``~policy``."""
    with xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"]) as master:
        master.deleteParam("/latency_bench", NODE_PARAMETERS)  # an error code, not an exception, when there are none


def _run_client(command: list[str], env: dict[str, str], node: subprocess.Popen[bytes], log: Path) -> dict[str, Any]:
    """Run the requesting process to its end and return what it printed; stop with the node's last
    log lines if the node exits first (the client would wait for it for ever) or after CLIENT_TIMEOUT_S."""
    client = subprocess.Popen(command, env=env, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + CLIENT_TIMEOUT_S
    while True:
        try:
            out, err = client.communicate(timeout=0.5)
            break
        except subprocess.TimeoutExpired:
            if node.poll() is None and time.monotonic() < deadline:
                continue
            client.kill()
            client.communicate()
            ended = node.returncode is not None
            why = f"the node exited with {node.returncode}" if ended else f"no result in {CLIENT_TIMEOUT_S:g} s"
            sys.exit(f"{why}; the node's log ends:\n" + "\n".join(log.read_text().splitlines()[-5:]))
    if client.returncode:
        sys.exit(f"the client failed ({client.returncode}): {err.strip().splitlines()[-1:]}")
    return dict(json.loads(out.splitlines()[-1]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", type=Path, default=MAPS_DIR, help="the maps folder (default: the package's)")
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--rate", type=float, default=10.0, help="requests per second per robot")
    parser.add_argument("--robots", default="1,4", help="team sizes, e.g. 1,4")
    parser.add_argument("--map-names", default=",".join(MAPS), help=f"which maps (of {', '.join(MAPS)})")
    parser.add_argument("--policies", default=",".join(POLICIES), help=f"which policies (of {', '.join(POLICIES)})")
    args = parser.parse_args()
    maps, policies = args.map_names.split(","), args.policies.split(",")
    for name, known in [*((m, MAPS) for m in maps), *((p, POLICIES) for p in policies)]:
        if name not in known:
            parser.error(f"unknown name {name!r} (known: {', '.join(known)})")
    port = _free_port()
    home = tempfile.mkdtemp(prefix="ros_latency_")
    env = {**os.environ, "ROS_MASTER_URI": f"http://localhost:{port}", "ROS_HOME": home}
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)  # fmt: skip
    while True:
        with contextlib.suppress(OSError), xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"]) as master:
            master.getSystemState("/probe")
            break
        time.sleep(0.2)
    rows = []
    try:
        for map_name in maps:
            scene = _scene(args.maps / MAPS[map_name], Path(home) / f"{map_name}.npz")
            for policy in policies:
                params = POLICIES[policy]
                for robots in (int(n) for n in args.robots.split(",")):
                    names = ",".join(f"tb3_{i}" for i in range(robots))
                    _forget_node_parameters(env)
                    log = Path(home) / "node.log"
                    with log.open("a") as out:
                        node = subprocess.Popen([sys.executable, "-m", "frontier_rl.ros.node", f"_robots:={names}",
                                                 "_max_map_age:=0", *params], env=env, cwd=REPO,
                                                stdout=out, stderr=subprocess.STDOUT)  # fmt: skip
                    try:
                        command = [sys.executable, __file__, "--client", str(scene), str(robots), str(args.seconds),
                                   str(args.rate)]  # fmt: skip
                        result = _run_client(command, env, node, log)
                    finally:
                        node.send_signal(signal.SIGINT)
                        node.wait(timeout=60)
                    ms = 1000 * np.asarray(result["latencies"])
                    row = {"map": map_name, "policy": policy, "robots": robots, "asked": result["asked"],
                           "answered": len(ms), "ranked": result["ranked"], "median_ms": float(np.median(ms)),
                           "p99_ms": float(np.percentile(ms, 99))}  # fmt: skip
                    print(json.dumps(row), flush=True)
                    rows.append(row)
    finally:
        core.send_signal(signal.SIGINT)
        core.wait(timeout=60)
    print("\n| map | policy | robots | median (ms) | p99 (ms) | answered | with frontiers |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['map']} | {r['policy']} | {r['robots']} | {r['median_ms']:.1f} | {r['p99_ms']:.1f} | "
              f"{r['answered']} / {r['asked']} | {r['ranked']} |")  # fmt: skip


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--client":
        client(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]))
    else:
        main()
