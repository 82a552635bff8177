"""``frontier-rl ros2``: the explorer that drives a robot through Nav2 (``explore``), the thesis's
ranking service (``rank``), and the simulator as ROS 2 robots to try them on (``sim``). The ``ros2``
extra; rclpy loads only here, once the arguments are checked."""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import fields
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, NamedTuple

import typer

from frontier_rl.cli.options import MAX_SEED, WORLD_HELP, fail
from frontier_rl.cli.output import OneLineGroup, friendly_errors, print_line, print_note
from frontier_rl.errors import SettingError
from frontier_rl.robot.explorer_params import ExplorerParams, Nav2Plugins, setting_help, time_cap_of_parameter
from frontier_rl.ros2.explorer_options import ExplorerNodeOptions
from frontier_rl.seeds import checked_seed
from frontier_rl.swarm.config import MAX_ROBOTS  # ros2 sim runs as many robots as a team of explore

if TYPE_CHECKING:
    from frontier_rl.robot.pose_source import PoseSource

ros2_app = typer.Typer(
    no_args_is_help=True,
    cls=OneLineGroup,
    help="ROS 2: explore with Nav2, or run a world as ROS 2 robots.",
)

_NO_ROS2 = (
    "ROS 2 is not installed in this environment: `make setup` (or pip install -e '.[ros2]' and "
    "python tools/build_ros2_interfaces.py) installs rclpy and builds nav2_msgs"
)


def _need_ros2() -> None:
    """A one-line error when rclpy or nav2_msgs cannot be imported."""
    try:
        import nav2_msgs.action  # noqa: F401
        import rclpy  # noqa: F401
    except ImportError as error:
        fail(f"{_NO_ROS2} ({error})")


ParamsFileOption = Annotated[
    list[Path] | None,
    typer.Option(help="A parameter file (explore_lite's explore.yaml), for what is not given here; repeatable."),
]


_WITH_ROS_ARGS = {"allow_extra_args": True, "ignore_unknown_options": True}
"""A command that takes ROS's arguments after its own (``--ros-args ...``: :func:`_ros_args`)."""


def _setting(name: str) -> Any:
    """The option of the explorer's setting ``name``, its help the setting's own."""
    return typer.Option(help=setting_help(name))


def _explorer_params(options: dict[str, Any]) -> ExplorerParams:
    """The explorer's settings among ``options`` (setting name -> value; a time cap of 0: none);
    a one-line error naming the option that is out of range (a file's values are checked as it is read)."""
    if not options["time_cap"] >= 0:
        fail(f"--time-cap must be a number of seconds (0: never), got {options['time_cap']!r}")
    settings = {setting.name: options[setting.name] for setting in fields(ExplorerParams) if setting.name in options}
    try:
        return ExplorerParams(**settings | {"time_cap": time_cap_of_parameter(options["time_cap"])})
    except SettingError as error:
        fail(f"{_option(error.setting)} {error.problem}")


def _with_parameter_files(ctx: typer.Context, paths: Sequence[Path], options: dict[str, Any]) -> dict[str, Any]:
    """``options`` with the values of the parameter files ``paths`` (in order: a later file's win)
    for those not given on the command line; what a file sets that means nothing here is named on
    standard error."""
    from frontier_rl.robot.explore_lite_file import explore_lite_parameters

    for path in paths:
        known, ignored = explore_lite_parameters(path)
        for name, value in known.items():
            source = ctx.get_parameter_source(name) if name in options else None  # None: no such option
            if source is None or source in (type(source).DEFAULT, type(source).DEFAULT_MAP):  # typer's own click
                options[name] = value
        if ignored:
            print_note(f"{path}: not used here: {', '.join(ignored)}")
    return options


def _ros_ready(
    ros_args: Sequence[str], namespaces: dict[str, Sequence[str]], pose_source: PoseSource | None = None
) -> None:
    """A one-line error, before a model loads or workers start, when ROS 2 cannot be imported,
    ``rclpy.init`` would refuse ROS's arguments ``ros_args``, or rclpy's own rules do not allow a
    namespace (``namespaces`` maps options to them; the option is named) or the pose topic."""
    _need_ros2()
    from rclpy.exceptions import NameValidationException
    from rclpy.validate_namespace import validate_namespace
    from rclpy.validate_topic_name import validate_topic_name

    from frontier_rl.robot.pose_source import PoseKind
    from frontier_rl.ros2.ros_args import check_ros_args

    check_ros_args(ros_args)  # a ConfigError: one line, exit status 2

    checks: list[tuple[str, str, Callable[[], object]]] = [
        (option, name, partial(validate_namespace, "/" + name.strip("/")))
        for option, names in namespaces.items()
        for name in names
        if name.strip("/")  # none: the root
    ]
    if pose_source is not None and pose_source.kind is not PoseKind.TF:
        checks.append(("--pose-topic", pose_source.topic, partial(validate_topic_name, pose_source.topic)))
    for option, name, validate in checks:
        try:
            validate()
        except NameValidationException as error:
            problem = str(error).splitlines()[0].rstrip(":").split(": ", 1)[-1]
            fail(f"{option} {name!r} is not a name ROS 2 allows: {problem}")


