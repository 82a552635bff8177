"""Running the ROS 2 nodes as processes: rclpy started and stopped around one node, Ctrl-C and
SIGTERM ending it with a summary, not a traceback."""

from __future__ import annotations

import numpy as np
import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.parameter import Parameter

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.core.world.worlds import World
from frontier_rl.robot.explorer import ExplorerParams, FrontierExplorer
from frontier_rl.robot.sim_robot import SimulatedRobot
from frontier_rl.ros2.explorer_node import ExplorerNode, ExplorerStatus
from frontier_rl.ros2.sim_node import SimNode


def run_sim(
    world: World, seed: int = 0, rate: float | None = 1.0, namespace: str = "", config: SimConfig | None = None
) -> str:
    """Serve ``world`` as a ROS 2 robot (:class:`SimNode`) until Ctrl-C or SIGTERM; one line on
    what the robot did."""
    rclpy.init()
    node = SimNode(SimulatedRobot(world, config, seed), rate, namespace)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        result = node.robot.result()
        node.destroy_node()
        rclpy.try_shutdown()
    return (
        f"{node.goals} goals, {100 * result.coverage:.1f} % of the explorable space mapped in "
        f"{result.sim_time_s:.1f} s of simulated time, {result.path_length_m:.1f} m driven"
    )


def run_explorer(
    policy: ExplorationPolicy,
    params: ExplorerParams,
    *,
    namespace: str = "",
    pose_topic: str = "pose",
    pose_type: str = "pose",
    visualize: bool = True,
    use_sim_time: bool = False,
    seed: int = 0,
    goal_silence_timeout: float = 10.0,
) -> tuple[ExplorerStatus, str]:
    """Explore with ``policy`` through Nav2 (:class:`ExplorerNode`) until the map is explored (or
    Ctrl-C, SIGTERM): the explorer's last status (``state`` is ``finished`` unless it was
    interrupted) and its summary line.
    ``seed`` seeds the policy's randomness as an in-process episode of that seed does."""
    rclpy.init()
    _, policy_rng = np.random.default_rng(seed).spawn(2)
    explorer = FrontierExplorer(policy, params, rng=policy_rng)
    node = ExplorerNode(explorer, pose_topic, pose_type, visualize, namespace, goal_silence_timeout)
    node.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, use_sim_time)])
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        executor.spin_until_future_complete(node.done)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        ended = node.finished is not None
        status = node.status("finished" if ended else "interrupted", "")
        summary = node.summary() if ended else "interrupted before the map was explored"
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    return status, summary
