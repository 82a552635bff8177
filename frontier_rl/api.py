"""The main jobs as Python functions: load a world, explore it, run a paired experiment, train a model.

Each is what a ``frontier-rl`` command does, with typed values in and out::

    import frontier_rl

    world = frontier_rl.load_world("office", seed=3)
    result = frontier_rl.explore(world, "nearest", seed=3)
    print(f"{result.sim_time_s:.0f} s, {result.coverage:.0%} covered")

    summary = frontier_rl.evaluate(["nearest", "my_policy.py:Greedy"], ["office"], 10, out="results/mine")
    print(summary.methods["my_policy.py:Greedy"].reduction_pct)

Only :func:`train` loads torch (and Gymnasium); the other three need neither.
"""

from __future__ import annotations

import inspect
import sys
from collections.abc import Callable, Mapping, Sequence
from functools import cache, partial
from pathlib import Path
from types import FrameType, UnionType
from typing import TYPE_CHECKING, overload

from frontier_rl.checked_values import python_integer
from frontier_rl.core.frontiers.thesis import THESIS_BASELINE
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.episode import DecisionContext, ExplorationPolicy, Ranking, run_episode, warm_up
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.sim.simulator import ExplorationSimulator
from frontier_rl.core.world.robot import Pose
from frontier_rl.core.world.scale import checked_resolution
from frontier_rl.core.world.worlds import World
from frontier_rl.errors import ConfigError, short_repr
from frontier_rl.policies import make_policy
from frontier_rl.policies.user_policies import checked_policy
from frontier_rl.seeds import checked_seed
from frontier_rl.swarm.config import Failure, TeamConfig
from frontier_rl.world_spec import resolve_world

if TYPE_CHECKING:  # loaded by the functions that need them: the command line's help loads this module
    from frontier_rl.evaluation.results.summary import ExperimentSummary
    from frontier_rl.evaluation.running.experiment import ExperimentConfig
    from frontier_rl.rl.config import TrainConfig
    from frontier_rl.swarm.result import TeamResult

DecisionHook = Callable[[ExplorationSimulator, DecisionContext, Ranking], None]
"""Called at every decision of a single robot's episode, before the robot drives."""


def load_world(
    name_or_path: str | Path, seed: int = 0, *, start: Pose | None = None, resolution: float | None = None
) -> World:
    """The world ``name_or_path`` names: a generator (``office``, ``rooms``, ``cluttered``, ``building``,
    ``cave``) drawn with ``seed``, a map of the catalogue (``nav2_depot``, ``dungeon/easy/img_10``) or a
    map file (ROS ``.yaml``, DungeonMaps ``.png``, HouseExpo ``.json``).

    Args:
        name_or_path: generator, catalogue name or path.
        seed: seeds the generator, or the random start on a map without a stored one.
        start: the start pose (m, m, rad), replacing the generated or stored one.
        resolution: cell size (m) of a map file that carries none (a bitmap, HouseExpo).

    Raises:
        UnknownNameError: no such generator, catalogue name or file.
        ConfigError: a seed, start pose or resolution no world can use.
        MapError: a map file that cannot be used.
    """
    return resolve_world(str(name_or_path), checked_seed(seed), start, checked_resolution(resolution, "resolution"))


@overload
def explore(
    world: World | str | Path,
    policy: ExplorationPolicy | str,
    *,
    seed: int = ...,
    config: SimConfig | None = ...,
    team: TeamConfig,
    resolution: float | None = ...,
    trust_model: bool = ...,
    on_decision: None = ...,
) -> TeamResult: ...


@overload
def explore(
    world: World | str | Path,
    policy: ExplorationPolicy | str,
    *,
    seed: int = ...,
    config: SimConfig | None = ...,
    team: None = ...,
    resolution: float | None = ...,
    trust_model: bool = ...,
    on_decision: DecisionHook | None = ...,
) -> EpisodeResult: ...


