"""The statistics of a paired experiment: every method against the baseline on the same episodes,
and the summary of its rows."""
