"""The command line loads what a command runs, no more: its help and its argument errors need none of
the engine (numba, SciPy, the simulator) and neither Gymnasium nor torch; its help, plain text, not
even rich (an error line is coloured by it)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

PROBE = """
import json, sys
from frontier_rl.cli import app
try:
    app(sys.argv[1:])
except SystemExit as end:
    code = end.code
heavy = ("numba", "scipy", "torch", "gymnasium", "matplotlib", "frontier_rl.core.sim.simulator", "frontier_rl.api",
         "frontier_rl.swarm.team")
print(json.dumps({"code": code, "loaded": [name for name in heavy if name in sys.modules],
                  "rich": "rich.console" in sys.modules}))
"""


def _run(*args: str) -> dict[str, object]:
    done = subprocess.run([sys.executable, "-c", PROBE, *args], capture_output=True, text=True, timeout=60)
    return json.loads(done.stdout.strip().splitlines()[-1])  # type: ignore[no-any-return]


@pytest.mark.parametrize(
    ("args", "code"),
    [
        (["--help"], 0),
        (["-h"], 0),
        (["--version"], 0),
        (["ros2", "explore", "-h"], 0),
        (["explore", "--help"], 0),
        (["evaluate", "--help"], 0),
        (["train", "--help"], 0),
        (["maps", "--help"], 0),
        (["benchmark", "ariadne", "--help"], 0),
        (["explore", "--seed", "-5"], 2),
        (["explore", "--resolution", "9"], 2),
        (["explore", "--start", "1,nan"], 2),
        (["explore", "--policy", "nearest:3"], 2),
        (["evaluate", "--methods", "nearest", "--out", "x", "--seed", "-1"], 2),
        (["train", "--out", "x", "--seed", "-1"], 2),
        (["ros2", "explore", "--help"], 0),
        (["ros2", "explore", "--planner-frequency", "0"], 2),
        (["ros2", "explore", "--pose-type", "gps"], 2),
        (["ros2", "explore", "--pose-type", "tf", "--robot-base-frame", "/"], 2),
        (["ros2", "explore", "--goal-silence-timeout", "nan"], 2),
        (["ros2", "sim", "--rate", "-1"], 2),
        (["ros2", "sim", "--robots", "9"], 2),
        (["ros2", "rank", "--stale-map", "maybe"], 2),
        (["ros2", "rank", "--robots", "a,,b"], 2),
        (["ros2", "rank", "--pose-type", "gps"], 2),
        (["ros2", "rank", "--pose-type", "tf", "--robot-base-frame", " "], 2),
        (["ros2", "explore", "--params-file", "no-such-explore.yaml"], 2),
    ],
)
def test_help_and_argument_errors_load_none_of_the_engine(args: list[str], code: int) -> None:
    outcome = _run(*args)
    assert outcome == {"code": code, "loaded": [], "rich": code != 0}, outcome


def test_a_command_that_runs_loads_the_engine_and_a_single_robot_not_the_team_engine() -> None:
    outcome = _run("explore", "--world", "lse_arena", "--max-time", "5", "--json")
    assert outcome["code"] in (0, None) and "numba" in outcome["loaded"]  # type: ignore[operator]
    assert "frontier_rl.swarm.team" not in outcome["loaded"]  # type: ignore[operator]
    team = _run("explore", "--world", "lse_arena", "--max-time", "5", "--robots", "2", "--json")
    assert team["code"] in (0, None) and "frontier_rl.swarm.team" in team["loaded"]  # type: ignore[operator]


@pytest.mark.parametrize("missing", ["torch", "stable_baselines3"])
def test_train_without_the_rl_extra_is_one_line_naming_it(missing: str, tmp_path: Path) -> None:
    script = f"import sys\nsys.modules[{missing!r}] = None\nfrom frontier_rl.cli import app\napp(sys.argv[1:])\n"
    args = ["train", "--out", str(tmp_path / "run"), "--timesteps", "8"]
    done = subprocess.run([sys.executable, "-c", script, *args], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert done.stderr.strip().splitlines() == [
        f"error: training needs {missing}, which is not installed: pip install 'frontier_rl[rl]'"
    ]
