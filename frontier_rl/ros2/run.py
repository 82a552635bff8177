"""Running the ROS 2 nodes as processes: rclpy started and stopped around one node, Ctrl-C and
SIGTERM ending it with a summary, not a traceback."""

from __future__ import annotations

import contextlib
import signal
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import replace

import numpy as np
import rclpy
from rclpy.exceptions import NameValidationException, ParameterException
from rclpy.executors import Executor, ExternalShutdownException, SingleThreadedExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.core.sim.metrics import time_to_coverage
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError
from frontier_rl.robot.explorer import FrontierExplorer
from frontier_rl.robot.explorer_params import ExplorerParams
from frontier_rl.robot.pose_source import PoseSource
from frontier_rl.robot.ranking_service import RankingService, ServiceSettings
from frontier_rl.robot.sim_robot import SimulatedRobot
from frontier_rl.ros2.explorer_node import ExplorerNode
from frontier_rl.ros2.explorer_options import ExplorerNodeOptions
from frontier_rl.ros2.explorer_status import ExplorerState, ExplorerStatus
from frontier_rl.ros2.ranking_node import RankingNode
from frontier_rl.ros2.ros_args import ros_args_error
from frontier_rl.ros2.sim_node import SimNode
from frontier_rl.swarm.config import TeamConfig
from frontier_rl.swarm.starts import team_starts

_INVALID_CONTEXT = "context is invalid"
"""What rclpy says of a node, publisher or action server made after a Ctrl-C shut its context down."""


@contextlib.contextmanager
def _ros_setup_errors() -> Iterator[None]:
    """rclpy's refusals while a node is set up as one-line errors: a name ROS does not allow (a
    namespace or topic, also one remapped with ``--ros-args -r``), ``--ros-args`` rcl cannot parse.
    rclpy is shut down again (as it is on any error there)."""
    try:
        yield
    except NameValidationException as error:
        rclpy.try_shutdown()
        raise ConfigError(str(error).splitlines()[0].rstrip(":")) from None
    except ParameterException as error:  # a ROS parameter of the wrong type (-p use_sim_time:=3)
        rclpy.try_shutdown()
        raise ConfigError(f"--ros-args: {error}") from None
    except (rclpy_implementation.RCLError, rclpy_implementation.UnknownROSArgsError, ValueError) as error:
        rclpy.try_shutdown()
        if _INVALID_CONTEXT in str(error):  # rclpy's own Ctrl-C handler shut the context as the node was made
            raise KeyboardInterrupt from None
        problem = ros_args_error(error)
        if problem is None:
            raise
        raise problem from None
    except BaseException:
        rclpy.try_shutdown()
        raise


def _spin(spin: Callable[[], None]) -> None:
    """Run ``spin`` until it ends or Ctrl-C, SIGTERM shut rclpy down; an error of the executor
    racing that shutdown (its wait set made on a context just shut down) is the same end."""
    try:
        spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except Exception:
        if rclpy.ok():
            raise


SPIN_POLL_S = 0.1
"""How often (s) a served node's executor wakes to see whether Ctrl-C or SIGTERM ended rclpy."""


def _spin_until(executor: Executor, finished: Callable[[], bool] = lambda: False) -> None:
    """Spin ``executor`` until rclpy is shut down or ``finished()``, waking every
    :data:`SPIN_POLL_S` to look (see :func:`_serve`)."""
    while rclpy.ok() and not finished():
        executor.spin_once(timeout_sec=SPIN_POLL_S)


def _serve(node: Node) -> None:
    """Spin ``node`` on an executor of its own until Ctrl-C or SIGTERM, then shut the executor down
    before destroying the node, as :func:`run_explorer` does. The executor waits at most
    :data:`SPIN_POLL_S` at a time: now and then a Ctrl-C did not wake a wait with no timeout, and
    ``ros2 rank`` went on waiting with nothing more to receive (spun by ``rclpy.spin``, the global
    executor, it hung in ``destroy_node`` instead; the stacks a test's ``stop`` had it write). Why
    rclpy's signal handling missed the wait is not known."""
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    try:
        _spin(lambda: _spin_until(executor))
    finally:
        executor.shutdown()
        node.destroy_node()


def simulated_team(
    world: World, namespaces: Sequence[str], seed: int = 0, config: SimConfig | None = None
) -> list[tuple[str, SimulatedRobot]]:
    """A robot per namespace in ``world``: the first on its start, the others beside it (as a
    team is set down, :func:`~frontier_rl.swarm.starts.team_starts`); each seeded from ``seed``
    (the first as an in-process episode of that seed)."""
    config = config or SimConfig()
    starts = team_starts(world, len(namespaces), config.robot.radius, TeamConfig().spacing_for(config.robot.radius))
    seeds = [seed, *(int(s.generate_state(1)[0]) for s in np.random.SeedSequence(seed).spawn(len(namespaces) - 1))]
    return [
        (namespace, SimulatedRobot(replace(world, start=start), config, robot_seed))
        for namespace, start, robot_seed in zip(namespaces, starts, seeds, strict=True)
    ]


CANCEL_WAIT_S = 2.0
"""How long a stopped explorer waits for Nav2 to answer the cancel of its goal (s)."""


