"""world: a layout (generated or loaded) → the ground truth :class:`~.worlds.World`: its occupancy grid, the
robot's start pose and the explorable space (what the robot's sensor can see from where it can go).

The named procedural worlds (``catalog``) are drawn by ``office`` (the maze), ``rooms`` (BSP rooms),
``rubble`` (the cluttered field), ``building`` (30-60 m floors) and ``cave`` (tunnels and chambers),
on the pieces ``layout`` holds.

Also the grid geometry every later stage shares: walking a ray through cells (``raycast``) and line of
sight from a set of cells (``visibility``).
"""
