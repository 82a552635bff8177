"""The user's code the policy tests run: a policy module, and an installed distribution registering
policies by entry point."""

from __future__ import annotations

import textwrap
from pathlib import Path

from frontier_rl.policies import ENTRY_POINT_GROUP

GREEDY = '''
"""A module of the user's."""
import numpy as np
from frontier_rl import DecisionContext, Ranking


class Greedy:
    """The largest frontier per metre to drive.

    More text that the report leaves out.
    """

    name = "greedy"

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        frontiers = context.frontiers
        return Ranking(np.argsort(-frontiers.sizes / (1.0 + frontiers.distances), kind="stable"))


class Counting:
    """Counts its decisions (state that must not carry over between episodes)."""

    name = "counting"

    def __init__(self) -> None:
        self.decisions = 0

    def rank(self, context: DecisionContext, rng: np.random.Generator) -> Ranking:
        self.decisions += 1
        return Ranking(np.argsort(context.frontiers.distances, kind="stable"))
'''


def fake_distribution(root: Path, entry_points: str, module: str = GREEDY) -> Path:
    """An installed distribution ``fake-policies`` 1.2 in ``root`` (a folder for sys.path), whose
    ``entry_points.txt`` has ``entry_points`` under the frontier_rl.policies group."""
    root.mkdir(exist_ok=True)
    (root / "fake_policies.py").write_text(module)
    info = root / "fake_policies-1.2.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fake-policies\nVersion: 1.2\n")
    (info / "entry_points.txt").write_text(f"[{ENTRY_POINT_GROUP}]\n{textwrap.dedent(entry_points)}")
    return root
