"""How the ROS 2 explorer node is run, besides its exploration settings
(:class:`~frontier_rl.robot.explorer_params.ExplorerParams`): its names, its pose, its clock and
what it hands to ROS. ROS-free, so that the command line checks them before rclpy loads."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from frontier_rl.errors import ConfigError, SettingError
from frontier_rl.robot.explorer_params import Nav2Plugins
from frontier_rl.robot.pose_source import PoseSource
from frontier_rl.seeds import MAX_SEED, checked_seed


@dataclass(frozen=True)
class ExplorerNodeOptions:
    """The explorer node's options.

    Attributes:
        namespace: the robot's namespace ("" for none): its map, pose, Nav2 action and the node's topics.
        teammates: the namespaces of robots whose maps (``/NAMESPACE/map``, in this robot's map frame)
            are merged into this one's (:func:`~frontier_rl.robot.map_merge.merged_map`): the explorer
            does not send the robot where a teammate has been. The merged map is published on
            ``explore/merged_map`` (latched, as map_server's) at each planner tick: a robot's Nav2 plans
            on it with its global costmap's static layer reading that topic. Kept without surrounding
            blanks and slashes.
        pose_source: where the robot's pose in the map comes from: a pose or odometry topic, or ``tf``
            (None: a ``PoseWithCovarianceStamped`` on the namespace's ``pose`` topic).
        visualize: publish the frontiers and the goal as RViz markers on ``explore/frontiers``.
        use_sim_time: take time from ``/clock`` (a simulator's).
        nav2_plugins: the Nav2 plugins its goals name (the node's parameters of the same names).
        seed: seeds the policy's randomness as an in-process episode of that seed does.
        goal_silence_timeout: a goal that Nav2 says nothing of (no response, feedback or result) for
            this long (wall s) is dropped, not blacklisted: its action server went away.
        policy_name: the policy as given, shown as the node's read-only parameter ``policy`` ("" for
            the policy's own name).
        ros_args: ROS's own arguments (``--ros-args ...``): parameter overrides, remappings.

    Raises:
        SettingError: a goal silence timeout that is not a positive number of seconds, teammates that
            are not other robots' namespaces, each once, or a seed that is none (naming the field, which
            a command line names as its option).
    """

    namespace: str = ""
    teammates: tuple[str, ...] = ()
    pose_source: PoseSource | None = None
    visualize: bool = True
    use_sim_time: bool = False
    nav2_plugins: Nav2Plugins = field(default_factory=Nav2Plugins)
    seed: int = 0
    goal_silence_timeout: float = 10.0
    policy_name: str = ""
    ros_args: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        timeout = self.goal_silence_timeout
        if not (math.isfinite(timeout) and timeout > 0):
            raise SettingError("goal_silence_timeout", f"must be a positive number of seconds, got {timeout!r}")
        names = tuple(name.strip().strip("/") for name in self.teammates)
        if "" in names or self.namespace.strip("/") in names or len(set(names)) < len(names):
            given = ",".join(self.teammates)
            raise SettingError("teammates", f"must name other robots' namespaces, each once, got {given!r}")
        try:
            checked_seed(self.seed)
        except ConfigError:
            raise SettingError("seed", f"must be a whole number from 0 to {MAX_SEED}, got {self.seed!r}") from None
        object.__setattr__(self, "teammates", names)
