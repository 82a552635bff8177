"""The thesis's fixed weight of eq. 3.1 and its baseline: plain names, so that the command line's
defaults quote them without loading the engine."""

THESIS_WEIGHT = 0.75
"""The thesis's fixed ranking weight w of eq. 3.1, its baseline."""

THESIS_BASELINE = f"fixed:{THESIS_WEIGHT}"
"""The thesis's baseline as a policy spec."""
