"""Paired experiments: statistics (and, to come, runners, plots and reports)."""

from frontier_rl.evaluation.statistics import PairedStats, compare_methods, paired_stats, table_4_1

__all__ = ["PairedStats", "compare_methods", "paired_stats", "table_4_1"]
