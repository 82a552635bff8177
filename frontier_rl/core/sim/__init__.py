"""sim: a world + a ranking policy → an episode: the clock, the legs to each chosen goal, other
robots as obstacles, and the result (coverage curve, decisions, why it ended)."""
