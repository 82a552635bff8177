"""One page per Gymnasium id and one for the PettingZoo team environment, as Minigrid documents its
environments: what the agent sees and does, the reward, how an episode ends, a picture of a real
instance and the code that makes one (run here, at build time, so it cannot go stale)."""

from __future__ import annotations

import inspect
from pathlib import Path
from typing import Any

import gymnasium as gym
from docstrings import to_myst
from env_facts import PICTURE_DECISIONS, EnvFacts, gym_facts, team_facts

from frontier_rl.envs.base import EnvConfig
from frontier_rl.envs.point_env import PointEnv
from frontier_rl.envs.rewards import REWARD_PRESETS, RewardConfig
from frontier_rl.envs.team_env import TeamExplorationEnv
from frontier_rl.registration import ENV_IDS

TEAM_PAGE = "team-v0"

_GYM_SNIPPET = """import gymnasium as gym

import frontier_rl.envs  # registers the FrontierRL/ ids

env = gym.make("{env_id}", worlds="office,rooms", render_mode="rgb_array")
observation, info = env.reset(seed=0)
observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
picture = env.render()  # an RGB array: the true world and path | the robot's map
"""

_TEAM_SNIPPET = """from frontier_rl.envs.team_env import parallel_env
from frontier_rl.swarm import TeamConfig

env = parallel_env(team=TeamConfig(robots=3, strategy="coordinated"), worlds="rooms")
observations, infos = env.reset(seed=0)
actions = {agent: env.action_space(agent).sample() for agent in env.agents}
observations, rewards, terminations, truncations, infos = env.step(actions)
"""


def generate(out_dir: Path) -> None:
    """Write ``index.md``, a page and a picture per id, and the team environment's page."""
    rows = []
    for env_id in ENV_IDS:
        stem = page_name(env_id)
        facts = gym_facts(env_id, out_dir / f"{stem}.png")
        snippet = _GYM_SNIPPET.format(env_id=env_id)
        _run(snippet)
        (out_dir / f"{stem}.md").write_text(render_page(facts, stem, snippet))
        rows.append(facts)
    team = team_facts(out_dir / f"{TEAM_PAGE}.png")
    _run(_TEAM_SNIPPET)
    (out_dir / f"{TEAM_PAGE}.md").write_text(render_page(team, TEAM_PAGE, _TEAM_SNIPPET))
    (out_dir / "index.md").write_text(render_index(rows, team.name))


def page_name(env_id: str) -> str:
    """The page of ``env_id``: ``FrontierRL/WeightMap64-v0`` -> ``weightmap64-v0``."""
    return env_id.split("/")[-1].lower()


def _run(snippet: str) -> None:
    """Run a page's example, as a reader would."""
    namespace: dict[str, Any] = {}
    exec(compile(snippet, "<environment page example>", "exec"), namespace)
    env = namespace.get("env")
    if env is not None:
        env.close()


def render_index(rows: list[EnvFacts], team_name: str) -> str:
    """The table of every id, a row per model, then the team environment."""
    lines = [
        "# Environments",
        "",
        "Importing `frontier_rl.envs` registers these Gymnasium ids: one per model and map image size, 250 × 250 "
        "pixels (the thesis's) or 64 × 64 (the ids ending in `64-v0`). One `step()` is one decision: the robot "
        "drives to the goal the action picks while the LiDAR and the mapper keep running. "
        '`gymnasium.make("frontier_rl.envs:FrontierRL/WeightMap-v0")` imports the module on the way.',
        "",
        "| model | ids | observation | action | in short |",
        "|---|---|---|---|---|",
    ]
    by_model: dict[int, list[EnvFacts]] = {}
    for facts in rows:
        assert facts.model is not None
        by_model.setdefault(facts.model.number, []).append(facts)
    for number, variants in by_model.items():
        ids = "<br>".join(f"[`{f.name}`]({page_name(f.name)}.md)" for f in variants)
        first = variants[0]
        assert first.model is not None
        observation = _space_summary(first.observation_space)
        lines.append(
            f"| {number} | {ids} | {observation} | {_space_summary(first.action_space)} | {first.model.description} |"
        )
    lines += [
        "",
        "The observation and action columns give the 250 × 250 id's spaces; the environment pages give each id's.",
        "",
        f"The team environment, [`{team_name}`]({TEAM_PAGE}.md), is a PettingZoo `ParallelEnv` in which every robot "
        "of a team is an agent.",
        "",
        "```{toctree}",
        ":hidden:",
        "",
        *(page_name(f.name) for f in rows),
        TEAM_PAGE,
        "```",
        "",
    ]
    return "\n".join(lines)