def explore(
    world: World | str | Path,
    policy: ExplorationPolicy | str,
    *,
    seed: int = 0,
    config: SimConfig | None = None,
    team: TeamConfig | None = None,
    resolution: float | None = None,
    trust_model: bool = False,
    on_decision: DecisionHook | None = None,
) -> EpisodeResult:
    """Explore ``world`` with ``policy`` until no frontier is left (or the sim-time cap), as
    ``frontier-rl explore`` does; the same seed gives the same episode, bit for bit.

    Args:
        world: a world, or a name or path for :func:`load_world` (drawn with ``seed``).
        policy: a policy object (anything with ``name`` and ``rank``), or a spec as on the command
            line: ``nearest``, ``fixed:0.75``, ``learned:models/model7.zip``, ``my_policy.py:Greedy``, ...
        seed: seeds the world (when named), the sensor noise and the policy's random stream.
        config: simulation settings (robot, LiDAR, mapping, navigation, time cap); the defaults if None.
        team: a team of robots that all run ``policy``, whose result is a :class:`~frontier_rl.swarm.TeamResult`
            (per-robot coverage, overlap, ...); None for one robot.
        resolution: cell size (m) of a map file that carries none.
        trust_model: admit SB3 zips from elsewhere for ``learned:`` (unpickles them: runs their code).
        on_decision: called at every decision of a single robot, before it drives (not for a team).

    Raises:
        FrontierRLError: a bad world, policy or setting, named in one line.
    """
    if team is not None and on_decision is not None:
        raise ConfigError("on_decision follows one robot's decisions; it cannot be given with a team")
    seed = checked_seed(seed)
    chosen = (
        make_policy(policy, trust_model=trust_model)
        if isinstance(policy, str)
        else checked_policy(policy, "explore() got")
    )
    the_world = world if isinstance(world, World) else load_world(world, seed, resolution=resolution)
    _warm_up()
    if team is not None:
        from frontier_rl.swarm.episode import run_team_episode  # the team engine, for a team only

        return run_team_episode(the_world, chosen, config, team, seed)
    return run_episode(the_world, chosen, config, seed, on_decision=on_decision)


@cache
def _warm_up() -> None:
    """Compile (or load) the engine's kernels once per process, so that no episode's wall time counts it."""
    warm_up()


def evaluate(
    methods: Sequence[str],
    worlds: Sequence[str | Path],
    episodes: int,
    *,
    out: str | Path,
    baseline: str = THESIS_BASELINE,
    oracle: bool = True,
    seed: int = 0,
    workers: int | None = None,
    backend: str = "process",
    ray_address: str | None = None,
    config: SimConfig | None = None,
    resolution: float | None = None,
    trust_model: bool = False,
    comm_range: float | None = None,
    failures: Sequence[Failure] = (),
    outliers: Sequence[float] | None = None,
    pictures: int | None = None,
    progress: bool = False,
    command: str | None = None,
) -> ExperimentSummary:
    """The paired experiment of ``frontier-rl evaluate``: every method on the same worlds, starts and
    sensor noise, compared with ``baseline``; the report, plots and ``summary.json`` go to ``out``
    (rerunning with the same ``out`` resumes), and the summary comes back typed.

    Args:
        methods: policy specs as on the command line (``nearest``, ``learned:models/model7.zip``,
            ``my_policy.py:Greedy``, ``nearest@2:coordinated`` for a team, ...); ``baseline`` is added if missing.
        worlds: generators, catalogue names, map files, folders of maps (each may be a comma list, as ``--worlds``).
        episodes: episodes per world; episode i uses seed ``seed + i``.
        out: the results folder.
        config: the simulation settings of every episode (the defaults if None).
        outliers: also compare without the episodes above these times (s); None: 1000 and 2000 s.
        pictures: draw each method's first episode on this many worlds (None: 3).
        command: how the report says to run the experiment again (None: this call).
        baseline, oracle, seed, workers, backend, ray_address, resolution, trust_model, comm_range, failures, progress:
            as the options of ``frontier-rl evaluate`` of the same names.

    Raises:
        FrontierRLError: a bad method, world or setting, or ``out`` holding another experiment.
    """
    from frontier_rl.evaluation.results.summary import ExperimentSummary
    from frontier_rl.evaluation.running.evaluate import evaluate as run_evaluation
    from frontier_rl.evaluation.running.experiment import ExperimentConfig

    if _importing_the_script_in_a_worker():
        raise SystemExit(NO_MAIN_GUARD_EXIT)
    seed = checked_seed(seed)
    names, places = _names(methods, worlds, baseline, oracle)
    sim = config or SimConfig()
    experiment = ExperimentConfig(
        names, places, episodes, seed, baseline, sim, resolution, trust_model, comm_range, tuple(failures)
    )
    cuts, shown, as_given = _report_settings(outliers, pictures)
    given = {"out": str(out), "oracle": oracle, **as_given}
    text = command or _call_text(list(methods), [str(w) for w in worlds], experiment, given)
    run = partial(run_evaluation, experiment, Path(out), backend=backend, workers=workers, ray_address=ray_address)
    report = _naming_a_missing_guard(partial(run, outliers=cuts, progress=progress, command=text, pictures=shown))
    return ExperimentSummary.load(report.parent)


NO_MAIN_GUARD_EXIT = 3
"""The exit code of a worker process that, importing the user's script as Python's process pools do,
found it calling :func:`evaluate` again (the script has no ``if __name__ == "__main__":``)."""

_GUARD_HINT = (
    "the script calls frontier_rl.evaluate() where its worker processes import it again: call it under `if "
    '__name__ == "__main__":`'
)


def _importing_the_script_in_a_worker() -> bool:
    """Whether this is a worker process importing the user's script as it starts (multiprocessing's
    ``spawn`` runs the parent's main script again, as ``__mp_main__``, before its first task)."""
    frame: FrameType | None = sys._getframe()
    while frame is not None:
        if (
            frame.f_code.co_name == "_fixup_main_from_path"
            and frame.f_globals.get("__name__") == "multiprocessing.spawn"
        ):
            return True
        frame = frame.f_back
    return False


