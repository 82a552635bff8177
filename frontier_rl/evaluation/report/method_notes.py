"""What each method of an experiment is: a one-line description and its parameters, for the
report's "Methods" table (a learned model's file, hash, metadata and training command)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from frontier_rl.core.frontiers.thesis import THESIS_WEIGHT
from frontier_rl.errors import FrontierRLError, short_repr, short_text
from frontier_rl.file_digest import file_sha256
from frontier_rl.policies import BuiltinPolicy, PolicySpec
from frontier_rl.policies.user_policies import describe_user_policy, user_policy_fingerprint
from frontier_rl.registration import MODELS
from frontier_rl.swarm.config import Strategy, TeamMethod

_POLICIES: dict[BuiltinPolicy, str] = {
    BuiltinPolicy.NEAREST: "Drives to the nearest frontier, by straight-line distance "
    "(Yamauchi 1997; eq. 3.1 with w = 1).",
    BuiltinPolicy.LARGEST: "Drives to the largest frontier (eq. 3.1 with w = 0).",
    BuiltinPolicy.EXPLORE_LITE: "explore_lite's rule (m-explore): cost = potential_scale · distance "
    "− gain_scale · size, small frontiers skipped.",
    BuiltinPolicy.INFO_GAIN: "Most unknown cells revealed per scan, discounted by distance: gain · exp(−λ·d) "
    "(González-Baños and Latombe).",
    BuiltinPolicy.RANDOM: "A uniformly random frontier at every decision.",
    BuiltinPolicy.ORACLE: "Knows the true map: plans a tour of viewpoints that sees all of it and drives it "
    "with the same robot, sensor and navigation. A reference, not a method a robot could run.",
}
_STRATEGIES = {
    Strategy.UNCOORDINATED: "each robot ranks the frontiers of its own merged map",
    Strategy.COORDINATED: "teammates' goals lower a frontier's utility (Burgard et al. 2000)",
    Strategy.RENDEZVOUS: "the thesis's commander and explorers, meeting every explore period to merge maps",
}
_TRAINING_CONFIGS = ("{stem}_config.yaml", "config.yaml")
"""Where a model's training config is looked for, beside the model file (the shipped models and
``frontier-rl train``'s run folders)."""


@dataclass(frozen=True)
class MethodNote:
    """One row of the report's methods table: the method, what it does, its parameters."""

    method: str
    description: str
    parameters: str


def describe_method(method: str, base_dir: Path | None = None) -> MethodNote:
    """What ``method`` (as on the command line: ``fixed:0.75``, ``learned:PATH``, ``POLICY@N:S``,
    ...) does; a model file is read relative to ``base_dir`` (default: the current directory)."""
    team = TeamMethod.parse(method)
    description, parameters = _policy(team.policy, base_dir or Path.cwd())
    if team.robots is not None:
        description = f"A team of {team.robots} robots, each: {description[0].lower()}{description[1:]}"
        team_part = f"robots = {team.robots}, strategy = {team.strategy.value}: {_STRATEGIES[team.strategy]}"
        parameters = f"{team_part}; {parameters}" if parameters else team_part
    return MethodNote(method, description, parameters)


def _policy(spec: PolicySpec, base_dir: Path) -> tuple[str, str]:
    if spec.is_user_code:
        return _user(spec.against(base_dir))
    if spec.builtin is BuiltinPolicy.FIXED:
        weight = spec.weight
        baseline = " (the thesis's baseline)" if weight == THESIS_WEIGHT else ""
        return (
            "Ranks frontiers by eq. 3.1, cost = w·d + (1−w)·(1−g), with a constant weight.",
            f"w = {weight:g}{baseline}",
        )
    if spec.builtin is BuiltinPolicy.LEARNED:
        return _learned(base_dir / spec.argument)
    if spec.builtin is BuiltinPolicy.TOUR:
        return (
            "Drives to the first stop of the shortest open tour (Held-Karp, on planner path costs) through the "
            "frontiers cheapest to reach, as FUEL (Zhou et al. 2021) and TARE (Cao et al. 2021) order theirs.",
            f"{spec.stops} stops",
        )
    builtin = spec.builtin
    return (_POLICIES.get(builtin, "A policy of this project.") if builtin else "A policy of this project."), ""


def _user(spec: PolicySpec) -> tuple[str, str]:
    """A user policy's description: the first line of its docstring, and where it comes from."""
    try:
        info = describe_user_policy(spec)
        fingerprint = user_policy_fingerprint(spec)
    except FrontierRLError as exc:
        return "A user policy that could not be loaded now.", short_text(str(exc))
    summary = info.summary or "(its class has no docstring)"
    parameters = f"{info.member} from {info.origin}"
    if fingerprint.startswith("sha256:"):  # a file's hash, as a model file's is shown
        parameters += f", sha256 {fingerprint.removeprefix('sha256:')}"
    return f"A user policy: {summary}", parameters


def _learned(path: Path) -> tuple[str, str]:
    """A model file's description from its checked metadata, and its hash and training command."""
    from frontier_rl.inference.model_file import read_metadata
    from frontier_rl.rl.config import TrainConfig  # torch only when a learned method is reported

    try:
        digest = file_sha256(path)
        info = read_metadata(path)
    except (OSError, FrontierRLError) as exc:
        return "A learned policy whose model file could not be read now.", f"file {path.name}: {exc}"
    parameters = [f"file {path.name}", f"sha256 {digest}"]
    if info is None:
        return "A Stable-Baselines3 model without this project's metadata (loaded with --trust-model).", ", ".join(
            parameters
        )
    spec = MODELS[info.model]
    description = f"Model {info.model} ({spec.description}), trained by this project with {info.algo.upper()}."
    parameters.append(f"{info.timesteps:,} decisions, {info.observation_size} px map image")
    for pattern in _TRAINING_CONFIGS:
        config_path = path.with_name(pattern.format(stem=path.stem))
        if config_path.is_file():
            try:
                parameters.append(f"trained with: {TrainConfig.load(config_path).command()} ({config_path.name})")
            except FrontierRLError as exc:
                parameters.append(f"training config {config_path.name} unreadable: {short_repr(str(exc))}")
            break
    else:
        parameters.append("no training config beside the file")
    return description, "; ".join(parameters)
