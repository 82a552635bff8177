"""Which last looks a robot takes when no candidate is left, and what their outcomes leave: the
looks' own state over an episode (:mod:`frontier_rl.core.sim.looks` says what each look is).

The simulated robot's :class:`~frontier_rl.core.sim.navigator.Navigator` and a real robot's
:class:`~frontier_rl.robot.explorer.FrontierExplorer` keep one each, so that a robot driven
through Nav2 takes the looks the simulator's episodes take.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from frontier_rl.core.frontiers.blacklist import Blacklist
from frontier_rl.core.sim.candidates import Candidates, Look
from frontier_rl.core.sim.config import SimConfig
from frontier_rl.core.sim.looks import (
    LOOK_PAYOFF_M2,
    blind_looks,
    last_looks,
    looks_into_unknown_left,
    may_look,
    spent_looks,
)
from frontier_rl.core.world.robot import Pose


class LookState:
    """The last looks of one robot's episode: whether they are still taken, and on what word."""

    def __init__(self) -> None:
        self.looking = True
        """Whether the last looks are still taken: until one with floor seen through its clusters
        reveals less than :data:`~frontier_rl.core.sim.looks.LOOK_PAYOFF_M2` (:meth:`looked`)."""
        self.confirmed = False
        """Whether a look has paid, so that the next need no floor seen near their clusters
        (``confirmed`` of :func:`~frontier_rl.core.sim.looks.last_looks`): until one of those misses."""
        self._confirmable = True  # no look taken on a paid look's word alone has missed yet
        # the blind looks (:func:`~frontier_rl.core.sim.looks.blind_looks`): whether one was taken,
        # and whether none has paid yet
        self._blind_begun, self._blind_open = False, True

    def looks(self, levels: list[Candidates], pose: Pose, config: SimConfig, blacklist: Blacklist) -> Candidates:
        """The last looks of ``levels`` (the candidates of the normal costmap and of the narrow-passage
        recovery's levels, none with a frontier left) from the first level that has one: at the
        small clusters while :attr:`looking`, else at those opening onto the unknown a frontier left
        opens onto, else at the frontiers given up after their tries (each at most twice, as a
        visit); ``levels[0]`` when there is none."""
        home = standing_on(levels)
        worth = self.looking and (self.confirmed or may_look(home.grid, home.reachable))
        for cand in levels if worth else ():
            looks = last_looks(cand.grid, pose, cand.reachable, config, blacklist, self.confirmed)
            if len(looks):
                return dataclasses.replace(cand, frontiers=looks, looks=Look.SMALL)
        if self.looking and self._blind_open and (self._blind_begun or not worth):  # no floor seen beyond
            looks = blind_looks(home.grid, pose, home.reachable, config, blacklist)
            if len(looks):
                return dataclasses.replace(home, frontiers=looks, looks=Look.BLIND)
        for cand in levels:  # the unknown a frontier left opens onto, before the robot gives it up
            looks = looks_into_unknown_left(cand.grid, pose, cand.reachable, config, blacklist)
            if len(looks):
                return dataclasses.replace(cand, frontiers=looks, looks=Look.UNKNOWN_LEFT)
        for cand in levels if blacklist.gave_up() else ():  # a frontier given up to look at
            looks = spent_looks(cand.grid, pose, cand.reachable, config, blacklist)
            if len(looks):
                return dataclasses.replace(cand, frontiers=looks, looks=Look.GIVEN_UP)
        return levels[0]

    def looked(self, revealed_m2: float, blind: bool = False) -> None:
        """A look at the small clusters mapped ``revealed_m2`` of floor (m², cells newly known
        free). One that paid :data:`~frontier_rl.core.sim.looks.LOOK_PAYOFF_M2` lets the next do
        without floor seen near their clusters. One that paid less, taken while a paid look's word
        held, ends that word for the episode (the looks with floor seen through their clusters go
        on); otherwise it ends every look at them. A ``blind`` look ends no look: once one is taken
        (where no floor was seen beyond) the blind looks go on whatever they show (each from
        elsewhere, each cluster looked at twice at most) until one pays, and that one is a paid look."""
        paid = revealed_m2 >= LOOK_PAYOFF_M2
        if blind:
            self._blind_begun, self._blind_open = True, not paid
        elif self.confirmed and not paid:
            self._confirmable = False
        else:
            self.looking = self.looking and paid
        self.confirmed = self.looking and paid and self._confirmable


def standing_on(levels: list[Candidates]) -> Candidates:
    """The first of ``levels`` that reaches at least half the cells the last one reaches: the
    normal costmap, but where a leg through a gap only a recovery level opens ended on an island of
    it (on ``brsu_c069`` islands of 2 and 43 cells beside the recovery's 31,500, from which every
    floor the robot had seen lay "beyond"; standing elsewhere on that map, the normal costmap
    reached 27,700 of them)."""
    most = np.count_nonzero(levels[-1].reachable)
    return next(level for level in levels if 2 * np.count_nonzero(level.reachable) >= most)