def _checked_rate(rate: float) -> float | None:
    if not (math.isfinite(rate) and rate >= 0):
        fail(f"--rate must be a number >= 0 (0: as fast as it can), got {rate!r}")
    return None if rate == 0 else rate


@ros2_app.command(context_settings=_WITH_ROS_ARGS)
@friendly_errors
def sim(
    ctx: typer.Context,
    world: Annotated[str, typer.Option(help=WORLD_HELP)] = "office",
    seed: Annotated[int, typer.Option(help=f"Seeds the world, the start and the sensor noise (0 to {MAX_SEED}).")] = 0,
    rate: Annotated[float, typer.Option(help="Simulated seconds per wall second (0: as fast as it can).")] = 1.0,
    namespace: Annotated[str, typer.Option(help="The robot's namespace (its topics and action).")] = "",
    robots: Annotated[int, typer.Option(help="Robots in the world (2 or more: namespaces tb3_0, tb3_1, ...).")] = 1,
) -> None:
    """Run a world as ROS 2 robots, for an explorer to drive.

    Each robot publishes map, pose, odom, scan and /clock, and serves Nav2's navigate_to_pose
    and follow_path;
    ROS's arguments (remappings, a log level) go after --ros-args."""
    ros_args = _ros_args(ctx.args)
    checked_seed(seed)
    paced = _checked_rate(rate)
    if not 1 <= robots <= MAX_ROBOTS:
        fail(f"--robots must be 1 to {MAX_ROBOTS}, got {robots!r}")
    if robots > 1 and namespace:
        fail("give --namespace for one robot, or --robots for a team (namespaces tb3_0, tb3_1, ...), not both")
    _ros_ready(ros_args, {"--namespace": [namespace]})
    from frontier_rl import api
    from frontier_rl.ros2.run import run_sim, simulated_team

    the_world = api.load_world(world, seed)
    namespaces = [namespace] if robots == 1 else [f"tb3_{i}" for i in range(robots)]
    team = simulated_team(the_world, namespaces, seed)
    print_line(f"simulating {the_world.name} with {robots} ROS 2 robot(s); Ctrl-C ends it")
    for line in run_sim(team, paced, ros_args):
        print_line(line)


