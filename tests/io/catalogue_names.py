"""The catalogue's names in ``catalogue.yaml``'s order, for the tests of the catalogue and of
``frontier-rl maps``."""

STANDALONE = (
    "turtlebot3_world", "aws_small_house", "nav2_depot", "nav2_warehouse", "lse_arena", "aws_bookstore", "willow_full",
    "willow_2010", "gdc_3ne", "gdc_3", "stata_basement", "ipa_office", "ipa_plant", "adblab", "brsu_c069",
    "uom_floor3", "elsabot_home",
)  # fmt: skip
"""The maps listed one by one, in the catalogue's order."""