@contextlib.contextmanager
def _stop_requests(stop: threading.Event) -> Iterator[None]:
    """Ctrl-C and SIGTERM set ``stop`` inside the block (even where Ctrl-C was ignored, a shell's
    background job, as rclpy's own handlers would), instead of shutting rclpy down at once: the
    explorer then still has ROS to cancel its goal with. The handlers before are put back after."""
    if threading.current_thread() is not threading.main_thread():  # only the main thread sets handlers
        yield
        return
    previous = {sig: signal.signal(sig, lambda signum, frame: stop.set()) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _cancel_goal(executor: Executor, node: ExplorerNode) -> bool:
    """Cancel the explorer's goal under way and wait (up to :data:`CANCEL_WAIT_S`) for Nav2's
    answer; whether Nav2 accepted the cancel."""
    future = node.cancel_goal()
    if future is None:
        return False
    deadline = time.monotonic() + CANCEL_WAIT_S
    while not future.done() and time.monotonic() < deadline and rclpy.ok():
        executor.spin_once(timeout_sec=SPIN_POLL_S)
    return future.done() and bool(future.result())


def run_sim(
    robots: Sequence[tuple[str, SimulatedRobot]], rate: float | None = 1.0, ros_args: Sequence[str] = ()
) -> list[str]:
    """Serve the robots as ROS 2 robots (:class:`SimNode`) until Ctrl-C or SIGTERM; a line per
    robot on what it did. ``ros_args``: ROS's arguments (``--ros-args -r ...``)."""
    with _ros_setup_errors():
        rclpy.init(args=["frontier-rl", *ros_args])
        node = SimNode(robots, rate)
    try:
        _serve(node)
    finally:
        rclpy.try_shutdown()
    lines = []
    for port in node.ports:
        result = port.robot.result()
        # when its map last grew: the shared clock runs on after a robot's explorer has finished
        mapped_s = time_to_coverage(result.coverage_times_s, result.coverage_curve, result.coverage) or 0.0
        lines.append(
            f"{port.namespace or 'robot'}: {port.goals} goals, {100 * result.coverage:.1f} % of the explorable space "
            f"mapped in {mapped_s:.1f} s of simulated time (of {result.sim_time_s:.1f} s served), "
            f"{result.path_length_m:.1f} m driven"
        )
    return lines


def run_ranking(
    settings: ServiceSettings,
    pose_source: PoseSource | None = None,
    use_sim_time: bool = False,
    ros_args: Sequence[str] = (),
) -> int:
    """Serve the ranking service (:class:`RankingNode`), each robot's pose from ``pose_source`` (in
    its namespace; a pose topic by default), until Ctrl-C or SIGTERM; the requests
    answered. ``use_sim_time`` sets the parameter (else ``ros_args``, ROS's arguments, may). Its
    workers start before rclpy: starting them holds Ctrl-C with Python's own handlers, which would
    replace rclpy's."""
    service = RankingService(settings)
    try:
        if not service.start(lambda: False):  # a Ctrl-C meanwhile is a KeyboardInterrupt
            return 0
        with _ros_setup_errors():
            rclpy.init(args=["frontier-rl", *ros_args])
            node = RankingNode(service, pose_source)
        if use_sim_time:
            node.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
        node.get_logger().info(f"ranking for robots {list(settings.robots)} with {service.policy_name}")
        _serve(node)
    except KeyboardInterrupt:  # while the workers start
        pass
    finally:
        service.close()
        rclpy.try_shutdown()
    return service.answered


def run_explorer(
    policy: ExplorationPolicy, params: ExplorerParams, options: ExplorerNodeOptions | None = None
) -> tuple[ExplorerStatus, str]:
    """Explore with ``policy`` and its settings ``params`` through Nav2 (:class:`ExplorerNode`, run as
    ``options`` say) until the map is explored (or Ctrl-C, SIGTERM: then the goal under way is
    cancelled, and the robot stops): the explorer's last status (``state`` is ``finished`` unless it
    was interrupted) and its summary line.

    Raises:
        ConfigError: the options' ``ros_args`` override a parameter with a bad value, or name what
            ROS does not allow; or Nav2 has not a plugin the goals name (the run ends at once).
    """
    options = options or ExplorerNodeOptions()
    _, policy_rng = np.random.default_rng(options.seed).spawn(2)
    explorer = FrontierExplorer(policy, params, rng=policy_rng)
    with _ros_setup_errors():
        rclpy.init(args=["frontier-rl", *options.ros_args], signal_handler_options=SignalHandlerOptions.NO)
        node = ExplorerNode(explorer, options)
    if options.use_sim_time:  # else as --ros-args say (-p use_sim_time:=true, a params file)
        node.set_parameters([Parameter("use_sim_time", Parameter.Type.BOOL, True)])
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    stop, cancelled = threading.Event(), False
    try:
        with _stop_requests(stop):
            _spin(lambda: _spin_until(executor, lambda: node.done.done() or stop.is_set()))
            cancelled = _cancel_goal(executor, node)  # on any end: the robot must not drive on to it
    finally:
        ended = node.finished is not None
        status = node.status(ExplorerState.FINISHED if ended else ExplorerState.INTERRUPTED, "")
        summary = node.summary() if ended else "interrupted before the map was explored"
        if cancelled:
            summary += "; Nav2's goal under way cancelled"
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
    if node.plugin_error is not None:
        raise ConfigError(node.plugin_error)
    return status, summary