@ros2_app.command(context_settings=_WITH_ROS_ARGS)
@friendly_errors
def rank(
    ctx: typer.Context,
    robots: Annotated[str, typer.Option(help="The robots' namespaces, comma-separated (none: one robot).")] = "",
    policy: Annotated[str, typer.Option(help="Any policy spec but the oracle and the point models.")] = "fixed:0.75",
    top_k: Annotated[int, typer.Option(help="Frontiers per answer.")] = 10,
    min_cluster_size: Annotated[
        int, typer.Option(help="Frontier clusters this many cells or smaller are left out.")
    ] = 4,
    max_map_age: Annotated[float, typer.Option(help="A map older than this is stale (s; 0: any age).")] = 30.0,
    stale_map: Annotated[
        str, typer.Option(help="A stale map is ranked and said so (stale) or answered empty.")
    ] = "stale",
    keep_last_map: Annotated[bool, typer.Option(help="Keep the last good map when a malformed one arrives.")] = True,
    max_pending: Annotated[int, typer.Option(help="Requests queued per robot; more are answered empty.")] = 8,
    pose_topic: Annotated[str, typer.Option(help="Each robot's pose topic, in its namespace.")] = "pose",
    pose_type: Annotated[
        str, typer.Option(help="pose (PoseWithCovarianceStamped), odom (Odometry) or tf (its namespace's tf).")
    ] = "pose",
    robot_base_frame: Annotated[str, typer.Option(help="Each robot's base frame, for --pose-type tf.")] = "base_link",
    use_sim_time: Annotated[bool, typer.Option(help="Time from /clock (a simulator's).")] = False,
) -> None:
    """The thesis's ranking service, for one or more robots.

    Each /frontier_request is answered on /frontier_list; ROS's arguments (remappings, -p
    use_sim_time:=true, a log level) go after --ros-args."""
    from frontier_rl.robot.node_settings import (
        count_parameter,
        robot_namespaces,
        seconds_parameter,
        settings_named,
        stale_map_parameter,
    )

    ros_args, pose_source = _ros_args(ctx.args), _pose_source(pose_type, pose_topic, robot_base_frame)
    with settings_named(_option):  # each bad one named as its option, the ROS 1 node's ~parameter
        stale = stale_map_parameter(stale_map)
        names = tuple(robot_namespaces(robots or [""]))
        top, pending = count_parameter("top_k", top_k, 1), count_parameter("max_pending", max_pending, 1)
        age = seconds_parameter("max_map_age", max_map_age, zero=True)
        count_parameter("min_cluster_size", min_cluster_size, 0)  # its upper bound is the engine's, checked below
        _ros_ready(ros_args, {"--robots": names}, pose_source)
        from frontier_rl.core.sim.config import MAX_FRONTIER_DROP_CELLS  # the engine, once the arguments are checked
        from frontier_rl.robot.ranking_service import ServiceSettings
        from frontier_rl.ros2.run import run_ranking

        settings = ServiceSettings(
            robots=names,
            policy=policy.strip(),
            top_k=top,
            min_cells=count_parameter("min_cluster_size", min_cluster_size, 0, MAX_FRONTIER_DROP_CELLS),
            max_map_age=age,
            stale=stale,
            keep_last_map=keep_last_map,
            max_pending=pending,
        )
        answered = run_ranking(settings, pose_source, use_sim_time, ros_args)
    print_line(f"{answered} requests answered")


@ros2_app.command(context_settings=_WITH_ROS_ARGS)
@friendly_errors
def explore(
    ctx: typer.Context,
    policy: Annotated[
        str, typer.Option(help="Any policy spec: nearest, fixed:0.75, tour, learned:PATH, ...")
    ] = "nearest",
    planner_frequency: Annotated[float, _setting("planner_frequency")] = ExplorerParams.planner_frequency,
    progress_timeout: Annotated[float, _setting("progress_timeout")] = ExplorerParams.progress_timeout,
    min_frontier_size: Annotated[float, _setting("min_frontier_size")] = ExplorerParams.min_frontier_size,
    return_to_init: Annotated[bool, _setting("return_to_init")] = ExplorerParams.return_to_init,
    visualize: Annotated[bool, _setting("visualize")] = True,
    time_cap: Annotated[float, _setting("time_cap")] = 0.0,
    namespace: Annotated[str, typer.Option(help="The robot's namespace.")] = "",
    teammates: Annotated[
        str, typer.Option(help="Teammates' namespaces (tb3_1,tb3_2): their maps are merged into this robot's.")
    ] = "",
    pose_topic: Annotated[str, typer.Option(help="Where the robot's pose is published (pose and odom).")] = "pose",
    pose_type: Annotated[
        str, typer.Option(help="pose (PoseWithCovarianceStamped), odom (Odometry) or tf (the map to the robot's base).")
    ] = "pose",
    robot_base_frame: Annotated[str, typer.Option(help="The robot's base frame, with --pose-type tf.")] = "base_link",
    use_sim_time: Annotated[bool, typer.Option(help="Time from /clock (a simulator's).")] = False,
    goal_silence_timeout: Annotated[
        float, typer.Option(help="A goal Nav2 says nothing of for this long is dropped (wall s).")
    ] = 10.0,
    seed: Annotated[int, typer.Option(help=f"Seeds the policy's randomness (0 to {MAX_SEED}).")] = 0,
    json_out: Annotated[bool, typer.Option("--json", help="Print the final status as JSON, not a sentence.")] = False,
    params_file: ParamsFileOption = None,
) -> None:
    """Explore with Nav2, a policy choosing among the map's frontiers.

    The settings are also the node's ROS parameters: after --ros-args, -p NAME:=VALUE overrides
    them, and ros2 param set changes them while it explores."""
    ros_args = _ros_args(ctx.args)
    checked_seed(seed)
    options: dict[str, Any] = dict(
        planner_frequency=planner_frequency,
        progress_timeout=progress_timeout,
        min_frontier_size=min_frontier_size,
        return_to_init=return_to_init,
        time_cap=time_cap,
        visualize=visualize,
        robot_base_frame=robot_base_frame,
        use_sim_time=use_sim_time,
    )
    chosen = _explorer_settings(ctx, params_file or [], options, (pose_type, pose_topic))
    node = _node_options(
        namespace=namespace,
        teammates=tuple(teammates.split(",")) if teammates.strip() else (),
        pose_source=chosen.pose_source,
        visualize=chosen.visualize,
        use_sim_time=chosen.use_sim_time,
        nav2_plugins=chosen.nav2_plugins,
        seed=seed,
        goal_silence_timeout=goal_silence_timeout,
        policy_name=policy,
        ros_args=ros_args,
    )
    _ros_ready(ros_args, {"--namespace": [namespace], "--teammates": node.teammates}, chosen.pose_source)
    _explore_with(policy, chosen.params, node, json_out)


