"""The names of the procedural worlds, in the order every list gives them: plain names, so that the
command line's help lists them without loading the generators (:mod:`frontier_rl.core.world.catalog`
maps each to its generator)."""

GENERATOR_NAMES: tuple[str, ...] = ("office", "rooms", "cluttered", "building", "cave", "slam_building")
"""The generators' names: ``office`` (the thesis's mazes), ``rooms``, ``cluttered`` (rubble), ``building``
(30-60 m floors), ``cave`` and ``slam_building`` (a building with a SLAM map's streaks, specks and
rough walls)."""
