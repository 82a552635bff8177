"""frontiers: the robot's map → frontier clusters (their centres, sizes and goals) → a ranking
(``cost = w·d + (1−w)·(1−g)`` and the baselines' costs), less the goals that failed (the blacklist)."""