def _node_options(**fields: Any) -> ExplorerNodeOptions:
    """The explorer node's options of ``fields`` (:class:`ExplorerNodeOptions`' own); one line naming a
    bad one as its option (``goal_silence_timeout``: ``--goal-silence-timeout``)."""
    try:
        return ExplorerNodeOptions(**fields)
    except SettingError as error:
        fail(f"{_option(error.setting)} {error.problem}")


class _ChosenSettings(NamedTuple):
    """What the command line and the parameter files chose for the explorer and its node."""

    params: ExplorerParams
    visualize: bool
    pose_source: PoseSource
    use_sim_time: bool
    nav2_plugins: Nav2Plugins


def _explorer_settings(
    ctx: typer.Context, params_files: Sequence[Path], options: dict[str, Any], pose: tuple[str, str]
) -> _ChosenSettings:
    """The explorer's settings, whether it draws markers, where its pose comes from (``pose``: the
    pose type and topic; the base frame is among the ``options``) and whether it takes the time from
    ``/clock``, from its ``options`` and, for those not given on the command line, the parameter
    files; one line naming a bad one."""
    options = _with_parameter_files(ctx, params_files, options)
    visualize, robot_base_frame = bool(options.pop("visualize")), str(options.pop("robot_base_frame"))
    use_sim_time = bool(options.pop("use_sim_time"))
    plugins = Nav2Plugins.of(options)
    source = _pose_source(*pose, robot_base_frame)
    return _ChosenSettings(_explorer_params(options), visualize, source, use_sim_time, plugins)


def _pose_source(pose_type: str, pose_topic: str, robot_base_frame: str) -> PoseSource:
    """Where the explorer reads the robot's pose; one line naming a bad option."""
    from frontier_rl.robot.pose_source import PoseKind, PoseSource

    try:
        kind = PoseKind(pose_type)
    except ValueError:
        fail(f"--pose-type must be pose, odom or tf, got {pose_type!r}")
    try:
        return PoseSource(kind, pose_topic, robot_base_frame)
    except SettingError as error:
        fail(f"{_option(error.setting)} {error.problem}")


def _option(setting: str) -> str:
    """The command-line option of a setting (``planner_frequency``: ``--planner-frequency``)."""
    return "--" + setting.replace("_", "-")


def _ros_args(extra: list[str]) -> tuple[str, ...]:
    """The arguments after the options: ROS's (``--ros-args ...``) or none; anything else is an
    option this command does not know."""
    if extra and extra[0] != "--ros-args":
        fail(f"no such option or argument: {extra[0]!r} (ROS's arguments go after --ros-args)")
    return tuple(extra)


def _explore_with(policy: str, params: ExplorerParams, node: ExplorerNodeOptions, json_out: bool) -> None:
    """Run the explorer with ``policy``, its settings ``params`` and the ``node``'s options; print how
    it ended (exit status 130 if it was interrupted; with ``json_out`` a status line even when that
    was before it ran)."""
    from frontier_rl.ros2.explorer_status import ExplorerState, ExplorerStatus

    try:
        from frontier_rl.policies.registry import make_policy
        from frontier_rl.robot.explorer import check_robot_policy
        from frontier_rl.ros2.run import run_explorer

        the_policy = make_policy(policy)
        check_robot_policy(the_policy, policy)
        status, summary = run_explorer(the_policy, params, node)
    except KeyboardInterrupt:  # before the node ran: a model loading, ROS starting
        if json_out:
            print(ExplorerStatus.not_started().to_json())
        raise
    if json_out:
        print(status.to_json())
    else:
        print_line(summary)
    if status.state is not ExplorerState.FINISHED:
        raise typer.Exit(130)
