"""The ROS frontier node against a real roscore: its answer equals frontier_rl's own ranking of
the map at that weight, in the map frame; bad maps, unknown robots and early requests get empty
answers, a malformed map leaves the last good one in use, and the node keeps serving. Plus the
ROS-free conversion of map messages."""

from __future__ import annotations

import json
import math
import os
import shutil
import socket
import subprocess
import sys
import time
import xmlrpc.client
from collections.abc import Iterator
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from frontier_rl.core.frontiers.detection import detect_frontiers
from frontier_rl.core.frontiers.ranking import rank, weighted_cost
from frontier_rl.core.navigation.costmap import Costmap
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose
from frontier_rl.errors import FrontierRLError, MapError
from frontier_rl.io import load_map
from frontier_rl.robot.map_message import grid_from_message

pytestmark = pytest.mark.slow  # the ROS node against a real roscore

WEIGHT = 0.6
CLIENT = Path(__file__).with_name("ros_client.py")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return int(s.getsockname()[1])


def _ros_available() -> bool:
    from frontier_rl.ros.ros_messages import import_rospy

    try:
        import_rospy()
    except FrontierRLError:
        return False
    return shutil.which("roscore") is not None


@pytest.fixture(scope="module")
def ros_env(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, str]]:
    if not _ros_available():
        pytest.skip("ROS 1 not installed (make test installs it with apt-get where it can)")
    port = _free_port()
    uri = f"http://localhost:{port}"
    env = {**os.environ, "ROS_MASTER_URI": uri, "ROS_HOME": str(tmp_path_factory.mktemp("ros_home"))}
    core = subprocess.Popen(["roscore", "-p", str(port)], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        try:
            with xmlrpc.client.ServerProxy(uri) as master:
                master.getSystemState("/probe")
            break
        except OSError:
            time.sleep(0.2)
    else:
        core.kill()
        pytest.fail("roscore did not come up")
    yield env
    core.terminate()
    core.wait(timeout=30)


def _scene(real_maps: Path, tmp_path: Path) -> tuple[Path, dict[str, np.ndarray]]:
    """turtlebot3_world's map, seen only within 1.5 m of a pose (so that it has frontiers), with
    probabilities instead of 0 and 100 in places: a map as a running SLAM publishes it."""
    grid = load_map(real_maps / "turtlebot3_world" / "map.yaml").grid
    rows, cols = np.indices(grid.shape)
    free = np.argwhere(grid.data == CellState.FREE)
    centre = free[len(free) // 2]
    pose_xy = grid.cell_to_world(int(centre[0]), int(centre[1]))
    seen = np.hypot(rows - centre[0], cols - centre[1]) * grid.resolution <= 1.5
    data = np.where(seen, grid.data, CellState.UNKNOWN).astype(np.int16)
    rng = np.random.default_rng(0)
    noisy = rng.random(data.shape) < 0.2
    data[noisy & (data == CellState.FREE)] = 12  # still free (below 19.6)
    data[noisy & (data == CellState.OCCUPIED)] = 88  # still occupied (above 65)
    arrays = {
        "width": np.array(grid.width), "height": np.array(grid.height), "resolution": np.array(grid.resolution),
        "origin": np.array(grid.origin), "pose": np.array(pose_xy), "data": data.reshape(-1),
    }  # fmt: skip
    path = tmp_path / "scene.npz"
    np.savez(path, **arrays)  # type: ignore[arg-type]
    return path, arrays


def _expected(arrays: dict[str, np.ndarray]) -> list[list[float]]:
    """frontier_rl's own ranking of the map at WEIGHT, computed here from the core functions."""
    data = arrays["data"].reshape(int(arrays["height"]), int(arrays["width"]))
    cells = np.full(data.shape, CellState.UNKNOWN, np.int8)
    cells[(data >= 0) & (data < 19.6)] = CellState.FREE
    cells[data > 65] = CellState.OCCUPIED
    origin = (float(arrays["origin"][0]), float(arrays["origin"][1]))
    grid = OccupancyGrid(cells, float(arrays["resolution"]), origin)
    pose = Pose(float(arrays["pose"][0]), float(arrays["pose"][1]), 0.0)
    sim = SimConfig()
    costmap = Costmap.build(grid, sim.robot, sim.navigation)
    reachable = costmap.reachable_known(grid.world_to_cell(pose.x, pose.y))
    frontiers = detect_frontiers(grid, pose, reachable, 4)
    order = rank(weighted_cost(frontiers, WEIGHT))[:10]
    return [[float(frontiers.centers[i, 0]), float(frontiers.centers[i, 1])] for i in order]


def test_node_answers_with_frontier_rls_own_ranking(ros_env: dict[str, str], real_maps: Path, tmp_path: Path) -> None:
    scene, arrays = _scene(real_maps, tmp_path)
    expected = _expected(arrays)
    assert len(expected) >= 2, "the scene should have several frontiers"
    node = subprocess.Popen(
        [sys.executable, "-m", "frontier_rl.ros.node", "_robots:=tb3_0", f"_weight:={WEIGHT}"],
        env=ros_env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        client = subprocess.run(
            [sys.executable, str(CLIENT), str(scene)], env=ros_env, capture_output=True, text=True, timeout=180
        )
        assert client.returncode == 0, client.stderr[-2000:]
        weight, early, answer, unknown, malformed, again = (json.loads(line) for line in client.stdout.splitlines())
        assert weight["weight"] == pytest.approx(WEIGHT)
        assert early["poses"] == [] and unknown["poses"] == []
        assert answer["frame"] == "tb3_0/map"
        assert np.allclose(answer["poses"], expected, atol=1e-6)
        assert malformed == answer and again == answer  # the malformed map was refused, the good one kept
        assert node.poll() is None, "the node must still be running"
    finally:
        node.terminate()
        _, log = node.communicate(timeout=30)
    assert "rejected" in log and "unknown robot 'nobody'" in log and "no usable map" in log


@pytest.mark.parametrize(
    ("width", "height", "resolution", "length", "needle"),
    [
        (0, 5, 0.05, 0, "no cells"),
        (4, 5, 0.0, 20, "resolution"),
        (4, 5, float("nan"), 20, "resolution"),
        (4, 5, 0.05, 19, "expected width × height = 20"),
    ],
)
def test_malformed_map_messages_are_map_errors(
    width: int, height: int, resolution: float, length: int, needle: str
) -> None:
    with pytest.raises(MapError, match=needle):
        grid_from_message(width, height, resolution, [0] * length)


@pytest.mark.parametrize("resolution", [0.05, 0.1, 0.03, 0.04375, 0.025])
def test_a_float32_resolution_is_read_as_the_decimal_it_was_written_as(resolution: float) -> None:
    """nav_msgs/OccupancyGrid carries a float32: 0.05 arrives as 0.0500000007, and sizes counted in
    cells (the frontier drop) would differ from the simulator's on the same map."""
    sent = float(np.float32(resolution))
    assert sent != resolution
    assert grid_from_message(2, 2, sent, [0] * 4).resolution == resolution


@pytest.mark.parametrize("resolution", [1e39, 1e-50, 3.0e38])
def test_a_resolution_no_float32_holds_is_kept_as_it_is(resolution: float) -> None:
    assert grid_from_message(2, 2, resolution, [0] * 4).resolution == pytest.approx(resolution, rel=1e-6)


def test_probabilities_are_thresholded_like_map_server() -> None:
    grid = grid_from_message(5, 1, 0.05, [-1, 0, 19, 50, 66])
    assert grid.data.tolist() == [[CellState.UNKNOWN, CellState.FREE, CellState.FREE, CellState.UNKNOWN,
                                   CellState.OCCUPIED]]  # fmt: skip


@pytest.mark.parametrize("model", ["models/model4.zip", "models/model5.zip"])
def test_learned_models_rank_a_map_message(model: str, real_maps: Path, tmp_path: Path) -> None:
    if not Path(model).exists():
        pytest.skip("shipped model missing")
    from frontier_rl.policies import make_policy
    from frontier_rl.robot.ranking import rank_frontiers

    _, arrays = _scene(real_maps, tmp_path)
    grid = grid_from_message(int(arrays["width"]), int(arrays["height"]), float(arrays["resolution"]), arrays["data"])
    origin = arrays["origin"]
    pose = Pose(float(arrays["pose"][0] - origin[0]), float(arrays["pose"][1] - origin[1]), 0.0)
    ranked, weight = rank_frontiers(grid, pose, make_policy(f"learned:{model}"), top_k=10, rng=np.random.default_rng(0))
    assert 1 <= len(ranked) <= 10
    assert (weight is not None) == model.endswith("model4.zip")  # model 5 picks a frontier, not a weight


def test_map_frames_with_a_rotated_origin_round_trip() -> None:
    from frontier_rl.robot.answers import MapFrame

    frame = MapFrame("map", 2.0, -1.0, 0.7)
    gx, gy = frame.to_grid(3.5, 4.25)
    assert frame.to_map(gx, gy) == pytest.approx((3.5, 4.25))
    assert frame.to_map(0.0, 0.0) == pytest.approx((2.0, -1.0))


def _message(x: float, y: float, stamp_ns: int) -> SimpleNamespace:
    """A stand-in for a ``nav_msgs/OccupancyGrid`` of 3 × 2 cells at origin (x, y), yaw 90°."""
    q = SimpleNamespace(x=0.0, y=0.0, z=math.sin(math.pi / 4), w=math.cos(math.pi / 4))
    origin = SimpleNamespace(position=SimpleNamespace(x=x, y=y, z=0.0), orientation=q)
    return SimpleNamespace(
        header=SimpleNamespace(frame_id="tb3_0/map", stamp=SimpleNamespace(to_nsec=lambda: stamp_ns)),
        info=SimpleNamespace(width=3, height=2, resolution=0.05, origin=origin),
        data=[0, 0, -1, 100, 0, -1],
    )


def test_a_map_message_carries_where_it_lies_and_when_it_was_made() -> None:
    from frontier_rl.ros.ros_messages import map_cells

    stamp_ns = 1_764_230_400_123_456_789  # a stamp of 2025: no float64 of seconds holds it to the nanosecond
    cells = map_cells(_message(1.5, -2.0, stamp_ns), sequence=4, now_s=99.0)
    info = cells.info
    assert (info.frame.frame_id, info.frame.x, info.frame.y) == ("tb3_0/map", 1.5, -2.0)
    assert info.frame.yaw == pytest.approx(math.pi / 2)
    assert (info.width, info.height, info.resolution, info.stamp_ns, info.sequence) == (3, 2, 0.05, stamp_ns, 4)
    assert cells.data.tolist() == [0, 0, -1, 100, 0, -1]
    assert map_cells(_message(1.5, -2.0, 0), sequence=0, now_s=99.0).info.stamp_s == 99.0  # no stamp: arrival


@pytest.mark.parametrize(
    ("x", "y", "needle"),
    [(math.nan, 0.0, "finite"), (0.0, math.inf, "finite"), (1e16, 0.0, "within"), (0.0, -2e6, "within")],
)
def test_a_map_origin_that_is_not_finite_or_too_far_is_a_map_error(x: float, y: float, needle: str) -> None:
    """At 10^16 m a float64 no longer tells the map's cells apart."""
    from frontier_rl.ros.ros_messages import map_cells

    with pytest.raises(MapError, match=f"map origin must (be|lie) {needle}"):
        map_cells(_message(x, y, 1), sequence=0, now_s=1.0)
    map_cells(_message(-1e6, 1e6, 1), sequence=0, now_s=1.0)  # at the bound: a map