def _naming_a_missing_guard(run: Callable[[], Path]) -> Path:
    """``run()``, the evaluation's run (it returns the report's path); a worker that died importing
    a script without the ``__main__`` guard is named as such."""
    from frontier_rl.evaluation.running.backends import EpisodeFailedError
    from frontier_rl.evaluation.running.worker_pool import WorkerDiedError

    try:
        return run()
    except EpisodeFailedError as failed:
        first = failed.first_error
        if isinstance(first, WorkerDiedError) and first.exit_code == NO_MAIN_GUARD_EXIT:
            raise EpisodeFailedError(f"{failed}; {_GUARD_HINT}", first) from None
        raise


def _call_text(methods: list[str], worlds: list[str], experiment: ExperimentConfig, given: Mapping[str, object]) -> str:
    """How the report says to run the experiment again: this call with its methods and worlds as
    given, ``out``, and the keyword arguments that differ from :func:`evaluate`'s defaults (read from
    its signature): the experiment's settings and the report's options ``given`` (checked values;
    failures and the simulation settings named as in ``experiment.json``, which holds them whole)."""
    defaults = {name: parameter.default for name, parameter in inspect.signature(evaluate).parameters.items()}
    values = {"baseline": experiment.baseline, "seed": experiment.seed, "resolution": experiment.resolution}
    values |= {"trust_model": experiment.trust_model, "comm_range": experiment.comm_range, **given}
    keywords = [  # in the signature's order
        f"{key}={values[key]!r}" for key in defaults if key in values and (key == "out" or values[key] != defaults[key])
    ]
    if experiment.failures:
        keywords.append("failures=<the failures in experiment.json>")
    if experiment.sim != SimConfig():
        keywords.append("config=<the sim settings in experiment.json>")
    return f"frontier_rl.evaluate({methods!r}, {worlds!r}, {experiment.episodes}, {', '.join(keywords)})"


def _names(
    methods: Sequence[str], worlds: Sequence[str | Path], baseline: str, oracle: bool
) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The methods (the baseline first, the oracle last) and worlds (folders expanded) of :func:`evaluate`."""
    from frontier_rl.evaluation.running.experiment import expand_worlds
    from frontier_rl.evaluation.running.methods import method_list

    if not (_list_of(methods, str) and _list_of(worlds, str | Path)):
        raise ConfigError(f"methods and worlds must be lists of names, got {short_repr(methods)}, {short_repr(worlds)}")
    return method_list(methods, baseline, oracle), tuple(w for item in worlds for w in expand_worlds(str(item)))


def _list_of(value: object, kind: type | UnionType) -> bool:
    """Whether ``value`` is a list (or tuple) of ``kind`` values, not a string."""
    return isinstance(value, Sequence) and not isinstance(value, str) and all(isinstance(v, kind) for v in value)


def _report_settings(
    outliers: Sequence[float] | None, pictures: int | None
) -> tuple[tuple[float, ...], int, dict[str, object]]:
    """The outlier thresholds (s) and pictured worlds of :func:`evaluate`, checked (None: the
    command's defaults), and the two as the report's line to run it again names them (checked
    values: a NumPy array's text would not run; None where not given)."""
    from frontier_rl.evaluation.running.evaluate import DEFAULT_OUTLIERS_S, DEFAULT_PICTURE_WORLDS, checked_thresholds

    cuts = DEFAULT_OUTLIERS_S if outliers is None else checked_thresholds(outliers, "outliers")
    pictures = python_integer(pictures)  # type: ignore[assignment]  # a NumPy integer
    if pictures is not None and (isinstance(pictures, bool) or not isinstance(pictures, int) or pictures < 0):
        raise ConfigError(f"pictures must be a whole number of worlds, 0 or more, got {short_repr(pictures)}")
    as_given: dict[str, object] = {"outliers": None if outliers is None else list(cuts), "pictures": pictures}
    return cuts, DEFAULT_PICTURE_WORLDS if pictures is None else pictures, as_given


def train(config: TrainConfig, out: str | Path, *, resume: bool = False, progress: bool = False) -> Path:
    """Train the model ``config`` describes into the run folder ``out`` (as ``frontier-rl train``
    does: checkpoints, validation, learning curve); returns the final model file, which
    ``learned:PATH`` names. Loads torch, Stable-Baselines3 and Gymnasium.

    Args:
        config: the run's settings (:class:`~frontier_rl.rl.config.TrainConfig`: model, worlds,
            timesteps, algorithm, ...).
        out: the run folder.
        resume: continue the run in ``out`` from its last checkpoint (the same settings and map files,
            but for ``timesteps``, which may grow).
        progress: show a progress bar.
    """
    from frontier_rl.rl.train import train as run_training

    return run_training(config, Path(out), resume=resume, progress=progress)
