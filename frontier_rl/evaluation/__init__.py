"""Paired experiments: configuration, runners and backends, results folders, statistics, plots and reports."""

from frontier_rl.evaluation.statistics import PairedStats, compare_methods, paired_stats
from frontier_rl.evaluation.tables import table_4_1

__all__ = ["PairedStats", "compare_methods", "paired_stats", "table_4_1"]