def render_page(facts: EnvFacts, stem: str, snippet: str) -> str:
    """The page of one environment."""
    title = facts.name if facts.model is None else f"`{facts.name}`"
    lead = _team_lead() if facts.model is None else f"Model {facts.model.number}: {facts.model.description}."
    lines = [
        f"# {title}",
        "",
        lead,
        "",
        f"![{facts.name} after {PICTURE_DECISIONS} decisions: the true world and the path driven, and the map the "
        f"robot built]({stem}.png)",
        "",
        "| | |",
        "|---|---|",
        f"| Observation space | {_space_summary(facts.observation_space)} |",
        f"| Action space | {_space_summary(facts.action_space)} |",
        f"| Class | {{py:class}}`~{facts.cls.__module__}.{facts.cls.__qualname__}` |",
        "",
        "## Description",
        "",
        to_myst(inspect.cleandoc(_description(facts.cls)), facts.cls),
        "",
        "## Observation",
        "",
        *_space_table(facts.observation_space),
        "",
        "## Action",
        "",
        *_space_table(facts.action_space),
        "",
        "## Reward",
        "",
        *_reward_section(facts.cls),
        "",
        "## Episode end",
        "",
        *_ending_section(facts.model is None),
        "",
        "## Info",
        "",
        "The `info` dictionary of `reset()` and `step()` holds "
        + ", ".join(f"`{key}`" for key in facts.info_keys)
        + (" (per agent)." if facts.model is None else "."),
        "",
        "## Usage",
        "",
        "```python",
        snippet.rstrip(),
        "```",
        "",
        "Keyword arguments are the fields of {py:class}`~frontier_rl.envs.base.EnvConfig` "
        "({ref}`the environment's configuration <config-env>`): `worlds`, `reward`, `observation_size`, "
        "`max_decisions`, `resolution`, `world_split` and `sim`, a {py:class}`~frontier_rl.core.sim.config.SimConfig`.",
        "",
    ]
    return "\n".join(lines)


def _description(cls: type[Any]) -> str:
    """``cls``'s docstring without its Args section (the usage section covers the arguments)."""
    return (cls.__doc__ or "").split("\n    Args:")[0]


def _team_lead() -> str:
    return (
        "A PettingZoo `ParallelEnv`: a team of robots explores one world, every robot an agent "
        "(`robot_0`, `robot_1`, ...)."
    )


def _space_summary(space: gym.Space[Any]) -> str:
    if isinstance(space, gym.spaces.Discrete):
        return f"`Discrete({space.n})`"
    if isinstance(space, gym.spaces.Dict):
        return "`Dict`: " + ", ".join(f"`{key}`" for key in space.spaces)
    if isinstance(space, gym.spaces.Box):
        return f"`{space.dtype}` array of shape `{tuple(space.shape)}`"
    return f"`{space}`"


def _space_table(space: gym.Space[Any]) -> list[str]:
    if isinstance(space, gym.spaces.Discrete):
        return [f"`Discrete({space.n})`: an integer from {space.start} to {space.start + space.n - 1}."]
    boxes = space.spaces if isinstance(space, gym.spaces.Dict) else {"": space}
    lines = ["| entry | shape | dtype | range |", "|---|---|---|---|"]
    for key, box in boxes.items():
        assert isinstance(box, gym.spaces.Box)
        low, high = box.low.min(), box.high.max()
        entry = f"`{key}`" if key else "(the array)"
        lines.append(f"| {entry} | `{tuple(box.shape)}` | `{box.dtype}` | {low:g} to {high:g} |")
    return lines


def _reward_section(cls: type[Any]) -> list[str]:
    presets = list(REWARD_PRESETS.items())
    lines = [
        "Each decision earns `scale × (per_free_cell × cells first mapped free + per_occupied_cell × cells first "
        "mapped occupied + per_coverage × coverage gained − per_second × the leg's sim time in s + end_bonus "
        "when exploration ends by itself)`"
        + (", plus the chosen cell's reward by its state in the image (thesis table 3.1)." if cls is PointEnv else "."),
        "The `reward` argument picks the preset; the team environment shares one reward among the agents."
        if cls is TeamExplorationEnv
        else "The `reward` argument picks the preset:",
        "",
        "| term | " + " | ".join(f"`{name}`" for name, _ in presets) + " |",
        "|---|" + "---|" * len(presets),
    ]
    terms = [name for name in RewardConfig.__dataclass_fields__ if cls is PointEnv or not name.startswith("chosen_")]
    for term in terms:
        lines.append(f"| `{term}` | " + " | ".join(f"{getattr(config, term):g}" for _, config in presets) + " |")
    default = EnvConfig().reward
    terms_doc = "{py:class}`~frontier_rl.envs.rewards.RewardConfig`"
    lines += ["", f"The default is `{default}`; {terms_doc} describes each term."]
    return lines


def _ending_section(team: bool) -> list[str]:
    config = EnvConfig()
    lines = [
        "- **Terminated** when the map is explored: no frontier touches the space the robot can reach "
        "(for a team: the team's map; a failed robot's agent terminates at once).",
        "- **Truncated** at the episode's sim-time cap ({py:meth}`SimConfig.time_cap "
        "<frontier_rl.core.sim.config.SimConfig.time_cap>`: `max_sim_time`, else "
        f"{config.sim.time_per_area:g} s per m² of explorable space and at least {config.sim.min_time_cap:g} s), "
        f"or after `max_decisions` decisions ({config.max_decisions} by default)"
        + (", counted over the whole team." if team else "."),
    ]
    return lines
