"""Fingerprints of a fixed set of episodes, to check that a refactor changes no episode bit for bit.

Run as ``python benchmarks/fingerprints.py [--out FILE] [--check FILE]``. It runs 48 single-robot
episodes (the three built-in worlds × four policies × four seeds), 12 with the shipped models
(``models/model4.zip`` and ``models/model5.zip`` on the office world, six seeds each), 10 on
other generators (``tour`` and model 7 on a building floor, ``nearest``, ``tour`` and model 7 in a
cave, two seeds each) and 12 team episodes (two to four robots, every strategy, a failure), and
hashes each result's every field but its wall time: the times, lengths, decisions, coverage curve,
trajectory, decision log, final map and frontiers left. ``--out`` writes the hashes as JSON;
``--check`` compares them with a file an earlier checkout wrote and exits 1 naming every episode
that differs.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from collections.abc import Callable, Iterator
from dataclasses import fields
from enum import Enum
from pathlib import Path

import numpy as np

from frontier_rl.core.sim.episode import run_episode
from frontier_rl.core.sim.metrics import EpisodeResult
from frontier_rl.core.world.catalog import generate_world
from frontier_rl.policies import make_policy
from frontier_rl.swarm import Failure, Strategy, TeamConfig, run_team_episode

ROOT = Path(__file__).resolve().parent.parent
WORLDS = ("office", "rooms", "cluttered")
POLICIES = ("nearest", "fixed:0.75", "explore-lite", "info-gain")
SEEDS = (0, 1, 2, 3)
MODELS = ("model4", "model5")
MORE_WORLDS = {"building": ("tour", "model7"), "cave": ("nearest", "tour", "model7")}
"""Policies run on two seeds of other generators too: a 30-60 m building floor (its map is
searched on blocks) and a cave."""
TEAMS = (
    (2, Strategy.UNCOORDINATED, ()),
    (2, Strategy.COORDINATED, ()),
    (3, Strategy.COORDINATED, ()),
    (2, Strategy.RENDEZVOUS, ()),
    (3, Strategy.RENDEZVOUS, ()),
    (3, Strategy.COORDINATED, (Failure(robot=1, time_s=60.0),)),
)


def fingerprint(result: EpisodeResult, skip: frozenset[str] = frozenset()) -> str:
    """A SHA-256 of every field of ``result`` except its wall time and the fields in ``skip`` (a
    field added since the baseline was taken), at any depth (``path_on_map`` of each frontier left)."""
    digest = hashlib.sha256()
    for f in fields(result):
        if f.name == "wall_time_s" or f.name in skip:
            continue
        digest.update(f.name.encode())
        _feed(digest, getattr(result, f.name), skip)
    return digest.hexdigest()


def _feed(digest: hashlib._Hash, value: object, skip: frozenset[str]) -> None:
    if isinstance(value, np.ndarray):
        digest.update(str(value.dtype).encode() + str(value.shape).encode() + np.ascontiguousarray(value).tobytes())
    elif isinstance(value, list | tuple):
        digest.update(b"[%d" % len(value))
        for item in value:
            _feed(digest, item, skip)
    elif isinstance(value, Enum):  # by its value, as when such fields were strings
        digest.update(repr(value.value).encode())
    elif isinstance(value, dict):  # enum keys by their values, as when they were strings
        digest.update(repr({key.value if isinstance(key, Enum) else key: item for key, item in value.items()}).encode())
    elif hasattr(value, "__dataclass_fields__"):
        for f in fields(value):  # type: ignore[arg-type]
            if f.name not in skip:
                _feed(digest, getattr(value, f.name), skip)
    elif hasattr(value, "__dict__") and not isinstance(value, type):
        for key in sorted(vars(value)):
            if key not in skip:
                _feed(digest, vars(value)[key], skip)
    else:
        digest.update(repr(value).encode())


def episodes() -> Iterator[tuple[str, Callable[[], EpisodeResult]]]:
    """Every episode as (name, run)."""
    for world in WORLDS:
        for policy in POLICIES:
            for seed in SEEDS:
                yield (
                    f"{world}/{policy}/{seed}",
                    lambda w=world, p=policy, s=seed: run_episode(generate_world(w, s), make_policy(p), seed=s),
                )
    for model in MODELS:
        spec = f"learned:{ROOT / 'models' / f'{model}.zip'}"
        for seed in range(6):
            yield (
                f"office/{model}/{seed}",
                lambda m=spec, s=seed: run_episode(generate_world("office", s), make_policy(m), seed=s),
            )
    for world, names in MORE_WORLDS.items():
        for name in names:
            spec = f"learned:{ROOT / 'models' / f'{name}.zip'}" if name.startswith("model") else name
            for seed in (0, 1):
                yield (
                    f"{world}/{name}/{seed}",
                    lambda w=world, m=spec, s=seed: run_episode(generate_world(w, s), make_policy(m), seed=s),
                )
    for i, (robots, strategy, failures) in enumerate(TEAMS):
        team = TeamConfig(robots=robots, strategy=strategy, failures=failures)
        for seed in (0, 1):
            yield (
                f"team{i}/{robots}x{strategy.value}/{seed}",
                lambda t=team, s=seed: run_team_episode(
                    generate_world("office", s), make_policy("fixed:0.75"), team=t, seed=s
                ),
            )


def main(argv: list[str] | None = None) -> int:
    """Run every episode and print (or write, or check) its fingerprint."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--out", type=Path, help="write the fingerprints here (JSON)")
    parser.add_argument("--check", type=Path, help="compare with fingerprints an earlier checkout wrote")
    parser.add_argument("--skip", action="append", default=[], metavar="FIELD",
                        help="leave a field out, at any depth (one added since the baseline); repeatable")  # fmt: skip
    args = parser.parse_args(argv)
    hashes = {}
    for name, run in episodes():
        hashes[name] = fingerprint(run(), frozenset(args.skip))
        print(f"{hashes[name][:16]}  {name}", flush=True)
    if args.out:
        args.out.write_text(json.dumps(hashes, indent=1) + "\n")
    if args.check:
        expected = json.loads(args.check.read_text())
        differ = sorted(n for n in expected.keys() | hashes.keys() if expected.get(n) != hashes.get(n))
        print(f"{len(hashes) - len(differ)} of {len(hashes)} episodes identical; differ: {', '.join(differ) or 'none'}")
        return 1 if differ else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
